// Loading scene files: memory stays a small multiple of the file, allocation failure is a status, non-regular files are refused without blocking.
#include <doctest/doctest.h>

#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/temp_dir.hpp"
#include "par2d/scene.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

using par2d::test::TempDir;

// ~`bytes` of scene text: many small circle occluders (the shape of a big level file).
std::string big_scene(std::size_t bytes) {
  std::string out = R"({"width": 4, "height": 4, "lights": [{"circle": {"center": [2, 2], "radius": 1}}], "occluders": [)";
  for (std::size_t k = 0; out.size() < bytes; ++k) {
    if (k) out += ',';
    out += R"({"circle":{"center":[)" + std::to_string(100 + k % 997) + "," + std::to_string(100 + k % 991) +
           R"(],"radius":1}})";
  }
  return out + "]}";
}

// Loads `path` in a fresh process whose address space may grow by at most `extra` bytes
// (tests/support/load_under_limit.cpp): 0 loaded, 2 out_of_memory status, 1 anything else,
// 128 + signal for a crash.
int load_with_headroom(const std::string& path, std::size_t extra) {
  const std::string extra_text = std::to_string(extra);
  char* argv[] = {const_cast<char*>(PAR2D_LOAD_HELPER_PATH), const_cast<char*>(path.c_str()),
                  const_cast<char*>(extra_text.c_str()), nullptr};
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, PAR2D_LOAD_HELPER_PATH, nullptr, nullptr, argv, environ) == 0);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

}  // namespace

TEST_CASE("an 8 MB scene loads within 3x its size of new memory and fails cleanly with a quarter of it") {
#if defined(__SANITIZE_ADDRESS__)
  // ASan's allocator aborts on an allocation failure instead of throwing, and its shadow
  // memory makes address-space limits meaningless; tools/ci/resources.sh covers the CLI.
  MESSAGE("not run under AddressSanitizer");
#else
  TempDir dir("par2d_load");
  const std::string text = big_scene(8u << 20);
  {
    std::ofstream(dir / "big.json", std::ios::binary) << text;
  }
  // A document parser needed ~14x the file (252 MB for 17.5 MB); the scene itself needs 40
  // bytes per circle against 40 bytes of text, plus vector growth.
  CHECK(load_with_headroom(dir / "big.json", 3 * text.size()) == 0);
  // Far too little: the allocation failure is the one-line out_of_memory status, no abort.
  CHECK(load_with_headroom(dir / "big.json", text.size() / 4) == 2);
  CHECK(load_with_headroom(dir / "big.json", text.size() / 64) == 2);
#endif
}

TEST_CASE("a FIFO with no writer, a directory and other non-regular scene files are refused without blocking") {
  TempDir dir("par2d_load");
  REQUIRE(::mkfifo((dir / "scene.fifo").c_str(), 0600) == 0);
  par2d::Scene scene;
  par2d::Status s = par2d::load_scene_file(dir / "scene.fifo", scene);
  CHECK(s.code() == par2d::StatusCode::io_error);
  CHECK(s.message() == (dir / "scene.fifo") + ": cannot read: not a regular file");
  fs::create_directory(dir / "scene.json");
  s = par2d::load_scene_file(dir / "scene.json", scene);
  CHECK(s.code() == par2d::StatusCode::io_error);
  CHECK(s.message().find("scene.json: cannot read: Is a directory") != std::string::npos);
  // A symbolic link to a regular scene file is read as that file.
  {
    std::ofstream(dir / "real.json") << R"({"width": 3, "height": 2})";
  }
  fs::create_symlink("real.json", dir / "link.json");
  REQUIRE(par2d::load_scene_file(dir / "link.json", scene).ok());
  CHECK(scene.width == 3);
}
