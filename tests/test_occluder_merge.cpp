// Tilemap box merging (world/occluder_merge.hpp): which boxes join, and that the merged scene
// renders the same image.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "grid_levels.hpp"
#include "support/render_checks.hpp"
#include "world/occluder_merge.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

Occluder box(double x0, double y0, double x1, double y1) {
  return Occluder{Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
}

Scene merged_scene(const Scene& scene) {
  Scene out = scene;
  out.occluders.clear();
  for (const detail::MergedOccluder& m : detail::merge_tilemap_boxes(scene.occluders)) out.occluders.push_back(m.occluder);
  return out;
}

}  // namespace

TEST_CASE("tilemap merging: a row of touching equal boxes becomes one box, then columns of the rest") {
  std::vector<Occluder> in{box(0, 0, 16, 16), box(16, 0, 32, 16), box(32, 0, 48, 16),  // a row of three
                           box(0, 16, 16, 32), box(0, 32, 16, 48),                       // a column under the first
                           box(64, 0, 80, 16), box(81, 0, 96, 16)};                      // a gap: not joined
  const auto out = detail::merge_tilemap_boxes(in);
  REQUIRE(out.size() == 4);
  CHECK(out[0].sources == std::vector<std::size_t>{0, 1, 2});
  CHECK(out[1].sources == std::vector<std::size_t>{3, 4});
  CHECK(out[2].sources == std::vector<std::size_t>{5});
  CHECK(out[3].sources == std::vector<std::size_t>{6});
  const auto& row = std::get<Polygon>(out[0].occluder.shape).vertices;
  CHECK(row[0].x == 0.0);
  CHECK(row[2].x == 48.0);
  CHECK(row[2].y == 16.0);
  const auto& column = std::get<Polygon>(out[1].occluder.shape).vertices;
  CHECK(column[0].y == 16.0);
  CHECK(column[2].y == 48.0);
}

TEST_CASE("tilemap merging: different properties, reflecting walls and other shapes stay apart") {
  Occluder glass = box(16, 0, 32, 16);
  glass.transmittance = {0.5, 0.5, 0.5};
  Occluder white = box(48, 0, 64, 16);
  Occluder white2 = box(64, 0, 80, 16);
  white.albedo = white2.albedo = {0.8, 0.8, 0.8};
  Occluder masked = box(96, 0, 112, 16);
  masked.mask = 2;
  std::vector<Occluder> in{box(0, 0, 16, 16), glass, white, white2, box(80, 0, 96, 16), masked,
                           Occluder{Circle{{120, 8}, 8}}, Occluder{Polygon{{{128, 0}, {144, 0}, {144, 16}, {129, 16}}}},
                           box(144, 0, 160, 16)};
  const auto out = detail::merge_tilemap_boxes(in);
  CHECK(out.size() == in.size());
}

// Why translucent and lit-interior rows stay apart: merging them would change the image. A
// light at the left end of a row of two boxes, a pixel past the right end looking along the
// row, and a pixel inside the first box.
TEST_CASE("tilemap merging: translucent and lit-interior rows stay apart, since merged they would light differently") {
  Scene scene;
  scene.width = 64;
  scene.height = 16;
  scene.view = {0, 0, 64, 16};
  scene.lights.push_back(Light{Circle{{2, 8}, 1.5}, {1, 1, 1}, 4.0});
  auto row = [](Occluder o) {
    Occluder a = o, b = o;
    a.shape = box(8, 6, 24, 10).shape;
    b.shape = box(24, 6, 40, 10).shape;
    return std::vector<Occluder>{a, b};
  };
  Occluder glass = box(0, 0, 1, 1);
  glass.transmittance = {0.5, 0.5, 0.5};
  Occluder lit = box(0, 0, 1, 1);
  lit.interior = Interior::lit;
  Occluder clear_red = box(0, 0, 1, 1);
  clear_red.transmittance = {1, 0, 0};  // channels of 0 and 1: merging changes nothing
  const Occluder kinds[] = {glass, lit, clear_red};
  for (int i = 0; i < 3; ++i) {
    const Occluder& kind = kinds[i];
    Scene apart = scene;
    apart.occluders = row(kind);
    Scene joined = scene;
    joined.occluders = {kind};
    joined.occluders[0].shape = box(8, 6, 40, 10).shape;
    const RenderedImage a = render_or_fail(apart, options_for(Backend::scalar, Isa::scalar));
    const RenderedImage j = render_or_fail(joined, options_for(Backend::scalar, Isa::scalar));
    const bool same = compare_renders(apart, a, j, 1e-6 * emission_max_sum(apart), 0.05).over == 0;
    const bool merges = detail::merge_tilemap_boxes(apart.occluders).size() == 1;
    CAPTURE(kind.transmittance[0]);
    CAPTURE(static_cast<int>(kind.interior));
    CHECK(merges == same);
    CHECK(merges == (i == 2));
  }
}

TEST_CASE("tilemap merging: the grid's tilemaps merge into the merged levels' boxes, and render the same image") {
  for (const double tile : {16.0, 32.0}) {
    bench::WallLevel level;
    level.width = 128;
    level.height = 96;
    level.tile = tile;
    level.torches = 3;
    level.overlap = -2.0;
    const Scene cells = bench::wall_level(level);
    level.style = bench::WallStyle::tilemap_merged;
    const Scene runs = bench::wall_level(level);
    const auto merged = detail::merge_tilemap_boxes(cells.occluders);
    CHECK(merged.size() == runs.occluders.size());
    std::vector<std::size_t> all;
    for (const auto& m : merged) all.insert(all.end(), m.sources.begin(), m.sources.end());
    std::sort(all.begin(), all.end());
    std::vector<std::size_t> expected(cells.occluders.size());
    std::iota(expected.begin(), expected.end(), std::size_t{0});
    CHECK(all == expected);
    // The same occluded set: the scalar reference gives the same image to rounding, and the
    // SIMD path's merged image stays within the contract's bound of the unmerged reference.
    const Scene m = merged_scene(cells);
    const RenderedImage ref = render_or_fail(cells, options_for(Backend::scalar, Isa::scalar));
    const RenderedImage ref_merged = render_or_fail(m, options_for(Backend::scalar, Isa::scalar));
    const Comparison c = compare_renders(cells, ref, ref_merged, 1e-6 * emission_max_sum(cells), 0.05 * pixel_width(cells));
    CHECK_MESSAGE(c.over == 0, c.first_failure);
    check_simd_against_scalar(
        m, ref, "merged tile " + std::to_string(tile), [&](Vec2 p) { return near_boundary(cells, p, 0.05 * pixel_width(cells)); },
        cells.width * cells.height / 2);
  }
}
