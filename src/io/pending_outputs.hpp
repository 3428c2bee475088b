// The registry of output temporaries that exist on disk, shared by the POSIX and Windows
// output files (each platform compiles one of them): remove_pending_outputs() may run in a
// signal handler, so the names live in fixed storage behind lock-free atomics, no allocation.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstring>
#include <string>

#include "par2d/status.hpp"

namespace par2d::detail {

// state: 0 free, 1 being filled, 2 holds a name to delete.
inline constexpr int kPendingSlots = 32;
inline constexpr std::size_t kPendingNameMax = 4096;
struct PendingSlot {
  std::atomic<int> state{0};
  char name[kPendingNameMax];
};
inline PendingSlot g_pending[kPendingSlots];

// A slot now naming `name`, or -1 (a name too long, or more outputs at once than slots: the
// file is still written, only not cleaned up by a signal handler).
inline int claim_pending(const std::string& name) noexcept {
  if (name.size() >= kPendingNameMax) return -1;
  for (int i = 0; i < kPendingSlots; ++i) {
    int expected = 0;
    if (!g_pending[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_pending[i].name, name.c_str(), name.size() + 1);
    g_pending[i].state.store(2);
    return i;
  }
  return -1;
}

inline void release_pending(int& slot) noexcept {
  if (slot >= 0) g_pending[slot].state.store(0);
  slot = -1;
}

inline std::string errno_text(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

inline Status io_error(std::string message) { return Status(StatusCode::io_error, std::move(message)); }

}  // namespace par2d::detail
