// The incremental-frame game loop on the torch hall (torch_hall.hpp), 1280 x 720,
// for a fixed number of frames after an untimed first one, with the per-frame time, the
// pixels recomputed, and a function for callgrind to count exactly the frames:
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*timed_frames*'
//       par2d_incremental_frames SCENARIO FRAMES [THREADS [LAYER_MIB [SCENE.json]]]
// SCENARIO: full (2 torches move, every pixel computed: the baseline), a (nothing changes),
// b (2 torches move), c (8 torches flicker and 2 move), d (the door moves), s (b, and every
// other light and occluder re-sent with the values it holds, as an engine syncing its
// entities each frame: s against b is the re-sync's cost); the camera panning 4 pixels a
// frame on the view's pixel grid (Renderer::set_view_offset): h (rightwards), v (downwards),
// g (diagonally), m (diagonally while 2 torches move), p (f: every pixel computed, the
// camera panning diagonally); H, V, G, M: h, v, g, m into a ring buffer
// (BufferLayout::ring: no pixel moves). LAYER_MIB: the
// light-layer cache's budget in MiB (default 0: off); the first, untimed frame fills it.
// SCENE.json: another level instead of the hall (levels built differently, e.g. by
// par2d_make_grid): of its N lights the first N/32 move and the next N/8 flicker (the hall's
// 2 and 8 of 64, rounded, at least 1 each), and occluder 0 is the door.
#include <algorithm>
#include <chrono>
#include <cmath>
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

par2d::Shape shifted(par2d::Shape shape, double dx, double dy) {
  if (auto* c = std::get_if<par2d::Circle>(&shape)) c->center = {c->center.x + dx, c->center.y + dy};
  if (auto* s = std::get_if<par2d::Segment>(&shape)) {
    s->a = {s->a.x + dx, s->a.y + dy};
    s->b = {s->b.x + dx, s->b.y + dy};
  }
  if (auto* p = std::get_if<par2d::Polygon>(&shape))
    for (par2d::Vec2& v : p->vertices) v = {v.x + dx, v.y + dy};
  return shape;
}

// What changes in frame f: the hall's own motion, or for another level (`level` given) its
// movers circling 10 units around where they were, its flickering lights varying as the
// hall's torches do, occluder 0 sliding up to 10 units sideways.
struct Motion {
  const par2d::Scene* level = nullptr;
  std::vector<int> movers, flickers;
  par2d::Light light(int t, int f, bool flicker) const {
    if (!level) return hall_torch(t, f, flicker);
    par2d::Light l = level->lights[static_cast<std::size_t>(t)];
    if (flicker) {
      l.intensity *= 0.85 + 0.1 * std::sin(1.7 * f + t) + 0.05 * std::sin(4.1 * f + 2.0 * t);
    } else {
      const double phase = 0.09 * f + 0.7 * t;
      l.shape = shifted(l.shape, 10.0 * std::cos(phase) - 10.0, 10.0 * std::sin(phase));
    }
    return l;
  }
  par2d::Occluder door(int f) const {
    if (!level) return par2d::bench::hall_door(f);
    par2d::Occluder o = level->occluders[0];
    o.shape = shifted(o.shape, 10.0 * std::sin(0.15 * f), 0.0);
    return o;
  }
};

__attribute__((noinline)) bool timed_frames(par2d::Renderer& r, const std::vector<par2d::LightHandle>& torches,
                                            const std::vector<par2d::OccluderHandle>& occluders,
                                            par2d::OccluderHandle door, char scenario, const par2d::FrameBuffer& buffer,
                                            int frames, const par2d::Scene& scene, const Motion& motion, FrameLog& log) {
  for (int f = 1; f <= frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    if (std::strchr("hvgmp", scenario) != nullptr) {
      const int step = 4;
      if (!r.set_view_offset(scenario == 'v' ? 0 : step * f, scenario == 'h' ? 0 : step * f).ok()) return false;
    }
    if (scenario == 'f' || scenario == 'b' || scenario == 'c' || scenario == 's' || scenario == 'm' || scenario == 'p') {
      for (int t : motion.movers)
        if (!r.update_light(torches[static_cast<std::size_t>(t)], motion.light(t, f, false)).ok()) return false;
    }
    if (scenario == 'c') {
      for (int t : motion.flickers) {
        const par2d::Light l = motion.light(t, f, true);
        if (!r.set_light_emission(torches[static_cast<std::size_t>(t)], l.color, l.intensity).ok()) return false;
      }
    }
    if (scenario == 'd' && !r.update_occluder(door, motion.door(f)).ok()) return false;
    if (scenario == 's') {
      for (std::size_t t = 0; t < torches.size(); ++t)
        if (std::find(motion.movers.begin(), motion.movers.end(), static_cast<int>(t)) == motion.movers.end() &&
            !r.update_light(torches[t], scene.lights[t]).ok())
          return false;
      for (std::size_t o = 0; o < occluders.size(); ++o)
        if (!r.update_occluder(occluders[o], scene.occluders[o]).ok()) return false;
    }
    if (scenario == 'f' || scenario == 'p') r.force_full_frame();
    if (!r.render(buffer).ok()) return false;
    log.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    log.pixels += r.frame_stats().pixels;
    log.rects += r.dirty_rects().size();
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 6 || std::strchr("fullabcdshvgmpHVGM", argv[1][0]) == nullptr) {
    std::fprintf(stderr, "usage: %s full|a|b|c|d|s|h|v|g|m|p|H|V|G|M FRAMES [THREADS [LAYER_MIB [SCENE.json]]]\n", argv[0]);
    return 2;
  }
  const bool ring = std::strchr("HVGM", argv[1][0]) != nullptr;
  const char scenario = ring ? static_cast<char>(argv[1][0] - 'A' + 'a') : argv[1][0];
  const int frames = std::atoi(argv[2]);
  const int threads = argc >= 4 ? std::atoi(argv[3]) : 1;
  const std::size_t layer_mib = argc >= 5 ? static_cast<std::size_t>(std::atoi(argv[4])) : 0;
  par2d::Scene scene;
  Motion motion;
  if (argc == 6) {
    if (par2d::Status s = par2d::load_scene_file(argv[5], scene); !s.ok()) {
      std::fprintf(stderr, "%s\n", s.message().c_str());
      return 1;
    }
    if (scene.lights.size() < 2 || scene.occluders.empty()) {
      std::fprintf(stderr, "%s: needs at least 2 lights and an occluder\n", argv[5]);
      return 1;
    }
    // The hall's shares of its 64 torches: 2 move (1/32), 8 flicker (1/8).
    motion.level = &scene;
    const int lights = static_cast<int>(scene.lights.size());
    const int movers = std::max(1, (lights + 16) / 32), flickers = std::max(1, (lights + 4) / 8);
    for (int t = 0; t < movers; ++t) motion.movers.push_back(t);
    for (int t = movers; t < movers + flickers; ++t) motion.flickers.push_back(t);
  } else {
    scene = par2d::bench::torch_hall(1280, 720);
    motion.movers = {5, 42};
    for (int t = 16; t < 24; ++t) motion.flickers.push_back(t);
  }
  const int width = scene.width, height = scene.height;
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3);
  const par2d::FrameBuffer buffer{pixels.data(), par2d::PixelFormat::rgb_f32, static_cast<std::ptrdiff_t>(width) * 12, 1.0};
  par2d::Renderer r;
  par2d::RenderOptions options;
  options.threads = threads;
  std::vector<par2d::LightHandle> torches;
  std::vector<par2d::OccluderHandle> occluders;
  bool ok = r.set_options(options).ok() && r.set_scene(scene, &torches, &occluders).ok() &&
            r.set_incremental(true).ok() && r.set_light_layer_budget(layer_mib << 20).ok() &&
            r.set_buffer_layout(ring ? par2d::BufferLayout::ring : par2d::BufferLayout::image).ok() && r.render(buffer).ok();
  FrameLog log;
  const std::size_t door = motion.level ? 0 : static_cast<std::size_t>(par2d::bench::hall_door_index());
  ok = ok && timed_frames(r, torches, occluders, occluders[door], scenario, buffer, frames, scene, motion, log);
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
