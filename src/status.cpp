// Names of status codes, for messages and logs.
#include "par2d/status.hpp"

namespace par2d {

const char* status_code_name(StatusCode code) noexcept {
  switch (code) {
    case StatusCode::ok: return "ok";
    case StatusCode::invalid_argument: return "invalid argument";
    case StatusCode::invalid_scene: return "invalid scene";
    case StatusCode::io_error: return "i/o error";
    case StatusCode::out_of_memory: return "out of memory";
    case StatusCode::unsupported: return "unsupported";
    case StatusCode::work_limit: return "work limit";
    case StatusCode::cancelled: return "cancelled";
  }
  return "unknown";
}

}  // namespace par2d
