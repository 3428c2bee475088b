// Lights that overlap or touch occluders on the SIMD path: against the scalar reference for
// every ISA this CPU runs (each forced in turn), and the scalar reference against ray casting.
//
// Such a pair has no separating line; the kernel cuts the occluder's arc at the directions of
// the points where the two boundaries meet and decides each piece by a depth test
// (simd/tile_work.hpp, general pairs). These scenes put that path under every shape kind and
// contact: half inside, containing, contained, touching at a vertex, along an edge, tangent.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "raycast/raycast_renderer.hpp"
#include "world/world.hpp"
#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "support/random_scenes.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

// The contract's SIMD bound: |E_simd - E_scalar| <= 1e-4 e_max at pixels farther than 0.05 pixel
// widths from every boundary; for every ISA, culling on and off.
void check_simd_matches_scalar(const Scene& scene, const std::string& what) {
  REQUIRE(validate_scene(scene).ok());
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  const double bound = 1e-4 * emission_max_sum(scene);
  const double exempt = 0.05 * pixel_width(scene);
  for (Isa isa : simd_isas_here()) {
    for (bool culling : {true, false}) {
      const RenderedImage got = render_or_fail(scene, options_for(Backend::simd, isa, culling));
      int checked = 0, over = 0;
      double worst = 0.0;
      std::string first;
      for (int j = 0; j < scene.height; ++j) {
        for (int i = 0; i < scene.width; ++i) {
          if (near_boundary(scene, pixel_center(scene, i, j), exempt)) continue;
          ++checked;
          for (int c = 0; c < 3; ++c) {
            const double err = std::abs(static_cast<double>(ref.at(i, j, c)) - got.at(i, j, c));
            worst = std::max(worst, err);
            if (!(err <= bound) && over++ == 0) {
              std::ostringstream s;
              s << "pixel (" << i << ", " << j << ") channel " << c << ": scalar " << ref.at(i, j, c) << ", simd "
                << got.at(i, j, c);
              first = s.str();
            }
          }
        }
      }
      INFO(what << " isa=" << isa_name(isa) << " culling=" << culling << " checked=" << checked
                << " worst=" << worst << " bound=" << bound);
      CHECK_MESSAGE(over == 0, first);
      CHECK(checked > scene.width * scene.height / 2);
    }
  }
}

// The ray caster's stratification bound (tests/test_raycast.cpp explains it): every
// visibility boundary of a light costs at most e_L / rays; an overlapping pair adds its
// boundary meeting points, `extra_boundaries` per light here (counted by the caller).
void check_scalar_matches_raycast(const Scene& scene, double extra_boundaries, const std::string& what) {
  constexpr int kRays = 4096;
  const RenderedImage image = render_or_fail(scene, options_for(Backend::scalar));
  const detail::RaycastRenderer caster(scene);
  const double skip = 1e-6 * pixel_width(scene);
  double worst_ratio = 0.0;
  std::string where;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      if (near_boundary(scene, p, skip)) continue;
      const Rgb ray = caster.irradiance(p, kRays, 0.5);
      for (int c = 0; c < 3; ++c) {
        double bound = 1e-6 * emission_max_sum(scene);
        for (const Light& l : scene.lights)
          bound += l.intensity * l.color[c] * (2.0 + 2.0 * static_cast<double>(scene.occluders.size()) + extra_boundaries) / kRays;
        const double ratio = std::abs(image.at(i, j, c) - ray[c]) / bound;
        if (ratio > worst_ratio) {
          worst_ratio = ratio;
          std::ostringstream s;
          s << "pixel (" << i << ", " << j << ") channel " << c << ": scalar " << image.at(i, j, c) << ", ray cast "
            << ray[c];
          where = s.str();
        }
      }
    }
  }
  INFO(what << " worst: " << where);
  CHECK(worst_ratio <= 1.0);
}

Scene blank(int width, int height) {
  Scene s;
  s.width = width;
  s.height = height;
  s.view = View{0.0, 0.0, static_cast<double>(width), static_cast<double>(height)};
  return s;
}

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

Light light_of(Shape shape, double intensity = 1.0) {
  Light l;
  l.shape = std::move(shape);
  l.color = {1.0, 0.7, 0.4};
  l.intensity = intensity;
  return l;
}

// A few occluders around that are disjoint from the lights, so that general pairs share
// the light's union with ordinary ones.
void add_clutter(Scene& s) {
  s.occluders.push_back(Occluder{Circle{{50.0, 10.0}, 3.0}});
  s.occluders.push_back(Occluder{Segment{{8.0, 40.0}, {20.0, 44.0}}});
}

// How many general (overlap) pairs the SIMD setup builds over all tiles, and how many of
// them carry boundary meeting points.
struct GeneralPairCount {
  int pairs = 0;
  int with_points = 0;
  int clipped_lights = 0;  // lights cut to their part outside an overlapping wall
};

GeneralPairCount count_general_pairs(const Scene& scene) {
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  detail::TileSetupScratch scratch;
  detail::TileWork work;
  GeneralPairCount count;
  for (int y = 0; y < scene.height; y += detail::kTileSize) {
    for (int x = 0; x < scene.width; x += detail::kTileSize) {
      const detail::TileRect tile{x, y, std::min(x + detail::kTileSize, scene.width),
                                  std::min(y + detail::kTileSize, scene.height)};
      detail::gather_block_candidates(prepared, tile, nullptr, scratch);
      detail::build_tile_work(prepared, tile, 1, false, work, scratch);
      for (const detail::KernelLight& l : work.lights) count.clipped_lights += l.shape.clipped;
      for (const detail::KernelPair& p : work.pairs) {
        count.pairs += p.general;
        count.with_points += p.general && p.point_count > 0;
      }
    }
  }
  return count;
}

}  // namespace

TEST_CASE("overlap fast path: a circle light half inside a wall box, a polygon light half inside a circle, a segment light through a wall") {
  Scene s = blank(64, 48);
  s.lights.push_back(light_of(Circle{{20.0, 20.0}, 4.0}, 2.0));  // center on the wall's top edge
  s.occluders.push_back(Occluder{box(10.0, 20.0, 36.0, 26.0)});
  s.lights.push_back(light_of(box(40.0, 30.0, 48.0, 36.0)));
  s.occluders.push_back(Occluder{Circle{{48.0, 36.0}, 4.5}});
  s.lights.push_back(light_of(Segment{{26.0, 14.0}, {30.0, 32.0}}, 0.5));
  add_clutter(s);
  const GeneralPairCount general = count_general_pairs(s);
  CHECK(general.with_points > 0);
  CHECK(general.clipped_lights > 0);
  check_simd_matches_scalar(s, "half inside");
  check_scalar_matches_raycast(s, 8.0, "half inside");
}

TEST_CASE("overlap fast path: a light containing an occluder is full inside itself and dark inside the occluder") {
  Scene s = blank(48, 40);
  s.lights.push_back(light_of(Circle{{24.0, 20.0}, 12.0}));
  s.occluders.push_back(Occluder{box(20.0, 17.0, 27.0, 22.0)});
  s.occluders.push_back(Occluder{Segment{{30.0, 14.0}, {32.0, 25.0}}});  // inside the light too
  check_simd_matches_scalar(s, "light contains occluders");
  check_scalar_matches_raycast(s, 0.0, "light contains occluders");
  // Pins: inside the light but outside both occluders E is the full emission.
  for (Isa isa : simd_isas_here()) {
    const RenderedImage got = render_or_fail(s, options_for(Backend::simd, isa));
    CHECK(got.at(15, 20, 0) == doctest::Approx(1.0).epsilon(1e-5));
    CHECK(got.at(23, 19, 0) == 0.0f);  // inside the box occluder
  }
}

TEST_CASE("overlap fast path: an occluder containing a light hides it everywhere") {
  Scene s = blank(40, 32);
  s.lights.push_back(light_of(Circle{{20.0, 16.0}, 3.0}, 3.0));
  s.lights.push_back(light_of(box(12.0, 12.0, 15.0, 14.0)));
  s.occluders.push_back(Occluder{box(8.0, 8.0, 30.0, 24.0)});
  s.lights.push_back(light_of(Circle{{34.0, 4.0}, 2.0}));  // a free light, so that E is not all 0
  check_simd_matches_scalar(s, "occluder contains lights");
  // Outside the big box the contained lights contribute nothing: E is the free light's alone.
  Scene free_only = s;
  free_only.lights.erase(free_only.lights.begin(), free_only.lights.begin() + 2);
  const RenderedImage expect = render_or_fail(free_only, options_for(Backend::scalar));
  for (Isa isa : simd_isas_here()) {
    const RenderedImage got = render_or_fail(s, options_for(Backend::simd, isa));
    double worst = 0.0;
    for (int j = 0; j < s.height; ++j)
      for (int i = 0; i < s.width; ++i)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(static_cast<double>(got.at(i, j, c)) - expect.at(i, j, c)));
    INFO("isa " << isa_name(isa));
    CHECK(worst <= 1e-4 * emission_max_sum(free_only));
  }
}

TEST_CASE("overlap fast path: shapes touching at a vertex, along an edge, and tangent") {
  Scene s = blank(64, 48);
  // A box light whose corner touches a wall's edge, a box light sitting on a wall (a shared
  // piece of edge), two boxes touching corner to corner, and a circle resting on a wall.
  s.lights.push_back(light_of(Polygon{{{10.0, 10.0}, {14.0, 6.0}, {18.0, 10.0}, {14.0, 14.0}}}));
  s.occluders.push_back(Occluder{box(6.0, 14.0, 24.0, 18.0)});  // the light's bottom vertex on its top edge
  s.lights.push_back(light_of(box(34.0, 8.0, 42.0, 12.0), 0.8));
  s.occluders.push_back(Occluder{box(30.0, 12.0, 50.0, 16.0)});  // shares the light's bottom edge
  s.lights.push_back(light_of(box(10.0, 30.0, 16.0, 34.0), 1.2));
  s.occluders.push_back(Occluder{box(16.0, 34.0, 22.0, 40.0)});  // corner to corner
  s.lights.push_back(light_of(Circle{{44.0, 31.0}, 3.0}, 1.5));
  s.occluders.push_back(Occluder{box(36.0, 34.0, 56.0, 38.0)});  // tangent from above
  const detail::PreparedScene prepared = detail::prepare_scene(s);
  for (const detail::PreparedLight& l : prepared.lights) REQUIRE(l.overlapping_occluders.size() == 1);
  CHECK(count_general_pairs(s).with_points > 0);
  check_simd_matches_scalar(s, "touching");
  check_scalar_matches_raycast(s, 8.0, "touching");
}

TEST_CASE("overlap fast path: 80 random scenes whose lights overlap occluders, at several views") {
  for (std::uint32_t seed = 2000; seed < 2080; ++seed) {
    RandomSceneOptions opt;
    opt.width = 48 + static_cast<int>(seed % 5) * 7;
    opt.height = 40 + static_cast<int>(seed % 3) * 9;
    opt.max_lights = 4;
    opt.max_occluders = 10;
    opt.min_size = 0.05;
    opt.max_size = 0.3;
    opt.lights_disjoint_from_occluders = false;
    if (seed % 4 == 1) opt.view = View{1e5, 1e5, 1e5 + opt.width, 1e5 + opt.height};
    if (seed % 4 == 2) opt.view = View{static_cast<double>(opt.width), 0.0, 0.0, static_cast<double>(opt.height)};
    if (seed % 4 == 3) opt.view = View{-3.0, -2.0, 5.0, 4.0};
    const Scene scene = random_scene(seed, opt);
    check_simd_matches_scalar(scene, "seed " + std::to_string(seed));
  }
}

TEST_CASE("overlap fast path: torches overlapping walls by 1 px, scalar against the ray caster and SIMD") {
  // Wall-mounted lights: each torch pokes 1 px into its wall.
  Scene s = blank(96, 64);
  s.occluders.push_back(Occluder{box(4.0, 4.0, 92.0, 8.0)});
  s.occluders.push_back(Occluder{box(4.0, 56.0, 92.0, 60.0)});
  s.occluders.push_back(Occluder{box(46.0, 20.0, 50.0, 44.0)});
  s.lights.push_back(light_of(Circle{{24.0, 10.5}, 3.5}));
  s.lights.push_back(light_of(Circle{{70.0, 53.5}, 3.5}));
  s.lights.push_back(light_of(box(42.0, 28.0, 47.0, 32.0), 0.7));
  // Each torch's cap lies inside its wall: the setup clips the torch at the wall's face and
  // pairs the rest with the wall as separated shapes (no depth tests).
  CHECK(count_general_pairs(s).clipped_lights > 0);
  check_simd_matches_scalar(s, "torches");
  check_scalar_matches_raycast(s, 8.0, "torches");
}

TEST_CASE("shapes far longer than their gap to a light: SIMD matches scalar for extents 1e3 to 1e30") {
  // A separating line computed for a segment from -1e17 to 1e17 used to cut through the
  // segment, so the kernel lit its shadow (up to 3.7 % of e_max); such pairs now take the
  // exact general path, whose depth test compares distances with a relative tolerance only
  // (an absolute one meant 167 pixels at 1e25). Larger extents: tests/test_far_shapes.cpp.
  for (double extent : {1e3, 1e6, 1e9, 1e12, 1e15, 1e17, 1e20, 1e25, 1e30}) {
    Scene s = blank(16, 16);
    s.lights.push_back(light_of(Circle{{8.0, 4.0}, 1.0}));
    s.occluders.push_back(Occluder{Segment{{-extent, 12.0}, {extent, 12.0}}});
    s.occluders.push_back(Occluder{box(-extent, 1.5, extent, 2.0)});
    std::ostringstream what;
    what << "extent " << extent;
    check_simd_matches_scalar(s, what.str());
    // Below the long segment every pixel is in its shadow.
    for (Isa isa : simd_isas_here()) {
      const RenderedImage got = render_or_fail(s, options_for(Backend::simd, isa));
      for (int j = 13; j < 16; ++j)
        for (int i = 0; i < 16; ++i) CHECK(got.at(i, j, 0) == 0.0f);
    }
  }
}
