// The few file calls whose POSIX and Windows forms differ, for the writers and readers that
// are otherwise the same on both (MinGW's C runtime has open/write/close/stat).
#pragma once

#include <fcntl.h>

#include <string>

namespace par2d::detail {

// Flags every open() adds: no descriptor leaks into child processes; on Windows also binary
// mode (text mode would write "\n" as "\r\n").
#ifdef _WIN32
inline constexpr int kOpenFlags = _O_BINARY | _O_NOINHERIT;
#else
inline constexpr int kOpenFlags = O_CLOEXEC;
#endif

// rename(from, to), replacing an existing `to` on Windows too (its rename() refuses one).
// 0, or -1 with errno set.
int replace_file(const std::string& from, const std::string& to) noexcept;

// Whether descriptor 1 is closed (then "-" cannot be written).
bool stdout_closed() noexcept;

// The absolute, canonical path of an existing directory or file; false when there is none.
bool canonical_path(const std::string& path, std::string& out);

}  // namespace par2d::detail
