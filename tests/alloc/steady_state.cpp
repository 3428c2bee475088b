// Steady-state frames of a persistent Renderer allocate nothing and start no threads: a
// global operator new and malloc that count while armed (its own executable, so the
// replacement does not touch the main test binary).
#include <dirent.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "game_level.hpp"
#include "par2d/renderer.hpp"

extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* __libc_memalign(std::size_t, std::size_t);
extern "C" void __libc_free(void*);

namespace {
std::atomic<bool> g_armed{false};
std::atomic<long> g_news{0};
std::atomic<long> g_mallocs{0};
}  // namespace

// Every heap allocation path of the process: C++ new goes through malloc here too, but is
// counted on its own so a failure says which.
extern "C" void* malloc(std::size_t n) {
  if (g_armed.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t s) {
  if (g_armed.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, s);
}
extern "C" void* realloc(void* p, std::size_t n) {
  if (g_armed.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
extern "C" void free(void* p) { __libc_free(p); }

void* operator new(std::size_t n) {
  if (g_armed.load(std::memory_order_relaxed)) g_news.fetch_add(1, std::memory_order_relaxed);
  if (void* p = __libc_malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (g_armed.load(std::memory_order_relaxed)) g_news.fetch_add(1, std::memory_order_relaxed);
  if (void* p = __libc_memalign(static_cast<std::size_t>(a), n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) { return operator new(n, a); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }

namespace {

int thread_count() {
  int n = 0;
  if (DIR* d = opendir("/proc/self/task")) {
    while (const dirent* e = readdir(d)) n += e->d_name[0] != '.';
    closedir(d);
  }
  return n;
}

constexpr int kFrames = 8;  // two open/close cycles of the door

// One animation frame as a game would do it: torches move and flicker, a door slides.
bool frame(par2d::Renderer& r, const std::vector<par2d::LightHandle>& torches, par2d::OccluderHandle door,
           par2d::Occluder& door_shape, int f, const par2d::FrameBuffer& buffer) {
  for (int t = 0; t < par2d::bench::kTorches; ++t) {
    if (!r.update_light(torches[static_cast<std::size_t>(t)], par2d::bench::torch_at(t, f)).ok()) return false;
  }
  auto& poly = std::get<par2d::Polygon>(door_shape.shape);
  const double x = 10.0 * 32.0 + (f % 4 < 2 ? 0.0 : 6.0);  // in the wall at column 10, rows 5-6
  poly.vertices[0] = {x, 5 * 32.0};
  poly.vertices[1] = {x + 8.0, 5 * 32.0};
  poly.vertices[2] = {x + 8.0, 7 * 32.0};
  poly.vertices[3] = {x, 7 * 32.0};
  if (!r.update_occluder(door, door_shape).ok()) return false;
  return r.render(buffer).ok();
}

int run(const char* what, par2d::Renderer& r, par2d::PixelFormat format, tbb::task_arena* host, int width, int height) {
  std::vector<par2d::LightHandle> torches;
  if (!r.set_scene(par2d::bench::game_level(width, height), &torches).ok()) return 1;
  par2d::Occluder door{par2d::Polygon{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  par2d::OccluderHandle door_handle;
  if (!r.add_occluder(door, &door_handle).ok()) return 1;
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 16);
  par2d::FrameBuffer buffer{pixels.data(), format, width * par2d::bytes_per_pixel(format), 1.5};
  bool ok = true;
  auto animation = [&](bool armed) {
    if (armed) g_armed = true;
    for (int f = 0; f < kFrames; ++f) ok = ok && frame(r, torches, door_handle, door, f, buffer);
    g_armed = false;
  };
  auto in_host = [&](bool armed) {
    if (host) {
      host->execute([&] { animation(armed); });
    } else {
      animation(armed);
    }
  };
  in_host(false);  // the first frames size every buffer
  const int threads_before = thread_count();
  g_news = 0;
  g_mallocs = 0;
  in_host(true);
  const int threads_after = thread_count();
  const par2d::RendererStats stats = r.stats();
  std::printf("%s, %dx%d: %d frames: %ld operator new, %ld malloc/calloc/realloc, threads %d -> %d, index builds %llu\n",
              what, width, height, kFrames, g_news.load(), g_mallocs.load(), threads_before, threads_after,
              static_cast<unsigned long long>(stats.index_builds));
  if (!ok) {
    std::printf("%s: a frame failed\n", what);
    return 1;
  }
  return (g_news.load() == 0 && g_mallocs.load() == 0 && threads_after == threads_before) ? 0 : 1;
}

// Lights moved to new places every frame, anywhere in the level: inside walls and pillars,
// across the border, near each other, with new sizes, ranges and brightness. Scratch that grew
// to each frame's largest need would keep allocating as new maxima turn up; after kWarmup
// frames nothing may allocate for kRandomFrames more.
constexpr int kWarmup = 10;
constexpr int kRandomFrames = 1000;

par2d::Light random_light(std::mt19937_64& rng, int torch) {
  std::uniform_real_distribution<double> x(-40.0, par2d::bench::kLevelWidth + 40.0);
  std::uniform_real_distribution<double> y(-40.0, par2d::bench::kLevelHeight + 40.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  par2d::Light light = par2d::bench::torch_at(torch, 0);
  const par2d::Vec2 c{x(rng), y(rng)};
  const double size = 0.5 + 40.0 * unit(rng) * unit(rng);
  switch (torch % 3) {
    case 0:
      light.shape = par2d::Circle{c, size};
      break;
    case 1: {
      const double a = 6.283185307179586 * unit(rng);
      light.shape = par2d::Segment{{c.x - size * std::cos(a), c.y - size * std::sin(a)},
                                   {c.x + size * std::cos(a), c.y + size * std::sin(a)}};
      break;
    }
    default: {
      const double a = 6.283185307179586 * unit(rng);
      std::vector<par2d::Vec2> v;
      for (int k = 0; k < 5; ++k) {
        const double t = a + 1.2566370614359172 * k;
        v.push_back({c.x + size * std::cos(t), c.y + size * std::sin(t)});
      }
      light.shape = par2d::Polygon{v};
    }
  }
  light.intensity = 0.5 + 4.0 * unit(rng);
  if (unit(rng) < 0.5) light.range = 20.0 + 400.0 * unit(rng);
  return light;
}

int run_random_motion(const char* what, int threads) {
  par2d::Renderer r;
  par2d::RenderOptions o;
  o.threads = threads;
  if (!r.set_options(o).ok()) return 1;
  constexpr int width = 320, height = 176;
  std::vector<par2d::LightHandle> torches;
  if (!r.set_scene(par2d::bench::game_level(width, height), &torches).ok()) return 1;
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
  const par2d::FrameBuffer buffer{pixels.data(), par2d::PixelFormat::rgba8_srgb, width * 4, 1.5};
  std::mt19937_64 rng(20261206);
  // The lights of every frame, drawn before arming (the vectors of polygon lights allocate).
  std::vector<std::vector<par2d::Light>> frames(kWarmup + kRandomFrames);
  for (auto& lights : frames) {
    for (int t = 0; t < par2d::bench::kTorches; ++t) lights.push_back(random_light(rng, t));
  }
  bool ok = true;
  long news_at_frame = -1;
  for (int f = 0; f < kWarmup + kRandomFrames && ok; ++f) {
    if (f == kWarmup) {
      g_news = 0;
      g_mallocs = 0;
      g_armed = true;
    }
    for (int t = 0; t < par2d::bench::kTorches; ++t) {
      ok = ok && r.update_light(torches[static_cast<std::size_t>(t)], frames[static_cast<std::size_t>(f)][static_cast<std::size_t>(t)]).ok();
    }
    ok = ok && r.render(buffer).ok();
    if (news_at_frame < 0 && g_armed && g_news.load() + g_mallocs.load() > 0) news_at_frame = f;
  }
  g_armed = false;
  std::printf("%s: %d frames of random motion after %d warm-up frames: %ld operator new, %ld malloc/calloc/realloc",
              what, kRandomFrames, kWarmup, g_news.load(), g_mallocs.load());
  if (news_at_frame >= 0) std::printf(" (the first in frame %ld)", news_at_frame);
  std::printf("\n");
  if (!ok) {
    std::printf("%s: a frame failed\n", what);
    return 1;
  }
  return (g_news.load() == 0 && g_mallocs.load() == 0) ? 0 : 1;
}

// A camera panning over the level (Renderer::set_view_offset) while the torches move, with
// incremental frames, into an image (kept pixels moved in place) or a ring buffer. The
// warm-up pans far enough to meet the most blocks a frame of this size spans on the grid.
int run_scrolling(const char* what, par2d::BufferLayout layout) {
  par2d::Renderer r;
  par2d::RenderOptions o;
  o.threads = 2;
  const int width = 320, height = 176;
  std::vector<par2d::LightHandle> torches;
  if (!r.set_options(o).ok() || !r.set_scene(par2d::bench::game_level(width, height), &torches).ok() ||
      !r.set_incremental(true).ok() || !r.set_buffer_layout(layout).ok())
    return 1;
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
  const par2d::FrameBuffer buffer{pixels.data(), par2d::PixelFormat::rgba8_srgb, width * 4, 1.5};
  bool ok = true;
  auto pan = [&](int f, int step) {
    for (int t = 0; t < par2d::bench::kTorches; ++t)
      ok = ok && r.update_light(torches[static_cast<std::size_t>(t)], par2d::bench::torch_at(t, f)).ok();
    ok = ok && r.set_view_offset(step * f, (step * f) / 2).ok() && r.render(buffer).ok();
  };
  for (int f = 0; f < kFrames; ++f) pan(f, 9);  // offsets up to 63: every block count
  const int threads_before = thread_count();
  g_news = 0;
  g_mallocs = 0;
  g_armed = true;
  for (int f = kFrames; f < 3 * kFrames; ++f) pan(f, 3);
  g_armed = false;
  const int threads_after = thread_count();
  std::printf("%s, %dx%d: %d panned frames: %ld operator new, %ld malloc/calloc/realloc, threads %d -> %d\n", what, width,
              height, 2 * kFrames, g_news.load(), g_mallocs.load(), threads_before, threads_after);
  if (!ok) {
    std::printf("%s: a frame failed\n", what);
    return 1;
  }
  return (g_news.load() == 0 && g_mallocs.load() == 0 && threads_after == threads_before) ? 0 : 1;
}

}  // namespace

int main() {
  int failures = 0;
  {
    par2d::Renderer r;
    par2d::RenderOptions o;
    o.threads = 2;
    if (!r.set_options(o).ok()) return 1;
    failures += run("own pool, 2 threads, rgba8_srgb", r, par2d::PixelFormat::rgba8_srgb, nullptr, 320, 176);
  }
  {
    par2d::Renderer r;
    par2d::RenderOptions o;
    o.backend = par2d::Backend::scalar;
    o.threads = 1;
    if (!r.set_options(o).ok()) return 1;
    failures += run("scalar, 1 thread, rgb_f32", r, par2d::PixelFormat::rgb_f32, nullptr, 80, 44);
  }
  {
    par2d::Renderer r;
    par2d::RenderOptions o;
    o.threading = par2d::Threading::caller_arena;
    if (!r.set_options(o).ok()) return 1;
    tbb::task_arena host(2);
    failures += run("host arena, rgba_f32", r, par2d::PixelFormat::rgba_f32, &host, 320, 176);
  }
  failures += run_random_motion("random motion, 1 thread", 1);
  failures += run_random_motion("random motion, 2 threads", 2);
  failures += run_scrolling("panning, image layout", par2d::BufferLayout::image);
  failures += run_scrolling("panning, ring layout", par2d::BufferLayout::ring);
  std::printf(failures == 0 ? "steady state: no allocation, no new thread\n" : "steady state: FAILED\n");
  return failures == 0 ? 0 : 1;
}
