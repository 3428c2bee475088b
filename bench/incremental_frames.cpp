// The incremental-frame game loop (issue 40) on the torch hall (torch_hall.hpp), 1280 x 720,
// for a fixed number of frames after an untimed first one, with the per-frame time, the
// pixels recomputed, and a function for callgrind to count exactly the frames:
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*timed_frames*'
//       par2d_incremental_frames SCENARIO FRAMES [THREADS [LAYER_MIB]]
// SCENARIO: full (2 torches move, every pixel computed: the baseline), a (nothing changes),
// b (2 torches move), c (8 torches flicker and 2 move), d (the door moves). LAYER_MIB: the
// light-layer cache's budget in MiB (default 0: off); the first, untimed frame fills it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "par2d/par2d.hpp"
#include "torch_hall.hpp"

namespace {

using par2d::bench::hall_torch;

struct FrameLog {
  std::vector<double> seconds;
  std::uint64_t pixels = 0;
  std::size_t rects = 0;
};

__attribute__((noinline)) bool timed_frames(par2d::Renderer& r, const std::vector<par2d::LightHandle>& torches,
                                            par2d::OccluderHandle door, char scenario, const par2d::FrameBuffer& buffer,
                                            int frames, FrameLog& log) {
  for (int f = 1; f <= frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    if (scenario == 'f' || scenario == 'b' || scenario == 'c') {
      for (int t : {5, 42})
        if (!r.update_light(torches[static_cast<std::size_t>(t)], hall_torch(t, f, false)).ok()) return false;
    }
    if (scenario == 'c') {
      for (int t = 16; t < 24; ++t) {
        const par2d::Light l = hall_torch(t, f);
        if (!r.set_light_emission(torches[static_cast<std::size_t>(t)], l.color, l.intensity).ok()) return false;
      }
    }
    if (scenario == 'd' && !r.update_occluder(door, par2d::bench::hall_door(f)).ok()) return false;
    if (scenario == 'f') r.force_full_frame();
    if (!r.render(buffer).ok()) return false;
    log.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    log.pixels += r.frame_stats().pixels;
    log.rects += r.dirty_rects().size();
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 5 || std::strchr("fullabcd", argv[1][0]) == nullptr) {
    std::fprintf(stderr, "usage: %s full|a|b|c|d FRAMES [THREADS [LAYER_MIB]]\n", argv[0]);
    return 2;
  }
  const char scenario = argv[1][0];
  const int frames = std::atoi(argv[2]);
  const int threads = argc >= 4 ? std::atoi(argv[3]) : 1;
  const std::size_t layer_mib = argc == 5 ? static_cast<std::size_t>(std::atoi(argv[4])) : 0;
  const int width = 1280, height = 720;
  const par2d::Scene scene = par2d::bench::torch_hall(width, height);
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3);
  const par2d::FrameBuffer buffer{pixels.data(), par2d::PixelFormat::rgb_f32, static_cast<std::ptrdiff_t>(width) * 12, 1.0};
  par2d::Renderer r;
  par2d::RenderOptions options;
  options.threads = threads;
  std::vector<par2d::LightHandle> torches;
  std::vector<par2d::OccluderHandle> occluders;
  bool ok = r.set_options(options).ok() && r.set_scene(scene, &torches, &occluders).ok() &&
            r.set_incremental(true).ok() && r.set_light_layer_budget(layer_mib << 20).ok() && r.render(buffer).ok();
  FrameLog log;
  ok = ok && timed_frames(r, torches, occluders[par2d::bench::hall_door_index()], scenario, buffer, frames, log);
  if (!ok || log.seconds.empty()) {
    std::printf("%s: FAILED\n", argv[1]);
    return 1;
  }
  std::vector<double> s = log.seconds;
  std::sort(s.begin(), s.end());
  const double median = s[s.size() / 2];
  const double p99 = s[std::min(s.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(s.size())))];
  std::printf("%s (layers %zu MiB, %.1f MiB held): %d frames, %d threads: median %.3f ms, p99 %.3f ms, %.0f pixels recomputed per frame (%.1f%%), %.1f rects\n",
              argv[1], layer_mib, static_cast<double>(r.light_layer_bytes()) / (1 << 20), frames, threads, 1e3 * median, 1e3 * p99, static_cast<double>(log.pixels) / frames,
              100.0 * static_cast<double>(log.pixels) / frames / (width * height), static_cast<double>(log.rects) / frames);
  return 0;
}
