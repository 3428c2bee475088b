// FrameStats and FrameDiagnostics (Renderer::frame_stats and frame_diagnostics, `par2d bench
// --stats`): counts that follow the frame's structure, agree across thread counts, and move
// the way culling says they should; and the scattered level generator's size knobs.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <variant>
#include <vector>

#include "par2d/par2d.hpp"
#include "scattered_scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;

namespace {

std::uint64_t cells(int pixels, int cell) { return static_cast<std::uint64_t>((pixels + cell - 1) / cell); }

// The best SIMD level here, named explicitly: PAR2D_ISA=scalar (one of ctest's runs) would
// otherwise send Backend::simd to the scalar reference, which counts no kernel work.
RenderOptions simd_options() {
  RenderOptions options;
  options.backend = Backend::simd;
  options.isa = test::simd_isas_here().back();
  return options;
}

using test::FrameCounts;
using Counts = FrameCounts;

std::vector<float> pixels_for(const Scene& scene) {
  return std::vector<float>(static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3);
}

ImageView view_of(std::vector<float>& pixels, const Scene& scene) {
  return ImageView{pixels.data(), scene.width, scene.height, 3 * static_cast<std::ptrdiff_t>(scene.width)};
}

Counts counts_of(const Renderer& renderer) { return test::frame_counts(renderer); }

// One frame of a Renderer that also samples what pixels need.
Counts stats_of(const Scene& scene, const RenderOptions& options) { return test::frame_counts(scene, options); }

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// A light in a closed room of four walls at the top-left of a larger view, and a second
// light outside: blocks far from the room cannot see the first light.
Scene closed_room() {
  Scene s;
  s.width = 256;
  s.height = 192;
  s.view = {0, 0, 256, 192};
  Light inside;
  inside.shape = Circle{{40, 40}, 4};
  s.lights.push_back(inside);
  Light outside;
  outside.shape = Circle{{200, 150}, 5};
  s.lights.push_back(outside);
  for (const Polygon& wall : {box(10, 10, 70, 14), box(10, 66, 70, 70), box(10, 10, 14, 70), box(66, 10, 70, 70)}) {
    Occluder o;
    o.shape = wall;
    s.occluders.push_back(o);
  }
  return s;
}

}  // namespace

TEST_CASE("FrameStats follow the frame's blocks and tiles, and the kernel's work per tile") {
  const Scene scene = bench::scattered_scene(12, 90, 7, 200, 136);
  RenderOptions options = simd_options();
  options.threads = 2;
  const Counts s = stats_of(scene, options);
  CHECK(s.pixels == 200u * 136u);
  CHECK(s.tiles == cells(200, 16) * cells(136, 16));
  CHECK(s.blocks == cells(200, 64) * cells(136, 64));
  CHECK(s.block_lights == s.blocks * 12u);
  CHECK(s.samples == s.tiles * 256u);
  // Culled tiles hand the kernel per-cell lists (render/cell_lists.cpp): every light, and only
  // the pairs whose shadow reaches the cell (cells wholly past the image edge get none).
  CHECK(s.light_samples <= s.tile_lights * 256u);
  CHECK(s.light_samples > s.tile_lights * 256u * 9u / 10u);
  CHECK(s.pair_samples < s.tile_pairs * 256u * 9u / 10u);
  CHECK(s.tile_lights > 0u);
  CHECK(s.tile_lights <= s.tiles * 12u);
  CHECK(s.block_proofs_succeeded <= s.block_proofs_tried);
  CHECK(s.tile_proofs_succeeded <= s.tile_proofs_tried);
  CHECK(s.umbra_hits <= s.umbra_tests);
  // Scattered occluders: some lie in front of a light but off every line from the tile to it.
  CHECK(s.tile_pairs_outside_hull > 0u);
  CHECK(s.tile_general_pairs == 0u);  // the generator keeps lights clear of occluders
  CHECK(s.scalar_tiles == 0u);

  SUBCASE("the sampled needs: one pixel per tile, visible lights among the kernel's, the same unculled") {
    CHECK(s.sampled_pixels == s.tiles);
    CHECK(s.sampled_visible_lights > 0u);
    CHECK(s.sampled_visible_lights <= s.tile_lights);
    CHECK(s.sampled_blocking_pairs > 0u);
    RenderOptions unculled = options;
    unculled.culling = false;
    const Counts u = stats_of(scene, unculled);
    CHECK(u.sampled_visible_lights == s.sampled_visible_lights);
    CHECK(u.sampled_blocking_pairs == s.sampled_blocking_pairs);
    CHECK(u.light_samples == u.tile_lights * 256u);  // no cells: the tile's lists
    CHECK(u.pair_samples == u.tile_pairs * 256u);
  }

  SUBCASE("the same counts at 1 thread, 4 samples per pixel scale the samples only") {
    RenderOptions one = options;
    one.threads = 1;
    const Counts t = stats_of(scene, one);
    CHECK(t.tile_lights == s.tile_lights);
    CHECK(t.tile_pairs == s.tile_pairs);
    CHECK(t.block_proofs_tried == s.block_proofs_tried);
    CHECK(t.tile_proofs_tried == s.tile_proofs_tried);
    CHECK(t.tile_proofs_skipped == s.tile_proofs_skipped);
    CHECK(t.umbra_tests == s.umbra_tests);
    CHECK(t.tile_pairs_outside_hull == s.tile_pairs_outside_hull);
    one.spp = 4;
    const Counts u = stats_of(scene, one);
    CHECK(u.samples == 4u * s.samples);
    CHECK(u.tile_lights == s.tile_lights);
  }

  SUBCASE("a Renderer without sample_needs reports the same frame and no sampled needs") {
    Renderer renderer;
    REQUIRE(renderer.set_options(options).ok());
    REQUIRE(renderer.set_scene(scene).ok());
    CHECK(renderer.frame_stats().tiles == 0u);
    std::vector<float> pixels = pixels_for(scene);
    REQUIRE(renderer.render(view_of(pixels, scene)).ok());
    const Counts r = counts_of(renderer);
    CHECK(r.tiles == s.tiles);
    CHECK(r.tile_lights == s.tile_lights);
    CHECK(r.tile_pairs == s.tile_pairs);
    CHECK(r.block_proofs_succeeded == s.block_proofs_succeeded);
    CHECK(r.sampled_pixels == 0u);
  }

  SUBCASE("the scalar reference counts its tiles as scalar tiles and nothing else") {
    RenderOptions scalar = options;
    scalar.backend = Backend::scalar;
    const Counts t = stats_of(scene, scalar);
    CHECK(t.scalar_tiles == s.tiles);
    CHECK(t.tiles == s.tiles);
    CHECK(t.tile_lights == 0u);
    CHECK(t.blocks == 0u);
  }
}

TEST_CASE("a frame's FrameStats hold what it computed and its FrameDiagnostics what culling did, zero before a frame, for a whole frame, a region and an unchanged incremental frame") {
  const Scene scene = closed_room();
  Renderer renderer;
  REQUIRE(renderer.set_options(simd_options()).ok());
  REQUIRE(renderer.set_scene(scene).ok());
  const Counts before = counts_of(renderer);
  CHECK(before.pixels == 0u);
  CHECK(before.tiles == 0u);
  CHECK(before.blocks == 0u);
  CHECK(before.samples == 0u);
  std::vector<float> pixels = pixels_for(scene);
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const Counts whole = counts_of(renderer);
  CHECK(whole.pixels == 256u * 192u);
  CHECK(whole.tiles == 16u * 12u);
  CHECK(whole.layer_tiles_reused == 0u);
  CHECK(whole.bounce_pieces == 0u);
  CHECK(whole.blocks == 4u * 3u);
  CHECK(whole.block_lights == 4u * 3u * 2u);
  CHECK(whole.samples == whole.tiles * 256u);
  // The walls hide the inner light from blocks beyond the room, by reach or by a proof.
  CHECK(whole.block_lights_out_of_reach + whole.block_proofs_succeeded > 0u);
  CHECK(whole.tile_pairs > 0u);
  CHECK(whole.umbra_tests > 0u);
  // A region: only its pixels and the blocks and tiles that meet it.
  const FrameBuffer part{pixels.data(), PixelFormat::rgb_f32, 48 * 3 * static_cast<std::ptrdiff_t>(sizeof(float))};
  REQUIRE(renderer.render(part, PixelRect{64, 64, 112, 96}).ok());
  const Counts region = counts_of(renderer);
  CHECK(region.pixels == 48u * 32u);
  CHECK(region.tiles == 3u * 2u);
  CHECK(region.blocks == 1u);
  // An incremental frame where nothing changed computes nothing, and says so in both.
  REQUIRE(renderer.set_incremental(true).ok());
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const Counts unchanged = counts_of(renderer);
  CHECK(unchanged.pixels == 0u);
  CHECK(unchanged.tiles == 0u);
  CHECK(unchanged.blocks == 0u);
  CHECK(unchanged.samples == 0u);
}

TEST_CASE("FrameStats: culling removes a walled-in light from the blocks outside its room; without culling every tile gets every light") {
  const Scene scene = closed_room();
  RenderOptions options = simd_options();
  const Counts culled = stats_of(scene, options);
  // The room spans one 64 px block's worth of pixels; blocks beyond it lose the inner light
  // to its reach or to a proof, and no tile far from the room computes it.
  CHECK(culled.block_lights_out_of_reach + culled.block_proofs_succeeded > 0u);
  CHECK(culled.tile_lights < culled.tiles * 2u);
  options.culling = false;
  const Counts unculled = stats_of(scene, options);
  CHECK(unculled.tile_lights == unculled.tiles * 2u);
  CHECK(unculled.block_lights_out_of_reach == 0u);
  CHECK(unculled.block_proofs_tried == 0u);
  CHECK(unculled.tile_proofs_tried == 0u);
  CHECK(unculled.tile_proofs_skipped == 0u);
  CHECK(unculled.umbra_tests == 0u);
  CHECK(unculled.tile_pairs_outside_hull == 0u);
  CHECK(unculled.tile_pairs == unculled.tiles * 2u * 4u);  // every light with every wall
}

TEST_CASE("FrameStats' sampled needs in closed cases: an open view sees every light; walls hide the walled-in one") {
  Scene open = closed_room();
  open.occluders.clear();
  RenderOptions options = simd_options();
  const Counts o = stats_of(open, options);
  CHECK(o.sampled_visible_lights == 2u * o.sampled_pixels);
  CHECK(o.sampled_blocking_pairs == 0u);
  // Only the walled-in light: it is visible exactly at the tile middles inside the room's
  // interior (14 < x, y < 66): x, y in {24.5, 40.5, 56.5}, 9 of the 192.
  Scene room = closed_room();
  room.lights.pop_back();
  const Counts w = stats_of(room, options);
  CHECK(w.sampled_pixels == 16u * 12u);
  CHECK(w.sampled_visible_lights == 9u);
  CHECK(w.sampled_blocking_pairs == 0u);  // from inside, no wall is in front of the light
}

TEST_CASE("FrameStats count a light containing an occluder as general pairs, on the SIMD path") {
  Scene scene = closed_room();
  scene.lights[1].shape = Circle{{200, 150}, 20};
  Occluder inner;
  inner.shape = box(195, 145, 205, 155);  // wholly inside the light: no line separates them
  scene.occluders.push_back(inner);
  RenderOptions options = simd_options();
  const Counts s = stats_of(scene, options);
  CHECK(s.tile_general_pairs > 0u);
  CHECK(s.scalar_tiles == 0u);
}

TEST_CASE("scattered levels: shape sizes stay in the asked bands, lights clear of occluders where there is room") {
  const bench::ScatteredSizes sizes{1.5, 4.0, 3.0, 5.0};
  const Scene s = bench::scattered_scene(40, 400, 11, 640, 360, sizes);
  REQUIRE(s.lights.size() == 40u);
  REQUIRE(s.occluders.size() == 400u);
  // Every shape's vertices lie on one circle (the generator's bounding circle): its center
  // is the circumcenter of any three of them.
  auto bounding = [](const Shape& shape, Vec2& center) {
    if (const auto* c = std::get_if<Circle>(&shape)) {
      center = c->center;
      return c->radius;
    }
    const auto& v = std::get<Polygon>(shape).vertices;
    const Vec2 a = v[0], b = v[1], c = v[2];
    const double d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
    const double a2 = a.x * a.x + a.y * a.y, b2 = b.x * b.x + b.y * b.y, c2 = c.x * c.x + c.y * c.y;
    center = {(a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d,
              (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d};
    return std::hypot(a.x - center.x, a.y - center.y);
  };
  std::vector<std::pair<Vec2, double>> occluders;
  for (const Occluder& o : s.occluders) {
    Vec2 c;
    const double r = bounding(o.shape, c);
    // Circles and triangles: the size drawn; rectangles: their diagonal, up to sqrt(2) times it.
    CHECK(2.0 * r >= 1.5 - 1e-9);
    CHECK(2.0 * r <= 4.0 * std::sqrt(2.0) + 1e-9);
    occluders.push_back({c, r});
  }
  for (const Light& l : s.lights) {
    Vec2 c;
    const double r = bounding(l.shape, c);
    CHECK(2.0 * r >= 3.0 - 1e-9);
    CHECK(2.0 * r <= 5.0 + 1e-9);
    for (const auto& [oc, orad] : occluders) CHECK(std::hypot(c.x - oc.x, c.y - oc.y) >= r + orad + 2.0 - 1e-9);
  }
  // Defaults reproduce the original level exactly (scaling tables stay comparable).
  const Scene a = bench::scattered_scene(16, 256, 20240611, 320, 180);
  const Scene b = bench::scattered_scene(16, 256, 20240611, 320, 180, bench::ScatteredSizes{4.0, 12.0, 6.0, 12.0});
  REQUIRE(a.lights.size() == b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    Vec2 ca, cb;
    CHECK(bounding(a.lights[i].shape, ca) == bounding(b.lights[i].shape, cb));
    CHECK(ca.x == cb.x);
    CHECK(ca.y == cb.y);
  }
}
