// POSIX and Windows forms of the calls in file_compat.hpp.
#include "io/file_compat.hpp"

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>

#ifdef _WIN32
#ifndef NOMINMAX
#define NOMINMAX
#endif
#define WIN32_LEAN_AND_MEAN
#include <io.h>
#include <windows.h>
#else
#include <unistd.h>
#endif

namespace par2d::detail {

int replace_file(const std::string& from, const std::string& to) noexcept {
#ifdef _WIN32
  if (MoveFileExA(from.c_str(), to.c_str(), MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH)) return 0;
  switch (GetLastError()) {
    case ERROR_FILE_NOT_FOUND:
    case ERROR_PATH_NOT_FOUND: errno = ENOENT; break;
    case ERROR_ACCESS_DENIED:
    case ERROR_SHARING_VIOLATION: errno = EACCES; break;
    case ERROR_DISK_FULL: errno = ENOSPC; break;
    default: errno = EIO; break;
  }
  return -1;
#else
  return std::rename(from.c_str(), to.c_str());
#endif
}

bool stdout_closed() noexcept {
#ifdef _WIN32
  return ::_get_osfhandle(1) < 0;
#else
  return ::fcntl(STDOUT_FILENO, F_GETFD) == -1;
#endif
}

bool canonical_path(const std::string& path, std::string& out) {
#ifdef _WIN32
  char buffer[_MAX_PATH];
  if (::_fullpath(buffer, path.c_str(), sizeof buffer) == nullptr) return false;
  if (GetFileAttributesA(buffer) == INVALID_FILE_ATTRIBUTES) return false;
#else
  char buffer[PATH_MAX];
  if (::realpath(path.c_str(), buffer) == nullptr) return false;
#endif
  out = buffer;
  return true;
}

}  // namespace par2d::detail
