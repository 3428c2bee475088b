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
#include <iterator>
#include <string>

#include "support/temp_dir.hpp"
#include "par2d/scene.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

using par2d::test::TempDir;

// ~`bytes` of scene text: many small circle occluders (the shape of a big level file).
// (Both helpers go unused under AddressSanitizer, where the case below does not run.)
[[maybe_unused]] std::string big_scene(std::size_t bytes) {
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
[[maybe_unused]] int load_with_headroom(const std::string& path, std::size_t extra) {
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

// AddressSanitizer, as GCC and clang each say it.
#if defined(__SANITIZE_ADDRESS__)
#define PAR2D_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PAR2D_TEST_ASAN 1
#endif
#endif

TEST_CASE("an 8 MB scene loads within 3x its size of new memory and fails cleanly with a quarter of it") {
#if defined(PAR2D_TEST_ASAN)
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

TEST_CASE("a NUL byte in a scene is refused with its offset and line, not taken for the end of the text") {
  // The issue: a file with a NUL byte and garbage after the JSON was accepted.
  TempDir dir("par2d_load");
  struct Case {
    std::string text;
    std::size_t offset, line;
  };
  const std::string scene = R"({"width": 4,)" "\n" R"( "height": 3})";
  const Case cases[] = {
      {scene + std::string("\0garbage", 8), scene.size(), 2},  // after the value
      {scene + "\n" + std::string(1, '\0'), scene.size() + 1, 3},  // at the very end
      {std::string(R"({"width": 4, "he)") + '\0' + R"(ight": 3})", 16, 1},  // inside a key
      {std::string(1, '\0') + scene, 0, 1},
  };
  for (const Case& c : cases) {
    const std::string expected = ": NUL byte at offset " + std::to_string(c.offset) + " (line " + std::to_string(c.line) +
                                 "); a scene is JSON text only";
    const std::string path = (dir.path / "nul.json").string();
    { std::ofstream(path, std::ios::binary) << c.text; }
    par2d::Scene out;
    out.width = 7;
    par2d::Status status = par2d::load_scene_file(path, out);
    CAPTURE(status.message());
    CHECK(status.code() == par2d::StatusCode::invalid_scene);
    CHECK(status.message() == path + expected);
    CHECK(out.width == 7);  // left as it was
    status = par2d::parse_scene(c.text, "text", out);
    CHECK(status.code() == par2d::StatusCode::invalid_scene);
    CHECK(status.message() == "text" + expected);
  }
  // The same scene without the NUL loads.
  par2d::Scene out;
  CHECK(par2d::parse_scene(scene, "text", out).ok());
  // The CLI: one line, non-zero, nothing written.
  { std::ofstream(dir.path / "nul.json", std::ios::binary) << scene << std::string("\0garbage", 8); }
  const std::string cmd = std::string(PAR2D_CLI_PATH) + " render " + (dir.path / "nul.json").string() + " -o " +
                          (dir.path / "out.png").string() + " 2> " + (dir.path / "err.txt").string();
  CHECK(std::system(cmd.c_str()) != 0);
  std::ifstream in(dir.path / "err.txt");
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(err == "par2d: " + (dir.path / "nul.json").string() + ": NUL byte at offset " + std::to_string(scene.size()) +
                   " (line 2); a scene is JSON text only\n");
  CHECK_FALSE(fs::exists(dir.path / "out.png"));
}
