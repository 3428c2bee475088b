// Work the plain kernel and the culling skip, held to the scalar reference and to the unculled
// path on scenes that reach each skip: packets whose light one occluder covers in every lane,
// packets inside occluders, intervals empty in every lane (tile_kernel.hpp); the one-segment
// check before an occlusion proof, the O(1) umbra precheck and the adaptive rule that skips
// tile proofs where they keep failing (culling/, render/tile_setup.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/occlusion_proof.hpp"
#include "par2d/render.hpp"
#include "render/cell_lists.hpp"
#include "render/kernel_table.hpp"
#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "scattered_scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"
#include "world/world.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

RenderOptions simd_options(Isa isa, bool culling) {
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = isa;
  o.culling = culling;
  return o;
}

// Culled SIMD against the scalar reference and against unculled SIMD, for every ISA, at the
// pixels 0.05 px or more from every boundary (docs/contract.md section 5).
void check_against_scalar_and_unculled(const Scene& scene, const std::string& what) {
  Status status;
  RenderOptions scalar;
  scalar.backend = Backend::scalar;
  const RenderedImage ref = render_image(scene, scalar, status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  const double bound = 1e-4 * emission_max_sum(scene);
  const double margin = 0.05 * pixel_width(scene);
  for (Isa isa : simd_isas_here()) {
    INFO(what, " isa ", std::string(isa_name(isa)));
    const RenderedImage culled = render_image(scene, simd_options(isa, true), status);
    REQUIRE_MESSAGE(status.ok(), status.message());
    const RenderedImage unculled = render_image(scene, simd_options(isa, false), status);
    REQUIRE_MESSAGE(status.ok(), status.message());
    const Comparison vs_scalar = compare_renders(scene, ref, culled, bound, margin);
    CHECK_MESSAGE(vs_scalar.over == 0, vs_scalar.first_failure);
    CHECK(vs_scalar.checked > scene.width * scene.height / 2);
    const Comparison vs_unculled = compare_renders(scene, unculled, culled, bound, margin);
    CHECK_MESSAGE(vs_unculled.over == 0, vs_unculled.first_failure);
    const Comparison unculled_vs_scalar = compare_renders(scene, ref, unculled, bound, margin);
    CHECK_MESSAGE(unculled_vs_scalar.over == 0, unculled_vs_scalar.first_failure);
  }
}

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// Scattered shapes of every kind on a width x height image, sizes in pixels across (bounding
// radius as a fraction of the 96 px view height), kept 2 px from the lights.
RandomSceneOptions scattered_options(int width, int lights_min, int lights_max, int occluders_min, int occluders_max,
                                     double min_px, double max_px) {
  RandomSceneOptions opt;
  opt.width = width;
  opt.height = 96;
  opt.min_lights = lights_min;
  opt.max_lights = lights_max;
  opt.min_occluders = occluders_min;
  opt.max_occluders = occluders_max;
  opt.min_size = 0.5 * min_px / 96.0;
  opt.max_size = 0.5 * max_px / 96.0;
  opt.gap = 2.0 / 96.0;
  return opt;
}

test::FrameCounts stats_of(const Scene& scene, const RenderOptions& options) { return test::frame_counts(scene, options); }

}  // namespace

TEST_CASE("a light one occluder covers in whole packets, and packets inside an occluder, match scalar") {
  // A 2 px light left of a 12 px tall wall 10 px away: the wall's umbra widens to the right,
  // so whole rows of packets (8 or 16 lanes) behind it see the light covered by that one
  // occluder, while each tile also has lit pixels (the light reaches the kernel). A large
  // box holds whole packets inside it; small boxes scattered behind add intervals that are
  // empty in every lane of most packets.
  Scene scene;
  scene.width = 96;
  scene.height = 64;
  scene.view = View{0.0, 0.0, 96.0, 64.0};
  Light light;
  light.shape = Circle{{12.3, 31.7}, 2.0};
  light.color = {1.0, 0.8, 0.6};
  light.intensity = 3.0;
  scene.lights.push_back(light);
  Light second = light;
  second.shape = Polygon{{{70.1, 6.2}, {73.4, 7.9}, {71.0, 9.8}}};
  scene.lights.push_back(second);
  scene.occluders.push_back(Occluder{box(22.2, 25.1, 24.7, 38.3)});
  scene.occluders.push_back(Occluder{box(40.3, 44.2, 75.6, 61.4)});
  for (int i = 0; i < 6; ++i)
    scene.occluders.push_back(Occluder{Circle{{34.0 + 9.0 * i, 20.5 + 3.1 * (i % 3)}, 0.9}});
  REQUIRE(validate_scene(scene).ok());
  check_against_scalar_and_unculled(scene, "wall umbra");
}

namespace {

// The many-lights level's sizes, scaled down: dense small occluders hide lights in whole
// packets (one occluder or several), fail most occlusion proofs by a visible segment and
// offer many umbra tests that cannot succeed. Odd seeds keep occluders apart, even ones let
// them overlap.
void check_small_shapes(std::uint32_t first_seed, std::uint32_t last_seed) {
  for (std::uint32_t seed = first_seed; seed <= last_seed; ++seed) {
    RandomSceneOptions opt = scattered_options(128, 5, 7, 220, 220, 1.5, 5.0);
    opt.occluders_may_overlap = seed % 2 == 0;
    const Scene scene = random_scene(seed, opt);
    REQUIRE(scene.occluders.size() > 150);
    check_against_scalar_and_unculled(scene, "seed " + std::to_string(seed));
  }
}

// The many-lights "rubble" level's density (par2d_make_field --occluder-size 1.5 4
// --light-size 3 5), scaled down: ~85 % of its tile proofs fail, so after a light's first
// failures in a block the rule stops trying; the image must stay the unculled and scalar one.
void check_rubble_tile_rule(const Scene& scene) {
  REQUIRE(validate_scene(scene).ok());
  check_against_scalar_and_unculled(scene, "rubble");
  for (Isa isa : simd_isas_here()) {
    INFO("isa ", std::string(isa_name(isa)));
    RenderOptions options = simd_options(isa, true);
    options.threads = 1;
    const test::FrameCounts one = stats_of(scene, options);
    CHECK(one.tile_proofs_skipped > one.tile_proofs_tried);
    // Decided per block from its own tiles: the same counts whatever the threads.
    options.threads = 3;
    const test::FrameCounts three = stats_of(scene, options);
    CHECK(three.tile_proofs_skipped == one.tile_proofs_skipped);
    CHECK(three.tile_proofs_tried == one.tile_proofs_tried);
    CHECK(three.tile_lights == one.tile_lights);
  }
}

// A block tries its first 24 block proofs (lights in scene order), then only while at least
// 1 in 16 succeeded: on rubble almost none do. The skipped lights go to the tiles, whose
// images must stay the unculled and scalar ones.
void check_rubble_block_rule(const Scene& scene) {
  REQUIRE(validate_scene(scene).ok());
  check_against_scalar_and_unculled(scene, "rubble, 40 lights");
  for (Isa isa : simd_isas_here()) {
    INFO("isa ", std::string(isa_name(isa)));
    RenderOptions options = simd_options(isa, true);
    options.threads = 1;
    const test::FrameCounts one = stats_of(scene, options);
    INFO("block proofs tried ", one.block_proofs_tried, ", succeeded ", one.block_proofs_succeeded, ", skipped ",
         one.block_proofs_skipped);
    CHECK(one.block_proofs_skipped > 0u);
    CHECK(one.block_proofs_tried + one.block_proofs_skipped + one.block_lights_out_of_reach <= one.block_lights);
    // Decided per block from its own tries: the same counts whatever the threads.
    options.threads = 3;
    const test::FrameCounts three = stats_of(scene, options);
    CHECK(three.block_proofs_skipped == one.block_proofs_skipped);
    CHECK(three.block_proofs_tried == one.block_proofs_tried);
    CHECK(three.tile_lights == one.tile_lights);
    // Without culling no proof is tried or skipped.
    const test::FrameCounts unculled = stats_of(scene, simd_options(isa, false));
    CHECK(unculled.block_proofs_skipped == 0u);
  }
}

const bench::ScatteredSizes kRubble{1.5, 4.0, 3.0, 5.0};

}  // namespace

TEST_CASE("small occluders and small lights (1.5-4 px, 3-5 px): culled SIMD matches scalar and unculled") {
  check_small_shapes(1501, 1502);  // apart and overlapping
}

TEST_CASE("small occluders and small lights, more seeds" * par2d::test::long_tier()) { check_small_shapes(1503, 1504); }

TEST_CASE("segment_passes agrees with dense sampling of the segment, and never passes through a touch") {
  PortableRandom rng(77);
  const Scene scene = random_scene(78, [] {
    RandomSceneOptions o;
    o.width = 64;
    o.height = 64;
    o.min_occluders = 40;
    o.max_occluders = 40;
    return o;
  }());
  const auto prepared = detail::prepare_scene(scene);
  int passes = 0, blocked = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Vec2 a{rng.uniform(-8.0, 72.0), rng.uniform(-8.0, 72.0)};
    const std::uint32_t k = static_cast<std::uint32_t>(rng.integer(0, static_cast<int>(prepared.occluders.size()) - 1));
    // Aimed near the occluder, so that hits and near misses are both common.
    const detail::ConvexShape& s = prepared.occluders[k];
    const double reach = std::max(s.bounds_max.x - s.bounds_min.x, s.bounds_max.y - s.bounds_min.y);
    const Vec2 b{s.centroid.x + rng.uniform(-reach, reach), s.centroid.y + rng.uniform(-reach, reach)};
    const bool pass = detail::segment_passes(a, b, prepared.occluders, &k, 1);
    // Dense samples: a sample inside the shape means the segment meets it.
    bool hit = false;
    for (int i = 0; i <= 2000 && !hit; ++i) {
      const double t = i / 2000.0;
      hit = detail::contains(prepared.occluders[k], {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
    if (hit) CHECK_MESSAGE(!pass, "trial ", trial);
    pass ? ++passes : ++blocked;
  }
  CHECK(passes > 100);
  CHECK(blocked > 100);
  // Touching counts as meeting: a segment ending on a box's corner, running along its edge,
  // tangent to a circle.
  const std::vector<detail::ConvexShape> shapes{detail::make_convex_shape(Shape{box(0.0, 0.0, 2.0, 2.0)}),
                                                detail::make_convex_shape(Shape{Circle{{10.0, 0.0}, 1.0}})};
  const std::uint32_t square = 0, circle = 1;
  CHECK(!detail::segment_passes({2.0, 2.0}, {5.0, 7.0}, shapes, &square, 1));
  CHECK(!detail::segment_passes({-1.0, 2.0}, {3.0, 2.0}, shapes, &square, 1));
  CHECK(detail::segment_passes({-1.0, 2.001}, {3.0, 2.001}, shapes, &square, 1));
  CHECK(!detail::segment_passes({8.0, 1.0}, {12.0, 1.0}, shapes, &circle, 1));
  CHECK(detail::segment_passes({8.0, 1.001}, {12.0, 1.001}, shapes, &circle, 1));
}

TEST_CASE("rubble (1.5-4 px occluders, 3-5 px lights): the adaptive rule skips failing tile proofs, same image") {
  check_rubble_tile_rule(bench::scattered_scene(8, 60, 77, 224, 136, kRubble));
}

TEST_CASE("rubble at 320 x 192: the adaptive tile rule, same image" * par2d::test::long_tier()) {
  check_rubble_tile_rule(bench::scattered_scene(8, 120, 77, 320, 192, kRubble));
}

TEST_CASE("rubble with many lights per block: the adaptive rule skips failing block proofs, same image") {
  check_rubble_block_rule(bench::scattered_scene(40, 150, 77, 160, 128, kRubble));
}

TEST_CASE("rubble with many lights per block at 256 x 192: the adaptive block rule, same image" * par2d::test::long_tier()) {
  check_rubble_block_rule(bench::scattered_scene(40, 360, 77, 256, 192, kRubble));
}

TEST_CASE("the benchmark's level (4-12 px occluders), where most tile proofs hide the light: the rule keeps them") {
  // Tile proofs pay here (~15 % of frame time on the 256-light level): a block whose tile
  // proofs succeed at least 1 in 2 times keeps trying them for every light. Past a block's
  // first 16 tries a light's first try must pass that gate too, which skips some where a
  // block's proofs mostly fail (1,275 skipped against 7,493 tried here, and 0.8 % fewer
  // instructions for the frame than with the first tries always made): most stay.
  const Scene scene = bench::scattered_scene(24, 388, 20240611, 512, 384);
  RenderOptions options = simd_options(simd_isas_here().back(), true);
  const test::FrameCounts stats = stats_of(scene, options);
  CHECK(stats.tile_proofs_succeeded * 2 > stats.tile_proofs_tried);
  CHECK(stats.tile_proofs_skipped * 4 < stats.tile_proofs_tried);
  // Its block proofs pay too (about 1 in 5 succeed, above the rule's 1 in 16): the block rule
  // skips only in the few blocks where they keep failing.
  INFO("block proofs tried ", stats.block_proofs_tried, ", succeeded ", stats.block_proofs_succeeded, ", skipped ",
       stats.block_proofs_skipped);
  CHECK(stats.block_proofs_succeeded * 6 > stats.block_proofs_tried);
  CHECK(stats.block_proofs_skipped * 5 < stats.block_proofs_tried + stats.block_proofs_skipped);
}

TEST_CASE("pairs whose occluder misses the hull of the tile and the light are dropped: culled SIMD matches scalar and unculled") {
  // Mid-sized scattered shapes of every kind: many occluders stand between a light and a
  // tile's direction to it (their pair survives the separating-line test) yet off every
  // segment from the tile to the light, so the tile drops them before the kernel.
  for (std::uint32_t seed = 2101; seed <= 2103; ++seed) {
    const RandomSceneOptions opt = scattered_options(160, 3, 5, 40, 60, 3.0, 10.0);
    const Scene scene = random_scene(seed, opt);
    RenderOptions options = simd_options(detect_isa(), true);
    const test::FrameCounts stats = stats_of(scene, options);
    CHECK(stats.tile_pairs_outside_hull > 0u);
    check_against_scalar_and_unculled(scene, "seed " + std::to_string(seed));
  }
}

TEST_CASE("one tile: a small disc 0.1 px outside the exact hull of the tile and a disc light is dropped, 0.1 px inside it is kept") {
  // The tile is the view [0, 16] x [16, 32]; the light's disc at (26, 2), r 2. The hull's
  // lower bridge runs from the corner (16, 32) along its tangent to the light; the occluder
  // (r 0.5) sits beside that bridge, 0.1 px outside or inside it, and well inside the box
  // hull of the tile and the light's bounding box (which keeps it as a candidate either way).
  for (const bool outside : {true, false}) {
    INFO("outside ", outside);
    Scene scene;
    scene.width = 16;
    scene.height = 16;
    scene.view = View{0.0, 16.0, 16.0, 32.0};
    Light light;
    light.shape = Circle{{26.0, 2.0}, 2.0};
    light.color = {1.0, 0.9, 0.7};
    light.intensity = 2.0;
    scene.lights.push_back(light);
    const Vec2 center = outside ? Vec2{25.5703, 9.9825} : Vec2{25.3850, 9.9074};
    scene.occluders.push_back(Occluder{Circle{center, 0.5}});
    REQUIRE(validate_scene(scene).ok());
    const test::FrameCounts stats = stats_of(scene, simd_options(detect_isa(), true));
    CHECK(stats.tiles == 1u);
    CHECK(stats.tile_lights == 1u);
    CHECK(stats.tile_pairs_outside_hull == (outside ? 1u : 0u));
    CHECK(stats.tile_pairs == (outside ? 0u : 1u));
    check_against_scalar_and_unculled(scene, outside ? "outside" : "inside");
  }
}

TEST_CASE("a light with one occluder in front: each way the occluder's arc can cut the light's matches scalar and unculled") {
  // A light of radius 6 and a smaller occluder 16 px to its right: beside the occluder its
  // arc cuts one end of the light's (either end, on either side of the axis), in the umbra
  // it holds the whole light, and past the umbra's tip (x = 44 for the discs) it lies inside
  // the light's arc, leaving a visible part on both sides of it; off the penumbra it cuts
  // nothing, and left of the separating line it is not in front. The kernel computes these
  // single-pair lights shape-major from the shapes' tangent directions
  // (tile_single_pair_lights); every kind of light and occluder takes that path here.
  const std::vector<Shape> lights{Circle{{20.0, 48.3}, 6.0},
                                  Polygon{{{14.1, 42.2}, {26.0, 42.6}, {25.7, 54.1}, {14.4, 53.8}}}};
  const std::vector<Shape> occluders{Circle{{36.2, 47.9}, 2.0},
                                     Polygon{{{34.3, 46.1}, {38.0, 46.4}, {37.9, 49.7}, {34.1, 50.2}}},
                                     Segment{{35.8, 45.6}, {36.4, 50.3}}};
  for (std::size_t l = 0; l < lights.size(); ++l) {
    for (std::size_t o = 0; o < occluders.size(); ++o) {
      Scene scene;
      scene.width = 96;
      scene.height = 96;
      scene.view = View{0.0, 0.0, 96.0, 96.0};
      Light light;
      light.shape = lights[l];
      light.color = {1.0, 0.85, 0.7};
      light.intensity = 2.5;
      scene.lights.push_back(light);
      scene.occluders.push_back(Occluder{occluders[o]});
      REQUIRE(validate_scene(scene).ok());
      const test::FrameCounts stats = stats_of(scene, simd_options(detect_isa(), true));
      CHECK(stats.tile_pairs > 0u);
      CHECK(stats.tile_pairs <= stats.tile_lights);  // one pair at most per light and tile
      check_against_scalar_and_unculled(scene, "light " + std::to_string(l) + " occluder " + std::to_string(o));
    }
  }
}

TEST_CASE("every tile's kernel writes only inside the kernel_scratch_floats it is given, on every ISA") {
  // The kernels lay out their scratch themselves (arc planes, packet scratch, light indices,
  // occluder bytes); the frame driver only sizes it. A layout that outgrows the size would
  // write past the buffer: here the buffer is exactly that size, followed by guard bytes
  // that must come back untouched. Plain scenes (tiles with and without per-cell lists, the
  // shape-major passes with and without packet lights) and lighting-model scenes.
  const std::vector<std::pair<std::string, Scene>> scenes = {
      {"scattered", random_scene(2201, scattered_options(160, 3, 5, 40, 60, 3.0, 10.0))},
      {"rubble", random_scene(2202, scattered_options(128, 5, 7, 220, 220, 1.5, 5.0))},
      {"random", random_scene(2203)},
      {"model", random_scene(2204, with_every_model_term({}))},
  };
  static constexpr std::size_t kGuardBytes = 256;
  static constexpr unsigned char kGuard = 0xA5;
  for (const auto& entry : scenes) {
    // Named references, not a structured binding: C++17 lambdas cannot capture those.
    const std::string& name = entry.first;
    const Scene& scene = entry.second;
    const detail::PreparedScene prepared = detail::prepare_scene(scene);
    std::vector<detail::LightReach> reach;
    detail::LightReachScratch reach_scratch;
    for (std::size_t l = 0; l < prepared.lights.size(); ++l)
      reach.push_back(detail::compute_light_reach(prepared, l, reach_scratch));
    for (Isa isa : simd_isas_here()) {
      const detail::KernelSet* kernels = detail::kernels_for(isa);
      REQUIRE(kernels != nullptr);
      detail::TileSetupScratch setup;
      detail::CellListScratch cells;
      detail::TileWork work;
      detail::TileResult result;
      std::size_t tiles = 0, packet_lights = 0, cell_tiles = 0, overruns = 0;
      std::pair<int, int> first_overrun{-1, -1};
      for (int by = 0; by < scene.height; by += detail::kBlockSize) {
        for (int bx = 0; bx < scene.width; bx += detail::kBlockSize) {
          const detail::TileRect block{bx, by, std::min(bx + detail::kBlockSize, scene.width),
                                       std::min(by + detail::kBlockSize, scene.height)};
          detail::gather_block_candidates(prepared, block, &reach, setup);
          detail::for_each_cell(block, detail::kTileSize, [&](const detail::TileRect& tile) {
            detail::build_tile_work(prepared, tile, 1, true, work, setup, true);
            detail::build_cell_lists(prepared, tile, kernels->lanes, setup, work, cells);
            for (const detail::KernelLight& light : work.lights) packet_lights += light.pair_count > 1 ? 1 : 0;
            cell_tiles += work.cells.empty() ? 0 : 1;
            const std::size_t floats = detail::kernel_scratch_floats(work, kernels->lanes);
            // 64-byte aligned start, `floats` floats, then the guard.
            std::vector<unsigned char> buffer(64 + floats * sizeof(float) + kGuardBytes, kGuard);
            const auto address = reinterpret_cast<std::uintptr_t>(buffer.data());
            unsigned char* start = buffer.data() + (64 - address % 64) % 64;
            kernels->render_tile(work, reinterpret_cast<float*>(start), result);
            const unsigned char* guard = start + floats * sizeof(float);
            const bool untouched =
                std::all_of(guard, guard + kGuardBytes, [](unsigned char b) { return b == kGuard; });
            if (!untouched && overruns++ == 0) first_overrun = {tile.x0, tile.y0};
            ++tiles;
          });
        }
      }
      INFO(name, " ", std::string(isa_name(isa)));
      CHECK_MESSAGE(overruns == 0u, "tiles whose kernel wrote past its scratch: ", overruns, ", the first at (",
                    first_overrun.first, ", ", first_overrun.second, ")");
      CHECK(tiles > 0u);
      CHECK(packet_lights > 0u);  // lights with two or more pairs: the packet path ran
      // Tiles with per-cell lists and tiles on the shape-major path in one scene.
      if (name == "scattered") CHECK((cell_tiles > 0u && cell_tiles < tiles));
    }
  }
}
