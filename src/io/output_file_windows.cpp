// Output files that appear whole or not at all, on Windows: the contract of output_file.cpp
// (see output_file.hpp) with Windows' calls. Bytes go to a named temporary next to the
// target, moved over it at commit; the destructor and remove_pending_outputs() delete it.
#include <fcntl.h>
#include <io.h>
#include <process.h>
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "io/file_compat.hpp"
#include "io/output_file.hpp"
#include "io/pending_outputs.hpp"
#include "par2d/image_io.hpp"

namespace par2d {
namespace detail {
namespace {

std::string unique_sibling(const std::string& target) {
  static std::atomic<unsigned> counter{0};
  return target + ".tmp" + std::to_string(::_getpid()) + "." + std::to_string(counter.fetch_add(1));
}

}  // namespace

OutputFile::~OutputFile() {
  if (fd_ >= 0 && !is_stdout_) ::_close(fd_);
  if (!named_temp_.empty()) ::_unlink(named_temp_.c_str());
  release_pending(pending_slot_);
}

Status OutputFile::open(const std::string& path) {
  path_ = path;
  if (path == "-") {
    if (stdout_closed()) return io_error("-: cannot write: standard output is closed");
    ::_setmode(1, _O_BINARY);  // image bytes, not text
    through_ = is_stdout_ = true;
    fd_ = 1;
    return {};
  }
  if (path.empty()) return Status(StatusCode::invalid_argument, "output path is empty");
  target_ = path;

  struct _stat64 st {};
  if (::_stat64(path.c_str(), &st) != 0) {
    if (errno != ENOENT) return io_error(errno_text(path, "cannot write", errno));
    return open_temporary();
  }
  existed_ = true;
  dev_ = st.st_dev;
  ino_ = st.st_ino;
  if ((st.st_mode & _S_IFMT) == _S_IFREG) {
    // Moving over a read-only file would succeed where writing it would not: refuse it.
    if (::_access(path.c_str(), 2) != 0) return io_error(errno_text(path, "cannot write", errno));
    return open_temporary();
  }
  if ((st.st_mode & _S_IFMT) == _S_IFCHR) {  // a device such as NUL: written through
    const int fd = ::_open(path.c_str(), _O_WRONLY | kOpenFlags);
    if (fd < 0) return io_error(errno_text(path, "cannot write", errno));
    fd_ = fd;
    through_ = true;
    return {};
  }
  if ((st.st_mode & _S_IFMT) == _S_IFDIR) return io_error(errno_text(path, "cannot write", EISDIR));
  return io_error(path + ": cannot write: not a regular file or device");
}

Status OutputFile::open_temporary() {
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = unique_sibling(target_);
    pending_slot_ = claim_pending(name);
    const int fd = ::_open(name.c_str(), _O_WRONLY | _O_CREAT | _O_EXCL | kOpenFlags, _S_IREAD | _S_IWRITE);
    if (fd >= 0) {
      fd_ = fd;
      named_temp_ = std::move(name);
      return {};
    }
    const int err = errno;
    release_pending(pending_slot_);
    if (err != EEXIST) return io_error(errno_text(path_, "cannot create", err));
  }
  return io_error(path_ + ": cannot create a unique temporary file next to it");
}

Status OutputFile::write(const void* data, std::size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const int n = ::_write(fd_, bytes, static_cast<unsigned>(std::min<std::size_t>(size, std::size_t{1} << 30)));
    if (n < 0) {
      if (errno == EINTR) continue;
      return io_error(errno_text(path_, "write failed", errno));
    }
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  return {};
}

Status OutputFile::commit() {
  if (through_) {
    if (is_stdout_) return {};
    const int fd = fd_;
    fd_ = -1;
    if (::_close(fd) != 0) return io_error(errno_text(path_, "write failed", errno));
    return {};
  }
  const int fd = fd_;
  fd_ = -1;
  if (::_close(fd) != 0) return io_error(errno_text(path_, "write failed", errno));
  if (replace_file(named_temp_, target_) != 0) return io_error(errno_text(path_, "cannot write", errno));
  named_temp_.clear();
  release_pending(pending_slot_);
  return {};
}

}  // namespace detail

void remove_pending_outputs() noexcept {
  for (detail::PendingSlot& slot : detail::g_pending)
    if (slot.state.load() == 2) ::_unlink(slot.name);
}

}  // namespace par2d
