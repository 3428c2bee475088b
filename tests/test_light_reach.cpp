// Light reach where it bites: closed rings and rooms just inside and just outside each radius of the reach ladder.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "culling/light_reach.hpp"
#include "world/world.hpp"
#include "support/random_scenes.hpp"
#include "support/test_tiers.hpp"

namespace {

using namespace par2d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kLightRadius = 2.0;
constexpr Vec2 kCenter{64, 64};

// The ladder of src/render/light_reach.cpp for a light of radius 2 and 1-unit pixels:
// radius + 8 * 2^j (j = 0..3 fit in a 128 x 128 view, whose farthest corner is 90.5 away).
double ladder(int j) { return kLightRadius + 8.0 * std::ldexp(1.0, j); }

// How close the chord that a sector proof at radius r tests comes to the center: r·cos(half),
// half = half a sector (pi / kSectors) widened by asin(light radius / r).
double chord_distance(double r) {
  return r * std::cos(kPi / detail::LightReach::kSectors + std::asin(kLightRadius / r));
}

// A closed ring of 64 overlapping wall pieces between radii r_in and r_out around `center`.
std::vector<Occluder> ring(double r_in, double r_out, Vec2 center = kCenter) {
  std::vector<Occluder> out;
  constexpr int kPieces = 64;
  for (int i = 0; i < kPieces; ++i) {
    const double a0 = 2 * kPi * (i - 0.25) / kPieces, a1 = 2 * kPi * (i + 1.25) / kPieces;
    auto at = [&](double r, double a) { return Vec2{center.x + r * std::cos(a), center.y + r * std::sin(a)}; };
    out.push_back({Polygon{{at(r_in, a0), at(r_out, a0), at(r_out, a1), at(r_in, a1)}}});
  }
  return out;
}

// A closed square room (four walls of thickness 1) whose inner half-width is `half`.
std::vector<Occluder> room(double half) {
  const double a = half, b = half + 1;
  auto rect = [](double x0, double y0, double x1, double y1) {
    return Occluder{Polygon{{{kCenter.x + x0, kCenter.y + y0}, {kCenter.x + x1, kCenter.y + y0},
                             {kCenter.x + x1, kCenter.y + y1}, {kCenter.x + x0, kCenter.y + y1}}}};
  };
  return {rect(-b, -b, b, -a), rect(-b, a, b, b), rect(-b, -a, -a, a), rect(a, -a, b, a)};
}

Scene lit_enclosure(std::vector<Occluder> walls, Vec2 center = kCenter) {
  Scene s;
  s.width = s.height = 128;
  s.view = {0, 0, 128, 128};
  Light l;
  l.shape = Circle{center, kLightRadius};
  s.lights.push_back(l);
  s.occluders = std::move(walls);
  return s;
}

// Largest difference between two renders at pixels farther than 0.05 px from every boundary.
double worst_difference(const Scene& scene, const RenderOptions& a, const RenderOptions& b, int& count_over) {
  Status status;
  const test::RenderedImage ia = test::render_image(scene, a, status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  const test::RenderedImage ib = test::render_image(scene, b, status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  double worst = 0.0;
  count_over = 0;
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) {
      if (test::near_boundary(scene, test::pixel_center(scene, i, j), 0.05)) continue;
      const double d = std::fabs(double(ia.at(i, j, 0)) - double(ib.at(i, j, 0)));
      worst = std::max(worst, d);
      count_over += d > 1e-4;
    }
  return worst;
}

// The SIMD render with culling against the one without, away from boundaries.
double culled_vs_unculled(const Scene& scene, int& count_over) {
  RenderOptions culled;
  culled.backend = Backend::simd;
  RenderOptions unculled = culled;
  unculled.culling = false;
  return worst_difference(scene, culled, unculled, count_over);
}

}  // namespace

TEST_CASE("light reach of a closed ring is the first ladder radius whose sector chords clear the ring") {
  for (int j = 0; j <= 3; ++j) {
    // Just inside the ladder radius: the chord at ladder(j) passes 0.3 outside the ring.
    const double r_out = chord_distance(ladder(j)) - 0.3, r_in = r_out - 1.0;
    REQUIRE(r_in > (j == 0 ? kLightRadius : ladder(j - 1)));  // the previous radius lies inside the ring
    const auto prepared = detail::prepare_scene(lit_enclosure(ring(r_in, r_out)));
    detail::LightReachScratch scratch;
    const detail::LightReach reach = detail::compute_light_reach(prepared, 0, scratch);
    const double scale = prepared.view.x1 / 128.0;
    for (int k = 0; k < detail::LightReach::kSectors; ++k) {
      INFO("ring just inside ladder radius ", ladder(j), ", sector ", k);
      CHECK(reach.reach[static_cast<std::size_t>(k)] == doctest::Approx(ladder(j) * scale).epsilon(1e-12));
    }
    // Just outside the ladder radius: that radius fails, the next one (if any) holds.
    const double out_in = ladder(j) + 0.3;
    const auto outside = detail::prepare_scene(lit_enclosure(ring(out_in, out_in + 1.0)));
    const detail::LightReach far = detail::compute_light_reach(outside, 0, scratch);
    for (int k = 0; k < detail::LightReach::kSectors; ++k) {
      INFO("ring just outside ladder radius ", ladder(j), ", sector ", k);
      const double r = far.reach[static_cast<std::size_t>(k)];
      if (j < 3) CHECK(r == doctest::Approx(ladder(j + 1) * scale).epsilon(1e-12));
      else CHECK(std::isinf(r));  // 130 is past the farthest corner: not tried
    }
  }
}

TEST_CASE("culled renders equal unculled ones and the scalar reference inside rings and rooms at every ladder radius" * par2d::test::per_isa()) {
  // A reach 5% short of the proof culls the lit band between 0.95·r and the wall: ~100
  // pixels at up to 26x the SIMD bound. Every ring and room here sits where that band is lit.
  std::vector<std::pair<std::string, Scene>> scenes;
  for (int j = 0; j <= 3; ++j) {
    const double inside = chord_distance(ladder(j)) - 0.3;
    scenes.emplace_back("ring inside " + std::to_string(j), lit_enclosure(ring(inside - 1.0, inside)));
    scenes.emplace_back("ring outside " + std::to_string(j), lit_enclosure(ring(ladder(j) + 0.3, ladder(j) + 1.3)));
    scenes.emplace_back("room inside " + std::to_string(j), lit_enclosure(room(inside / std::sqrt(2.0) - 1.0)));
  }
  // The reach is tested per 64-pixel block, so a block must straddle the lit band: the light
  // 62.8 from the edge x = 64 of the block [64, 128] x [0, 64], the ring from 63.7 to 64.1
  // (the proof at ladder radius 66 reaches in to 65.5): pixel column 64.5 is lit within ~7
  // rows of y = 32, and a reach of 0.95·66 = 62.7 would skip the light in the whole block.
  const Vec2 near_block{64.0 - 62.8, 32.0};
  scenes.emplace_back("ring across a block edge", lit_enclosure(ring(63.7, 64.1, near_block), near_block));
  for (const auto& named : scenes) {
    const auto& name = named.first;  // not a structured binding: clang's INFO cannot capture those
    int over = 0;
    const double worst = culled_vs_unculled(named.second, over);
    INFO(name, ": culled vs unculled worst ", worst, ", pixels over 1e-4: ", over);
    CHECK(worst <= 1e-4);
  }
  // One of each against the scalar reference (slow: every pixel sees 64 wall pieces).
  for (int k : {4, 5}) {
    RenderOptions culled;
    culled.backend = Backend::simd;
    RenderOptions scalar;
    scalar.backend = Backend::scalar;
    int over = 0;
    const double worst = worst_difference(scenes[static_cast<std::size_t>(k)].second, culled, scalar, over);
    INFO(scenes[static_cast<std::size_t>(k)].first, ": culled SIMD vs scalar worst ", worst);
    CHECK(worst <= 1e-4);
  }
}

TEST_CASE("LightReach::hides: the sectors a box spans, against its boundary's directions sampled one by one") {
  // Random reaches (finite or not per sector) and boxes around the center. The expected answer
  // takes the box's directions from points along its whole boundary, each by atan2 relative
  // to the box's middle direction (the span is narrower than pi), and asks every sector those
  // directions fall in. Boxes whose span ends within 1e-7 of a sector edge are left out: the
  // function widens the span by 1e-9 there, for atan2's rounding.
  test::PortableRandom rng(20261204);
  constexpr int kSectors = detail::LightReach::kSectors;
  const double sector_width = 2 * kPi / kSectors;
  const double inf = std::numeric_limits<double>::infinity();
  int hidden = 0, seen = 0, spanning_several = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    detail::LightReach reach;
    reach.center = {rng.uniform(-50, 50), rng.uniform(-50, 50)};
    reach.radius = rng.uniform(0.5, 4);
    const double open_share = rng.uniform(0.0, 0.4);
    for (double& r : reach.reach) r = rng.chance(open_share) ? inf : rng.uniform(5, 70);
    reach.nearest = *std::min_element(reach.reach.begin(), reach.reach.end());
    reach.farthest = *std::max_element(reach.reach.begin(), reach.reach.end());
    const double x0 = reach.center.x + rng.uniform(-90, 80), y0 = reach.center.y + rng.uniform(-90, 80);
    const detail::Aabb box{x0, y0, x0 + rng.uniform(0.5, 40), y0 + rng.uniform(0.5, 40)};
    const double dx = std::max({box.min_x - reach.center.x, 0.0, reach.center.x - box.max_x});
    const double dy = std::max({box.min_y - reach.center.y, 0.0, reach.center.y - box.max_y});
    const double distance = std::hypot(dx, dy);
    if (!(distance > reach.radius)) {
      CHECK_FALSE(reach.hides(box));
      continue;
    }
    const Vec2 middle{0.5 * (box.min_x + box.max_x) - reach.center.x, 0.5 * (box.min_y + box.max_y) - reach.center.y};
    const double toward = std::atan2(middle.y, middle.x);
    double lo = inf, hi = -inf;
    constexpr int kSteps = 64;
    for (int side = 0; side < 4; ++side)
      for (int s = 0; s <= kSteps; ++s) {
        const double t = double(s) / kSteps;
        const double x = side == 0 ? box.min_x + t * (box.max_x - box.min_x) : side == 1 ? box.max_x
                         : side == 2 ? box.max_x - t * (box.max_x - box.min_x) : box.min_x;
        const double y = side == 0 ? box.min_y : side == 1 ? box.min_y + t * (box.max_y - box.min_y)
                         : side == 2 ? box.max_y : box.max_y - t * (box.max_y - box.min_y);
        double a = std::atan2(y - reach.center.y, x - reach.center.x) - toward;
        if (a > kPi) a -= 2 * kPi;
        if (a < -kPi) a += 2 * kPi;
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
    auto near_edge = [&](double a) {
      const double u = (toward + a + kPi) / sector_width;
      return std::abs(u - std::round(u)) < 1e-7 / sector_width;
    };
    if (near_edge(lo) || near_edge(hi)) continue;
    const int first = static_cast<int>(std::floor((toward + lo + kPi) / sector_width));
    const int last = static_cast<int>(std::floor((toward + hi + kPi) / sector_width));
    bool expected = true;
    for (int k = first; k <= last; ++k)
      expected = expected && reach.reach[static_cast<std::size_t>(((k % kSectors) + kSectors) % kSectors)] <= distance;
    INFO("trial ", trial, ": center (", reach.center.x, ", ", reach.center.y, "), box (", box.min_x, ", ", box.min_y,
         ") - (", box.max_x, ", ", box.max_y, "), sectors ", first, "..", last, ", distance ", distance);
    CHECK(reach.hides(box) == expected);
    (expected ? hidden : seen) += 1;
    spanning_several += last > first;
  }
  // Both answers, and spans over several sectors (those that pick the two end corners), occur often.
  CHECK(hidden >= 300);
  CHECK(seen >= 300);
  CHECK(spanning_several >= 1000);
}

TEST_CASE("light reach of a room with a doorway: open only toward the doorway, and culled renders equal unculled ones" * par2d::test::per_isa()) {
  // The square room of half-width 20 with a 6-unit gap in its right wall (y in [61, 67]).
  const double half = 20.0;
  std::vector<Occluder> walls = room(half);
  walls.pop_back();  // the right wall, replaced by two pieces around the doorway
  auto rect = [](double x0, double y0, double x1, double y1) {
    return Occluder{Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
  };
  walls.push_back(rect(kCenter.x + half, kCenter.y - half, kCenter.x + half + 1, kCenter.y - 3));
  walls.push_back(rect(kCenter.x + half, kCenter.y + 3, kCenter.x + half + 1, kCenter.y + half));
  const Scene scene = lit_enclosure(walls);
  const auto prepared = detail::prepare_scene(scene);
  detail::LightReachScratch scratch;
  const detail::LightReach reach = detail::compute_light_reach(prepared, 0, scratch);
  constexpr int kSectors = detail::LightReach::kSectors;
  int open = 0;
  for (int k = 0; k < kSectors; ++k) {
    const double mid = -kPi + (k + 0.5) * 2 * kPi / kSectors;
    const double r = reach.reach[static_cast<std::size_t>(k)];
    INFO("sector ", k, " (middle direction ", mid, "): reach ", r);
    // Directions within 30 degrees of +x see through the doorway (at distance 20 it spans
    // +-8.5 degrees, widened by the light's 2 units), all others meet a wall.
    if (std::abs(mid) < kPi / 6) {
      open += std::isinf(r);
    } else if (std::abs(mid) > kPi / 3) {
      CHECK(std::isfinite(r));
    }
  }
  CHECK(open >= 2);  // the two sectors either side of +x
  int over = 0;
  const double worst = culled_vs_unculled(scene, over);
  INFO("culled vs unculled worst ", worst, ", pixels over 1e-4: ", over);
  CHECK(worst <= 1e-4);
}
