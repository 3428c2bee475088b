// Incremental frames (Renderer::set_incremental): random game-loop sequences of updates, every
// frame byte for byte against a fresh one-shot render of the same state; untouched pixels,
// dirty rectangles and no-change frames checked with canaries.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "par2d/renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

Shape box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// A small level: wall boxes on a grid of cells, torches (most with a range) in the open.
struct Level {
  Scene scene;
  std::vector<Light> lights;  // as given, parallel to the handles
  std::vector<Occluder> occluders;
  std::vector<LightHandle> light_handles;
  std::vector<OccluderHandle> occluder_handles;
};

Light random_torch(PortableRandom& rng, double w, double h) {
  Light l;
  l.shape = Circle{{rng.uniform(0.0, w), rng.uniform(0.0, h)}, rng.uniform(0.5, 2.5)};
  l.color = {rng.uniform(0.3, 1.0), rng.uniform(0.3, 1.0), rng.uniform(0.3, 1.0)};
  l.intensity = rng.uniform(0.5, 3.0);
  if (rng.chance(0.8)) l.range = rng.uniform(8.0, 50.0);
  if (rng.chance(0.15)) l.cone = Cone{rng.uniform(0.0, 360.0), rng.uniform(20.0, 180.0), 0.0};
  if (rng.chance(0.1)) l.mask = 1u + static_cast<std::uint32_t>(rng.integer(0, 2));
  return l;
}

Occluder random_wall(PortableRandom& rng, double w, double h) {
  const double x = rng.uniform(0.0, w), y = rng.uniform(0.0, h);
  Occluder o;
  if (rng.chance(0.5)) {
    o.shape = box(x, y, x + rng.uniform(2.0, 24.0), y + rng.uniform(1.0, 4.0));
  } else if (rng.chance(0.6)) {
    o.shape = box(x, y, x + rng.uniform(1.0, 4.0), y + rng.uniform(2.0, 24.0));
  } else {
    o.shape = Circle{{x, y}, rng.uniform(1.0, 4.0)};
  }
  if (rng.chance(0.1)) o.transmittance = {rng.uniform(), rng.uniform(), rng.uniform()};
  if (rng.chance(0.1)) o.mask = 1u + static_cast<std::uint32_t>(rng.integer(0, 2));
  if (rng.chance(0.05)) o.interior = Interior::lit;
  return o;
}

Shape moved(const Shape& shape, double dx, double dy) {
  Shape out = shape;
  if (auto* p = std::get_if<Polygon>(&out)) {
    for (Vec2& v : p->vertices) v = {v.x + dx, v.y + dy};
  } else if (auto* c = std::get_if<Circle>(&out)) {
    c->center = {c->center.x + dx, c->center.y + dy};
  }
  return out;
}

// A one-shot render of `r`'s state; `grid` (the view set_frame gave): by a new Renderer at
// r's view offset on that grid.
std::vector<float> fresh_render(const Renderer& r, const RenderOptions& options, const View* grid = nullptr) {
  Scene snap = r.snapshot();
  std::vector<float> pixels(static_cast<std::size_t>(snap.width) * snap.height * 3, -1.0f);
  const ImageView image{pixels.data(), snap.width, snap.height, static_cast<std::ptrdiff_t>(snap.width) * 3};
  if (grid) {
    snap.view = *grid;
    Renderer fresh;
    REQUIRE(fresh.set_options(options).ok());
    REQUIRE(fresh.set_scene(snap).ok());
    REQUIRE(fresh.set_view_offset(r.view_offset_x(), r.view_offset_y()).ok());
    const Status s = fresh.render(image);
    REQUIRE_MESSAGE(s.ok(), s.message());
    return pixels;
  }
  const Status s = render(snap, options, image);
  REQUIRE_MESSAGE(s.ok(), s.message());
  return pixels;
}

struct Outcome {
  int frames = 0, partial = 0, untouched = 0, shifted = 0;
  std::uint64_t reused = 0, filled = 0;  // light-layer tiles over the frames
  double worst = 0.0;  // with the light-layer cache: the largest |cached - full| / e_max seen
};

// The brightest emission of a state (intensity x colour channel, directional lights too).
double brightest_emission(const Scene& scene) {
  double e = 0.0;
  for (const Light& l : scene.lights)
    for (double c : l.color) e = std::max(e, l.intensity * c);
  for (const DirectionalLight& d : scene.directional_lights)
    for (double c : d.color) e = std::max(e, d.intensity * c);
  return e;
}

// `frames` frames of random updates on a random level; each frame's incremental buffer is
// compared with a one-shot render, and the pixels outside the dirty rectangles with the
// previous frame. The frames alternate between 1 and 2 threads (options.threads is replaced):
// which frame computed a block must not matter. With a `layer_budget`, the light-layer cache
// is on: every frame within 1e-6 x the brightest emission of the one-shot render (docs/api.md)
// instead of byte-equal, and the layers within the budget. With `scroll`, the view also pans
// by whole pixels on its grid (set_view_offset; now and then farther than a frame, or back to
// the start by set_frame), each frame compared with a new Renderer's at the same offset, and
// the pixels outside the dirty rectangles with the previous frame's, shifted (frame_shift).
// With the ring layout (BufferLayout::ring), the frame is read out of the ring at the view
// offset before it is compared, and no pixel may move between frames.
Outcome run_sequence(std::uint32_t seed, int frames, RenderOptions options, int width, int height,
                     std::size_t layer_budget = 0, bool scroll = false, BufferLayout layout = BufferLayout::image) {
  PortableRandom rng(seed);
  const double w = width, h = height;
  Level level;
  level.scene.width = width;
  level.scene.height = height;
  level.scene.view = View{0.0, 0.0, w, h};
  for (int i = 0, n = rng.integer(10, 30); i < n; ++i) level.scene.occluders.push_back(random_wall(rng, w, h));
  for (int i = 0, n = rng.integer(3, 10); i < n; ++i) level.scene.lights.push_back(random_torch(rng, w, h));
  Renderer r;
  REQUIRE(r.set_options(options).ok());
  REQUIRE(r.set_scene(level.scene, &level.light_handles, &level.occluder_handles).ok());
  level.lights = level.scene.lights;
  level.occluders = level.scene.occluders;
  REQUIRE(r.set_incremental(true).ok());
  CHECK(r.incremental());
  REQUIRE(r.set_buffer_layout(layout).ok());
  const bool ring = layout == BufferLayout::ring;
  if (layer_budget) REQUIRE(r.set_light_layer_budget(layer_budget).ok());
  CHECK(r.light_layer_budget() == layer_budget);

  const std::size_t floats = static_cast<std::size_t>(width) * height * 3;
  std::vector<float> buffer(floats, -1.0f), previous(floats);
  const ImageView view{buffer.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3};
  Outcome out;
  for (int frame = 0; frame < frames; ++frame) {
    // 0 .. 3 updates, about a fifth of the frames none.
    const int updates = rng.chance(0.2) ? 0 : rng.integer(1, 3);
    std::string ops;
    for (int u = 0; u < updates; ++u) {
      const int op = rng.integer(0, 13);
      const std::size_t nl = level.lights.size(), no = level.occluders.size();
      const std::size_t li = nl ? static_cast<std::size_t>(rng.integer(0, static_cast<int>(nl) - 1)) : 0;
      const std::size_t oi = no ? static_cast<std::size_t>(rng.integer(0, static_cast<int>(no) - 1)) : 0;
      ops += std::to_string(op) + (op <= 10 ? "@" + std::to_string(op <= 8 ? li : oi) : std::string()) + " ";
      if (op <= 2 && nl) {  // a torch moves
        level.lights[li].shape = moved(level.lights[li].shape, rng.uniform(-4.0, 4.0), rng.uniform(-4.0, 4.0));
        REQUIRE(r.update_light(level.light_handles[li], level.lights[li]).ok());
      } else if (op <= 5 && nl) {  // flicker; sometimes dark (the light leaves the lit list) and back
        level.lights[li].intensity = rng.chance(0.15) ? 0.0 : rng.uniform(0.2, 3.0);
        REQUIRE(r.set_light_emission(level.light_handles[li], level.lights[li].color, level.lights[li].intensity).ok());
      } else if (op == 6 && nl) {  // lighting-model keys of a light
        Light& l = level.lights[li];
        switch (rng.integer(0, 3)) {
          case 0: l.range = rng.chance(0.2) ? std::optional<double>() : std::optional<double>(rng.uniform(5.0, 60.0)); break;
          case 1: l.cone = rng.chance(0.3) ? std::optional<Cone>() : std::optional<Cone>(Cone{rng.uniform(0.0, 360.0), rng.uniform(10.0, 180.0), 0.0}); break;
          case 2: l.mask = rng.chance(0.5) ? kAllMaskBits : 1u + static_cast<std::uint32_t>(rng.integer(0, 2)); break;
          default: l.color = {rng.uniform(), rng.uniform(), rng.uniform()}; break;
        }
        REQUIRE(r.update_light(level.light_handles[li], l).ok());
      } else if (op == 7 && nl > 1) {  // a torch goes out for good
        REQUIRE(r.remove_light(level.light_handles[li]).ok());
        level.lights.erase(level.lights.begin() + static_cast<std::ptrdiff_t>(li));
        level.light_handles.erase(level.light_handles.begin() + static_cast<std::ptrdiff_t>(li));
      } else if (op == 8 && nl < 14) {  // a torch is lit
        LightHandle handle;
        const Light l = random_torch(rng, w, h);
        REQUIRE(r.add_light(l, &handle).ok());
        level.lights.push_back(l);
        level.light_handles.push_back(handle);
      } else if (op == 9 && no) {  // a door moves
        level.occluders[oi].shape = moved(level.occluders[oi].shape, rng.uniform(-6.0, 6.0), rng.uniform(-6.0, 6.0));
        if (rng.chance(0.2)) level.occluders[oi].transmittance = {rng.uniform(), rng.uniform(), rng.uniform()};
        REQUIRE(r.update_occluder(level.occluder_handles[oi], level.occluders[oi]).ok());
      } else if (op == 10 && no > 1) {  // a wall is destroyed
        REQUIRE(r.remove_occluder(level.occluder_handles[oi]).ok());
        level.occluders.erase(level.occluders.begin() + static_cast<std::ptrdiff_t>(oi));
        level.occluder_handles.erase(level.occluder_handles.begin() + static_cast<std::ptrdiff_t>(oi));
      } else if (op == 11 && no < 40) {  // a wall is built
        OccluderHandle handle;
        const Occluder o = random_wall(rng, w, h);
        REQUIRE(r.add_occluder(o, &handle).ok());
        level.occluders.push_back(o);
        level.occluder_handles.push_back(handle);
      } else if (op == 12 && rng.chance(0.3)) {  // scene-wide terms: rare
        switch (rng.integer(0, 3)) {
          case 0: REQUIRE(r.set_ambient({rng.uniform(0.0, 0.1), rng.uniform(0.0, 0.1), 0.0}).ok()); break;
          case 1: REQUIRE(r.set_normal({rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), 1.0}).ok()); break;
          case 2: REQUIRE(r.clear_normal_source().ok()); break;
          default:
            REQUIRE(r.set_directional_lights(rng.chance(0.5) ? std::vector<DirectionalLight>{}
                                                               : std::vector<DirectionalLight>{DirectionalLight{30.0, 60.0, {1.0, 0.9, 0.7}, 0.2}})
                        .ok());
            break;
        }
      } else if (op == 13 && rng.chance(0.1)) {
        r.force_full_frame();
      }
    }
    if (scroll) {
      const double move = rng.uniform();
      std::int64_t x = r.view_offset_x(), y = r.view_offset_y();
      if (move < 0.6) {  // a pan of a few pixels, any direction
        x += rng.integer(-9, 9);
        y += rng.integer(-9, 9);
      } else if (move < 0.7) {  // a jump: farther than the frame, or anywhere near it
        x += rng.chance(0.5) ? rng.integer(-3 * width, 3 * width) : rng.integer(-70, 70);
        y += rng.integer(-2 * height, 2 * height);
      } else if (move < 0.75) {  // back to the start
        REQUIRE(r.set_frame(width, height, level.scene.view).ok());
        x = y = 0;
      }
      ops += "offset " + std::to_string(x) + "," + std::to_string(y);
      REQUIRE(r.set_view_offset(x, y).ok());
      CHECK(r.view_offset_x() == x);
      CHECK(r.view_offset_y() == y);
    }
    options.threads = 1 + frame % 2;
    REQUIRE(r.set_options(options).ok());
    // Now and then a watched frame (computed aside, moved and copied out once complete).
    if (scroll && rng.chance(0.2)) {
      r.set_progress([](const Progress&) { return true; });
    } else {
      r.set_progress({});
    }
    std::memcpy(previous.data(), buffer.data(), floats * sizeof(float));
    const Status s = r.render(view);
    REQUIRE_MESSAGE(s.ok(), s.message());
    const std::vector<float> expected = fresh_render(r, options, scroll ? &level.scene.view : nullptr);
    // The frame as shown: the buffer itself, or read out of the ring at the view offset.
    std::vector<float> shown_storage;
    if (ring) {
      shown_storage.resize(floats);
      const auto wrap = [](std::int64_t p, int n) { return static_cast<std::size_t>(((p % n) + n) % n); };
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          std::memcpy(&shown_storage[3 * (static_cast<std::size_t>(y) * width + x)],
                      &buffer[3 * (wrap(r.view_offset_y() + y, height) * width + wrap(r.view_offset_x() + x, width))],
                      3 * sizeof(float));
    }
    const std::vector<float>& shown = ring ? shown_storage : buffer;
    INFO("seed ", seed, " threads ", options.threads, " frame ", frame, " ops ", ops);
    out.reused += r.frame_stats().layer_tiles_reused;
    out.filled += r.frame_stats().layer_tiles_filled;
    if (layer_budget) {
      REQUIRE(r.light_layer_bytes() <= layer_budget);
      const double e_max = brightest_emission(r.snapshot());
      double worst = 0.0;
      std::size_t at = 0;
      for (std::size_t p = 0; p < floats; ++p) {
        const double error = std::abs(static_cast<double>(shown[p]) - expected[p]);
        if (!(error <= worst)) {  // NaN too
          worst = error;
          at = p;
        }
      }
      INFO("pixel ", (at / 3) % width, ",", (at / 3) / width, ": ", shown[at], " vs ", expected[at]);
      REQUIRE(worst <= 1e-6 * e_max);
      if (e_max > 0.0) out.worst = std::max(out.worst, worst / e_max);
    } else if (std::memcmp(shown.data(), expected.data(), floats * sizeof(float)) != 0) {
      std::size_t p = 0;
      while (shown[p] == expected[p]) ++p;
      MESSAGE("first difference at pixel ", (p / 3) % width, ",", (p / 3) / width, ": ", shown[p], " vs ", expected[p],
              "; computed ", r.frame_stats().pixels, " pixels in ", r.dirty_rects().size(), " rects");
    }
    if (!layer_budget) REQUIRE(std::memcmp(shown.data(), expected.data(), floats * sizeof(float)) == 0);
    // The rectangles: inside the frame, disjoint, exactly the pixels computed; every pixel
    // outside them is the previous frame's, bit for bit (never written).
    std::vector<unsigned char> inside(static_cast<std::size_t>(width) * height, 0);
    std::uint64_t area = 0;
    for (const PixelRect& rect : r.dirty_rects()) {
      REQUIRE(0 <= rect.x0);
      REQUIRE(rect.x0 < rect.x1);
      REQUIRE(rect.x1 <= width);
      REQUIRE(0 <= rect.y0);
      REQUIRE(rect.y0 < rect.y1);
      REQUIRE(rect.y1 <= height);
      for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x) {
          REQUIRE(inside[static_cast<std::size_t>(y) * width + x] == 0);
          inside[static_cast<std::size_t>(y) * width + x] = 1;
        }
      area += static_cast<std::uint64_t>(rect.x1 - rect.x0) * static_cast<std::uint64_t>(rect.y1 - rect.y0);
    }
    CHECK(area == r.frame_stats().pixels);
    const PixelShift shift = r.frame_shift();
    if (!scroll || ring) REQUIRE((shift.dx == 0 && shift.dy == 0));
    if (shift.dx != 0 || shift.dy != 0) ++out.shifted;
    if (frame > 0) {
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * width + x;
          if (inside[p]) continue;
          const int sx = x + shift.dx, sy = y + shift.dy;
          INFO("pixel ", x, ",", y, " shift ", shift.dx, ",", shift.dy);
          REQUIRE((0 <= sx && sx < width && 0 <= sy && sy < height));  // uncovered pixels are computed
          REQUIRE(std::memcmp(&buffer[3 * p], &previous[3 * (static_cast<std::size_t>(sy) * width + sx)], 3 * sizeof(float)) == 0);
        }
      }
    }
    if (area < inside.size()) ++out.partial;
    // Sometimes a frame with no change, into canaries: nothing may be written.
    if (rng.chance(0.1)) {
      std::memcpy(previous.data(), buffer.data(), floats * sizeof(float));
      std::fill(buffer.begin(), buffer.end(), 12345.0f);
      REQUIRE(r.render(view).ok());
      CHECK(r.dirty_rects().empty());
      CHECK(r.frame_stats().pixels == 0);
      REQUIRE(std::all_of(buffer.begin(), buffer.end(), [](float v) { return v == 12345.0f; }));
      std::memcpy(buffer.data(), previous.data(), floats * sizeof(float));
      ++out.untouched;
    }
    ++out.frames;
  }
  return out;
}

}  // namespace

TEST_CASE("incremental frames equal fresh full renders byte for byte over 500 random game-loop frames, 1 and 2 threads" * per_isa()) {
  // The scalar reference recomputes whole frames on any change: fewer frames keep it quick
  // (the long tier runs more).
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const int frames = scalar ? 40 : 500;
  const Outcome o = run_sequence(20261206u, frames, RenderOptions{}, 128, 96);
  CHECK(o.frames == frames);
  CHECK(o.untouched > 0);
  if (!scalar) CHECK(o.partial > o.frames / 4);  // many frames recompute part of the frame
}

TEST_CASE("scrolling: frames panned on the pixel grid equal a Renderer's at that offset byte for byte, 1 and 2 threads" * per_isa()) {
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const int frames = scalar ? 30 : 300;
  // 130 x 90: the frame's edges cut blocks and tiles wherever the view is.
  const Outcome o = run_sequence(20261207u, frames, RenderOptions{}, 130, 90, 0, true);
  CHECK(o.frames == frames);
  // Pans keep pixels unless a directional light is on (a sixth to a third of the frames here);
  // the scalar reference computes every pixel again on any change in the world.
  CHECK(o.shifted > (scalar ? 0 : frames / 5));
  if (!scalar) CHECK(o.partial > o.frames / 5);
}

TEST_CASE("scrolling into a ring buffer: no pixel moves, frames read at the offset equal a Renderer's, 1 and 2 threads" * per_isa()) {
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const int frames = scalar ? 30 : 300;
  const Outcome o = run_sequence(20261208u, frames, RenderOptions{}, 130, 90, 0, true, BufferLayout::ring);
  CHECK(o.frames == frames);
  if (!scalar) CHECK(o.partial > o.frames / 5);
}

TEST_CASE("scrolling with the light-layer cache: panned frames within 1e-6 of the brightest emission" * per_isa()) {
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const int frames = scalar ? 20 : 200;
  const Outcome o = run_sequence(7u, frames, RenderOptions{}, 130, 90, std::size_t{64} << 20, true);
  CHECK(o.frames == frames);
  CHECK(o.shifted > (scalar ? 0 : frames / 5));
  if (!scalar) CHECK(o.reused > 0);  // flickers still recombine after pans
}

TEST_CASE("incremental frames over longer sequences and more levels, every ISA" * long_tier()) {
  std::vector<Isa> isas{Isa::scalar};
  for (Isa isa : kSimdIsas)
    if (isa_supported(isa)) isas.push_back(isa);
  for (Isa isa : isas) {
    // Sized for CI's long tier (a few minutes on 2 cores in all): the scalar reference renders
    // every frame twice (incremental and fresh), so it gets fewer frames and smaller levels.
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      RenderOptions options;
      options.backend = isa == Isa::scalar ? Backend::scalar : Backend::simd;
      options.isa = isa;
      const int frames = isa == Isa::scalar ? 24 : 400;
      const int grow = isa == Isa::scalar ? 8 : 29;
      const Outcome o = run_sequence(seed * 7919u, frames, options, 96 + grow * static_cast<int>(seed),
                                     80 + grow * static_cast<int>(seed));
      CHECK(o.partial > 0);
      // The same levels panned, into an image and into a ring (shorter: each frame is
      // compared with a new renderer's).
      const int panned = isa == Isa::scalar ? 12 : 150;
      const BufferLayout layout = seed % 2 ? BufferLayout::image : BufferLayout::ring;
      const Outcome p = run_sequence(seed * 104729u, panned, options, 96 + grow * static_cast<int>(seed),
                                     80 + grow * static_cast<int>(seed), 0, true, layout);
      CHECK(p.frames == panned);
    }
  }
}

namespace {

// An incremental Renderer's frame into `buffer` (kept between frames), byte for byte against a
// fresh render of its state; returns the frame.
const std::vector<float>& incremental_frame(Renderer& r, std::vector<float>& buffer, const char* step) {
  INFO(step);
  const Status s = r.render(ImageView{buffer.data(), r.width(), r.height(), static_cast<std::ptrdiff_t>(r.width()) * 3});
  REQUIRE_MESSAGE(s.ok(), s.message());
  const std::vector<float> expected = fresh_render(r, RenderOptions{});
  if (std::memcmp(buffer.data(), expected.data(), buffer.size() * sizeof(float)) != 0) {
    std::size_t p = 0;
    while (buffer[p] == expected[p]) ++p;
    FAIL("first difference at pixel ", (p / 3) % r.width(), ",", (p / 3) / r.width(), ": ", buffer[p], " vs ",
         expected[p]);
  }
  return buffer;
}

float red_at(const std::vector<float>& frame, int width, int x, int y) {
  return frame[(static_cast<std::size_t>(y) * width + x) * 3];
}

// Three ranged torches in a row across a 320 x 128 frame (five blocks wide), each lighting
// only the blocks around it, and pillars between them.
Scene torch_row() {
  Scene scene;
  scene.width = 320;
  scene.height = 128;
  scene.view = View{0.0, 0.0, 320.0, 128.0};
  for (const double x : {40.0, 160.0, 280.0}) scene.lights.push_back(Light{Circle{{x, 64.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 30.0});
  for (const double x : {100.0, 220.0}) scene.occluders.push_back(Occluder{box(x, 40.0, x + 4.0, 88.0)});
  return scene;
}

}  // namespace

// The random sequences above move torches a few units a frame, so a light's old and new blocks
// mostly coincide and a missed old footprint shows only after a hundred frames or more. Here
// a torch jumps across the frame: the blocks it left must be computed again (dark now).
TEST_CASE("incremental frames: a torch moved far leaves its old blocks dark" * per_isa()) {
  Renderer r;
  std::vector<LightHandle> lights;
  REQUIRE(r.set_scene(torch_row(), &lights).ok());
  REQUIRE(r.set_incremental(true).ok());
  std::vector<float> buffer(static_cast<std::size_t>(320) * 128 * 3, -1.0f);
  CHECK(red_at(incremental_frame(r, buffer, "first frame"), 320, 40, 70) > 0.0f);
  for (const double x : {130.0, 250.0, 300.0}) {
    REQUIRE(r.update_light(lights[0], Light{Circle{{x, 20.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 30.0}).ok());
    const std::vector<float>& frame = incremental_frame(r, buffer, "moved");
    CHECK(red_at(frame, 320, 40, 70) == 0.0f);  // where it was first: dark
  }
}

// Erasing a light gives its number to the last one (world_changes.hpp): the erased light's
// blocks go dark, and the renumbered light keeps its own old footprint, so that moving it then
// recomputes the blocks it leaves.
TEST_CASE("incremental frames: erasing a torch renumbers the last; both keep their blocks right" * per_isa()) {
  Renderer r;
  std::vector<LightHandle> lights;
  REQUIRE(r.set_scene(torch_row(), &lights).ok());
  REQUIRE(r.set_incremental(true).ok());
  std::vector<float> buffer(static_cast<std::size_t>(320) * 128 * 3, -1.0f);
  CHECK(red_at(incremental_frame(r, buffer, "first frame"), 320, 280, 70) > 0.0f);
  REQUIRE(r.remove_light(lights[0]).ok());  // the torch at x 280 takes number 0
  CHECK(red_at(incremental_frame(r, buffer, "first erased"), 320, 40, 70) == 0.0f);
  REQUIRE(r.update_light(lights[2], Light{Circle{{40.0, 64.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 30.0}).ok());
  const std::vector<float>& frame = incremental_frame(r, buffer, "last moved to the first's place");
  CHECK(red_at(frame, 320, 280, 70) == 0.0f);
  CHECK(red_at(frame, 320, 40, 70) > 0.0f);
  // The last torch (x 160, number 1) moves, and number 0 is erased in the same frame.
  REQUIRE(r.update_light(lights[1], Light{Circle{{300.0, 100.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 30.0}).ok());
  REQUIRE(r.remove_light(lights[2]).ok());
  const std::vector<float>& last = incremental_frame(r, buffer, "moved and the other erased");
  CHECK(red_at(last, 320, 40, 70) == 0.0f);
  CHECK(red_at(last, 320, 160, 70) == 0.0f);
  CHECK(red_at(last, 320, 300, 110) > 0.0f);
}

TEST_CASE("a frame with nothing changed writes no pixel; a forced frame writes them all" * per_isa()) {
  Scene scene;
  scene.width = 130;
  scene.height = 70;
  scene.view = View{0.0, 0.0, 130.0, 70.0};
  scene.lights.push_back(Light{Circle{{20.0, 30.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 40.0});
  scene.occluders.push_back(Occluder{box(40.0, 10.0, 44.0, 60.0)});
  Renderer r;
  REQUIRE(r.set_scene(scene).ok());
  REQUIRE(r.set_incremental(true).ok());
  std::vector<unsigned char> buffer(static_cast<std::size_t>(130) * 70 * 4, 0);
  FrameBuffer fb{buffer.data(), PixelFormat::rgba8_srgb, 130 * 4, 1.0};
  REQUIRE(r.render(fb).ok());
  REQUIRE(r.dirty_rects().size() == 1);
  CHECK(r.dirty_rects()[0].x1 == 130);
  CHECK(r.dirty_rects()[0].y1 == 70);
  std::fill(buffer.begin(), buffer.end(), static_cast<unsigned char>(0xA5));
  for (int i = 0; i < 3; ++i) {
    REQUIRE(r.render(fb).ok());
    CHECK(r.dirty_rects().empty());
    REQUIRE(std::all_of(buffer.begin(), buffer.end(), [](unsigned char v) { return v == 0xA5; }));
  }
  // A new exposure changes every byte's meaning: the whole frame.
  fb.exposure = 2.0;
  REQUIRE(r.render(fb).ok());
  CHECK(r.frame_stats().pixels == 130u * 70u);
  std::fill(buffer.begin(), buffer.end(), static_cast<unsigned char>(0xA5));
  r.force_full_frame();
  REQUIRE(r.render(fb).ok());
  CHECK(r.frame_stats().pixels == 130u * 70u);
  for (std::size_t p = 3; p < buffer.size(); p += 4) REQUIRE(buffer[p] == 255);  // alpha of every pixel written
  // Region renders compute their region and leave the tracking alone.
  std::vector<float> part(static_cast<std::size_t>(20) * 10 * 3, -1.0f);
  REQUIRE(r.render(FrameBuffer{part.data(), PixelFormat::rgb_f32, 20 * 12, 1.0}, PixelRect{5, 5, 25, 15}).ok());
  REQUIRE(r.dirty_rects().size() == 1);
  CHECK(r.dirty_rects()[0].x0 == 5);
  std::fill(buffer.begin(), buffer.end(), static_cast<unsigned char>(0xA5));
  REQUIRE(r.render(fb).ok());
  CHECK(r.dirty_rects().empty());
  // Off again: every pixel each frame.
  REQUIRE(r.set_incremental(false).ok());
  REQUIRE(r.render(fb).ok());
  CHECK(r.frame_stats().pixels == 130u * 70u);
}

TEST_CASE("light-layer cache: 500 random game-loop frames within 1e-6 of the brightest emission, 1 and 2 threads" * per_isa()) {
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const int frames = scalar ? 40 : 500;
  // Room for every layer (the budget-limited path: the next case).
  const Outcome roomy = run_sequence(20261207u, frames, RenderOptions{}, 128, 96, std::size_t{64} << 20);
  MESSAGE("largest difference from full renders: ", roomy.worst, " x e_max");
  if (scalar) {  // the scalar reference computes every light itself
    CHECK(roomy.reused + roomy.filled == 0u);
    return;
  }
  CHECK(roomy.reused > 0u);
  CHECK(roomy.filled > 0u);
  CHECK(roomy.partial > roomy.frames / 4);
}

// The budget-limited path (layers for a few blocks; the other lights computed with their
// emissions next to the stored ones) on fewer frames: this one also runs under the sanitizers
// (TSan too: blocks' layers are touched by whichever thread renders the block) and the ARM64
// emulator, where the 500 frames above take minutes.
TEST_CASE("light-layer cache: 60 random game-loop frames with a budget of a few blocks, 1 and 2 threads" * per_isa()) {
  const bool scalar = resolved_isa(RenderOptions{}) == Isa::scalar;
  const Outcome tight = run_sequence(20261208u, scalar ? 20 : 60, RenderOptions{}, 128, 96, 6 * 48 * 1024);
  MESSAGE("largest difference from full renders: ", tight.worst, " x e_max");
  if (scalar) {
    CHECK(tight.reused + tight.filled == 0u);
    return;
  }
  CHECK(tight.reused > 0u);
  CHECK(tight.filled > 0u);
}

TEST_CASE("light-layer cache: a flicker recombines stored layers; the image does not depend on threads" * per_isa()) {
  if (resolved_isa(RenderOptions{}) == Isa::scalar) return;  // no layers on the scalar path (checked above)
  Scene scene;
  scene.width = 200;
  scene.height = 140;
  scene.view = View{0.0, 0.0, 200.0, 140.0};
  scene.lights.push_back(Light{Circle{{30.0, 40.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 60.0});
  scene.lights.push_back(Light{Circle{{150.0, 90.0}, 3.0}, {0.5, 0.8, 1.0}, 1.5, 70.0});
  scene.occluders.push_back(Occluder{box(60.0, 20.0, 64.0, 120.0)});
  Occluder glass{box(100.0, 60.0, 130.0, 64.0)};
  glass.transmittance = {0.9, 0.5, 0.2};  // coloured: three planes where it shades the light
  scene.occluders.push_back(glass);
  const std::size_t floats = static_cast<std::size_t>(200) * 140 * 3;
  std::vector<LightHandle> handles;
  Renderer r[2];
  std::vector<float> buffer[2] = {std::vector<float>(floats), std::vector<float>(floats)};
  for (int i = 0; i < 2; ++i) {
    RenderOptions options;
    options.threads = 1 + i;
    REQUIRE(r[i].set_options(options).ok());
    REQUIRE(r[i].set_scene(scene, &handles).ok());
    REQUIRE(r[i].set_incremental(true).ok());
    REQUIRE(r[i].set_light_layer_budget(std::size_t{16} << 20).ok());
  }
  for (int frame = 0; frame < 6; ++frame) {
    for (int i = 0; i < 2; ++i) {
      if (frame > 0) REQUIRE(r[i].set_light_emission(handles[frame % 2], {1.0, 0.9, 0.8}, 0.5 + frame).ok());
      REQUIRE(r[i].render(ImageView{buffer[i].data(), 200, 140, 200 * 3}).ok());
      const FrameCounts st = frame_counts(r[i]);
      INFO("frame ", frame, " threads ", i + 1);
      if (frame == 0) {
        CHECK(st.layer_tiles_filled > 0u);
        CHECK(st.layer_tiles_reused == 0u);
      } else {  // only an emission changed: every share of the dirty blocks comes from a layer
        CHECK(st.layer_tiles_filled == 0u);
        CHECK(st.layer_tiles_reused > 0u);
        CHECK(st.tile_lights == 0u);  // nothing handed to the kernel
        CHECK(st.pixels > 0u);
        CHECK(st.pixels < 200u * 140u);
      }
      CHECK(r[i].light_layer_bytes() > 0u);
      CHECK(r[i].light_layer_bytes() <= r[i].light_layer_budget());
    }
    CHECK(std::memcmp(buffer[0].data(), buffer[1].data(), floats * sizeof(float)) == 0);
    const std::vector<float> expected = fresh_render(r[0], RenderOptions{});
    const double bound = 1e-6 * brightest_emission(r[0].snapshot());
    double worst = 0.0;
    for (std::size_t p = 0; p < floats; ++p) worst = std::max(worst, std::abs(static_cast<double>(buffer[0][p]) - expected[p]));
    CHECK(worst <= bound);
  }
  // Off: freed, and the next frame is whole and byte-equal to a full render.
  REQUIRE(r[0].set_light_layer_budget(0).ok());
  CHECK(r[0].light_layer_bytes() == 0u);
  REQUIRE(r[0].render(ImageView{buffer[0].data(), 200, 140, 200 * 3}).ok());
  CHECK(r[0].frame_stats().pixels == 200u * 140u);
  const std::vector<float> expected = fresh_render(r[0], RenderOptions{});
  CHECK(std::memcmp(buffer[0].data(), expected.data(), floats * sizeof(float)) == 0);
}

}  // namespace par2d::test
