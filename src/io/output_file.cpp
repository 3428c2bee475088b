// Output files that appear whole or not at all, with the cleanup a signal handler may run.
#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>

#include "io/pending_outputs.hpp"
#include "par2d/image_io.hpp"

namespace par2d {
namespace detail {
namespace {

std::string unique_sibling(const std::string& target) {
  static std::atomic<unsigned> counter{0};
  return target + ".tmp" + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Linking an O_TMPFILE file into place goes through /proc/self/fd (linkat with AT_EMPTY_PATH
// needs a capability). PAR2D_NAMED_TEMPORARIES=1 forces named temporaries, as on filesystems
// without O_TMPFILE, so that tests can check their cleanup on signals.
bool unnamed_temporaries() {
  static const bool available = std::getenv("PAR2D_NAMED_TEMPORARIES") == nullptr && ::access("/proc/self/fd", X_OK) == 0;
  return available;
}

}  // namespace

OutputFile::~OutputFile() {
  if (fd_ >= 0 && !is_stdout_) ::close(fd_);
  if (!named_temp_.empty()) ::unlink(named_temp_.c_str());
  release_pending(pending_slot_);
}

Status OutputFile::open(const std::string& path) {
  path_ = path;
  if (path == "-") {
    if (::fcntl(STDOUT_FILENO, F_GETFD) == -1) return io_error("-: cannot write: standard output is closed");
    through_ = is_stdout_ = true;
    fd_ = STDOUT_FILENO;
    return {};
  }
  if (path.empty()) return Status(StatusCode::invalid_argument, "output path is empty");

  // Follow symbolic links to the file they name, so that the link stays a link.
  std::string p = path;
  for (int hops = 0;; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0) {
      if (errno == ENOENT) break;
      return io_error(errno_text(path, "cannot write", errno));
    }
    if (!S_ISLNK(st.st_mode)) break;
    if (hops == 40) return io_error(errno_text(path, "cannot write", ELOOP));
    char buffer[PATH_MAX];
    const ssize_t n = ::readlink(p.c_str(), buffer, sizeof buffer - 1);
    if (n < 0) return io_error(errno_text(path, "cannot write", errno));
    std::string link(buffer, static_cast<std::size_t>(n));
    p = link[0] == '/' ? link : (p.rfind('/') == std::string::npos ? link : p.substr(0, p.rfind('/') + 1) + link);
  }
  target_ = p;

  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) {
    if (errno != ENOENT) return io_error(errno_text(path, "cannot write", errno));
    return open_temporary();
  }
  existed_ = true;
  dev_ = st.st_dev;
  ino_ = st.st_ino;
  if (S_ISREG(st.st_mode)) {
    // Renaming over a read-only file would succeed where writing it would not: refuse it.
    if (::access(p.c_str(), W_OK) != 0) return io_error(errno_text(path, "cannot write", errno));
    mode_ = st.st_mode & 07777;
    uid_ = st.st_uid;
    gid_ = st.st_gid;
    return open_temporary();
  }
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) || S_ISFIFO(st.st_mode)) {
    const int fd = ::open(p.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return io_error(errno_text(path, "cannot write", errno));
    fd_ = fd;
    through_ = true;
    return {};
  }
  if (S_ISDIR(st.st_mode)) return io_error(errno_text(path, "cannot write", EISDIR));
  return io_error(path + ": cannot write: not a regular file, device or FIFO");
}

Status OutputFile::open_temporary() {
  const std::string dir = directory_of(target_);
  // An existing file's mode is set with fchmod at commit; until then only we can read it.
  const mode_t create_mode = existed_ ? 0600 : 0666;
#ifdef O_TMPFILE
  if (unnamed_temporaries()) {
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, create_mode);
    if (fd >= 0) {
      fd_ = fd;
      unnamed_ = true;
      return {};
    }
    // Filesystems without O_TMPFILE answer one of these; anything else is a real error.
    if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
      return io_error(errno_text(path_, "cannot create", errno));
  }
#endif
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = unique_sibling(target_);
    pending_slot_ = claim_pending(name);
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, create_mode);
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
    // Some kernels cap one write() at about 2 GiB; loop over partial writes.
    const ssize_t n = ::write(fd_, bytes, std::min<std::size_t>(size, std::size_t{1} << 30));
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
    if (::close(fd) != 0) return io_error(errno_text(path_, "write failed", errno));
    return {};
  }
  if (existed_) {
    if (::fchmod(fd_, mode_) != 0) return io_error(errno_text(path_, "cannot set permissions", errno));
    // Only root can give a file away; for anyone else the owner is already right or cannot be.
    if (::geteuid() == 0) (void)!::fchown(fd_, uid_, gid_);
  }
  if (unnamed_) {
    // The file gets a name only now, for the instant between linkat and rename.
    std::string name = unique_sibling(target_);
    pending_slot_ = claim_pending(name);
    const std::string proc = "/proc/self/fd/" + std::to_string(fd_);
    if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) != 0) {
      const int err = errno;
      release_pending(pending_slot_);
      return io_error(errno_text(path_, "cannot write", err));
    }
    named_temp_ = std::move(name);
  }
  const int fd = fd_;
  fd_ = -1;
  // close() reports deferred write errors (NFS, quota), so its result matters.
  if (::close(fd) != 0) return io_error(errno_text(path_, "write failed", errno));
  if (::rename(named_temp_.c_str(), target_.c_str()) != 0) return io_error(errno_text(path_, "cannot write", errno));
  named_temp_.clear();
  release_pending(pending_slot_);
  return {};
}

}  // namespace detail

void remove_pending_outputs() noexcept {
  for (detail::PendingSlot& slot : detail::g_pending)
    if (slot.state.load() == 2) ::unlink(slot.name);
}

}  // namespace par2d
