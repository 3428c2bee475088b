// Lights poking into walls: the pairs, proofs and separating lines use the part of
// the light outside the wall it sits in (culling/visible_light.hpp, render/pair_setup.cpp).
// Levels as 2D games build them, against the scalar reference on every ISA, culling on and off.
#include <doctest/doctest.h>

#include <string>

#include "grid_levels.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

void check_scene(const Scene& scene, const std::string& what) {
  REQUIRE(validate_scene(scene).ok());
  REQUIRE(!scene.lights.empty());
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar, Isa::scalar));
  const double exempt = 0.05 * pixel_width(scene);
  check_simd_against_scalar(
      scene, ref, what, [&](Vec2 p) { return near_boundary(scene, p, exempt); }, scene.width * scene.height / 2);
}

void check_level(const bench::WallLevel& level, const std::string& what) { check_scene(bench::wall_level(level), what); }

bench::WallLevel small_level(std::uint32_t seed) {
  bench::WallLevel level;
  level.width = 112;
  level.height = 80;
  level.tile = 16;
  level.torches = 3;
  level.seed = seed;
  return level;
}

}  // namespace

TEST_CASE("torches poking into tilemap walls match the scalar reference (every ISA, culling on and off)") {
  struct Case {
    double radius, overlap;
    bench::WallStyle style;
    double range;
  };
  const Case cases[] = {{5.0, 1.0, bench::WallStyle::tilemap, 0.0},
                        {6.0, 3.0, bench::WallStyle::free_form, 0.0},
                        {2.5, 0.1, bench::WallStyle::tilemap, 40.0}};
  std::uint32_t seed = 3901;
  for (const Case& c : cases) {
    bench::WallLevel level = small_level(seed++);
    level.torch_radius = c.radius;
    level.overlap = c.overlap;
    level.style = c.style;
    if (c.range > 0.0) level.range = c.range;
    check_level(level, "seed " + std::to_string(level.seed) + " radius " + std::to_string(c.radius) + " overlap " +
                           std::to_string(c.overlap));
  }
}

TEST_CASE("torches poking into walls over the grid's tile sizes, depths and styles match the scalar reference" *
          par2d::test::long_tier()) {
  std::uint32_t seed = 3950;
  for (const double tile : {16.0, 24.0, 32.0}) {
    for (const double overlap : {0.1, 1.0, 2.5}) {
      for (const bench::WallStyle style : {bench::WallStyle::tilemap, bench::WallStyle::tilemap_merged,
                                           bench::WallStyle::free_form}) {
        bench::WallLevel level = small_level(seed++);
        level.width = 160;
        level.height = 96;
        level.tile = tile;
        level.overlap = overlap;
        level.style = style;
        level.torches = 4;
        check_level(level, "seed " + std::to_string(level.seed));
      }
    }
  }
}

// Tiles wholly inside a wall skip the lights the wall shadows (render/tile_setup.cpp): only an
// opaque wall, dark inside, acting on the light. Walls that let light through or in, or that
// do not act on the torches, must leave those tiles their lights.
TEST_CASE("tiles inside walls: only opaque, dark walls acting on a light drop it (every ISA, culling on and off)") {
  const Scene plain = bench::wall_level(small_level(3950));
  for (int variant = 0; variant < 4; ++variant) {
    Scene scene = plain;
    for (std::size_t k = 0; k < scene.occluders.size(); ++k) {
      Occluder& o = scene.occluders[k];
      if (k % 2 != 0) continue;  // every other wall box changes: mixed rows
      if (variant == 1) o.transmittance = {0.5, 0.25, 0.0};
      if (variant == 2) o.interior = Interior::lit;
      if (variant == 3) o.mask = 2;  // the torches keep the default mask (all bits): still acts
    }
    if (variant == 3)
      for (Light& l : scene.lights) l.mask = 1;  // ... now it does not act on them
    check_scene(scene, "variant " + std::to_string(variant));
  }
}
