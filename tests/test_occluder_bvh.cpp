// Tests for the occluder BVH and convex_hull: every query must return exactly the brute-force set.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "world/occluder_bvh.hpp"

namespace {

using par2d::Vec2;
using par2d::detail::Aabb;
using par2d::detail::convex_hull;
using par2d::detail::OccluderBvh;

// Reference separating-axis test written from the definition: project all four corners and all
// hull points on x, y and every hull edge normal; touching intervals do not separate. The normal is
// formed like the library's so that both round identically on exact-touch cases.
bool brute_intersects(const Aabb& b, const std::vector<Vec2>& hull) {
  const Vec2 corners[4] = {{b.min_x, b.min_y}, {b.max_x, b.min_y}, {b.max_x, b.max_y}, {b.min_x, b.max_y}};
  auto separated_on = [&](double nx, double ny) {
    double blo = INFINITY, bhi = -INFINITY, hlo = INFINITY, hhi = -INFINITY;
    for (const Vec2& c : corners) {
      blo = std::min(blo, nx * c.x + ny * c.y);
      bhi = std::max(bhi, nx * c.x + ny * c.y);
    }
    for (const Vec2& p : hull) {
      hlo = std::min(hlo, nx * p.x + ny * p.y);
      hhi = std::max(hhi, nx * p.x + ny * p.y);
    }
    return bhi < hlo || blo > hhi;
  };
  if (separated_on(1.0, 0.0) || separated_on(0.0, 1.0)) return false;
  const size_t n = hull.size();
  const size_t edges = n < 2 ? 0 : (n == 2 ? 1 : n);
  for (size_t i = 0; i < edges; ++i) {
    const Vec2 a = hull[i], c = hull[(i + 1) % n];
    const double len = std::hypot(c.x - a.x, c.y - a.y);
    if (!(len > 0.0)) continue;
    if (separated_on((a.y - c.y) / len, (c.x - a.x) / len)) return false;
  }
  return true;
}

bool brute_overlap(const Aabb& a, const Aabb& b) {
  return !(a.max_x < b.min_x || b.max_x < a.min_x || a.max_y < b.min_y || b.max_y < a.min_y);
}

std::vector<uint32_t> brute_convex(const std::vector<Aabb>& boxes, const std::vector<Vec2>& hull) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (brute_intersects(boxes[i], hull)) out.push_back(static_cast<uint32_t>(i));
  }
  return out;
}

std::vector<uint32_t> brute_box(const std::vector<Aabb>& boxes, const Aabb& q) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (brute_overlap(boxes[i], q)) out.push_back(static_cast<uint32_t>(i));
  }
  return out;
}

enum class Layout { scattered, clustered, identical };

std::vector<Aabb> random_boxes(size_t n, Layout layout, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, 1000.0);
  std::uniform_real_distribution<double> size(0.0, 20.0);
  std::normal_distribution<double> spread(0.0, 15.0);
  Vec2 clusters[5];
  for (Vec2& c : clusters) c = {pos(rng), pos(rng)};
  std::vector<Aabb> boxes;
  for (size_t i = 0; i < n; ++i) {
    double x = 0, y = 0;
    if (layout == Layout::scattered) {
      x = pos(rng);
      y = pos(rng);
    } else if (layout == Layout::clustered) {
      const Vec2 c = clusters[rng() % 5];
      x = c.x + spread(rng);
      y = c.y + spread(rng);
    } else {
      x = 400.0;
      y = 300.0;
    }
    const double w = layout == Layout::identical ? 10.0 : size(rng);
    const double h = layout == Layout::identical ? 5.0 : size(rng);
    boxes.push_back({x, y, x + w, y + h});
  }
  return boxes;
}

// Query hulls of every kind the renderer makes: points, segments, rectangles, triangles and long
// thin slivers (a tile corner to a far light).
std::vector<std::vector<Vec2>> random_hulls(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-50.0, 1050.0);
  std::uniform_real_distribution<double> small(0.0, 64.0);
  std::vector<std::vector<Vec2>> hulls;
  for (int i = 0; i < 40; ++i) {
    const Vec2 b{pos(rng), pos(rng)};
    const Vec2 p{pos(rng), pos(rng)};
    hulls.push_back({p});
    hulls.push_back({p, b});
    const double w = small(rng), h = small(rng);
    hulls.push_back({p, {p.x + w, p.y}, {p.x + w, p.y + h}, {p.x, p.y + h}});
    hulls.push_back(convex_hull({p, b, {pos(rng), pos(rng)}}));
    // Sliver: a 1e-3-wide triangle from p to b, in both windings.
    const double dx = b.x - p.x, dy = b.y - p.y, len = std::hypot(dx, dy) + 1e-9;
    const Vec2 off{-dy / len * 1e-3, dx / len * 1e-3};
    hulls.push_back({p, {b.x + off.x, b.y + off.y}, {b.x - off.x, b.y - off.y}});
    hulls.push_back({p, {b.x - off.x, b.y - off.y}, {b.x + off.x, b.y + off.y}});
    // A tile plus a light: the hull the renderer queries with.
    hulls.push_back(convex_hull({p, {p.x + 32, p.y}, {p.x + 32, p.y + 32}, {p.x, p.y + 32}, b,
                                 {b.x + w, b.y + h}}));
  }
  return hulls;
}

std::vector<uint32_t> bvh_convex(const OccluderBvh& bvh, const std::vector<Vec2>& hull) {
  std::vector<uint32_t> out;
  bvh.query_convex(hull.data(), static_cast<int>(hull.size()), out);
  return out;
}

std::vector<uint32_t> bvh_box(const OccluderBvh& bvh, const Aabb& q) {
  std::vector<uint32_t> out;
  bvh.query_box(q, out);
  return out;
}

void check_against_brute_force(const std::vector<Aabb>& boxes, uint64_t seed) {
  OccluderBvh bvh;
  bvh.build(boxes);
  CHECK(bvh.node_count() <= (boxes.empty() ? 0 : 2 * boxes.size() - 1));
  for (const auto& hull : random_hulls(seed)) {
    REQUIRE(bvh_convex(bvh, hull) == brute_convex(boxes, hull));
  }
  std::mt19937_64 rng(seed + 7);
  std::uniform_real_distribution<double> pos(-50.0, 1050.0);
  std::uniform_real_distribution<double> size(0.0, 100.0);
  for (int i = 0; i < 50; ++i) {
    const double x = pos(rng), y = pos(rng);
    const Aabb q{x, y, x + size(rng), y + size(rng)};
    REQUIRE(bvh_box(bvh, q) == brute_box(boxes, q));
  }
}

double cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

bool same_points(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].x != b[i].x || a[i].y != b[i].y) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("convex_hull: square with interior, duplicate and edge points gives its 4 corners, positive turn") {
  const std::vector<Vec2> hull =
      convex_hull({{1, 1}, {0, 0}, {2, 0}, {0.5, 0.5}, {2, 2}, {1, 0}, {0, 2}, {2, 2}, {0, 1}});
  CHECK(same_points(hull, {{0, 0}, {2, 0}, {2, 2}, {0, 2}}));
  for (size_t i = 0; i < hull.size(); ++i) {
    CHECK(cross(hull[i], hull[(i + 1) % hull.size()], hull[(i + 2) % hull.size()]) > 0.0);
  }
}

TEST_CASE("convex_hull: a clockwise triangle comes back counter-clockwise from its lowest point") {
  CHECK(same_points(convex_hull({{0, 1}, {1, 0}, {0, 0}}), {{0, 0}, {1, 0}, {0, 1}}));
}

TEST_CASE("convex_hull: degenerate inputs keep 0, 1 or 2 points") {
  CHECK(convex_hull({}).empty());
  CHECK(same_points(convex_hull({{3, 4}}), {{3, 4}}));
  CHECK(same_points(convex_hull({{3, 4}, {3, 4}, {3, 4}}), {{3, 4}}));
  CHECK(same_points(convex_hull({{5, 5}, {1, 2}}), {{1, 2}, {5, 5}}));
  CHECK(same_points(convex_hull({{2, 2}, {0, 0}, {3, 3}, {1, 1}, {3, 3}}), {{0, 0}, {3, 3}}));
}

TEST_CASE("OccluderBvh: empty tree has no nodes and leaves the output untouched") {
  OccluderBvh bvh;
  bvh.build({});
  CHECK(bvh.node_count() == 0);
  std::vector<uint32_t> out{42};
  const Vec2 p{0, 0};
  bvh.query_convex(&p, 1, out);
  bvh.query_box({-1e9, -1e9, 1e9, 1e9}, out);
  CHECK(out == std::vector<uint32_t>{42});
}

TEST_CASE("OccluderBvh: results are appended after existing output, sorted") {
  const auto boxes = random_boxes(1000, Layout::scattered, 3);
  OccluderBvh bvh;
  bvh.build(boxes);
  std::vector<uint32_t> out{7, 3};
  bvh.query_box({0, 0, 1000, 1000}, out);
  REQUIRE(out.size() == 1002);
  CHECK(out[0] == 7);
  CHECK(out[1] == 3);
  CHECK(std::is_sorted(out.begin() + 2, out.end()));
}

TEST_CASE("OccluderBvh: touching counts as intersecting, for every hull kind") {
  const std::vector<Aabb> boxes{{0, 0, 1, 1}};
  OccluderBvh bvh;
  bvh.build(boxes);
  const std::vector<uint32_t> hit{0}, miss{};
  CHECK(bvh_convex(bvh, {{1, 1}}) == hit);                              // point on a corner
  CHECK(bvh_convex(bvh, {{1, 0.5}, {3, 0.5}}) == hit);                  // segment ending on an edge
  CHECK(bvh_convex(bvh, {{1, 1}, {2, 1}, {1, 2}}) == hit);              // triangle sharing a corner
  CHECK(bvh_convex(bvh, {{1, 2}, {2, 1}, {2, 2}}) == miss);             // diagonal gap: needs the edge axis
  CHECK(bvh_convex(bvh, {{0.5, 2}, {2, 0.5}, {2, 2}}) == miss);         // bounding boxes overlap, hull misses
  CHECK(bvh_convex(bvh, {{1.5, 0}, {0, 1.5}, {2, 2}}) == hit);          // crosses the corner
  CHECK(bvh_convex(bvh, {{-1, 0}, {2, 0}, {2, -1}}) == hit);            // shares the bottom edge
  CHECK(bvh_box(bvh, {1, 1, 2, 2}) == hit);
  CHECK(bvh_box(bvh, {1.0000001, 0, 2, 2}) == miss);
}

TEST_CASE("OccluderBvh: one box") {
  check_against_brute_force({{10, 10, 20, 30}}, 1);
}

TEST_CASE("OccluderBvh: random scattered, clustered and identical boxes match brute force") {
  for (const size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{5}, size_t{1000}, size_t{4096}}) {
    for (const Layout layout : {Layout::scattered, Layout::clustered, Layout::identical}) {
      for (const uint64_t seed : {uint64_t{1}, uint64_t{2}}) {
        CAPTURE(n);
        CAPTURE(static_cast<int>(layout));
        CAPTURE(seed);
        check_against_brute_force(random_boxes(n, layout, seed * 1000 + n), seed);
      }
    }
  }
}

TEST_CASE("OccluderBvh: 4096 identical boxes build a balanced tree with leaves of <= 4") {
  const auto boxes = random_boxes(4096, Layout::identical, 0);
  OccluderBvh bvh;
  bvh.build(boxes);
  // Halving 4096 down to leaves of 4 gives 1024 leaves: 2047 nodes.
  CHECK(bvh.node_count() == 2047);
  CHECK(bvh_box(bvh, boxes[0]).size() == 4096);
}

TEST_CASE("OccluderBvh: rebuilding over new boxes forgets the old ones") {
  OccluderBvh bvh;
  bvh.build(random_boxes(4096, Layout::scattered, 5));
  const auto boxes = random_boxes(1000, Layout::clustered, 6);
  bvh.build(boxes);
  check_against_brute_force(boxes, 9);
  OccluderBvh fresh;
  fresh.build(boxes);
  CHECK(fresh.node_count() == bvh.node_count());
  for (const auto& hull : random_hulls(4)) CHECK(bvh_convex(bvh, hull) == bvh_convex(fresh, hull));
}

TEST_CASE("OccluderBvh: scaling the scene by 2^+-500 keeps the same answers") {
  const auto boxes = random_boxes(1000, Layout::scattered, 11);
  OccluderBvh bvh;
  bvh.build(boxes);
  const auto hulls = random_hulls(12);
  for (const int e : {500, -500}) {
    std::vector<Aabb> scaled = boxes;
    for (Aabb& b : scaled) {
      b = {std::ldexp(b.min_x, e), std::ldexp(b.min_y, e), std::ldexp(b.max_x, e), std::ldexp(b.max_y, e)};
    }
    OccluderBvh big;
    big.build(scaled);
    for (auto hull : hulls) {
      const auto expected = bvh_convex(bvh, hull);
      for (Vec2& p : hull) p = {std::ldexp(p.x, e), std::ldexp(p.y, e)};
      CAPTURE(e);
      REQUIRE(bvh_convex(big, hull) == brute_convex(scaled, hull));
      CHECK(bvh_convex(big, hull) == expected);
    }
  }
}

TEST_CASE("OccluderBvh: boxes near +-DBL_MAX and exponentially spaced boxes build and query correctly") {
  std::vector<Aabb> boxes;
  // Exponential spacing makes SAH peel one box per level; the depth cap must take over.
  for (int i = 0; i < 2000; ++i) {
    const double x = std::ldexp(1.0, i % 1000 - 500);
    boxes.push_back({x, -x, x * 1.5, x});
  }
  boxes.push_back({-1e308, -1e308, 1e308, 1e308});
  boxes.push_back({1e308, 1e308, 1.7e308, 1.7e308});
  OccluderBvh bvh;
  bvh.build(boxes);
  std::vector<uint32_t> all(boxes.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
  CHECK(bvh_box(bvh, {-1.7e308, -1.7e308, 1.7e308, 1.7e308}) == all);
  for (const std::vector<Vec2>& hull : std::vector<std::vector<Vec2>>{
           {{0, 0}}, {{1, 0}, {2, 0.25}}, {{1e-100, 0}, {1e100, 1e90}, {1e100, -1e90}}, {{1e300, 1e300}}}) {
    REQUIRE(bvh_convex(bvh, hull) == brute_convex(boxes, hull));
  }
}

TEST_CASE("OccluderBvh: hulls with more edges than the cached axes stay exact") {
  const auto boxes = random_boxes(4096, Layout::scattered, 13);
  OccluderBvh bvh;
  bvh.build(boxes);
  std::vector<Vec2> circle;
  for (int i = 0; i < 100; ++i) {
    const double a = 2.0 * M_PI * i / 100.0;
    circle.push_back({500.0 + 200.0 * std::cos(a), 500.0 + 200.0 * std::sin(a)});
  }
  CHECK(bvh_convex(bvh, circle) == brute_convex(boxes, circle));
}

TEST_CASE("the hull of two boxes answers box tests exactly like the general convex hull") {
  // BoxPairHull (the tile-and-light filter) against ConvexQuery over convex_hull of the
  // eight corners, on random boxes in every relative position, including nested ones.
  std::mt19937 rng(77);
  auto unit = [&] { return static_cast<double>(rng() >> 5) / 134217728.0; };  // [0, 1)
  auto random_box = [&](double scale) {
    const double x = (unit() - 0.5) * 200.0, y = (unit() - 0.5) * 200.0;
    return Aabb{x, y, x + unit() * scale, y + unit() * scale};
  };
  int agree = 0, touching = 0;
  // One object reassigned on every trial as well, as the tile setup reuses it: nothing of the
  // previous pair's hull may stay.
  par2d::detail::BoxPairHull reused;
  for (int trial = 0; trial < 4000; ++trial) {
    const Aabb a = random_box(trial % 3 == 0 ? 100.0 : 10.0), b = random_box(trial % 5 == 0 ? 80.0 : 6.0);
    reused.assign(a, b);
    std::vector<Vec2> corners = {{a.min_x, a.min_y}, {a.max_x, a.min_y}, {a.max_x, a.max_y}, {a.min_x, a.max_y},
                                 {b.min_x, b.min_y}, {b.max_x, b.min_y}, {b.max_x, b.max_y}, {b.min_x, b.max_y}};
    const std::vector<Vec2> hull = convex_hull(corners);
    const par2d::detail::ConvexQuery general(hull.data(), static_cast<int>(hull.size()));
    const par2d::detail::BoxPairHull pair(a, b);
    for (int q = 0; q < 20; ++q) {
      const Aabb query = random_box(q % 4 == 0 ? 40.0 : 4.0);
      const bool expected = general.touches(query);
      touching += expected;
      INFO("trial ", trial, " query ", q);
      CHECK(pair.touches(query) == expected);
      CHECK(reused.touches(query) == expected);
      ++agree;
    }
  }
  CHECK(touching > 1000);  // both answers occur often
  CHECK(touching < agree - 1000);
}
