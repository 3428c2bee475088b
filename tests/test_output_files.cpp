// Image files: sRGB and PFM values, and what writing does to what is already there (regular files, links, FIFOs, signals).
#include <doctest/doctest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "support/temp_dir.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"

extern char** environ;

namespace {

using namespace par2d;
namespace fs = std::filesystem;

// A fresh directory under the system temp dir, removed at scope exit.
using par2d::test::TempDir;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

// Decoded 8-bit RGB pixels of a PNG file.
std::vector<unsigned char> decode_png(const std::string& bytes, int& w, int& h) {
  int channels = 0;
  unsigned char* data = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<int>(bytes.size()), &w, &h, &channels, 3);
  REQUIRE_MESSAGE(data != nullptr, "stb_image could not decode the PNG");
  std::vector<unsigned char> out(data, data + static_cast<std::size_t>(w) * h * 3);
  stbi_image_free(data);
  return out;
}

// The sRGB transfer function (IEC 61966-2-1), written here independently of the library.
int srgb8(double linear) {
  const double v = std::min(1.0, std::max(0.0, linear));
  const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<int>(std::lround(255.0 * s));
}

struct Pixels {
  int width, height;
  std::vector<float> data;
  ImageView view() { return ImageView{data.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3}; }
};

Pixels gray_row(const std::vector<float>& values) {
  Pixels p{static_cast<int>(values.size()), 1, {}};
  for (float v : values) p.data.insert(p.data.end(), {v, v, v});
  return p;
}

Scene small_scene() {
  Scene s;
  s.width = 24;
  s.height = 16;
  s.view = {0, 0, 24, 16};
  Light l;
  l.shape = Circle{{6, 5}, 2};
  l.color = {1.0, 0.5, 0.25};
  l.intensity = 3.0;
  s.lights.push_back(l);
  s.occluders.push_back({Polygon{{{12, 4}, {16, 4}, {14, 10}}}});
  return s;
}

// Runs the CLI with `args`; returns the exit status (or 128 + signal).
int run_cli(const std::vector<std::string>& args) {
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, PAR2D_CLI_PATH, nullptr, nullptr, argv.data(), environ) == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// What a CLI run left: its exit status (or 128 + signal) and its standard error.
struct CliResult {
  int status = -1;
  std::string err;
};

// Runs the CLI with `args`, its standard error captured; `close_stdout`: it starts with
// descriptor 1 closed; `stdout_path`: descriptor 1 appends to that file (created if need be);
// `env`: its whole environment (NAME=VALUE) when given.
CliResult run_cli_captured(const std::vector<std::string>& args, bool close_stdout = false,
                           const std::string& stdout_path = "", const std::vector<std::string>* env = nullptr) {
  TempDir capture("par2d_cli_err");
  const std::string err_path = capture / "stderr.txt";
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<char*> envp;
  if (env != nullptr) {
    for (const std::string& e : *env) envp.push_back(const_cast<char*>(e.c_str()));
    envp.push_back(nullptr);
  }
  posix_spawn_file_actions_t actions;
  REQUIRE(posix_spawn_file_actions_init(&actions) == 0);
  REQUIRE(posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600) == 0);
  if (close_stdout) REQUIRE(posix_spawn_file_actions_addclose(&actions, 1) == 0);
  if (!stdout_path.empty())
    REQUIRE(posix_spawn_file_actions_addopen(&actions, 1, stdout_path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0600) == 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, PAR2D_CLI_PATH, &actions, nullptr, argv.data(), env ? envp.data() : environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(spawned == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CliResult result;
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.err = read_all(err_path);
  return result;
}

// A failure the standards ask for: exactly one line, on standard error, starting "par2d: ".
bool one_error_line(const std::string& err) {
  return err.rfind("par2d: ", 0) == 0 && err.find('\n') == err.size() - 1;
}

std::string scene_file(const TempDir& dir, const Scene& s) {
  std::string json = R"({"width": )" + std::to_string(s.width) + R"(, "height": )" + std::to_string(s.height) +
                     R"(, "lights": [{"circle": {"center": [6, 5], "radius": 2}, "color": [1, 0.5, 0.25], "intensity": 3}],)"
                     R"( "occluders": [{"polygon": [[12, 4], [16, 4], [14, 10]]}]})";
  write_all(dir / "scene.json", json);
  return dir / "scene.json";
}

}  // namespace

TEST_CASE("PNG golden values: linear 0.0031308, 0.214, 0.2141, 0.5, 1.0 give sRGB 10, 127, 128, 188, 255 (decoded back)") {
  // Code 128 starts at linear 0.214041 (the inverse curve at 127.5/255), so 0.214 is still 127.
  // Gamma 2.2 instead of the sRGB curve gives 127 for 0.2141 and 186 for 0.5.
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.0f, 0.0031308f, 0.214f, 0.2141f, 0.5f, 1.0f, 2.0f, -1.0f, NAN, 0.25f});
  REQUIRE(write_png(dir / "g.png", p.view()).ok());
  int w = 0, h = 0;
  const std::vector<unsigned char> got = decode_png(read_all(dir / "g.png"), w, h);
  REQUIRE(w == 10);
  REQUIRE(h == 1);
  const int expected[] = {0, 10, 127, 128, 188, 255, 255, 0, 0, 137};
  for (int i = 0; i < 10; ++i)
    for (int c = 0; c < 3; ++c) {
      INFO("pixel ", i, " channel ", c);
      CHECK(int(got[3 * i + c]) == expected[i]);
    }
  // Exposure scales before the curve: 0.25 * 2 = 0.5 -> 188.
  REQUIRE(write_png(dir / "e.png", gray_row({0.25f}).view(), 2.0).ok());
  CHECK(int(decode_png(read_all(dir / "e.png"), w, h)[0]) == 188);
  // Every 8-bit code: a ramp of 4096 values matches the independent transfer function.
  std::vector<float> ramp;
  for (int k = 0; k < 4096; ++k) ramp.push_back(static_cast<float>(k / 4095.0));
  REQUIRE(write_png(dir / "r.png", gray_row(ramp).view()).ok());
  const std::vector<unsigned char> r = decode_png(read_all(dir / "r.png"), w, h);
  int mismatches = 0;
  for (int k = 0; k < 4096; ++k) mismatches += int(r[3 * k]) != srgb8(double(ramp[k]));
  CHECK(mismatches == 0);
}

TEST_CASE("PFM round trip through the API: header, bottom row first, bits unchanged") {
  TempDir dir("par2d_out");
  Pixels p{3, 2, {}};
  for (int k = 0; k < 18; ++k) p.data.push_back(k == 5 ? -0.0f : static_cast<float>(k * 0.37 - 1.0));
  REQUIRE(write_pfm(dir / "x.pfm", p.view()).ok());
  const std::string bytes = read_all(dir / "x.pfm");
  const std::string header = "PF\n3 2\n-1.0\n";
  REQUIRE(bytes.size() == header.size() + 18 * 4);
  CHECK(bytes.substr(0, header.size()) == header);
  float first = 0;  // the file's first float is the bottom row's first value
  std::memcpy(&first, bytes.data() + header.size(), 4);
  CHECK(first == p.data[9]);
  int w = 0, h = 0;
  std::vector<float> back;
  REQUIRE(read_pfm(dir / "x.pfm", w, h, back).ok());
  CHECK(w == 3);
  CHECK(h == 2);
  CHECK(std::memcmp(back.data(), p.data.data(), 18 * 4) == 0);
}

TEST_CASE("CLI PNG and PFM hold exactly the API's render") {
  TempDir dir("par2d_out");
  const Scene scene = small_scene();
  const std::string json = scene_file(dir, scene);
  REQUIRE(run_cli({"render", json, "-o", dir / "out.png", "--pfm", dir / "out.pfm", "--backend", "scalar",
                   "--exposure", "0.5"}) == 0);
  RenderOptions o;
  o.backend = Backend::scalar;
  Status status;
  const test::RenderedImage api = test::render_image(scene, o, status);
  REQUIRE(status.ok());
  int w = 0, h = 0;
  std::vector<float> pfm;
  REQUIRE(read_pfm(dir / "out.pfm", w, h, pfm).ok());
  REQUIRE(pfm.size() == api.pixels.size());
  CHECK(std::memcmp(pfm.data(), api.pixels.data(), pfm.size() * 4) == 0);
  const std::vector<unsigned char> png = decode_png(read_all(dir / "out.png"), w, h);
  int mismatches = 0;
  for (std::size_t k = 0; k < api.pixels.size(); ++k) mismatches += int(png[k]) != srgb8(0.5 * double(api.pixels[k]));
  CHECK(mismatches == 0);
  // "-o -" writes the same PNG to standard output.
  const std::string cmd = std::string(PAR2D_CLI_PATH) + " render " + json + " --backend scalar --exposure 0.5 -o - > " +
                          (dir / "stdout.png");
  REQUIRE(std::system(cmd.c_str()) == 0);
  CHECK(read_all(dir / "stdout.png") == read_all(dir / "out.png"));
}

TEST_CASE("replacing a regular file keeps its permission bits and leaves no temporary") {
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.5f, 0.25f});
  write_all(dir / "a.png", "old");
  fs::permissions(dir / "a.png", fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read,
                  fs::perm_options::replace);
  REQUIRE(write_png(dir / "a.png", p.view()).ok());
  CHECK(read_all(dir / "a.png").substr(1, 3) == "PNG");
  CHECK((fs::status(dir / "a.png").permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  CHECK(dir.names() == std::vector<std::string>{"a.png"});
}

TEST_CASE("a symbolic link is followed: the link stays, its target gets the image") {
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.5f});
  fs::create_directory(dir / "sub");
  write_all(dir / "sub/target.pfm", "old");
  fs::create_symlink("sub/target.pfm", dir / "link.pfm");
  REQUIRE(write_pfm(dir / "link.pfm", p.view()).ok());
  CHECK(fs::is_symlink(dir / "link.pfm"));
  CHECK(read_all(dir / "sub/target.pfm").substr(0, 3) == "PF\n");
  // A dangling link gets its target created.
  fs::create_symlink("new.pfm", dir / "dangling.pfm");
  REQUIRE(write_pfm(dir / "dangling.pfm", p.view()).ok());
  CHECK(fs::is_symlink(dir / "dangling.pfm"));
  CHECK(read_all(dir / "new.pfm").substr(0, 3) == "PF\n");
}

TEST_CASE("a FIFO is written through, not replaced by a regular file") {
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.5f, 1.0f});
  REQUIRE(::mkfifo((dir / "pipe").c_str(), 0600) == 0);
  std::string received;
  std::thread reader([&] { received = read_all(dir / "pipe"); });
  const Status s = write_pfm(dir / "pipe", p.view());
  reader.join();
  CHECK_MESSAGE(s.ok(), s.message());
  CHECK(fs::is_fifo(dir / "pipe"));
  CHECK(received.size() == std::string("PF\n2 1\n-1.0\n").size() + 24);
  CHECK(dir.names() == std::vector<std::string>{"pipe"});
}

TEST_CASE("a character device is written through, not replaced (a null device node made in a temp dir)") {
  TempDir dir("par2d_out");
  // Making a device node needs root (CAP_MKNOD); elsewhere this case says so and checks nothing.
  if (::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    MESSAGE("cannot mknod here (not root): the device case is covered by the FIFO case only");
    return;
  }
  Pixels p = gray_row({0.5f});
  REQUIRE(write_png(dir / "null", p.view()).ok());
  struct stat st {};
  REQUIRE(::stat((dir / "null").c_str(), &st) == 0);
  CHECK(S_ISCHR(st.st_mode));
  CHECK(dir.names() == std::vector<std::string>{"null"});
}

TEST_CASE("a file the user may not write is refused, and stays as it was") {
  TempDir dir("par2d_out");
  write_all(dir / "ro.png", "keep");
  fs::permissions(dir / "ro.png", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read,
                  fs::perm_options::replace);
  Pixels p = gray_row({0.5f});
  // Root may write anything, so as root the check runs in a child that drops to nobody.
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    const Status s = write_png(dir / "ro.png", p.view());
    const bool refused = s.code() == StatusCode::io_error && s.message().find("ro.png: cannot write") != std::string::npos;
    ::_exit(refused ? 0 : 1);
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(read_all(dir / "ro.png") == "keep");
  CHECK(dir.names() == std::vector<std::string>{"ro.png"});
}

TEST_CASE("a failed batch leaves every pre-existing file exactly as it was (API and CLI)") {
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.5f});
  write_all(dir / "old.png", "old png");
  const Status s = write_images({{dir / "old.png", ImageOutput::Format::png, 1.0},
                                 {dir / "nodir/x.pfm", ImageOutput::Format::pfm, 1.0}},
                                p.view());
  CHECK(!s.ok());
  CHECK(s.message().find("nodir/x.pfm") != std::string::npos);
  CHECK(read_all(dir / "old.png") == "old png");
  CHECK(dir.names() == std::vector<std::string>{"old.png"});
  // The issue's command line.
  const std::string json = scene_file(dir, small_scene());
  CHECK(run_cli({"render", json, "-o", dir / "old.png", "--pfm", dir / "nodir/x.pfm"}) == 1);
  CHECK(read_all(dir / "old.png") == "old png");
  CHECK(dir.names() == std::vector<std::string>{"old.png", "scene.json"});
}

TEST_CASE("two outputs naming one file by different strings are refused before anything is written") {
  TempDir dir("par2d_out");
  Pixels p = gray_row({0.5f});
  const std::string a = dir / "a.png";
  const std::string dotted = (dir.path / "." / "a.png").string();
  Status s = write_images({{a, ImageOutput::Format::png, 1.0}, {dotted, ImageOutput::Format::pfm, 1.0}}, p.view());
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(s.message().find("are the same file") != std::string::npos);
  CHECK(dir.names().empty());
  write_all(a, "old");
  fs::create_symlink("a.png", dir / "l.pfm");
  s = write_images({{a, ImageOutput::Format::png, 1.0}, {dir / "l.pfm", ImageOutput::Format::pfm, 1.0}}, p.view());
  CHECK(s.message().find("are the same file") != std::string::npos);
  CHECK(read_all(a) == "old");
  // The CLI refuses it before rendering, with a usage error.
  const std::string json = scene_file(dir, small_scene());
  CHECK(run_cli({"render", json, "-o", a, "--pfm", dotted}) == 2);
  CHECK(run_cli({"render", json, "-o", dir / "l.pfm", "--pfm", a}) == 2);
  CHECK(read_all(a) == "old");
}

TEST_CASE("SIGTERM or SIGINT while the CLI writes leaves no partial file and the old ones untouched") {
  // The PFM goes to a FIFO that is opened but never read: the CLI blocks once the pipe is
  // full, with the PNG's temporary complete but not yet renamed. Both temporary kinds are
  // tried (unnamed O_TMPFILE, and named ones as on filesystems without it).
  for (const char* mode : {"", "1"}) {
    for (int sig : {SIGTERM, SIGINT}) {
      TempDir dir("par2d_out");
      Scene scene = small_scene();
      scene.width = scene.height = 256;  // a 786 kB PFM: far more than a pipe holds
      std::string json = read_all(scene_file(dir, small_scene()));
      json.replace(json.find("\"width\": 24"), 11, "\"width\": 256");
      json.replace(json.find("\"height\": 16"), 12, "\"height\": 256");
      write_all(dir / "scene.json", json);
      write_all(dir / "old.png", "old png");
      REQUIRE(::mkfifo((dir / "pipe").c_str(), 0600) == 0);
      const int read_end = ::open((dir / "pipe").c_str(), O_RDONLY | O_NONBLOCK);
      REQUIRE(read_end >= 0);
      if (*mode) ::setenv("PAR2D_NAMED_TEMPORARIES", mode, 1);
      const std::string scene_path = dir / "scene.json", png = dir / "old.png", pfm = dir / "pipe";
      char* argv[] = {const_cast<char*>(PAR2D_CLI_PATH), const_cast<char*>("render"), const_cast<char*>(scene_path.c_str()),
                      const_cast<char*>("-o"), const_cast<char*>(png.c_str()), const_cast<char*>("--pfm"),
                      const_cast<char*>(pfm.c_str()), nullptr};
      pid_t pid = 0;
      REQUIRE(posix_spawn(&pid, PAR2D_CLI_PATH, nullptr, nullptr, argv, environ) == 0);
      ::unsetenv("PAR2D_NAMED_TEMPORARIES");
      // Wait (up to 60 s) until the pipe is full, i.e. its byte count stops growing for 300 ms
      // (its capacity depends on how writes fill its pages): the CLI is then blocked mid-write.
      int queued = 0, stable = 0;
      for (int k = 0; k < 6000 && stable < 30; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        int now = 0;
        ::ioctl(read_end, FIONREAD, &now);
        stable = (now > 0 && now == queued) ? stable + 1 : 0;
        queued = now;
      }
      INFO("temporaries ", *mode ? "named" : "unnamed", ", signal ", sig, ", bytes in pipe ", queued);
      CHECK(queued >= 16384);
      CHECK(queued < 786432);  // blocked before the end of the PFM
      ::kill(pid, sig);
      int status = 0;
      REQUIRE(::waitpid(pid, &status, 0) == pid);
      ::close(read_end);
      CHECK(WIFSIGNALED(status));
      if (WIFSIGNALED(status)) CHECK(WTERMSIG(status) == sig);
      CHECK(read_all(dir / "old.png") == "old png");
      CHECK(dir.names() == std::vector<std::string>{"old.png", "pipe", "scene.json"});
    }
  }
}

TEST_CASE("with standard output closed, '-' is refused and no output file can take descriptor 1") {
  // The issue: the first output's temporary got descriptor 1, so "-" wrote into it.
  TempDir dir("par2d_out");
  const std::string json = scene_file(dir, small_scene());
  for (const auto& args : {std::vector<std::string>{"-o", dir / "a.png", "--pfm", "-"},
                           std::vector<std::string>{"--pfm", dir / "a.pfm", "-o", "-"},
                           std::vector<std::string>{"--plain-pfm", "-", "--plain-png", dir / "a.png"}}) {
    std::vector<std::string> all{"render", json, "--backend", "scalar"};
    all.insert(all.end(), args.begin(), args.end());
    const CliResult run = run_cli_captured(all, /*close_stdout=*/true);
    CAPTURE(args[0]);
    CAPTURE(run.err);
    CHECK(run.status == 2);
    CHECK(one_error_line(run.err));
    CHECK(run.err.find("standard output is closed") != std::string::npos);
    CHECK(dir.names() == std::vector<std::string>{"scene.json"});
  }
  // Files only: the same bytes as with standard output open.
  REQUIRE(run_cli({"render", json, "--backend", "scalar", "-o", dir / "open.png", "--pfm", dir / "open.pfm"}) == 0);
  const CliResult closed = run_cli_captured(
      {"render", json, "--backend", "scalar", "-o", dir / "closed.png", "--pfm", dir / "closed.pfm"}, true);
  CHECK(closed.status == 0);
  CHECK(closed.err.empty());
  CHECK(read_all(dir / "closed.png") == read_all(dir / "open.png"));
  CHECK(read_all(dir / "closed.pfm") == read_all(dir / "open.pfm"));
}

TEST_CASE("an output that is the scene file, by any name, is refused before anything is written") {
  TempDir dir("par2d_out");
  const std::string json = scene_file(dir, small_scene());
  const std::string original = read_all(json);
  fs::create_symlink("scene.json", dir / "link.png");
  fs::create_hard_link(json, dir / "hard.pfm");
  const std::string dotted = (dir.path / "." / "scene.json").string();
  for (const char* option : {"-o", "--pfm", "--plain-png", "--plain-pfm"}) {
    for (const std::string& name : {json, dotted, dir / "link.png", dir / "hard.pfm"}) {
      const CliResult run = run_cli_captured({"render", json, "--backend", "scalar", option, name});
      CAPTURE(option);
      CAPTURE(name);
      CAPTURE(run.err);
      CHECK(run.status == 2);
      CHECK(one_error_line(run.err));
      CHECK(run.err.find(std::string(option) + " '" + name + "'") != std::string::npos);
      CHECK(run.err.find("scene file '" + json + "'") != std::string::npos);
      CHECK(read_all(json) == original);
      CHECK(dir.names() == std::vector<std::string>{"hard.pfm", "link.png", "scene.json"});
    }
  }
  // Standard output appending to the scene file is the scene file too.
  const CliResult run = run_cli_captured({"render", json, "--backend", "scalar", "-o", "-"}, false, json);
  CAPTURE(run.err);
  CHECK(run.status == 2);
  CHECK(one_error_line(run.err));
  CHECK(read_all(json) == original);
}

TEST_CASE("view with no usable display says so in one line and fails") {
  TempDir dir("par2d_out");
  const std::string json = scene_file(dir, small_scene());
  if (run_cli_captured({"view", "--help"}, false, dir / "help.txt").status != 0) {
    MESSAGE("this par2d has no view command (built without the viewer)");
    return;
  }
  // DISPLAY set but empty names no display; without XDG_RUNTIME_DIR libwayland would add a
  // line of its own if SDL were left to probe.
  const std::vector<std::string> env{"DISPLAY=", "WAYLAND_DISPLAY=", "PATH=/usr/bin:/bin", "HOME=" + dir.path.string()};
  const CliResult run = run_cli_captured({"view", json}, false, "", &env);
  CAPTURE(run.err);
  CHECK(run.status == 1);
  CHECK(one_error_line(run.err));
  CHECK(run.err.find("no display") != std::string::npos);
  // DISPLAY naming an X server that is not there (no socket for it, as a file or abstract):
  // still one line, and SDL is never loaded for it.
  std::string unix_sockets;
  {
    std::ifstream in("/proc/net/unix");
    unix_sockets.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  int number = 77;
  while (fs::exists("/tmp/.X11-unix/X" + std::to_string(number)) ||
         unix_sockets.find("@/tmp/.X11-unix/X" + std::to_string(number)) != std::string::npos)
    ++number;
  const std::vector<std::string> dead{"DISPLAY=:" + std::to_string(number), "PATH=/usr/bin:/bin",
                                      "HOME=" + dir.path.string()};
  const CliResult dead_run = run_cli_captured({"view", json}, false, "", &dead);
  CAPTURE(dead_run.err);
  CHECK(dead_run.status == 1);
  CHECK(one_error_line(dead_run.err));
  CHECK(dead_run.err.find("no display (DISPLAY=:" + std::to_string(number) + " cannot be opened: no X server listens on") !=
        std::string::npos);
}
