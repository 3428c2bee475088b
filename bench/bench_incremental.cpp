// Google Benchmark: incremental frames (Renderer::set_incremental) on the torch hall
// (bench/torch_hall.hpp: 1280x720, 64 ranged torches, 300 walls and crates, a door), one
// iteration per frame, updates included: full (2 torches move, every pixel computed), a
// (nothing changes), b (2 torches move), c (8 torches flicker, 2 move), d (the door moves),
// s (2 torches move and every other light and occluder is re-sent with the values it has, as
// an engine syncing its entities each frame does: s against b is what the re-sync costs),
// g (the camera pans 4 px a frame diagonally on the view's pixel grid, set_view_offset),
// m (g while 2 torches move), p (g, every pixel computed: the pan's full frame).
// 100 frames each. Counters: median and p99 frame time, pixels recomputed per frame. Run with
// --benchmark_filter=incremental; bench/incremental_frames.cpp is the same loop for callgrind.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "torch_hall.hpp"

namespace {

void incremental(benchmark::State& state, char scenario, int threads, std::size_t layer_bytes) {
  const int width = 1280, height = 720;
  par2d::Renderer r;
  par2d::RenderOptions options;
  options.threads = threads;
  std::vector<par2d::LightHandle> torches;
  std::vector<par2d::OccluderHandle> occluders;
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3);
  const par2d::FrameBuffer buffer{pixels.data(), par2d::PixelFormat::rgb_f32, static_cast<std::ptrdiff_t>(width) * 12, 1.0};
  const par2d::Scene hall = par2d::bench::torch_hall(width, height);
  if (!r.set_options(options).ok() || !r.set_scene(hall, &torches, &occluders).ok() ||
      !r.set_incremental(true).ok() || !r.set_light_layer_budget(layer_bytes).ok() || !r.render(buffer).ok())
    return state.SkipWithError("setup failed");
  const par2d::OccluderHandle door = occluders[par2d::bench::hall_door_index()];
  std::vector<double> ms;
  double pixels_sum = 0.0;
  int f = 1;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    if ((scenario == 'g' || scenario == 'm' || scenario == 'p') && !r.set_view_offset(4 * f, 4 * f).ok())
      return state.SkipWithError("set_view_offset failed");
    if (scenario == 'f' || scenario == 'b' || scenario == 'c' || scenario == 's' || scenario == 'm' || scenario == 'p')
      for (int t : {5, 42}) r.update_light(torches[static_cast<std::size_t>(t)], par2d::bench::hall_torch(t, f, false));
    if (scenario == 'c') {
      for (int t = 16; t < 24; ++t) {
        const par2d::Light l = par2d::bench::hall_torch(t, f);
        r.set_light_emission(torches[static_cast<std::size_t>(t)], l.color, l.intensity);
      }
    }
    if (scenario == 'd') r.update_occluder(door, par2d::bench::hall_door(f));
    if (scenario == 's') {
      for (std::size_t t = 0; t < torches.size(); ++t)
        if (t != 5 && t != 42) r.update_light(torches[t], hall.lights[t]);
      for (std::size_t o = 0; o < occluders.size(); ++o) r.update_occluder(occluders[o], hall.occluders[o]);
    }
    if (scenario == 'f' || scenario == 'p') r.force_full_frame();
    if (!r.render(buffer).ok()) return state.SkipWithError("render failed");
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    pixels_sum += static_cast<double>(r.frame_stats().pixels);
    ++f;
  }
  std::sort(ms.begin(), ms.end());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[std::min(ms.size() - 1, (ms.size() * 99) / 100)];
  state.counters["pixels"] = pixels_sum / static_cast<double>(ms.size());
}

void register_incremental() {
  const struct {
    const char* name;
    char scenario;
  } scenarios[] = {{"full", 'f'}, {"a_nothing", 'a'}, {"b_2_move", 'b'}, {"c_8_flicker_2_move", 'c'}, {"d_door", 'd'}, {"s_2_move_resync_all", 's'},
                   {"p_pan_full", 'p'}, {"g_pan_diagonal", 'g'}, {"m_pan_2_move", 'm'}};
  // Without and (1 thread) with the light-layer cache, 64 MiB (the hall's layers take about 20).
  for (int threads : {1, 2})
    for (const std::size_t layers : {std::size_t{0}, std::size_t{64} << 20}) {
      if (layers && threads != 1) continue;
      for (const auto& s : scenarios)
        benchmark::RegisterBenchmark((std::string(layers ? "incremental_layers/" : "incremental/") + s.name +
                                      "/threads:" + std::to_string(threads))
                                         .c_str(),
                                     [=](benchmark::State& st) { incremental(st, s.scenario, threads, layers); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(100);  // one setup (scene, reach, a whole first frame) per run, not per estimate
    }
}

const int registered = (register_incremental(), 0);

}  // namespace
