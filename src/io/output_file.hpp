// One output file in progress: a hidden temporary replacing a regular file, or the open target for devices, FIFOs and stdout.
#pragma once

#include <sys/types.h>

#include <string>

#include "par2d/status.hpp"

namespace par2d::detail {

// What happens to each kind of target (docs/contract.md: no partial output, a failed run
// leaves every pre-existing file as it was):
// - a regular file, or none yet: bytes go to an unnamed temporary (O_TMPFILE) in the target's
//   directory, given the target's permission bits (and, for root, owner) and renamed over it
//   only at commit(). Where O_TMPFILE is missing, a named temporary that the destructor and
//   remove_pending_outputs() delete.
// - a character or block device, or a FIFO: written through (replacing one by a regular file
//   would break it); nothing can be undone there, so batches write these last.
// - "-": standard output, written through (refused when descriptor 1 is closed).
// Symbolic links are followed to their final target (a dangling link gets its target
// created). A regular file the user may not write is refused, as is anything else
// (directories, sockets).
// On Windows (output_file_windows.cpp) the same, with what it has: always a named temporary,
// moved over the target at commit; no links followed, no permission bits or owner copied.
class OutputFile {
 public:
  OutputFile() = default;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();  // discards an uncommitted temporary

  Status open(const std::string& path);
  Status write(const void* data, std::size_t size);
  // Makes the new content visible under the path (rename), or finishes a write-through.
  Status commit();

  bool writes_through() const noexcept { return through_; }
  const std::string& path() const noexcept { return path_; }
  // Identity of the final target (after symbolic links) when it exists: dev/ino, else 0/0.
  dev_t device() const noexcept { return dev_; }
  ino_t inode() const noexcept { return ino_; }
  // The final target's path (symbolic links resolved), for comparing outputs that do not exist yet.
  const std::string& target() const noexcept { return target_; }

 private:
  Status open_temporary();

  std::string path_;    // as given, for messages
  std::string target_;  // after following symbolic links
  std::string named_temp_;
  int fd_ = -1;
  int pending_slot_ = -1;
  bool through_ = false;
  bool is_stdout_ = false;
  bool unnamed_ = false;
  bool existed_ = false;
#ifndef _WIN32
  mode_t mode_ = 0;
  uid_t uid_ = 0;
  gid_t gid_ = 0;
#endif
  dev_t dev_ = 0;
  ino_t ino_ = 0;
};

}  // namespace par2d::detail
