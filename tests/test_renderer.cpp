// par2d::Renderer: persistent world updates against one-shot renders, index and reach
// bookkeeping, refused updates, pixel formats, regions and threading modes.
#include <doctest/doctest.h>
#if PAR2D_HAVE_TBB
#include <tbb/task_arena.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "game_level.hpp"
#include "par2d/renderer.hpp"
#include "render/frame_output.hpp"
#include "world/occluder_bvh.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

std::vector<Isa> isas_here() {
  std::vector<Isa> out{Isa::scalar};
  for (Isa isa : par2d::kSimdIsas) {
    if (isa_supported(isa)) out.push_back(isa);
  }
  return out;
}

RenderOptions options_for(Isa isa) {
  RenderOptions o;
  o.backend = isa == Isa::scalar ? Backend::scalar : Backend::simd;
  o.isa = isa;
  o.threads = 2;
  return o;
}




Shape moved(const Shape& shape, double dx, double dy) {
  Shape out = shape;
  if (auto* p = std::get_if<Polygon>(&out)) {
    for (Vec2& v : p->vertices) v = {v.x + dx, v.y + dy};
  } else if (auto* c = std::get_if<Circle>(&out)) {
    c->center = {c->center.x + dx, c->center.y + dy};
  } else if (auto* s = std::get_if<Segment>(&out)) {
    s->a = {s->a.x + dx, s->a.y + dy};
    s->b = {s->b.x + dx, s->b.y + dy};
  }
  return out;
}

}  // namespace

// The lights include ones of several entries (a partial shadow's two parts, a concave light's
// pieces), dimmed to 0 and back, re-split, removed and added: a frame must sum every pixel's
// lights in the order a one-shot render of the snapshot does.
TEST_CASE("Renderer after random light and occluder updates equals a one-shot render of its snapshot, bit for bit") {
  for (Isa isa : isas_here()) {
    for (std::uint32_t seed = 1; seed <= 12; ++seed) {
      RandomSceneOptions opt;
      opt.width = 48 + static_cast<int>(seed % 3) * 23;
      opt.height = 40 + static_cast<int>(seed % 4) * 11;
      opt.max_occluders = 20;
      // Overlaps are allowed: updates must keep the light/occluder overlap lists right too.
      opt.lights_disjoint_from_occluders = seed % 3 != 0;
      const Scene scene = random_scene(seed, opt);
      Renderer r;
      REQUIRE(r.set_options(options_for(isa)).ok());
      std::vector<LightHandle> lights;
      std::vector<OccluderHandle> occluders;
      REQUIRE(r.set_scene(scene, &lights, &occluders).ok());
      std::vector<Light> light_state = scene.lights;
      std::vector<Occluder> occluder_state = scene.occluders;
      PortableRandom rng(seed * 7919u);
      const double size = std::min(opt.width, opt.height);
      for (int step = 0; step < 12; ++step) {
        const int op = static_cast<int>(rng.uniform() * 10.0);
        INFO("isa ", isa_name(isa), " seed ", seed, " step ", step, " op ", op);
        if (op == 0 && !lights.empty()) {  // move a light
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(lights.size()));
          light_state[i].shape = moved(light_state[i].shape, (rng.uniform() - 0.5) * 0.2 * size, (rng.uniform() - 0.5) * 0.2 * size);
          REQUIRE(r.update_light(lights[i], light_state[i]).ok());
        } else if (op == 1 && !lights.empty()) {  // flicker, sometimes to dark and back
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(lights.size()));
          REQUIRE(r.set_light_emission(lights[i], light_state[i].color, rng.chance(0.3) ? 0.0 : rng.uniform() * 3.0).ok());
        } else if (op == 2 && !occluders.empty()) {  // move an occluder
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(occluders.size()));
          occluder_state[i].shape = moved(occluder_state[i].shape, (rng.uniform() - 0.5) * 0.3 * size, (rng.uniform() - 0.5) * 0.3 * size);
          REQUIRE(r.update_occluder(occluders[i], occluder_state[i]).ok());
        } else if (op == 3 && !occluders.empty()) {  // remove an occluder
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(occluders.size()));
          REQUIRE(r.remove_occluder(occluders[i]).ok());
          CHECK(r.remove_occluder(occluders[i]).code() == StatusCode::invalid_argument);  // stale now
          occluders.erase(occluders.begin() + static_cast<std::ptrdiff_t>(i));
          occluder_state.erase(occluder_state.begin() + static_cast<std::ptrdiff_t>(i));
        } else if (op == 4) {  // add an occluder
          const Occluder o{Circle{{rng.uniform() * opt.width, rng.uniform() * opt.height}, 0.02 * size + rng.uniform() * 0.1 * size}};
          OccluderHandle h;
          REQUIRE(r.add_occluder(o, &h).ok());
          occluders.push_back(h);
          occluder_state.push_back(o);
        } else if (op == 5 && lights.size() > 1) {  // remove a light
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(lights.size()));
          REQUIRE(r.remove_light(lights[i]).ok());
          lights.erase(lights.begin() + static_cast<std::ptrdiff_t>(i));
          light_state.erase(light_state.begin() + static_cast<std::ptrdiff_t>(i));
        } else if (op == 6) {  // add a light
          const Light l{Circle{{rng.uniform() * opt.width, rng.uniform() * opt.height}, 0.01 * size + rng.uniform() * 0.05 * size},
                        {rng.uniform(), rng.uniform(), rng.uniform()}, 1.0 + rng.uniform()};
          LightHandle h;
          REQUIRE(r.add_light(l, &h).ok());
          lights.push_back(h);
          light_state.push_back(l);
        } else if (op == 7 && !lights.empty()) {  // a light's shadow made partial, full or none
          // A partial shadow renders as two entries, a full one as one: the light's entries
          // are laid out anew.
          const std::size_t i = static_cast<std::size_t>(rng.uniform() * static_cast<double>(lights.size()));
          const double strengths[3] = {1.0, 0.0, 0.25 + 0.5 * rng.uniform()};
          light_state[i].shadow.strength = strengths[rng.integer(0, 2)];
          REQUIRE(r.update_light(lights[i], light_state[i]).ok());
        } else {  // add a light of two or more entries: a partial shadow, a concave outline, or both
          const Vec2 c{rng.uniform() * opt.width, rng.uniform() * opt.height};
          const double a = 0.02 * size + rng.uniform() * 0.04 * size;
          Light l{Circle{c, a}, {rng.uniform(), rng.uniform(), rng.uniform()}, 1.0 + rng.uniform()};
          if (op == 8 || rng.chance(0.5)) l.shadow = Shadow{0.2 + 0.6 * rng.uniform(), {0.0, 0.5 * rng.uniform(), 0.0}};
          if (op == 9) {  // an L: two convex pieces and the boundary they share
            l.shape = Polygon{{{c.x, c.y}, {c.x + 2 * a, c.y}, {c.x + 2 * a, c.y + a}, {c.x + a, c.y + a},
                               {c.x + a, c.y + 2 * a}, {c.x, c.y + 2 * a}}};
          } else if (rng.chance(0.5)) {  // a ranged light with its own falloff
            l.range = 0.3 * size + rng.uniform() * 0.5 * size;
            l.falloff = 0.5 + 3.0 * rng.uniform();
          }
          LightHandle h;
          REQUIRE(r.add_light(l, &h).ok());
          lights.push_back(h);
          light_state.push_back(l);
        }
        CHECK(r.light_count() == lights.size());
        CHECK(r.occluder_count() == occluders.size());
        const Scene snap = r.snapshot();
        CHECK(snap.occluders.size() == occluders.size());
        CHECK(same_bits(frame_rgb(r), one_shot(snap, options_for(isa))));
      }
    }
  }
}

TEST_CASE("moving and flickering lights never rebuilds or updates the occluder index") {
  for (Isa isa : isas_here()) {
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    std::vector<LightHandle> torches;
    REQUIRE(r.set_scene(bench::game_level(160, 88), &torches).ok());
    frame_rgb(r);
    const RendererStats before = r.stats();
    for (int frame = 1; frame <= 10; ++frame) {
      for (int t = 0; t < bench::kTorches; ++t) REQUIRE(r.update_light(torches[static_cast<std::size_t>(t)], bench::torch_at(t, frame)).ok());
      frame_rgb(r);
    }
    const RendererStats after = r.stats();
    INFO("isa ", isa_name(isa));
    CHECK(after.index_builds == before.index_builds);
    CHECK(after.index_updates == before.index_updates);
    CHECK(after.full_prepares == before.full_prepares);
    CHECK(after.frames == before.frames + 10);
    // Culling proves reach again for exactly the moved lights; the scalar path needs none.
    CHECK(after.reach_computations - before.reach_computations == (isa == Isa::scalar ? 0u : 10u * bench::kTorches));
    // Emission only: no reach, no index.
    const RendererStats mid = r.stats();
    REQUIRE(r.set_light_emission(torches[0], {1.0, 0.5, 0.25}, 2.0).ok());
    frame_rgb(r);
    CHECK(r.stats().reach_computations == mid.reach_computations);
    CHECK(r.stats().index_builds == mid.index_builds);
  }
}

TEST_CASE("moving one pillar updates the index in place and re-proves only the lights that looked there" * par2d::test::per_isa()) {
  Renderer r;
  REQUIRE(r.set_options(options_for(default_isa() == Isa::scalar ? Isa::scalar : detect_isa())).ok());
  const Scene level = bench::game_level(320, 176);
  std::vector<OccluderHandle> occluders;
  REQUIRE(r.set_scene(level, nullptr, &occluders).ok());
  frame_rgb(r);
  const RendererStats before = r.stats();
  // The last square pillar (10 units across; the walls are 32-unit cells, merged in rows).
  std::size_t last = level.occluders.size();
  while (last-- > 0) {
    const auto* p = std::get_if<Polygon>(&level.occluders[last].shape);
    if (p && p->vertices[1].x - p->vertices[0].x == 10.0) break;
  }
  REQUIRE(last < level.occluders.size());
  Occluder pillar = level.occluders[last];
  pillar.shape = moved(pillar.shape, 3.0, -2.0);
  REQUIRE(r.update_occluder(occluders[last], pillar).ok());
  const std::vector<float> image = frame_rgb(r);
  const RendererStats after = r.stats();
  CHECK(after.index_builds == before.index_builds);
  CHECK(after.index_updates == before.index_updates + 1);
  if (detect_isa() != Isa::scalar) {
    const std::uint64_t reproved = after.reach_computations - before.reach_computations;
    MESSAGE("lights re-proven after moving one pillar: ", reproved, " of ", bench::kTorches);
    CHECK(reproved < static_cast<std::uint64_t>(bench::kTorches));
  }
  CHECK(same_bits(image, one_shot(r.snapshot(), r.options())));
}

// A light's reach proof rests on the occluders it looked at. A wall that hides half the view
// from a torch, moved far away, must make the torch's reach stale (its proof looked at the
// wall's old place, not the new one); the torch moved to the wall's other side likewise. A
// stale reach would keep the newly lit half black: each frame equals a one-shot render.
TEST_CASE("moving the wall a reach proof rests on, or the light itself, re-proves the light's reach" * par2d::test::per_isa()) {
  {
    const Isa isa = default_isa() == Isa::scalar ? Isa::scalar : detect_isa();
    Scene scene;
    scene.width = 128;
    scene.height = 64;
    scene.view = {0, 0, 128, 64};
    scene.lights.push_back(Light{Circle{{10.0, 32.0}, 3.0}, {1.0, 0.8, 0.6}, 2.0});
    scene.occluders.push_back(Occluder{Polygon{{{20.0, -4.0}, {24.0, -4.0}, {24.0, 68.0}, {20.0, 68.0}}}});
    // Small pillars on the far side, so the index has more than the wall in it.
    for (int k = 0; k < 6; ++k) {
      const double x = 40.0 + 14.0 * k;
      scene.occluders.push_back(Occluder{Polygon{{{x, 20.0}, {x + 2.0, 20.0}, {x + 2.0, 22.0}, {x, 22.0}}}});
    }
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    std::vector<LightHandle> lights;
    std::vector<OccluderHandle> occluders;
    REQUIRE(r.set_scene(scene, &lights, &occluders).ok());
    const std::vector<float> walled = frame_rgb(r);
    CHECK(same_bits(walled, one_shot(r.snapshot(), r.options())));
    // Far right of the wall is black while the wall stands.
    CHECK(walled[(32u * 128u + 100u) * 3u] == 0.0f);

    Occluder wall = scene.occluders[0];
    wall.shape = moved(wall.shape, 400.0, 0.0);  // far outside the view: meets nothing the torch saw
    REQUIRE(r.update_occluder(occluders[0], wall).ok());
    const std::vector<float> open = frame_rgb(r);
    CHECK(open[(32u * 128u + 100u) * 3u] > 0.0f);
    CHECK(same_bits(open, one_shot(r.snapshot(), r.options())));

    // The wall back, then the torch to its far side: what was lit is now in its shadow.
    REQUIRE(r.update_occluder(occluders[0], scene.occluders[0]).ok());
    frame_rgb(r);
    Light torch = scene.lights[0];
    torch.shape = Circle{{110.0, 40.0}, 3.0};
    REQUIRE(r.update_light(lights[0], torch).ok());
    const std::vector<float> moved_torch = frame_rgb(r);
    CHECK(moved_torch[(32u * 128u + 10u) * 3u] == 0.0f);
    CHECK(moved_torch[(32u * 128u + 100u) * 3u] > 0.0f);
    CHECK(same_bits(moved_torch, one_shot(r.snapshot(), r.options())));
  }
}

TEST_CASE("a refused update names the handle and the problem and keeps the previous state" * par2d::test::per_isa()) {
  Renderer r;
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(r.set_scene(bench::game_level(64, 35), &lights, &occluders).ok());
  const std::vector<float> before = frame_rgb(r);
  const RendererStats stats = r.stats();

  const Light crossed{Polygon{{{10, 10}, {30, 30}, {30, 10}, {10, 30}}}};
  Status s = r.update_light(lights[2], crossed);
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("light " + std::to_string(lights[2].id)) == 0);
  CHECK(s.message().find("polygon: edges 0 and 2 cross") != std::string::npos);

  s = r.update_occluder(occluders[5], Occluder{Circle{{5, 5}, -1.0}});
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("occluder " + std::to_string(occluders[5].id) + ": circle") == 0);
  s = r.update_occluder(occluders[5], Occluder{Segment{{5, 5}, {5, 5}}});
  CHECK(s.code() == StatusCode::invalid_scene);
  s = r.update_light(lights[0], Light{Circle{{1, 1}, 1}, {1, std::nan(""), 1}, 1});
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(r.set_light_emission(lights[1], {1, 1, 1}, -2.0).code() == StatusCode::invalid_scene);
  CHECK(r.add_occluder(Occluder{Polygon{{{0, 0}, {1, 1}}}}, nullptr).code() == StatusCode::invalid_argument);
  OccluderHandle h;
  s = r.add_occluder(Occluder{Polygon{{{0, 0}, {1, 1}, {2, 2}}}}, &h);
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("add_occluder: polygon") == 0);
  CHECK(r.update_light(LightHandle{occluders[0].id}, Light{}).code() == StatusCode::invalid_argument);
  CHECK(r.update_light(LightHandle{0}, Light{}).code() == StatusCode::invalid_argument);
  CHECK(r.update_light(LightHandle{lights[0].id + (std::uint64_t{1} << 32)}, Light{}).code() == StatusCode::invalid_argument);

  CHECK(r.light_count() == static_cast<std::size_t>(bench::kTorches));
  CHECK(same_bits(frame_rgb(r), before));
  CHECK(r.stats().index_builds == stats.index_builds);
  CHECK(r.stats().index_updates == stats.index_updates);
}

TEST_CASE("the lights' total emission stays within 1e38 per channel through every update path" * par2d::test::per_isa()) {
  Renderer r;
  REQUIRE(r.set_frame(16, 16).ok());
  LightHandle a, b;
  REQUIRE(r.add_light(Light{Circle{{4, 4}, 1}, {1, 1, 1}, 6e37}, &a).ok());
  // A second light alone is fine, but the sum would pass float's range.
  Status s = r.add_light(Light{Circle{{12, 12}, 1}, {1, 1, 1}, 6e37}, &b);
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("add_light: emission too large") == 0);
  CHECK(r.light_count() == 1);
  REQUIRE(r.add_light(Light{Circle{{12, 12}, 1}, {1, 1, 1}, 3e37}, &b).ok());
  // Replacing a light counts it once, not twice.
  CHECK(r.update_light(a, Light{Circle{{5, 5}, 1}, {1, 1, 1}, 7e37}).ok());
  s = r.update_light(a, Light{Circle{{5, 5}, 1}, {1, 1, 1}, 8e37});
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("light " + std::to_string(a.id) + ": emission too large") == 0);
  CHECK(r.set_light_emission(b, {1, 2, 1}, 3e37).code() == StatusCode::invalid_scene);
  CHECK(r.set_light_emission(b, {1, 1, 1}, 3e37).ok());
  const std::vector<float> pixels = frame_rgb(r);
  CHECK(std::all_of(pixels.begin(), pixels.end(), [](float v) { return std::isfinite(v) && v >= 0.0f; }));
}

TEST_CASE("every pixel format and any region equal the same pixels of the whole float frame") {
  const Scene level = bench::game_level(150, 83);
  for (Isa isa : isas_here()) {
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    REQUIRE(r.set_scene(level).ok());
    const std::vector<float> full = frame_rgb(r);
    const int w = r.width();
    std::mt19937 rng(42);
    const double exposure = 0.75;
    for (int trial = 0; trial < 12; ++trial) {
      PixelRect region;
      region.x0 = static_cast<int>(rng() % static_cast<unsigned>(w));
      region.x1 = region.x0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(w - region.x0));
      region.y0 = static_cast<int>(rng() % static_cast<unsigned>(r.height()));
      region.y1 = region.y0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(r.height() - region.y0));
      if (trial == 0) region = {0, 0, w, r.height()};
      const int rw = region.x1 - region.x0, rh = region.y1 - region.y0;
      INFO("isa ", isa_name(isa), " region ", region.x0, ",", region.y0, ",", region.x1, ",", region.y1);
      for (PixelFormat format : {PixelFormat::rgb_f32, PixelFormat::rgba_f32, PixelFormat::rgba8_srgb}) {
        const int bpp = bytes_per_pixel(format);
        const std::ptrdiff_t stride = rw * bpp + 12;  // padded rows: the padding must stay untouched
        std::vector<unsigned char> buffer(static_cast<std::size_t>(stride) * rh, 0xAB);
        FrameBuffer fb;
        fb.data = buffer.data();
        fb.format = format;
        fb.row_stride = stride;
        fb.exposure = exposure;
        const Status s = r.render(fb, region);
        REQUIRE_MESSAGE(s.ok(), s.message());
        bool same = true, padding = true;
        for (int j = 0; j < rh && same; ++j) {
          const unsigned char* row = buffer.data() + static_cast<std::ptrdiff_t>(j) * stride;
          for (int i = 0; i < rw; ++i) {
            const float* e = &full[(static_cast<std::size_t>(region.y0 + j) * w + static_cast<std::size_t>(region.x0 + i)) * 3];
            const unsigned char* p = row + static_cast<std::ptrdiff_t>(i) * bpp;
            if (format == PixelFormat::rgba8_srgb) {
              for (int c = 0; c < 3; ++c) {
                const double v = std::clamp(exposure * static_cast<double>(e[c]), 0.0, 1.0);
                const double srgb = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
                const long expected = std::lround(255.0 * srgb);
                // The threshold search and pow may disagree only right at a rounding boundary.
                if (std::abs(static_cast<long>(p[c]) - expected) > 1 ||
                    (static_cast<long>(p[c]) != expected && std::abs(255.0 * srgb - std::floor(255.0 * srgb) - 0.5) > 1e-6))
                  same = false;
              }
              if (p[3] != 255) same = false;
            } else {
              float v[4];
              std::memcpy(v, p, static_cast<std::size_t>(bpp));
              if (std::memcmp(v, e, 3 * sizeof(float)) != 0) same = false;
              if (format == PixelFormat::rgba_f32 && v[3] != 1.0f) same = false;
            }
          }
          for (std::ptrdiff_t k = rw * bpp; k < stride; ++k) padding = padding && row[k] == 0xAB;
        }
        CHECK_MESSAGE(same, "format ", static_cast<int>(format));
        CHECK(padding);
      }
    }
  }
}

TEST_CASE("render refuses bad buffers and regions with a message" * par2d::test::per_isa()) {
  Renderer r;
  std::vector<float> pixels(16 * 16 * 4);
  FrameBuffer fb{pixels.data(), PixelFormat::rgba_f32, 16 * 16, 1.0};
  CHECK(r.render(fb).code() == StatusCode::invalid_argument);  // no frame yet
  REQUIRE(r.set_frame(16, 16).ok());
  CHECK(r.render(fb).ok());
  CHECK(r.render(fb, PixelRect{0, 0, 17, 4}).code() == StatusCode::invalid_argument);
  CHECK(r.render(fb, PixelRect{3, 3, 3, 4}).code() == StatusCode::invalid_argument);
  fb.row_stride = 15 * 16;
  const Status s = r.render(fb);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(s.message().find("row_stride") != std::string::npos);
  fb.row_stride = 16 * 16;
  fb.exposure = -1.0;
  CHECK(r.render(fb).code() == StatusCode::invalid_argument);
  fb.exposure = 1.0;
  fb.data = nullptr;
  CHECK(r.render(fb).code() == StatusCode::invalid_argument);
  CHECK(r.set_frame(0, 5).code() == StatusCode::invalid_scene);
  RenderOptions unknown;
  unknown.backend = static_cast<Backend>(3);  // past scalar: no backend
  CHECK(r.set_options(unknown).code() == StatusCode::invalid_argument);
  RenderOptions negative;
  negative.threads = -1;
  CHECK(r.set_options(negative).code() == StatusCode::invalid_argument);
}

TEST_CASE("threading: own pool of N, resolved thread count, and rendering inside the host's arena give the same bytes" * par2d::test::per_isa()) {
  const Scene level = bench::game_level(96, 53);
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  RenderOptions o;
  o.threads = 64;
  CHECK(resolved_threads(o) == std::min(64, hardware));
  o.threads = 1;
  Renderer one;
  REQUIRE(one.set_options(o).ok());
  CHECK(one.threads() == 1);
  REQUIRE(one.set_scene(level).ok());
  const std::vector<float> reference = frame_rgb(one);

  o.threads = 0;
  Renderer all;
  REQUIRE(all.set_options(o).ok());
  REQUIRE(all.set_scene(level).ok());
  CHECK(same_bits(frame_rgb(all), reference));

  o.threading = Threading::caller_arena;
  Renderer hosted;
#if PAR2D_HAVE_TBB
  REQUIRE(hosted.set_options(o).ok());
  REQUIRE(hosted.set_scene(level).ok());
  tbb::task_arena host(3);
  std::vector<float> image;
  int seen_threads = 0;
  host.execute([&] {
    image = frame_rgb(hosted);
    seen_threads = hosted.threads();
  });
  CHECK(seen_threads == 3);
  CHECK(same_bits(image, reference));
#else
  // A build without TBB has no caller's arena to run in: the mode is refused, not emulated.
  const Status refused = hosted.set_options(o);
  CHECK(refused.code() == StatusCode::invalid_argument);
  CHECK(refused.message() ==
        "set_options: threading caller_arena needs par2d built with TBB (this build schedules on std::threads)");
#endif
}

TEST_CASE("OccluderBvh updated in place (refit, insert, remove) answers as a fresh build and as brute force") {
  using detail::Aabb;
  std::mt19937 rng(7);
  auto coord = [&] { return static_cast<double>(rng() % 10000) / 10.0; };
  auto random_box = [&] {
    const double x = coord(), y = coord();
    return Aabb{x, y, x + 1 + static_cast<double>(rng() % 300) / 10.0, y + 1 + static_cast<double>(rng() % 300) / 10.0};
  };
  std::vector<Aabb> boxes(200);
  for (Aabb& b : boxes) b = random_box();
  detail::OccluderBvh bvh;
  bvh.build(boxes);
  int rebuilds = 0;
  for (int step = 0; step < 600; ++step) {
    const auto op = rng() % 3;
    if (op == 0 && !boxes.empty()) {
      const auto i = static_cast<std::uint32_t>(rng() % boxes.size());
      boxes[i] = random_box();
      bvh.update(i, boxes[i]);
    } else if (op == 1) {
      boxes.push_back(random_box());
      bvh.insert(boxes.back());
    } else if (!boxes.empty()) {
      const auto i = static_cast<std::uint32_t>(rng() % boxes.size());
      boxes[i] = boxes.back();
      boxes.pop_back();
      bvh.remove(i);
    }
    REQUIRE(bvh.size() == boxes.size());
    if (bvh.needs_rebuild() && step % 2 == 0) {
      bvh.build(boxes);
      ++rebuilds;
    }
    const Aabb q = random_box();
    std::vector<std::uint32_t> got, want;
    bvh.query_box(q, got);
    for (std::uint32_t k = 0; k < boxes.size(); ++k) {
      const Aabb& b = boxes[k];
      if (b.min_x <= q.max_x && q.min_x <= b.max_x && b.min_y <= q.max_y && q.min_y <= b.max_y) want.push_back(k);
    }
    REQUIRE(got == want);
    const std::vector<Vec2> hull{{q.min_x, q.min_y}, {q.max_x + 40, q.min_y}, {q.min_x, q.max_y + 25}};
    got.clear();
    bvh.query_convex(hull.data(), 3, got);
    detail::OccluderBvh fresh;
    fresh.build(boxes);
    want.clear();
    fresh.query_convex(hull.data(), 3, want);
    REQUIRE(got == want);
  }
  MESSAGE("rebuilds asked for in 600 random updates: ", rebuilds);
  CHECK(rebuilds > 0);
}

}  // namespace par2d::test

namespace par2d::test {
TEST_CASE("8-bit sRGB table look-up equals the threshold search at every threshold and 1e6 random values") {
  std::mt19937_64 rng(3);
  std::uint64_t differences = 0;
  auto check = [&](double v) { differences += detail::encode_srgb8(v) != detail::encode_srgb8_search(v); };
  for (int k = 1; k <= 255; ++k) {
    const double s = (k - 0.5) / 255.0;
    const double t = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    for (double v : {t, std::nextafter(t, 0.0), std::nextafter(t, 1.0)}) check(v);
  }
  for (int i = 0; i < 1000000; ++i) {
    const double u = static_cast<double>(rng() >> 11) * 0x1p-53;
    check(u);
    check(u * u * u * 0.01);  // dense near 0, where the codes step fastest
  }
  for (double v : {0.0, -0.0, -1.0, 1.0, 2.0, std::nan(""), 1e-300, std::nextafter(1.0, 0.0)}) check(v);
  CHECK(differences == 0);
  CHECK(detail::encode_srgb8(std::nextafter(1.0, 0.0)) == 255);
  CHECK(detail::encode_srgb8(0.5) == 188);  // round(255 * (1.055 * 0.5^(1/2.4) - 0.055)) = 188
}
}  // namespace par2d::test

namespace par2d::test {

TEST_CASE("a segment light cut from an occluder's edge stays hidden when the occluder is added to a persistent Renderer") {
  // A light within the contact tolerance of an occluder touches it (docs/contract.md section 5):
  // the edge piece here rounded 1e-16 of its length outside the edge's line, and the SIMD path
  // showed 7 % to 31 % of the light (tests/fuzz/FINDINGS.md #9). The occluder arrives through
  // add_occluder, which finds the light's contact pairs on its own (World::occluder_changed).
  Scene scene;
  scene.width = 14;
  scene.height = 3;
  scene.view = {-1.5e301, -1.5e301, -1.0000000000000006e300, -1.2000000000000001e301};
  Light light;
  light.shape = Segment{{-1.1186238887459775e300, -6.9665648774750444e300}, {3.1067743734805095e299, -1.3331532722195445e301}};
  scene.lights.push_back(light);
  const Occluder occluder{Polygon{{{1.2945272043763045e301, -1.2714666525255044e301},
                                   {1.0214666525255047e301, -5.5472795623695649e299},
                                   {-1.9452720437630463e300, -3.2853334747449615e300},
                                   {7.8533347474494858e299, -1.544527204376304e301}}}};
  for (Isa isa : isas_here()) {
    INFO("isa " << isa_name(isa));
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    REQUIRE(r.set_scene(scene).ok());
    const std::vector<float> lit = frame_rgb(r);
    CHECK(*std::max_element(lit.begin(), lit.end()) > 0.05f);  // the light alone is seen
    OccluderHandle h;
    REQUIRE(r.add_occluder(occluder, &h).ok());
    for (float v : frame_rgb(r)) CHECK(v == 0.0f);
  }
}

// A light overlapping an occluder carries what the tile setup asks of the pair (where the
// boundaries meet, whether the light lies inside, the edge that clips it: LightOverlap), made
// once per change of either shape. Every update path must keep it in step: the frames must
// equal one-shot renders, which prepare it afresh, bit for bit.
TEST_CASE("a torch overlapping a wall keeps its clip and containment in step through moves and removals") {
  Scene scene;
  scene.width = 64;
  scene.height = 48;
  scene.view = {0.0, 0.0, 64.0, 48.0};
  Light torch;
  torch.shape = Circle{{28.0, 24.0}, 5.0};
  torch.color = {1.0, 0.8, 0.5};
  torch.intensity = 2.0;
  scene.lights.push_back(torch);
  scene.lights.push_back(Light{Circle{{8.0, 8.0}, 3.0}, {0.5, 0.5, 1.0}, 1.0});
  auto box = [](double x0, double y0, double x1, double y1) {
    return Occluder{Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
  };
  scene.occluders.push_back(box(14.0, 30.0, 18.0, 34.0));  // a crate, removed below
  scene.occluders.push_back(box(30.0, 4.0, 40.0, 44.0));   // the wall: 3 px into the torch
  for (Isa isa : isas_here()) {
    INFO("isa ", std::string(isa_name(isa)));
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    std::vector<LightHandle> lights;
    std::vector<OccluderHandle> occluders;
    const Status set = r.set_scene(scene, &lights, &occluders);
    REQUIRE_MESSAGE(set.ok(), set.message());
    auto check_frame = [&](const char* step) {
      INFO(step);
      CHECK(same_bits(frame_rgb(r), one_shot(r.snapshot(), options_for(isa))));
    };
    check_frame("clipped by the wall's left edge");
    REQUIRE(r.update_occluder(occluders[1], box(20.0, 4.0, 40.0, 44.0)).ok());
    check_frame("the wall grown over the whole torch: inside it");
    REQUIRE(r.update_occluder(occluders[1], box(34.0, 4.0, 44.0, 44.0)).ok());
    check_frame("the wall moved off the torch");
    REQUIRE(r.update_occluder(occluders[1], box(16.0, 4.0, 25.0, 44.0)).ok());
    check_frame("the wall moved to the torch's other side, clipping it there");
    REQUIRE(r.remove_occluder(occluders[0]).ok());  // the wall takes the crate's index
    check_frame("the crate removed");
    Light moved_torch = torch;
    moved_torch.shape = Circle{{22.0, 26.0}, 5.0};
    REQUIRE(r.update_light(lights[0], moved_torch).ok());
    check_frame("the torch moved deeper into the wall");
    moved_torch.shape = Circle{{20.0, 26.0}, 3.0};
    REQUIRE(r.update_light(lights[0], moved_torch).ok());
    check_frame("the torch moved inside the wall");
  }
}

// A light with a partial shadow is two entries (shadowed and unshadowed parts), a concave light
// one per piece and shared boundary. A World keeps each light's entries together, in the order
// a load of its snapshot lays them out, whatever was added, dimmed to 0 (no entry: the
// snapshot lists it after the emitting lights) or removed before it; else a pixel several
// lights reach sums them in another order and rounds differently (by 1 ulp to 4e-6 here).
TEST_CASE("shadow-split lights among others: frames stay a one-shot render of the snapshot bit for bit through edits") {
  Scene scene;
  scene.width = 64;
  scene.height = 48;
  scene.view = {0.0, 0.0, 64.0, 48.0};
  scene.occluders.push_back(Occluder{Polygon{{{26, 20}, {38, 20}, {38, 26}, {26, 26}}}});
  Light split{Circle{{24.0, 14.0}, 3.0}, {1.0, 0.9, 0.7}, 1.3};
  split.shadow = Shadow{0.6, {0.0, 0.2, 0.4}};
  Light plain{Circle{{40.0, 12.0}, 2.5}, {0.4, 0.7, 1.0}, 0.9};
  Light ranged{Circle{{32.0, 36.0}, 2.0}, {0.8, 0.3, 0.5}, 1.7};
  ranged.range = 40.0;
  ranged.falloff = 16.0;
  scene.lights = {split, plain, ranged};
  for (Isa isa : isas_here()) {
    INFO("isa ", std::string(isa_name(isa)));
    Renderer r;
    REQUIRE(r.set_options(options_for(isa)).ok());
    std::vector<LightHandle> lights;
    REQUIRE(r.set_scene(scene, &lights).ok());
    auto check_frame = [&](const std::string& step) {
      INFO(step);
      CHECK(same_bits(frame_rgb(r), one_shot(r.snapshot(), options_for(isa))));
    };
    check_frame("as loaded");
    LightHandle added;
    REQUIRE(r.add_light(Light{Circle{{18.0, 30.0}, 2.0}, {0.9, 0.9, 0.2}, 1.1}, &added).ok());
    check_frame("a light added after the split one");
    REQUIRE(r.set_light_emission(lights[0], split.color, 0.0).ok());
    check_frame("the split light dimmed to 0");
    REQUIRE(r.set_light_emission(lights[0], split.color, split.intensity).ok());
    check_frame("the split light lit again");
    REQUIRE(r.set_light_emission(lights[1], plain.color, 0.0).ok());
    check_frame("the first of the plain lights dimmed to 0");
    REQUIRE(r.remove_light(lights[2]).ok());
    check_frame("a light before the split one removed");
    Light l_shape = split;
    l_shape.shape = Polygon{{{44, 30}, {52, 30}, {52, 34}, {48, 34}, {48, 40}, {44, 40}}};
    LightHandle concave;
    REQUIRE(r.add_light(l_shape, &concave).ok());
    REQUIRE(r.set_light_emission(lights[1], plain.color, plain.intensity).ok());
    check_frame("a concave split light added, a plain one lit after it");
    REQUIRE(r.remove_light(added).ok());
    check_frame("a plain light between split ones removed");
    split.shadow.strength = 1.0;
    REQUIRE(r.update_light(lights[0], split).ok());
    check_frame("the split light's shadow made full (one entry)");
  }
}

}  // namespace par2d::test

namespace par2d::test {

// The tile-relative sample offsets are kept between tiles and frames while the sampling,
// the pixel size and the scale stay (TileWork::sample_grid): one Renderer taken through
// changes of each must still equal a one-shot render of every frame, bit for bit.
TEST_CASE("Renderer through spp, view and size changes equals one-shot renders bit for bit") {
  for (Isa isa : isas_here()) {
    RandomSceneOptions opt;
    opt.width = 53;
    opt.height = 37;
    Scene scene = random_scene(77, opt);
    Renderer r;
    RenderOptions options = options_for(isa);
    REQUIRE(r.set_options(options).ok());
    REQUIRE(r.set_scene(scene).ok());
    for (int step = 0; step < 5; ++step) {
      if (step == 1) options.spp = 3;                                  // sampling
      if (step == 2) scene.view = {scene.view.x0, scene.view.y0, scene.view.x1 * 1.5, scene.view.y1 * 1.5};  // pixel size
      if (step == 3) scene.width = 71;                                 // pixel width only
      if (step == 4) options.spp = 1;
      REQUIRE(r.set_options(options).ok());
      REQUIRE(r.set_scene(scene).ok());
      std::vector<float> persistent(static_cast<std::size_t>(scene.width) * scene.height * 3, -1.0f);
      std::vector<float> one_shot(persistent.size(), -2.0f);
      REQUIRE(r.render(ImageView{persistent.data(), scene.width, scene.height, scene.width * 3}).ok());
      REQUIRE(render(scene, options, ImageView{one_shot.data(), scene.width, scene.height, scene.width * 3}).ok());
      INFO("isa ", isa_name(isa), " step ", step);
      CHECK(std::memcmp(persistent.data(), one_shot.data(), persistent.size() * sizeof(float)) == 0);
    }
  }
}

}  // namespace par2d::test
