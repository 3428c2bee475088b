// The library's one exception-to-status wrapper: every public entry that can allocate runs
// its body through `guarded`, so no exception crosses the API (out of memory becomes a
// Status). The C API adds its own at the C boundary, where unknown exceptions must stop too.
#pragma once

#include <exception>
#include <new>
#include <string>

#include "par2d/status.hpp"

namespace par2d::detail {

// Runs fn (returning Status), turning exceptions into a status prefixed by `who`.
template <class Fn>
Status guarded(const char* who, Fn&& fn) {
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, std::string(who) + ": out of memory");
  } catch (const std::exception& e) {
    return Status(StatusCode::invalid_argument, std::string(who) + ": " + e.what());
  }
}

}  // namespace par2d::detail
