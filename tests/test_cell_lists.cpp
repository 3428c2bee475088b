// Per-cell light lists (render/cell_lists.cpp): a cell keeps only the pairs whose occluder can
// stand between it and the light, and the image stays the unculled path's and the scalar
// reference's.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <string>

#include "par2d/render.hpp"
#include "render/cell_lists.hpp"
#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "culling/light_reach.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"
#include "world/world.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

// Culled SIMD (cells) against unculled SIMD (no cells) and the scalar reference, every ISA,
// at pixels 0.05 px or more from every boundary (docs/contract.md section 5).
void check_cells_against_unculled(const Scene& scene, int spp, const std::string& what) {
  RenderOptions scalar = options_for(Backend::scalar);
  scalar.spp = spp;
  const RenderedImage ref = render_or_fail(scene, scalar);
  const double bound = 1e-4 * emission_max_sum(scene);
  const double margin = 0.05 * pixel_width(scene);
  for (Isa isa : simd_isas_here()) {
    INFO(what, " isa ", std::string(isa_name(isa)), " spp ", spp);
    RenderOptions culled = options_for(Backend::simd, isa, true);
    culled.spp = spp;
    RenderOptions unculled = options_for(Backend::simd, isa, false);
    unculled.spp = spp;
    const RenderedImage with_cells = render_or_fail(scene, culled);
    const RenderedImage without = render_or_fail(scene, unculled);
    const Comparison vs_unculled = compare_renders(scene, without, with_cells, bound, margin);
    CHECK_MESSAGE(vs_unculled.over == 0, vs_unculled.first_failure);
    CHECK(vs_unculled.checked > scene.width * scene.height / 2);
    const Comparison vs_scalar = compare_renders(scene, ref, with_cells, bound, margin);
    CHECK_MESSAGE(vs_scalar.over == 0, vs_scalar.first_failure);
  }
}

Scene rubble_scene(std::uint32_t seed, std::optional<View> view, RandomSceneOptions opt = {}) {
  opt.width = 96;
  opt.height = 80;
  opt.view = view;
  opt.min_lights = 6;
  opt.max_lights = 8;
  opt.min_occluders = 160;
  opt.max_occluders = 160;
  opt.min_size = 0.75 / 80.0;  // bounding radius in view sizes: 1.5 px across ...
  opt.max_size = 2.5 / 80.0;   // ... to 5 px across
  opt.gap = 2.0 / 80.0;
  opt.occluders_may_overlap = seed % 2 == 0;
  return random_scene(seed, opt);
}

// Over the tiles of `scene` (each its own block, culled as in production, lists for `lanes`
// lanes) that get cells of their own (more than the one whole-tile cell of a game-model
// tile): how many there are, and the most occluders one of them takes to the kernel.
struct CellTiles {
  int count = 0;
  std::size_t most_occluders = 0;
};

CellTiles cell_tiles(const Scene& scene, int lanes) {
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  detail::TileSetupScratch setup;
  detail::CellListScratch cells;
  detail::TileWork work;
  CellTiles found;
  for (int y = 0; y < scene.height; y += detail::kTileSize) {
    for (int x = 0; x < scene.width; x += detail::kTileSize) {
      const detail::TileRect tile{x, y, x + detail::kTileSize, y + detail::kTileSize};
      detail::gather_block_candidates(prepared, tile, nullptr, setup);
      detail::build_tile_work(prepared, tile, 1, true, work, setup, true);
      detail::build_cell_lists(prepared, tile, lanes, setup, work, cells);
      if (work.cells.size() <= 1) continue;
      ++found.count;
      found.most_occluders = std::max(found.most_occluders, work.occluders.size());
    }
  }
  return found;
}

int tiles_with_cells(const Scene& scene, int lanes) { return cell_tiles(scene, lanes).count; }

}  // namespace

TEST_CASE("cell lists: a pair reaches only the cells inside its shadow cone") {
  // A 2 px light at (8, 16) and a 1.5 px disc 12 px to its right cast a shadow cone along
  // y = 16 that widens by about 0.31 px per px. Over the tile x 32..48, y 0..16 it covers the
  // cells of the bottom row and the top right one (x 40..48, down to y = 5.9 at x = 48), not
  // the top left one (x 32..40, y 0..8; the cone starts at y = 8.3 at x = 40). Fifteen 0.5 px
  // discs further along the axis (x 23..30) cast narrower cones that stay below y = 10.8 over
  // the tile: in the bottom cells only (and the tile has enough pairs for cells).
  Scene scene;
  scene.width = 64;
  scene.height = 32;
  scene.view = View{0.0, 0.0, 64.0, 32.0};
  Light light;
  light.shape = Circle{{8.0, 16.0}, 2.0};
  scene.lights.push_back(light);
  scene.occluders.push_back(Occluder{Circle{{20.0, 16.0}, 1.5}});
  for (int j = 0; j < 15; ++j) scene.occluders.push_back(Occluder{Circle{{23.0 + 0.5 * j, 16.0}, 0.5}});
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  detail::TileSetupScratch setup;
  detail::CellListScratch cells;
  detail::TileWork work;
  const detail::TileRect tile{32, 0, 48, 16};
  detail::gather_block_candidates(prepared, tile, nullptr, setup);
  detail::build_tile_work(prepared, tile, 1, true, work, setup);
  REQUIRE(work.lights.size() == 1);
  REQUIRE(work.pairs.size() == 16);
  detail::build_cell_lists(prepared, tile, 8, setup, work, cells);
  REQUIRE(work.cell_width == 8);
  REQUIRE(work.cell_height == 8);
  REQUIRE(work.cells.size() == 4);
  auto pairs_in = [&](int cell) {
    const detail::KernelCell& c = work.cells[static_cast<std::size_t>(cell)];
    REQUIRE(c.light_count == 1);  // the light stays: only its pairs are culled
    return work.cell_lights[c.first_light].pair_count;
  };
  auto arcs_in = [&](int cell) { return work.cells[static_cast<std::size_t>(cell)].occluder_count; };
  CHECK(pairs_in(0) == 0);
  CHECK(pairs_in(1) == 1);
  CHECK(pairs_in(2) == 16);
  CHECK(pairs_in(3) == 16);
  CHECK(arcs_in(0) == 0);
  CHECK(arcs_in(1) == 1);
  CHECK(arcs_in(3) == 16);
  // The unculled path keeps the tile's lists.
  detail::build_tile_work(prepared, tile, 1, false, work, setup);
  detail::build_cell_lists(prepared, tile, 8, setup, work, cells);
  CHECK(work.cells.empty());
  // 16 lanes: cells are tile rows of 16 x 4 pixels; the big disc's cone misses the top one
  // (y 0..4) and reaches the next, the small discs' reach the bottom one only among the top three.
  detail::build_tile_work(prepared, tile, 1, true, work, setup);
  detail::build_cell_lists(prepared, tile, 16, setup, work, cells);
  REQUIRE(work.cells.size() == 4);
  CHECK(work.cell_width == 16);
  CHECK(pairs_in(0) == 0);
  CHECK(pairs_in(1) == 1);
  CHECK(pairs_in(3) == 16);
}

TEST_CASE("cell lists: small occluders and lights (1.5-5 px), mirrored and far views, 1 and 4 spp, match unculled and scalar") {
  const Scene plain = rubble_scene(2701, std::nullopt);
  REQUIRE(plain.occluders.size() > 100);
  check_cells_against_unculled(plain, 1, "seed 2701");
  check_cells_against_unculled(rubble_scene(2704, View{96.0, 80.0, 0.0, 0.0}), 1, "mirrored");
  check_cells_against_unculled(rubble_scene(2705, View{1e5, 1e5, 1e5 + 96.0, 1e5 + 80.0}), 1, "far");
  check_cells_against_unculled(rubble_scene(2706, std::nullopt), 4, "4 spp");
}

TEST_CASE("cell lists: small occluders and lights, more seeds" * par2d::test::long_tier()) {
  for (std::uint32_t seed = 2702; seed <= 2703; ++seed) {
    const Scene plain = rubble_scene(seed, std::nullopt);
    REQUIRE(plain.occluders.size() > 100);
    check_cells_against_unculled(plain, 1, "seed " + std::to_string(seed));
  }
}

TEST_CASE("cell lists: an image whose size is no multiple of the tile size (cells wholly past its edge) matches unculled and scalar") {
  // 84 x 74 pixels: the last tile column keeps 4 columns and the last tile row 10 rows, so
  // that column's right-hand 8 x 8 cells and that row's last 16 x 4 cells lie wholly in the
  // padding; the kernel leaves them dark and must still compute the cells beside them.
  Scene scene = rubble_scene(2707, std::nullopt);
  scene.width = 84;
  scene.height = 74;
  CHECK(tiles_with_cells(scene, 8) > 4);
  CHECK(tiles_with_cells(scene, 16) > 4);
  check_cells_against_unculled(scene, 1, "84 x 74");
  check_cells_against_unculled(scene, 4, "84 x 74, 4 spp");
}

TEST_CASE("cell lists: tiles with more occluders than the arc planes hold (a dense cluster) match unculled and scalar") {
  // 4,400 overlapping discs of radius 0.5 px in a cluster 2 px across, between a 16 x 16 image
  // and a lamp twice the cluster's size: every pixel sees the lamp around the cluster, so no
  // proof hides it, and every tile takes all the discs. Past kMaxArcPlaneOccluders the
  // kernel computes each packet's arcs itself (no planes of 2 KiB per occluder), culled with
  // cells and unculled without; the union stays a few intervals wide, so float rounding
  // stays far inside the bound.
  Scene scene;
  scene.width = 16;
  scene.height = 16;
  scene.view = View{0.0, 0.0, 16.0, 16.0};
  scene.lights.push_back(Light{Circle{{8.0, -14.0}, 4.0}, {1.0, 0.9, 0.8}, 1.0});
  for (int k = 0; k < 4400; ++k) {
    // A golden-angle spiral fills the cluster's disc evenly.
    const double radius = 1.5 * std::sqrt((k + 0.5) / 4400.0), angle = 2.39996322972865332 * k;
    scene.occluders.push_back(Occluder{Circle{{8.0 + radius * std::cos(angle), -6.0 + radius * std::sin(angle)}, 0.5}});
  }
  CHECK(cell_tiles(scene, 8).most_occluders > detail::kMaxArcPlaneOccluders);
  CHECK(cell_tiles(scene, 16).most_occluders > detail::kMaxArcPlaneOccluders);
  check_cells_against_unculled(scene, 1, "dense cluster");
}

namespace {

void check_model_cells(std::uint32_t first_seed, std::uint32_t last_seed) {
  for (std::uint32_t seed = first_seed; seed <= last_seed; ++seed) {
    const Scene scene = rubble_scene(seed, std::nullopt, with_every_model_term({}));
    REQUIRE(scene.directional_lights.size() == 2);
    REQUIRE(scene.normal_map.has_value());
    CHECK(tiles_with_cells(scene, 8) > 10);
    check_cells_against_unculled(scene, 1, "every term, seed " + std::to_string(seed));
  }
}

}  // namespace

TEST_CASE("cell lists: game-model scenes with every term on small occluders match unculled and scalar") {
  // Ranges, cones, masks, translucent and lit-interior occluders, ambient, a normal map and two
  // directional lights (whose pairs keep every cell: a light at infinity has no shadow cone)
  // over rubble, so the model kernel runs from cells in most tiles.
  check_model_cells(2711, 2712);
  check_cells_against_unculled(rubble_scene(2715, View{96.0, 80.0, 0.0, 0.0}, with_every_model_term({})), 1,
                               "every term, mirrored");
  check_cells_against_unculled(rubble_scene(2716, std::nullopt, with_every_model_term({})), 4, "every term, 4 spp");
}

TEST_CASE("cell lists: game-model scenes with every term, more seeds" * par2d::test::long_tier()) {
  check_model_cells(2713, 2714);
}

namespace {

// Two columns of 2 px squares, one every 3 px, the second 1.5 px behind the first and offset
// by half a period: a ray through a gap of the first meets a square of the second unless it
// climbs more than 0.5 px over the 1.5 px between them. A lamp at (6, 48) shines at it; a
// second lamp above the fence lights the rest.
Scene staggered_fence() {
  Scene scene;
  scene.width = 128;
  scene.height = 96;
  scene.view = View{0.0, 0.0, 128.0, 96.0};
  scene.lights.push_back(Light{Circle{{6.0, 48.0}, 4.0}, {1.0, 0.9, 0.8}, 1.0});
  scene.lights.push_back(Light{Polygon{{{80.0, -8.0}, {86.0, -8.0}, {86.0, -3.0}, {80.0, -3.0}}}, {0.3, 0.5, 1.0}, 0.5});
  for (int column = 0; column < 2; ++column) {
    const double x = 20.0 + 3.5 * column;
    for (double y = -8.0 + 1.5 * column; y < 104.0; y += 3.0)
      scene.occluders.push_back(Occluder{Polygon{{{x, y}, {x + 2.0, y}, {x + 2.0, y + 2.0}, {x, y + 2.0}}}});
  }
  return scene;
}

}  // namespace

TEST_CASE("cell lists: lights hidden only by several small occluders together (a staggered fence) match unculled and scalar") {
  // Behind the fence the lamp is hidden by two or three squares together where the rays to
  // it are shallow and seen through the gaps where they are steeper, so the kernel's blocked
  // prefix (extended by each interval that starts inside it, the candidates ordered by angle
  // per block) closes the cover in some lanes and must stop at a gap in others: an error of
  // 0.02 rad in that test moved pixels by 15 times the bound. The penumbra's tiles get cells
  // of their own.
  Scene scene = staggered_fence();
  REQUIRE(scene.occluders.size() > 70);
  CHECK(tiles_with_cells(scene, 8) > 0);
  CHECK(tiles_with_cells(scene, 16) > 0);
  check_cells_against_unculled(scene, 1, "fence");
  check_cells_against_unculled(scene, 4, "fence, 4 spp");
  // The same with the view mirrored: the tiles and packets cross the fence the other way.
  scene.view = View{128.0, 96.0, 0.0, 0.0};
  check_cells_against_unculled(scene, 1, "fence, mirrored");
}

TEST_CASE("block candidates: 16 or more for a light come ordered by direction from the block, counter-clockwise from the light's") {
  // The kernel's blocked prefix closes a cover made of several occluders only when their
  // intervals arrive in the order of their starts, so the order's direction matters: the
  // reverse order rendered the same images and cost more (docs/performance.md, "Covers made of several
  // occluders"). The block (0, 0)-(64, 64) holds the lamp and 42 squares of the fence.
  const Scene scene = staggered_fence();
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  std::vector<detail::LightReach> reach;
  detail::LightReachScratch reach_scratch;
  for (std::size_t l = 0; l < prepared.lights.size(); ++l)
    reach.push_back(detail::compute_light_reach(prepared, l, reach_scratch));
  detail::TileSetupScratch setup;
  const detail::TileRect block{0, 0, 64, 64};
  detail::gather_block_candidates(prepared, block, &reach, setup);
  const std::vector<std::uint32_t>& ids = setup.block_candidates[0];
  REQUIRE(ids.size() >= 16);
  // Every occluder whose box meets the block is there, once.
  std::vector<std::uint32_t> sorted_ids = ids;
  std::sort(sorted_ids.begin(), sorted_ids.end());
  CHECK(std::adjacent_find(sorted_ids.begin(), sorted_ids.end()) == sorted_ids.end());
  // The block's corners in the world (the view maps pixel rows downwards).
  const Vec2 a = detail::sample_position(prepared, 0, 0, 0.0, 0.0), b = detail::sample_position(prepared, 64, 64, 0.0, 0.0);
  const double min_x = std::min(a.x, b.x), max_x = std::max(a.x, b.x), min_y = std::min(a.y, b.y), max_y = std::max(a.y, b.y);
  std::size_t meeting = 0;
  for (const detail::ConvexShape& o : prepared.occluders)
    meeting += o.bounds_max.x >= min_x && o.bounds_min.x <= max_x && o.bounds_max.y >= min_y && o.bounds_min.y <= max_y;
  CHECK(ids.size() == meeting);
  // Angles from the block's centre, measured counter-clockwise from the lamp's direction
  // (atan2 here, the setup's own stand-in there), never decrease along the list.
  const Vec2 center{0.5 * (min_x + max_x), 0.5 * (min_y + max_y)};
  const Vec2 to_light = detail::operator-(prepared.lights[0].shape.centroid, center);
  double previous = -detail::kPi;
  int increases = 0;
  for (const std::uint32_t k : ids) {
    const Vec2 to_occluder = detail::operator-(prepared.occluders[k].centroid, center);
    const double angle = std::atan2(detail::cross(to_light, to_occluder), detail::dot(to_light, to_occluder));
    CHECK(angle >= previous);
    increases += angle > previous;
    previous = angle;
  }
  CHECK(increases > 30);  // the list is not one long tie
}
