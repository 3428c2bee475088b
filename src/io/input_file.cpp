// Opening regular input files without blocking on FIFOs (see input_file.hpp).
#include "io/input_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace par2d::detail {

#ifdef _WIN32
// Windows has no FIFOs to block on and no O_NONBLOCK: a plain binary open, then the same checks.
Status open_regular_file(const std::string& path, FileHandle& file, struct stat& info) {
  FileHandle opened(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!opened) {
    const int error = errno;
    return Status(StatusCode::io_error, path + ": cannot open: " + std::strerror(error));
  }
  if (::fstat(::_fileno(opened.get()), &info) != 0) {
    const int error = errno;
    return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(error));
  }
  if (S_ISDIR(info.st_mode)) return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(EISDIR));
  if (!S_ISREG(info.st_mode)) return Status(StatusCode::io_error, path + ": cannot read: not a regular file");
  file = std::move(opened);
  return {};
}
#else
Status open_regular_file(const std::string& path, FileHandle& file, struct stat& info) {
  // O_NONBLOCK: opening a FIFO that has no writer must not wait for one.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int error = errno;
    return Status(StatusCode::io_error, path + ": cannot open: " + std::strerror(error));
  }
  FileHandle opened(::fdopen(fd, "rb"), &std::fclose);
  if (!opened) {
    const int error = errno;
    ::close(fd);
    return Status(StatusCode::io_error, path + ": cannot open: " + std::strerror(error));
  }
  if (::fstat(fd, &info) != 0) {
    const int error = errno;
    return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(error));
  }
  if (S_ISDIR(info.st_mode)) return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(EISDIR));
  if (!S_ISREG(info.st_mode)) return Status(StatusCode::io_error, path + ": cannot read: not a regular file");
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  file = std::move(opened);
  return {};
}
#endif

}  // namespace par2d::detail
