// Google Benchmark: a game loop (bench/game_level.hpp: ~300 walls and pillars, 8 torches that
// move and flicker every frame) with a persistent Renderer against one-shot render(), at
// 1280x720 and 320x180, 1 and all threads. Each iteration is one frame, updates included;
// counters give the median and 99th percentile of the frames' wall times. Run with
// --benchmark_filter=game_loop; the order interleaves variants so machine load hits all alike.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "game_level.hpp"
#include "par2d/par2d.hpp"

namespace {

using Clock = std::chrono::steady_clock;

void report(benchmark::State& state, std::vector<double>& ms, int threads_used) {
  if (ms.empty()) return;
  std::sort(ms.begin(), ms.end());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[std::min(ms.size() - 1, (ms.size() * 99) / 100)];
  state.counters["threads_used"] = threads_used;
  state.counters["frames"] = static_cast<double>(ms.size());
}

par2d::RenderOptions options_for(int threads) {
  par2d::RenderOptions o;
  o.threads = threads;
  return o;
}

void persistent(benchmark::State& state, int width, int height, int threads, par2d::PixelFormat format) {
  par2d::Renderer renderer;
  if (!renderer.set_options(options_for(threads)).ok()) return state.SkipWithError("set_options failed");
  std::vector<par2d::LightHandle> torches;
  if (!renderer.set_scene(par2d::bench::game_level(width, height), &torches).ok())
    return state.SkipWithError("set_scene failed");
  const int pixel = par2d::bytes_per_pixel(format);
  std::vector<unsigned char> texture(static_cast<std::size_t>(width) * height * static_cast<std::size_t>(pixel));
  const par2d::FrameBuffer buffer{texture.data(), format, static_cast<std::ptrdiff_t>(width) * pixel, 1.0};
  if (!renderer.render(buffer).ok()) return state.SkipWithError("render failed");  // first frame: sizes buffers
  std::vector<double> ms;
  int frame = 1;
  for (auto _ : state) {
    const auto start = Clock::now();
    for (int t = 0; t < par2d::bench::kTorches; ++t)
      renderer.update_light(torches[static_cast<std::size_t>(t)], par2d::bench::torch_at(t, frame));
    if (!renderer.render(buffer).ok()) return state.SkipWithError("render failed");
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    ++frame;
  }
  report(state, ms, renderer.threads());
}

void one_shot(benchmark::State& state, int width, int height, int threads) {
  par2d::Scene scene = par2d::bench::game_level(width, height);
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3);
  const par2d::ImageView image{pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3};
  const par2d::RenderOptions options = options_for(threads);
  std::vector<double> ms;
  int frame = 1;
  for (auto _ : state) {
    const auto start = Clock::now();
    for (int t = 0; t < par2d::bench::kTorches; ++t)
      scene.lights[static_cast<std::size_t>(t)] = par2d::bench::torch_at(t, frame);
    if (!par2d::render(scene, options, image).ok()) return state.SkipWithError("render failed");
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    ++frame;
  }
  report(state, ms, par2d::resolved_threads(options));
}

const bool registered = [] {
  const int all = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::vector<int> thread_counts{1};
  if (all > 1) thread_counts.push_back(all);
  for (const auto& size : {std::pair<int, int>{1280, 720}, std::pair<int, int>{320, 180}}) {
    for (const int threads : thread_counts) {
      const std::string suffix = "/" + std::to_string(size.first) + "x" + std::to_string(size.second) +
                                 "/threads:" + std::to_string(threads);
      // Float RGB, what one-shot render() writes, for a like-for-like ratio; and the 8-bit
      // sRGB texture a game uploads (one-shot would need a conversion pass on top).
      benchmark::RegisterBenchmark(("game_loop/persistent" + suffix).c_str(),
                                   [size, threads](benchmark::State& s) {
                                     persistent(s, size.first, size.second, threads, par2d::PixelFormat::rgb_f32);
                                   })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("game_loop/persistent_rgba8" + suffix).c_str(),
                                   [size, threads](benchmark::State& s) {
                                     persistent(s, size.first, size.second, threads, par2d::PixelFormat::rgba8_srgb);
                                   })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("game_loop/one_shot" + suffix).c_str(),
                                   [size, threads](benchmark::State& s) { one_shot(s, size.first, size.second, threads); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
  return true;
}();

}  // namespace
