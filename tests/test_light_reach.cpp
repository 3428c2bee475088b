// Light reach where it bites: closed rings and rooms just inside and just outside each radius of the reach ladder,
// lights that walls do not act on, proofs made stale by walls longer than the view, and the reach cache's erase.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "par2d/par2d.hpp"
#include "culling/light_reach.hpp"
#include "culling/reach_cache.hpp"
#include "parallel/scheduler.hpp"
#include "world/world.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
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

// Reach only counts occluders acting on the light (docs/contract.md section 6): a light whose
// mask misses the walls, and the part of a light with shadow strength 0.5 that no occluder
// shadows, shine through a closed room that hides a plain light from everything beyond it.
// The room is small and off to the left of a 256 x 128 view, so that whole 64-pixel blocks lie
// beyond the walls' reach (the open scenes of the shadow tests never shrink a reach). A reach
// that counted the walls there would skip those lights in the blocks on the right.
TEST_CASE("light reach in a closed room: a light whose mask misses the walls and a half-strength shadow shine through") {
  const Vec2 center{40, 64};
  auto rect = [&](double x0, double y0, double x1, double y1) {
    return Occluder{Polygon{{{center.x + x0, center.y + y0}, {center.x + x1, center.y + y0},
                             {center.x + x1, center.y + y1}, {center.x + x0, center.y + y1}}}};
  };
  const double a = 16, b = 17;
  const std::vector<Occluder> walls = {rect(-b, -b, b, -a), rect(-b, a, b, b), rect(-b, -a, -a, a), rect(a, -a, b, a)};
  Scene base;
  base.width = 256;
  base.height = 128;
  base.view = {0, 0, 256, 128};
  base.occluders = walls;
  base.lights.push_back(Light{Circle{center, kLightRadius}, {1.0, 0.8, 0.6}, 2.0});

  // The plain light: every sector's reach is finite, short of the blocks on the right.
  {
    const auto prepared = detail::prepare_scene(base);
    REQUIRE(prepared.lights.size() == 1);
    detail::LightReachScratch scratch;
    const detail::LightReach reach = detail::compute_light_reach(prepared, 0, scratch);
    CHECK(reach.farthest * 256.0 / prepared.view.x1 < 128.0 - center.x);
    const test::RenderedImage plain = test::render_or_fail(base, test::options_for(Backend::scalar));
    CHECK(plain.at(200, 64, 0) == 0.0f);
  }

  Scene masked = base;
  masked.lights[0].mask = 1u;
  for (Occluder& o : masked.occluders) o.mask = 2u;
  Scene half = base;
  half.lights[0].shadow = Shadow{0.5, {0.0, 0.0, 0.0}};
  // A mask shared with one wall only: the other three let the light through.
  Scene one_wall = masked;
  one_wall.occluders[2].mask = 3u;  // the left wall
  const std::pair<const char*, const Scene*> cases[] = {
      {"mask missing the walls", &masked}, {"shadow strength 0.5", &half}, {"mask meeting one wall", &one_wall}};
  for (const auto& named : cases) {
    const Scene& scene = *named.second;
    INFO(named.first);
    const test::RenderedImage ref = test::render_or_fail(scene, test::options_for(Backend::scalar));
    // Far right of the room the light is seen: whole through masked walls, half through the
    // half shadow (the one wall that acts is the left one).
    CHECK(ref.at(200, 64, 0) > 0.0f);
    CHECK(ref.at(200, 10, 0) > 0.0f);
    const double pixel = 1.0;
    test::check_simd_against_scalar(
        scene, ref, named.first, [&](Vec2 p) { return test::near_boundary(scene, p, 0.05 * pixel); },
        scene.width * scene.height / 2);
  }
}

// A light's reach proof goes stale when an occluder changes anywhere its proofs looked: where
// the changed box meets the box they looked in, not only where it lies inside it. Walls much
// longer than the view stick out of that box at both ends; moved away, the pixels behind them
// must light up (each frame bit for bit a one-shot render), on every ISA with culling.
TEST_CASE("a wall much longer than the view, moved away, makes the reach of the light it hid stale") {
  for (const Isa isa : test::simd_isas_here()) {
    INFO("isa ", isa_name(isa));
    for (const bool vertical : {true, false}) {
      INFO((vertical ? "vertical wall" : "horizontal wall"));
      Scene scene;
      scene.width = 128;
      scene.height = 128;
      scene.view = {0, 0, 128, 128};
      scene.lights.push_back(Light{Circle{{20.0, 20.0}, 3.0}, {1.0, 0.8, 0.6}, 2.0});
      // 20,000 units long, 4 thick, 10 units from the light; a few pillars so that the index
      // holds more than the wall.
      auto long_wall = [&](double offset) {
        return vertical ? Occluder{Polygon{{{30 + offset, -1e4}, {34 + offset, -1e4}, {34 + offset, 1e4}, {30 + offset, 1e4}}}}
                        : Occluder{Polygon{{{-1e4, 30 + offset}, {1e4, 30 + offset}, {1e4, 34 + offset}, {-1e4, 34 + offset}}}};
      };
      scene.occluders.push_back(long_wall(0.0));
      for (int k = 0; k < 4; ++k) {
        const double p = 50.0 + 18.0 * k;
        scene.occluders.push_back(Occluder{Polygon{{{p, 5}, {p + 2, 5}, {p + 2, 7}, {p, 7}}}});
      }
      Renderer r;
      REQUIRE(r.set_options(test::options_for(Backend::simd, isa, true)).ok());
      std::vector<OccluderHandle> occluders;
      REQUIRE(r.set_scene(scene, nullptr, &occluders).ok());
      // Behind the wall (the far corner of the view) is dark while it stands; `between` lies in
      // the same 64-pixel block, between the light and the wall once it has moved 50 units.
      const std::size_t behind = (110u * 128u + 110u) * 3u;
      const std::size_t between = vertical ? (110u * 128u + 70u) * 3u : (70u * 128u + 110u) * 3u;
      const std::vector<float> walled = test::frame_rgb(r);
      CHECK(walled[behind] == 0.0f);
      CHECK(test::same_bits(walled, test::one_shot(r.snapshot(), r.options())));
      // Moved 50 units on: still longer than the view, now past the pixel `between`.
      REQUIRE(r.update_occluder(occluders[0], long_wall(50.0)).ok());
      const std::vector<float> nearer = test::frame_rgb(r);
      CHECK(nearer[between] > 0.0f);
      CHECK(nearer[behind] == 0.0f);
      CHECK(test::same_bits(nearer, test::one_shot(r.snapshot(), r.options())));
      // Moved out of the view: everything behind it lights up.
      REQUIRE(r.update_occluder(occluders[0], long_wall(400.0)).ok());
      const std::vector<float> open = test::frame_rgb(r);
      CHECK(open[behind] > 0.0f);
      CHECK(test::same_bits(open, test::one_shot(r.snapshot(), r.options())));
    }
  }
}

namespace {

// Every light's cached reach against the reach proven from scratch on the same prepared scene.
void check_cache_fresh(const detail::ReachCache& cache, const detail::PreparedScene& prepared, const char* step) {
  INFO(step);
  REQUIRE(cache.reach().size() == prepared.lights.size());
  detail::LightReachScratch scratch;
  for (std::size_t p = 0; p < prepared.lights.size(); ++p) {
    INFO("light ", p);
    const detail::LightReach fresh = detail::compute_light_reach(prepared, p, scratch);
    const detail::LightReach& kept = cache.reach()[p];
    CHECK(kept.center.x == fresh.center.x);
    CHECK(kept.center.y == fresh.center.y);
    CHECK(kept.radius == fresh.radius);
    CHECK(kept.reach == fresh.reach);
  }
}

}  // namespace

// Erasing a light gives its number to the last light (world_changes.hpp): the cache must move
// that light's reach, the box its proofs looked in and whether it is stale along with it. Each
// step below fails if one of the three stays behind: the erased light's reach kept under the
// number (step 2), the erased light's box deciding whether a wall the moved light's proof
// rests on matters (step 3), the erased light's staleness kept when the moved light changed
// in the same commit (step 4).
TEST_CASE("the reach cache moves the last light's reach, proof box and staleness into an erased light's number") {
  Scene scene = lit_enclosure(room(16.0));  // A: walled in, its proofs near (64, 64)
  scene.width = 256;
  scene.view = {0, 0, 256, 128};
  scene.lights.push_back(Light{Circle{{128, 20}, 2.0}});   // B: in the open
  scene.lights.push_back(Light{Circle{{190, 64}, 2.0}});   // C: a wall on its right
  const Occluder wall{Polygon{{{200, 20}, {204, 20}, {204, 108}, {200, 108}}}};
  scene.occluders.push_back(wall);

  detail::ReachCache cache;
  detail::World world;
  world.observe(&cache);
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(world.set_scene(scene, &lights, &occluders).ok());
  detail::Scheduler scheduler;
  scheduler.configure(1, Threading::own_pool);
  auto commit = [&](const char* step) {
    const detail::PreparedScene& prepared = world.commit();
    cache.update(prepared, scheduler);
    check_cache_fresh(cache, prepared, step);
    return prepared.lights.size();
  };
  REQUIRE(commit("set_scene") == 3);
  // C's reach is finite toward the wall, and A's proofs looked nowhere near the wall.
  REQUIRE(std::isfinite(cache.reach()[2].reach[detail::LightReach::kSectors / 2]));

  // 2: A erased; C takes number 0.
  REQUIRE(world.remove_light(lights[0]).ok());
  REQUIRE(commit("A erased") == 2);
  // 3: the wall C's reach rests on moves away: C's reach opens toward +x.
  REQUIRE(world.update_occluder(occluders[4], Occluder{Polygon{{{600, 20}, {604, 20}, {604, 108}, {600, 108}}}}).ok());
  commit("the wall moved away");
  CHECK(std::isinf(cache.reach()[0].reach[detail::LightReach::kSectors / 2]));
  // 4: a light D added (number 2, proven), then moved in the commit that erases C: D takes
  // number 0 and must be proven again where it is now.
  LightHandle d;
  REQUIRE(world.add_light(Light{Circle{{60, 100}, 2.0}}, &d).ok());
  REQUIRE(commit("D added") == 3);
  REQUIRE(world.update_light(d, Light{Circle{{230, 40}, 2.0}}).ok());
  REQUIRE(world.remove_light(lights[2]).ok());
  REQUIRE(commit("D moved, C erased") == 2);
}
