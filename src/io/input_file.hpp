// Opening an input file (a scene, a normal map) the same careful way everywhere: a FIFO with
// no writer never blocks, and only regular files are read.
#pragma once

#include <sys/stat.h>

#include <cstdio>
#include <memory>
#include <string>

#include "par2d/status.hpp"

namespace par2d::detail {

using FileHandle = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// Opens `path` for reading in blocking mode if it is a regular file; `info` gets its stat.
// Otherwise an io_error status: `PATH: cannot open: REASON` or `PATH: cannot read: REASON`.
Status open_regular_file(const std::string& path, FileHandle& file, struct stat& info);

}  // namespace par2d::detail
