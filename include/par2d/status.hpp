// Status: how every fallible par2d call reports failure (a code plus a one-line message).
#pragma once

#include <string>
#include <utility>

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

enum class StatusCode {
  ok = 0,
  invalid_argument,  // API misuse: bad buffer, size, stride, option
  invalid_scene,     // the scene breaks docs/contract.md section 3
  io_error,          // a file could not be read or written
  out_of_memory,     // an allocation the request needs could not be made
  unsupported,       // the request names something this build or CPU lacks
  work_limit,        // the frame's estimated work is past RenderOptions::work_limit (nothing written)
  cancelled,         // the frame was cancelled (progress function or Renderer::cancel; nothing written)
};

// A status value: `ok()` or a code with a message meant for a human, on one line.
// Scene errors read `FILE: PATH.TO.FIELD: what is wrong`.
class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status success() { return {}; }

  bool ok() const noexcept { return code_ == StatusCode::ok; }
  explicit operator bool() const noexcept { return ok(); }
  StatusCode code() const noexcept { return code_; }
  const std::string& message() const noexcept { return message_; }

 private:
  StatusCode code_ = StatusCode::ok;
  std::string message_;
};

const char* status_code_name(StatusCode code) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
