// Long renders: the work estimate and limit, progress reports and cancellation (docs/api.md,
// "Long renders"), through the C++ API and the CLI.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "par2d/par2d.hpp"
#include "support/temp_dir.hpp"
#include "support/test_tiers.hpp"

extern char** environ;

namespace {

using namespace par2d;
using par2d::test::TempDir;

constexpr double kPi = 3.14159265358979323846;
constexpr float kSentinel = -7.25f;  // what an untouched pixel holds

// One light beside a white circle wall cut into ceil(2 pi r / piece) bounce pieces.
Scene bounce_scene(int width, int height, double wall_radius, double piece) {
  Scene s;
  s.width = width;
  s.height = height;
  s.view = {0, 0, double(width), double(height)};
  Light l;
  l.shape = Circle{{width * 0.2, height * 0.3}, 3.0};
  l.color = {1, 1, 1};
  l.intensity = 2.0;
  s.lights.push_back(l);
  Occluder wall;
  wall.shape = Circle{{width * 0.6, height * 0.6}, wall_radius};
  wall.albedo = {1, 1, 1};
  s.occluders.push_back(wall);
  s.bounce.piece = piece;
  return s;
}

// Two lights and three occluders, no bounce.
Scene plain_scene(int width, int height) {
  Scene s;
  s.width = width;
  s.height = height;
  s.view = {0, 0, double(width), double(height)};
  for (int k = 0; k < 2; ++k) {
    Light l;
    l.shape = Circle{{width * (0.2 + 0.5 * k), height * 0.3}, 4.0};
    l.color = {1, 0.8, 0.6};
    l.intensity = 1.5;
    s.lights.push_back(l);
  }
  s.occluders.push_back({Polygon{{{width * 0.4, height * 0.4}, {width * 0.5, height * 0.4}, {width * 0.45, height * 0.6}}}});
  s.occluders.push_back({Circle{{width * 0.7, height * 0.7}, 6.0}});
  s.occluders.push_back({Segment{{width * 0.1, height * 0.8}, {width * 0.3, height * 0.9}}});
  return s;
}

std::vector<float> filled(const Scene& s, float value = kSentinel) {
  return std::vector<float>(static_cast<std::size_t>(s.width) * s.height * 3, value);
}

ImageView view_of(std::vector<float>& pixels, const Scene& s) {
  return ImageView{pixels.data(), s.width, s.height, static_cast<std::ptrdiff_t>(s.width) * 3};
}

bool untouched(const std::vector<float>& pixels) {
  for (const float v : pixels)
    if (std::memcmp(&v, &kSentinel, sizeof v) != 0) return false;
  return true;
}

// Tiles of 16x16 meeting [x0, x1) x [y0, y1).
std::uint64_t tiles_of(int x0, int y0, int x1, int y1) {
  return std::uint64_t((x1 - 1) / 16 - x0 / 16 + 1) * std::uint64_t((y1 - 1) / 16 - y0 / 16 + 1);
}

// What a progress function saw.
struct Calls {
  std::vector<Progress> seen;
  std::vector<std::thread::id> threads;
  // Rising tiles_done, one total, all on `caller`.
  void check(std::thread::id caller, std::uint64_t total) const {
    REQUIRE(!seen.empty());
    for (std::size_t k = 0; k < seen.size(); ++k) {
      INFO("call ", k);
      CHECK(threads[k] == caller);
      CHECK(seen[k].tiles == total);
      CHECK(seen[k].tiles_done <= total);
      if (k > 0) CHECK(seen[k].tiles_done > seen[k - 1].tiles_done);
    }
  }
};

ProgressFunction recorder(Calls& calls, std::uint64_t cancel_at = 0) {
  return [&calls, cancel_at](const Progress& p) {
    calls.seen.push_back(p);
    calls.threads.push_back(std::this_thread::get_id());
    return cancel_at == 0 || p.tiles_done < cancel_at;
  };
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs the CLI with `args`, standard error into `err`; returns the exit status.
int run_cli(const std::vector<std::string>& args, std::string& err) {
  TempDir capture("par2d_cli_err");
  const std::string err_path = capture / "stderr.txt";
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  REQUIRE(posix_spawn_file_actions_init(&actions) == 0);
  REQUIRE(posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600) == 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, PAR2D_CLI_PATH, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(spawned == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  err = read_all(err_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A 202-byte scene: one light, one white circle wall of radius 10 cut
// into pieces of 6.29e-5 (998,917 pieces, under the 1,048,576 cap), at 1024x1024: about 13
// hours on one core.
const char* const kHugeBounceJson =
    R"({"width": 1024, "height": 1024, "bounce": {"piece": 6.29e-5},)"
    R"( "lights": [{"circle": {"center": [100, 100], "radius": 10}, "color": [1, 1, 1], "intensity": 1}],)"
    R"( "occluders": [{"circle": {"center": [512, 512], "radius": 10}, "albedo": [1, 1, 1]}]})";

}  // namespace

TEST_CASE("a bounce frame past work_limit is refused before any pixel is written; a higher limit renders it") {
  const Scene scene = bounce_scene(64, 64, 8.0, 0.25);  // 202 pieces: about 8.3e5 units
  RenderOptions options;
  options.backend = Backend::scalar;
  options.bounce = BounceTerm::only;  // the bounce alone: no direct light in the estimate
  options.threads = 2;
  WorkEstimate estimate;
  REQUIRE(estimate_work(scene, options, estimate).ok());
  const double pieces = std::ceil(2.0 * kPi * 8.0 / 0.25);
  CHECK(estimate.samples == 64.0 * 64.0);
  CHECK(estimate.bounce == pieces * (64.0 * 64.0 + 1.0 * (1.0 + 1.0)));
  CHECK(estimate.scalar == 0.0);
  CHECK(estimate.total == estimate.bounce);

  options.work_limit = estimate.total * 0.99;
  std::vector<float> pixels = filled(scene);
  const Status refused = render(scene, options, view_of(pixels, scene));
  CHECK(refused.code() == StatusCode::work_limit);
  CHECK(refused.message().find("work limit") != std::string::npos);
  CHECK(untouched(pixels));

  options.work_limit = estimate.total;  // at the limit: allowed
  REQUIRE(render(scene, options, view_of(pixels, scene)).ok());
  CHECK(!untouched(pixels));
}

TEST_CASE("a 202-byte one-circle bounce scene at 1024x1024 (1e12 units) is refused by the default limit at once") {
  Scene scene;
  REQUIRE(parse_scene(kHugeBounceJson, "huge.json", scene).ok());
  const double pieces = std::ceil(2.0 * kPi * 10.0 / 6.29e-5);
  REQUIRE(pieces < kMaxBouncePieces);
  RenderOptions options;
  options.backend = Backend::scalar;
  WorkEstimate estimate;
  REQUIRE(estimate_work(scene, options, estimate).ok());
  CHECK(estimate.bounce == pieces * (1024.0 * 1024.0 + 1.0 * 2.0));
  CHECK(estimate.scalar == 1024.0 * 1024.0 * 1.0 * 2.0);
  CHECK(estimate.total > 10.0 * kDefaultWorkLimit);
  // Through a Renderer (the path every front door takes), with the default options.
  Renderer renderer;
  REQUIRE(renderer.set_options(options).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  std::vector<float> pixels = filled(scene);
  const Status s = renderer.render(view_of(pixels, scene));
  CHECK(s.code() == StatusCode::work_limit);
  CHECK(untouched(pixels));
  CHECK(renderer.stats().frames == 0);
}

TEST_CASE("the estimate by counts: scalar reference, regions, spp and the ray caster") {
  const Scene scene = plain_scene(64, 48);
  RenderOptions options;
  options.backend = Backend::scalar;
  options.spp = 2;
  WorkEstimate e;
  REQUIRE(estimate_work(scene, options, e).ok());
  CHECK(e.samples == 64.0 * 48 * 2);
  CHECK(e.scalar == 64.0 * 48 * 2 * 2 * (3 + 1));
  CHECK(e.bounce == 0.0);
  CHECK(e.total == e.scalar);

  Renderer renderer;
  REQUIRE(renderer.set_options(options).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  WorkEstimate region;
  REQUIRE(renderer.estimate_work(PixelRect{8, 4, 40, 20}, region).ok());
  CHECK(region.samples == 32.0 * 16 * 2);
  CHECK(region.scalar == 32.0 * 16 * 2 * 2 * 4);
  CHECK(renderer.estimate_work(PixelRect{0, 0, 65, 48}, region).code() == StatusCode::invalid_argument);

  options.rays = 64;
  REQUIRE(estimate_raycast_work(scene, options, e).ok());
  CHECK(e.raycast == 64.0 * (64 * 48 * 2) * (2 + 3));
  CHECK(e.total == e.raycast);
  options.work_limit = e.total / 2;
  std::vector<float> pixels = filled(scene);
  CHECK(render_raycast(scene, options, view_of(pixels, scene)).code() == StatusCode::work_limit);
  CHECK(untouched(pixels));

  options.work_limit = -1.0;
  CHECK(estimate_work(scene, options, e).code() == StatusCode::invalid_argument);
  options.work_limit = NAN;
  CHECK(Renderer().set_options(options).code() == StatusCode::invalid_argument);
}

TEST_CASE("work_limit 0 means no limit, and a Renderer checks the limit at each frame" * par2d::test::per_isa()) {
  Scene scene = bounce_scene(48, 40, 6.0, 0.5);
  Renderer renderer;
  RenderOptions options;
  options.work_limit = 1.0;
  REQUIRE(renderer.set_options(options).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  std::vector<float> pixels = filled(scene);
  CHECK(renderer.render(view_of(pixels, scene)).code() == StatusCode::work_limit);
  CHECK(untouched(pixels));
  options.work_limit = 0.0;
  REQUIRE(renderer.set_options(options).ok());
  CHECK(renderer.render(view_of(pixels, scene)).ok());
  CHECK(!untouched(pixels));
}

TEST_CASE("progress: from the calling thread only, rising, ending at the frame's tiles; the image unchanged" *
          par2d::test::per_isa()) {
  const Scene scene = plain_scene(200, 150);
  RenderOptions options;
  options.threads = 4;
  std::vector<float> reference = filled(scene);
  REQUIRE(render(scene, options, view_of(reference, scene)).ok());

  Renderer renderer;
  REQUIRE(renderer.set_options(options).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  Calls calls;
  renderer.set_progress(recorder(calls));
  std::vector<float> pixels = filled(scene);
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const std::uint64_t total = tiles_of(0, 0, 200, 150);
  calls.check(std::this_thread::get_id(), total);
  CHECK(calls.seen.back().tiles_done == total);
  CHECK(pixels == reference);

  // A region counts the tiles that meet it.
  calls = Calls{};
  std::vector<float> part(static_cast<std::size_t>(90 - 20) * (100 - 30) * 3, kSentinel);
  FrameBuffer buffer{part.data(), PixelFormat::rgb_f32, (90 - 20) * 3 * static_cast<std::ptrdiff_t>(sizeof(float))};
  REQUIRE(renderer.render(buffer, PixelRect{20, 30, 90, 100}).ok());
  calls.check(std::this_thread::get_id(), tiles_of(20, 30, 90, 100));
  CHECK(calls.seen.back().tiles_done == tiles_of(20, 30, 90, 100));
  for (int y = 30; y < 100; ++y)
    for (int x = 20; x < 90; ++x)
      for (int c = 0; c < 3; ++c)
        REQUIRE(part[(static_cast<std::size_t>(y - 30) * 70 + (x - 20)) * 3 + c] ==
                reference[(static_cast<std::size_t>(y) * 200 + x) * 3 + c]);
}

TEST_CASE("cancel from the progress function after N tiles: status cancelled, buffer untouched, next frame whole" *
          par2d::test::per_isa()) {
  // With 3 threads the other two would have to finish 317 of the 320 tiles while the calling
  // thread computes its first for the frame to complete before the cancel.
  const Scene scene = plain_scene(320, 256);
  std::vector<float> reference = filled(scene);
  RenderOptions options;
  REQUIRE(render(scene, options, view_of(reference, scene)).ok());
  for (const int threads : {1, 3}) {
    for (const Backend backend : {Backend::automatic, Backend::scalar}) {
      INFO("threads ", threads, " backend ", backend_name(backend));
      options.threads = threads;
      options.backend = backend;
      Renderer renderer;
      REQUIRE(renderer.set_options(options).ok());
      REQUIRE(renderer.set_scene(scene).ok());
      Calls calls;
      renderer.set_progress(recorder(calls, 3));
      std::vector<float> pixels = filled(scene);
      const Status s = renderer.render(view_of(pixels, scene));
      CHECK(s.code() == StatusCode::cancelled);
      CHECK(untouched(pixels));
      CHECK(renderer.stats().frames == 0);
      calls.check(std::this_thread::get_id(), tiles_of(0, 0, 320, 256));
      CHECK(calls.seen.back().tiles_done >= 3);
      CHECK(calls.seen.back().tiles_done < tiles_of(0, 0, 320, 256));
      // The next frame renders whole.
      renderer.set_progress(nullptr);
      REQUIRE(renderer.render(view_of(pixels, scene)).ok());
      if (backend == Backend::automatic) CHECK(pixels == reference);
      else CHECK(!untouched(pixels));
    }
  }
}

TEST_CASE("cancel from another thread: mid-frame in a watched frame, before the start otherwise; used up once" *
          par2d::test::per_isa()) {
  const Scene scene = plain_scene(160, 128);
  Renderer renderer;
  RenderOptions options;
  options.threads = 1;  // the frame cannot finish before the cancelling thread has run
  REQUIRE(renderer.set_options(options).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  std::vector<float> pixels = filled(scene);
  // Asked before the frame (no progress function, the SIMD path: written in place): it does
  // not start.
  std::thread([&renderer] { renderer.cancel(); }).join();
  CHECK(renderer.render(view_of(pixels, scene)).code() == StatusCode::cancelled);
  CHECK(untouched(pixels));
  // The request was used up.
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  std::vector<float> reference = pixels;

  // Asked by another thread while the frame runs (the progress function waits for it).
  std::fill(pixels.begin(), pixels.end(), kSentinel);
  int calls = 0;
  renderer.set_progress([&renderer, &calls](const Progress&) {
    if (calls++ == 0) std::thread([&renderer] { renderer.cancel(); }).join();
    return true;
  });
  CHECK(renderer.render(view_of(pixels, scene)).code() == StatusCode::cancelled);
  CHECK(untouched(pixels));
  CHECK(calls >= 1);
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  CHECK(pixels == reference);
}

TEST_CASE("a cancelled incremental frame leaves the buffer as the last frame and the next frame is whole" *
          par2d::test::per_isa()) {
  Scene scene = plain_scene(192, 128);
  Renderer renderer;
  RenderOptions one;
  one.threads = 1;  // the first tile's report comes before the frame's last tile
  REQUIRE(renderer.set_options(one).ok());
  REQUIRE(renderer.set_incremental(true).ok());
  std::vector<LightHandle> lights;
  REQUIRE(renderer.set_scene(scene, &lights).ok());
  std::vector<float> pixels = filled(scene);
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const std::vector<float> first = pixels;
  scene.lights[0].shape = Circle{{60, 50}, 4.0};
  REQUIRE(renderer.update_light(lights[0], scene.lights[0]).ok());
  renderer.set_progress([](const Progress& p) { return p.tiles_done < 1; });
  CHECK(renderer.render(view_of(pixels, scene)).code() == StatusCode::cancelled);
  CHECK(pixels == first);
  renderer.set_progress(nullptr);
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  std::vector<float> expected = filled(scene);
  REQUIRE(render(scene, RenderOptions{}, view_of(expected, scene)).ok());
  CHECK(pixels == expected);
}

TEST_CASE("one-shot render with a RenderControl: progress, a cancel flag, and the ray caster" * par2d::test::per_isa()) {
  const Scene scene = plain_scene(96, 80);
  RenderOptions options;
  options.threads = 2;
  std::vector<float> reference = filled(scene);
  REQUIRE(render(scene, options, view_of(reference, scene)).ok());

  Calls calls;
  RenderControl control;
  control.progress = recorder(calls);
  std::vector<float> pixels = filled(scene);
  REQUIRE(render(scene, options, view_of(pixels, scene), control).ok());
  calls.check(std::this_thread::get_id(), tiles_of(0, 0, 96, 80));
  CHECK(calls.seen.back().tiles_done == tiles_of(0, 0, 96, 80));
  CHECK(pixels == reference);

  std::atomic<bool> cancel{true};
  RenderControl stop;
  stop.cancel = &cancel;
  std::fill(pixels.begin(), pixels.end(), kSentinel);
  CHECK(render(scene, options, view_of(pixels, scene), stop).code() == StatusCode::cancelled);
  CHECK(untouched(pixels));

  // The ray caster reports its 64x64 blocks as their tiles, and stops the same way.
  options.rays = 16;
  calls = Calls{};
  control.progress = recorder(calls);
  REQUIRE(render_raycast(scene, options, view_of(pixels, scene), control).ok());
  calls.check(std::this_thread::get_id(), tiles_of(0, 0, 96, 80));
  CHECK(calls.seen.back().tiles_done == tiles_of(0, 0, 96, 80));
  calls = Calls{};
  control.progress = recorder(calls, 1);
  options.threads = 1;  // the first block's report comes before the last block
  std::fill(pixels.begin(), pixels.end(), kSentinel);
  CHECK(render_raycast(scene, options, view_of(pixels, scene), control).code() == StatusCode::cancelled);
  CHECK(untouched(pixels));
}

TEST_CASE("CLI: a frame past the work limit is refused in one line naming --work-limit, writing nothing") {
  TempDir dir("par2d_long");
  {
    std::ofstream(dir / "huge.json") << kHugeBounceJson;
  }
  std::string err;
  CHECK(run_cli({"render", dir / "huge.json", "-o", dir / "huge.png"}, err) == 1);
  CHECK(err.rfind("par2d: render: ", 0) == 0);
  CHECK(err.find('\n') == err.size() - 1);
  CHECK(err.find("--work-limit") != std::string::npos);
  CHECK(err.find(dir / "huge.json") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "huge.png"));

  // A small bounce scene renders by default and is refused under a low limit.
  {
    std::ofstream(dir / "small.json")
        << R"({"width": 48, "height": 32, "bounce": {"piece": 0.5},)"
           R"( "lights": [{"circle": {"center": [10, 10], "radius": 3}, "color": [1, 1, 1], "intensity": 1}],)"
           R"( "occluders": [{"circle": {"center": [30, 20], "radius": 5}, "albedo": [1, 1, 1]}]})";
  }
  CHECK(run_cli({"render", dir / "small.json", "--pfm", dir / "small.pfm", "--work-limit", "1000"}, err) == 1);
  CHECK(err.find("--work-limit") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "small.pfm"));
  CHECK(run_cli({"render", dir / "small.json", "--pfm", dir / "small.pfm", "--work-limit", "-1"}, err) == 2);
  REQUIRE(run_cli({"render", dir / "small.json", "--pfm", dir / "small.pfm"}, err) == 0);
  CHECK(err.empty());  // standard error is no terminal: no progress bar
  CHECK(std::filesystem::exists(dir / "small.pfm"));
}

TEST_CASE("CLI: --progress always draws the bar on standard error up to 100 %, ending its line") {
  TempDir dir("par2d_long");
  {
    std::ofstream(dir / "s.json")
        << R"({"width": 80, "height": 48, "lights": [{"circle": {"center": [10, 10], "radius": 3},)"
           R"( "color": [1, 1, 1], "intensity": 1}], "occluders": [{"polygon": [[30, 10], [40, 10], [35, 30]]}]})";
  }
  std::string err;
  REQUIRE(run_cli({"render", dir / "s.json", "--pfm", dir / "s.pfm", "--progress", "always", "--threads", "2"}, err) ==
          0);
  CHECK(err.find("100% 15/15 tiles") != std::string::npos);  // 5 x 3 tiles
  CHECK(err.back() == '\n');
  CHECK(run_cli({"render", dir / "s.json", "--pfm", dir / "t.pfm", "--progress", "never"}, err) == 0);
  CHECK(err.empty());
  CHECK(run_cli({"render", dir / "s.json", "--pfm", dir / "t.pfm", "--progress", "sometimes"}, err) == 2);
}
