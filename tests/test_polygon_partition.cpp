// partition_convex (src/geometry/polygon_partition.hpp): closed forms, the partition's
// properties on random star polygons with holes and on tile-map rooms with pillars (convex
// pieces, exact total area, every interior point covered once, no exterior point covered, the
// Hertel-Mehlhorn piece bound), refusals that name the ring, a 4096-vertex polygon, and combs
// of up to 65,534 vertices, whose work the partition counts.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "comb_outline.hpp"
#include "geometry/polygon_partition.hpp"

namespace par2d::test {
namespace {

using detail::orientation;
using detail::partition_convex;
using detail::PolygonRings;
using Pieces = std::vector<std::vector<Vec2>>;

// Uniform in [0, 1) from the top 53 bits (the same numbers on every standard library).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }
int uniform_int(std::mt19937_64& rng, int lo, int hi) {  // [lo, hi]
  return lo + static_cast<int>(rng() % static_cast<std::uint64_t>(hi - lo + 1));
}

// Twice the signed area (shoelace), of the ring with its coordinates divided by `unit` (so
// that coordinates near 1e300 do not overflow).
double area2(const std::vector<Vec2>& ring, double unit = 1.0) {
  double sum = 0.0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    sum += (a.x / unit) * (b.y / unit) - (a.y / unit) * (b.x / unit);
  }
  return sum;
}

double polygon_area(const PolygonRings& polygon, double unit = 1.0) {
  double area = std::fabs(area2(polygon.outer, unit));
  for (const auto& hole : polygon.holes) area -= std::fabs(area2(hole, unit));
  return 0.5 * area;
}

double pieces_area(const Pieces& pieces, double unit = 1.0) {
  double area = 0.0;
  for (const auto& piece : pieces) area += area2(piece, unit);
  return 0.5 * area;
}

bool within_box(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// -1 outside, 0 on the boundary, 1 inside (even-odd over every ring), decided exactly.
int classify(const PolygonRings& polygon, Vec2 p) {
  bool inside = false;
  const auto ring_pass = [&](const std::vector<Vec2>& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
      if (orientation(a, b, p) == 0 && within_box(a, b, p)) return false;
      if ((a.y > p.y) != (b.y > p.y)) {
        const Vec2 lo = a.y < b.y ? a : b, hi = a.y < b.y ? b : a;
        if (orientation(lo, hi, p) > 0) inside = !inside;
      }
    }
    return true;
  };
  if (!ring_pass(polygon.outer)) return 0;
  for (const auto& hole : polygon.holes)
    if (!ring_pass(hole)) return 0;
  return inside ? 1 : -1;
}

// Vertices with an interior angle above 180 degrees (straight and repeated vertices dropped):
// reflex vertices of the outer ring and convex corners of the holes.
int reflex_count(const PolygonRings& polygon) {
  int count = 0;
  const auto ring_pass = [&](std::vector<Vec2> ring, bool hole) {
    std::vector<Vec2> kept;
    for (const Vec2 v : ring)
      if (kept.empty() || v.x != kept.back().x || v.y != kept.back().y) kept.push_back(v);
    while (kept.size() > 1 && kept.back().x == kept.front().x && kept.back().y == kept.front().y) kept.pop_back();
    const bool ccw = area2(kept) > 0.0;
    const std::size_t n = kept.size();
    for (std::size_t i = 0; i < n; ++i) {
      const int o = orientation(kept[(i + n - 1) % n], kept[i], kept[(i + 1) % n]);
      if (o != 0 && ((o < 0) == (ccw != hole))) ++count;
    }
  };
  ring_pass(polygon.outer, false);
  for (const auto& hole : polygon.holes) ring_pass(hole, true);
  return count;
}

struct Sampled {
  int inside = 0, outside = 0;
};

// Checks the partition's properties; `samples` are probed for coverage. `area`: whether a
// shoelace sum in doubles can tell the total area (not for slivers of 1e-310 beside 1e308).
Sampled check_partition(const PolygonRings& polygon, const Pieces& pieces, const std::vector<Vec2>& samples,
                        bool area = true) {
  std::set<std::pair<double, double>> input;
  for (const Vec2 v : polygon.outer) input.insert({v.x, v.y});
  for (const auto& hole : polygon.holes)
    for (const Vec2 v : hole) input.insert({v.x, v.y});
  bool convex = true, from_input = true;
  for (const auto& piece : pieces) {
    const std::size_t n = piece.size();
    if (n < 3) convex = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (orientation(piece[(i + n - 1) % n], piece[i], piece[(i + 1) % n]) <= 0) convex = false;
      if (!input.count({piece[i].x, piece[i].y})) from_input = false;
    }
  }
  CHECK(convex);  // strictly convex, counter-clockwise, at least 3 vertices
  CHECK(from_input);
  double unit = 0.0;
  for (const Vec2 v : polygon.outer) unit = std::max({unit, std::fabs(v.x), std::fabs(v.y)});
  const double expected = polygon_area(polygon, unit);
  if (area) CHECK(std::fabs(pieces_area(pieces, unit) - expected) <= 1e-12 * expected);
  // Hertel-Mehlhorn: every kept diagonal is needed at a reflex end, at most 2 per reflex vertex,
  // and d diagonals cut a polygon with h holes into d + 1 - h pieces.
  const int bound = 2 * reflex_count(polygon) + 1 - static_cast<int>(polygon.holes.size());
  CHECK(static_cast<int>(pieces.size()) <= bound);

  Sampled sampled;
  int uncovered = 0, covered_twice = 0, covered_outside = 0;
  for (const Vec2 p : samples) {
    const int where = classify(polygon, p);
    if (where == 0) continue;
    int closed = 0, strict = 0;
    for (const auto& piece : pieces) {
      int lowest = 1;
      for (std::size_t i = 0; i < piece.size() && lowest >= 0; ++i)
        lowest = std::min(lowest, orientation(piece[i], piece[(i + 1) % piece.size()], p));
      if (lowest >= 0) ++closed;
      if (lowest > 0) ++strict;
    }
    if (where > 0) {
      ++sampled.inside;
      if (closed == 0) ++uncovered;
      if (strict > 1) ++covered_twice;
    } else {
      ++sampled.outside;
      if (closed > 0) ++covered_outside;
    }
  }
  CHECK(uncovered == 0);
  CHECK(covered_twice == 0);
  CHECK(covered_outside == 0);
  return sampled;
}

Pieces partition_ok(const PolygonRings& polygon) {
  Pieces pieces;
  std::string error;
  const bool ok = partition_convex(polygon, pieces, error);
  CHECK_MESSAGE(ok, error);
  return pieces;
}

std::vector<Vec2> random_samples(std::mt19937_64& rng, const std::vector<Vec2>& outer, int count) {
  Vec2 lo = outer[0], hi = outer[0];
  for (const Vec2 v : outer) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y)};
  }
  const double mx = 0.1 * (hi.x - lo.x), my = 0.1 * (hi.y - lo.y);
  std::vector<Vec2> samples;
  for (int i = 0; i < count; ++i)
    samples.push_back({lo.x - mx + (hi.x - lo.x + 2 * mx) * uniform(rng), lo.y - my + (hi.y - lo.y + 2 * my) * uniform(rng)});
  return samples;
}

// A polygon star-shaped about `center`: angles spread so that consecutive ones are less than pi
// apart, radii in [0.2, 1] * radius.
std::vector<Vec2> random_star(std::mt19937_64& rng, int n, Vec2 center, double radius) {
  std::vector<Vec2> ring;
  for (int k = 0; k < n; ++k) {
    const double angle = 2.0 * 3.14159265358979323846 * (k + 0.45 * uniform(rng)) / n;
    const double r = radius * (0.2 + 0.8 * uniform(rng));
    ring.push_back({center.x + r * std::cos(angle), center.y + r * std::sin(angle)});
  }
  if (rng() % 2) std::reverse(ring.begin(), ring.end());
  return ring;
}

double segment_distance(Vec2 a, Vec2 b, Vec2 p) {
  const double ex = b.x - a.x, ey = b.y - a.y;
  double t = ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey);
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey));
}

// Up to `holes` small star holes (radius about `size`, centers within `spread` of the origin),
// each well clear of the outer boundary and of the others.
void add_random_holes(std::mt19937_64& rng, PolygonRings& polygon, int holes, double size = 0.1,
                      double spread = 1.0) {
  std::vector<std::pair<Vec2, double>> placed;
  for (int attempt = 0; attempt < 200 && static_cast<int>(placed.size()) < holes; ++attempt) {
    const Vec2 c{spread * (2.0 * uniform(rng) - 1.0), spread * (2.0 * uniform(rng) - 1.0)};
    const double r = size * (0.2 + uniform(rng));
    PolygonRings probe{polygon.outer, {}};
    if (classify(probe, c) <= 0) continue;
    bool clear = true;
    for (std::size_t i = 0; i < polygon.outer.size() && clear; ++i)
      clear = segment_distance(polygon.outer[i], polygon.outer[(i + 1) % polygon.outer.size()], c) > 1.5 * r;
    for (const auto& [q, rq] : placed) clear = clear && std::hypot(c.x - q.x, c.y - q.y) > 1.2 * (r + rq);
    if (!clear) continue;
    placed.push_back({c, r});
    polygon.holes.push_back(random_star(rng, uniform_int(rng, 3, 8), c, r));
  }
}

// A tile-map room: columns i = 0..w-1 of cells [lo_i, hi_i), consecutive columns overlapping,
// outlined on an integer grid of cell size 4 (straight vertices where neighbours line up);
// pillars (whole cells or cells inset by 1) where a cell and its 8 neighbours are floor and
// no other pillar is within one cell.
PolygonRings random_room(std::mt19937_64& rng) {
  const int w = uniform_int(rng, 2, 16);
  std::vector<int> lo(w), hi(w);
  lo[0] = uniform_int(rng, 0, 4);
  hi[0] = lo[0] + uniform_int(rng, 1, 8);
  for (int i = 1; i < w; ++i) {
    lo[i] = uniform_int(rng, std::max(0, lo[i - 1] - 3), hi[i - 1] - 1);
    hi[i] = uniform_int(rng, std::max(lo[i], lo[i - 1]) + 1, hi[i - 1] + 3);
  }
  PolygonRings room;
  for (int i = 0; i < w; ++i) {
    room.outer.push_back({4.0 * i, 4.0 * lo[i]});
    room.outer.push_back({4.0 * (i + 1), 4.0 * lo[i]});
  }
  for (int i = w - 1; i >= 0; --i) {
    room.outer.push_back({4.0 * (i + 1), 4.0 * hi[i]});
    room.outer.push_back({4.0 * i, 4.0 * hi[i]});
  }
  if (rng() % 2) std::reverse(room.outer.begin(), room.outer.end());
  std::vector<std::pair<int, int>> pillars;
  for (int i = 1; i + 1 < w; ++i)
    for (int j = 0; j < 16; ++j) {
      bool floor = true;
      for (int c = i - 1; c <= i + 1; ++c) floor = floor && lo[c] <= j - 1 && hi[c] >= j + 2;
      if (!floor || rng() % 3 != 0) continue;
      bool apart = true;
      for (const auto& [pi, pj] : pillars) apart = apart && std::max(std::abs(pi - i), std::abs(pj - j)) >= 2;
      if (!apart) continue;
      pillars.push_back({i, j});
      const double inset = rng() % 2 ? 1.0 : 0.0;
      const double x0 = 4.0 * i + inset, x1 = 4.0 * (i + 1) - inset, y0 = 4.0 * j + inset, y1 = 4.0 * (j + 1) - inset;
      std::vector<Vec2> hole{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
      if (rng() % 2) hole.insert(hole.begin() + 1, Vec2{0.5 * (x0 + x1), y0});  // a straight vertex
      if (rng() % 2) std::reverse(hole.begin(), hole.end());
      room.holes.push_back(hole);
    }
  return room;
}

}  // namespace

TEST_CASE("orientation: exact for any finite coordinates") {
  CHECK(orientation({0, 0}, {1, 0}, {0, 1}) == 1);
  CHECK(orientation({0, 0}, {0, 1}, {1, 0}) == -1);
  CHECK(orientation({0, 0}, {1, 1}, {3, 3}) == 0);
  // Products overflow (1e600) and cancel exactly; the smallest subnormal decides.
  CHECK(orientation({1e300, 1e300}, {-1e300, -1e300}, {0, 0}) == 0);
  CHECK(orientation({1e300, 1e300}, {-1e300, -1e300}, {0, 0x1p-1074}) == -1);
  CHECK(orientation({1e300, 1e300}, {-1e300, -1e300}, {0x1p-1074, 0}) == 1);
  // The doubles 0.1 and 0.3: 0.1 * 3 - 0.3 is about 2.8e-17 exactly, below the filter's reach.
  CHECK(orientation({0, 0}, {0.1, 1}, {0.3, 3}) == 1);
  CHECK(orientation({0, 0}, {0.3, 3}, {0.1, 1}) == -1);
  // Underflowing products: a turn of 2^-2000 - 2^-2002 is still seen to be to the left.
  CHECK(orientation({0, 0}, {0x1p-1000, 0x1p-1001}, {0x1p-1001, 0x1p-1000}) == 1);
  CHECK(orientation({0x1p-1070, 0x1p-1070}, {0x1p-1069, 0x1p-1069}, {0x1p-1068, 0x1p-1068}) == 0);
}

TEST_CASE("partition_convex: closed forms") {
  SUBCASE("a square is one piece, its own four corners") {
    const PolygonRings square{{{0, 0}, {2, 0}, {2, 2}, {0, 2}}, {}};
    const Pieces pieces = partition_ok(square);
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0].size() == 4);
    CHECK(pieces_area(pieces) == 4.0);
  }
  SUBCASE("an L is exactly two pieces") {
    const PolygonRings ell{{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, {}};
    const Pieces pieces = partition_ok(ell);
    CHECK(pieces.size() == 2);
    CHECK(pieces_area(pieces) == 3.0);
    check_partition(ell, pieces, {{0.5, 0.5}, {1.5, 0.5}, {0.5, 1.5}, {1.5, 1.5}, {1, 1}, {1, 0.5}, {0.5, 1}});
  }
  SUBCASE("a 4 x 4 square with a 2 x 2 hole: area 12, 4 to 8 pieces") {
    const PolygonRings framed{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}};
    const Pieces pieces = partition_ok(framed);
    CHECK(pieces_area(pieces) == 12.0);
    CHECK(pieces.size() >= 4);  // each hole corner needs a cut
    CHECK(pieces.size() <= 8);  // 2 * 4 reflex corners + 1 - 1 hole
    std::vector<Vec2> grid;
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 16; ++j) grid.push_back({0.25 * i, 0.25 * j});
    check_partition(framed, pieces, grid);
  }
  SUBCASE("a U (comb with two teeth) and a comb with four") {
    const PolygonRings u{{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}, {}};
    const Pieces pieces = partition_ok(u);
    CHECK(pieces_area(pieces) == 7.0);
    CHECK(pieces.size() >= 3);
    CHECK(pieces.size() <= 5);
    std::vector<Vec2> comb{{0, 0}, {7, 0}};
    for (int t = 3; t >= 0; --t) {  // teeth [2t, 2t + 1] x [1, 3] on a [0, 7] x [0, 1] base
      const double x = 2.0 * t;
      comb.insert(comb.end(), {{x + 1, 3}, {x, 3}});
      if (t > 0) comb.insert(comb.end(), {{x, 1}, {x - 1, 1}});
    }
    const PolygonRings comb_polygon{comb, {}};
    const Pieces comb_pieces = partition_ok(comb_polygon);
    CHECK(pieces_area(comb_pieces) == 7.0 + 4 * 2.0);
    std::vector<Vec2> grid;
    for (int i = 0; i <= 28; ++i)
      for (int j = 0; j <= 12; ++j) grid.push_back({0.25 * i, 0.25 * j});
    check_partition(comb_polygon, comb_pieces, grid);
  }
  SUBCASE("straight and repeated vertices are tolerated and dropped") {
    const PolygonRings noisy{{{0, 0}, {0, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}, {0, 0}}, {}};
    const Pieces pieces = partition_ok(noisy);
    REQUIRE(pieces.size() == 1);
    CHECK(pieces[0].size() == 4);
    CHECK(pieces_area(pieces) == 4.0);
  }
  SUBCASE("both windings give the same pieces' area") {
    std::vector<Vec2> outer{{0, 0}, {5, 0}, {5, 5}, {3, 2}, {0, 5}};
    std::vector<Vec2> hole{{1, 1}, {2, 1}, {2, 2}};
    const PolygonRings ccw{outer, {hole}};
    std::reverse(outer.begin(), outer.end());
    std::reverse(hole.begin(), hole.end());
    const PolygonRings cw{outer, {hole}};
    const Pieces a = partition_ok(ccw), b = partition_ok(cw);
    CHECK(pieces_area(a) == doctest::Approx(polygon_area(ccw)).epsilon(1e-15));
    CHECK(pieces_area(a) == pieces_area(b));
    CHECK(a.size() == b.size());
  }
  SUBCASE("far beyond 2^500 and far below 2^-500 the decisions stay exact") {
    for (const double s : {1e300, 1e-300}) {
      CAPTURE(s);
      const PolygonRings ell{{{0, 0}, {2 * s, 0}, {2 * s, s}, {s, s}, {s, 2 * s}, {0, 2 * s}}, {}};
      const Pieces pieces = partition_ok(ell);
      CHECK(pieces.size() == 2);
      for (const auto& piece : pieces)
        for (const Vec2 v : piece) CHECK((std::isfinite(v.x) && std::isfinite(v.y)));
      check_partition(ell, pieces, {{0.5 * s, 0.5 * s}, {1.5 * s, 0.5 * s}, {0.5 * s, 1.5 * s}, {1.5 * s, 1.5 * s}});
    }
  }
  SUBCASE("holes lined up on one horizontal line, their vertices level with one another") {
    // Vertices at equal heights, which the triangulation's sweep orders by x.
    PolygonRings row{{{0, 0}, {20, 0}, {20, 4}, {0, 4}}, {}};
    for (int k = 0; k < 6; ++k) {
      const double x = 1.0 + 3.0 * k;
      row.holes.push_back({{x, 1}, {x + 1, 2}, {x + 2, 2}, {x + 1, 3}});
    }
    const Pieces pieces = partition_ok(row);
    std::vector<Vec2> grid;
    for (int i = 0; i <= 80; ++i)
      for (int j = 0; j <= 16; ++j) grid.push_back({0.25 * i, 0.25 * j});
    check_partition(row, pieces, grid);
  }
}

TEST_CASE("partition_convex: random star polygons with and without holes") {
  std::mt19937_64 rng(20240611);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    CAPTURE(trial);
    const int n = trial < 20 ? 3 + trial : uniform_int(rng, 3, 200);
    PolygonRings polygon{random_star(rng, n, {0, 0}, 1.0), {}};
    if (trial % 2) add_random_holes(rng, polygon, uniform_int(rng, 1, 5));
    const Pieces pieces = partition_ok(polygon);
    std::vector<Vec2> samples = random_samples(rng, polygon.outer, 300);
    // Points near every hole too, where diagonals and the pieces around them are.
    for (const auto& hole : polygon.holes)
      for (const Vec2 v : hole)
        for (int k = 0; k < 4; ++k) samples.push_back({v.x + 0.02 * (uniform(rng) - 0.5), v.y + 0.02 * (uniform(rng) - 0.5)});
    const Sampled s = check_partition(polygon, pieces, samples);
    inside += s.inside;
    outside += s.outside;
  }
  CHECK(inside > 10000);  // the sampling did probe both sides
  CHECK(outside > 10000);
}

TEST_CASE("partition_convex: tile-map rooms with pillars, probed on the grid lines") {
  std::mt19937_64 rng(777);
  int with_holes = 0;
  for (int trial = 0; trial < 200; ++trial) {
    CAPTURE(trial);
    const PolygonRings room = random_room(rng);
    with_holes += room.holes.empty() ? 0 : 1;
    const Pieces pieces = partition_ok(room);
    // Integer coordinates: the areas are exact.
    CHECK(pieces_area(pieces) == polygon_area(room));
    std::vector<Vec2> samples = random_samples(rng, room.outer, 200);
    double top = 0.0, right = 0.0;
    for (const Vec2 v : room.outer) {
      top = std::max(top, v.y);
      right = std::max(right, v.x);
    }
    // Half-integer points: many on grid lines, piece edges and vertices.
    for (int k = 0; k < 400; ++k)
      samples.push_back({0.5 * uniform_int(rng, -2, static_cast<int>(2 * right) + 2),
                         0.5 * uniform_int(rng, -2, static_cast<int>(2 * top) + 2)});
    check_partition(room, pieces, samples);
  }
  CHECK(with_holes > 50);
}

TEST_CASE("partition_convex: small-integer polygons, where diagonals meet vertices and lines") {
  // Coordinates on a coarse grid: vertices level with one another (the sweep's ties), lines
  // through vertices run through other vertices and along edges, holes share their largest x,
  // many vertices are collinear. Random rings may be invalid (refused, never for an internal
  // reason); the valid ones must partition exactly.
  std::mt19937_64 rng(99);
  int accepted = 0, holed = 0;
  for (int trial = 0; trial < 600; ++trial) {
    CAPTURE(trial);
    PolygonRings polygon;
    for (const Vec2 v : random_star(rng, uniform_int(rng, 3, 24), {0, 0}, 12.0))
      polygon.outer.push_back({std::round(v.x), std::round(v.y)});
    Pieces pieces;
    std::string error;
    const auto try_partition = [&] {
      if (partition_convex(polygon, pieces, error)) return true;
      CHECK_MESSAGE(error.find("internal") == std::string::npos, error);
      CHECK(pieces.empty());
      return false;
    };
    if (!try_partition()) continue;
    // Holes kept only where the polygon stays valid.
    const int holes = uniform_int(rng, 0, 8);
    for (int h = 0; h < holes; ++h) {
      const Vec2 c{static_cast<double>(uniform_int(rng, -8, 8)), static_cast<double>(uniform_int(rng, -8, 8))};
      std::vector<Vec2> hole;
      for (const Vec2 v : random_star(rng, uniform_int(rng, 3, 6), {0, 0}, 3.0))
        hole.push_back({c.x + std::round(v.x), c.y + std::round(v.y)});
      polygon.holes.push_back(hole);
      if (!try_partition()) polygon.holes.pop_back();
    }
    REQUIRE(try_partition());
    ++accepted;
    holed += polygon.holes.empty() ? 0 : 1;
    CHECK(pieces_area(pieces) == polygon_area(polygon));
    std::vector<Vec2> samples;
    for (int i = -26; i <= 26; ++i)
      for (int j = -26; j <= 26; ++j) samples.push_back({0.5 * i, 0.5 * j});
    check_partition(polygon, pieces, samples);
  }
  CHECK(accepted > 200);
  CHECK(holed > 100);
}

TEST_CASE("partition_convex: arbitrary rings of extreme coordinates neither crash nor slip") {
  // Coordinates from the largest doubles to subnormals: products overflow and underflow, so
  // every decision goes through the exact fallback. Refusals must be the input's fault, and an
  // acceptance must still give strictly convex pieces of input vertices.
  std::mt19937_64 rng(5);
  const double values[] = {0.0, 1.0, -1.0, 3.0, -0.5, 1e308, -1e308, 1.7e308, 1e-310, -1e-310, 0x1p-1074, 7e200};
  std::vector<Vec2> probes;  // every pair of values and of their halves: exact, on many lines
  for (const double x : values)
    for (const double y : values) {
      probes.push_back({x, y});
      probes.push_back({0.5 * x, 0.5 * y});
    }
  int accepted = 0, probed = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    CAPTURE(trial);
    PolygonRings polygon;
    const auto ring = [&](int n) {
      std::vector<Vec2> r;
      for (int k = 0; k < n; ++k) r.push_back({values[rng() % 12], values[rng() % 12]});
      return r;
    };
    polygon.outer = ring(uniform_int(rng, 3, 8));
    if (rng() % 4 == 0) polygon.holes.push_back(ring(uniform_int(rng, 3, 5)));
    Pieces pieces;
    std::string error;
    if (!partition_convex(polygon, pieces, error)) {
      CHECK_MESSAGE(error.find("internal") == std::string::npos, error);
      CHECK(pieces.empty());
      continue;
    }
    ++accepted;
    probed += check_partition(polygon, pieces, probes, false).inside;
  }
  CHECK(accepted > 100);
  CHECK(probed > 100);
}

TEST_CASE("partition_convex: refusals name the ring and leave no pieces") {
  const auto refused = [](const PolygonRings& polygon, const std::string& expected) {
    Pieces pieces{{{9, 9}, {9, 9}, {9, 9}}};
    std::string error;
    CHECK_FALSE(partition_convex(polygon, pieces, error));
    CHECK_MESSAGE(error.find(expected) != std::string::npos, error);
    CHECK(pieces.empty());
  };
  const std::vector<Vec2> square{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  refused({{{0, 0}, {1, 1}, {1, 0}, {0, 1}}, {}}, "outer: edges 0 and 2 cross");
  refused({{{0, 0}, {2, 0}, {1, 1}, {2, 2}, {0, 2}, {1, 1}}, {}}, "touch");  // a vertex visited twice
  refused({{{0, 0}, {4, 0}, {4, 4}, {2, 0}, {0, 4}}, {}}, "outer: edges");  // a vertex on another edge
  refused({square, {{{3, 1}, {5, 1}, {5, 2}, {3, 2}}}}, "holes[0] crosses the outer boundary");
  refused({square, {{{0, 1}, {1, 1}, {1, 2}}}}, "holes[0] touches the outer boundary");
  refused({square, {{{5, 5}, {6, 5}, {6, 6}}}}, "holes[0]: not inside the outer boundary");
  refused({{{1, 1}, {2, 1}, {2, 2}}, {square}}, "holes[0]: not inside the outer boundary");  // the hole holds the outer ring
  refused({square, {{{1, 1}, {3, 1}, {3, 2}}, {{2.5, 1.2}, {3.5, 3}, {2, 3}}}}, "holes[0] and holes[1] overlap");
  refused({square, {{{1, 1}, {2, 1}, {2, 2}}, {{2, 2}, {3, 2}, {3, 3}}}}, "holes[0] and holes[1] touch");
  refused({square, {{{0.5, 0.5}, {3.5, 0.5}, {3.5, 3.5}, {0.5, 3.5}}, {{1, 1}, {2, 1}, {2, 2}}}},
          "holes[1] lies inside holes[0] (nested holes)");
  refused({{{0, 0}, {1, 1}, {0, 0}, {1, 1}}, {}}, "outer: fewer than 3 distinct vertices");
  refused({{}, {}}, "outer: fewer than 3 distinct vertices");
  refused({square, {{}}}, "holes[0]: fewer than 3 distinct vertices");
  refused({{{0, 0}, {1, 1}, {2, 2}, {3, 3}}, {}}, "outer: zero area");
  refused({square, {{{1, 1}, {2, 2}, {3, 3}}}}, "holes[0]: zero area");
  refused({{{0, 0}, {4, 0}, {6, 0}, {4, 0}, {4, 4}, {0, 4}}, {}}, "outer: the edges at vertex 2 fold back");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  refused({{{0, 0}, {nan, 0}, {1, 1}}, {}}, "outer: vertex 1 is not finite");
  refused({square, {{{1, 1}, {2, 1}, {2, -inf}}}}, "holes[0]: vertex 2 is not finite");
  refused({{{0, 0}, {1, 0}, {1, inf}}, {}}, "outer: vertex 2 is not finite");
  std::vector<Vec2> huge(detail::kMaxPartitionVertices + 1);
  for (std::size_t i = 0; i < huge.size(); ++i) huge[i] = {std::cos(1e-4 * static_cast<double>(i)), std::sin(1e-4 * static_cast<double>(i))};
  refused({huge, {}}, "too many vertices");
}

TEST_CASE("partition_convex: a 4096-vertex star polygon") {
  std::mt19937_64 rng(4096);
  PolygonRings polygon{random_star(rng, 4096, {0, 0}, 1.0), {}};
  Pieces pieces;
  std::string error;
  const auto start = std::chrono::steady_clock::now();
  const bool ok = partition_convex(polygon, pieces, error);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  MESSAGE("4096-vertex star: " << pieces.size() << " pieces in " << seconds * 1e3 << " ms");
  REQUIRE_MESSAGE(ok, error);
  check_partition(polygon, pieces, random_samples(rng, polygon.outer, 2000));
  // And with 20 holes.
  add_random_holes(rng, polygon, 20, 0.02, 0.2);
  CHECK(polygon.holes.size() >= 10);
  const Pieces holed = partition_ok(polygon);
  check_partition(polygon, holed, random_samples(rng, polygon.outer, 2000));
}

std::vector<Vec2> comb(int teeth, bool sideways) { return bench::comb_outline(teeth, sideways); }

TEST_CASE("partition_convex: combs with their teeth along either axis, exact, their validation and shared boundaries linear in their teeth") {
  // Eight times the teeth: the pairs of edges the validation compares and the pairs of piece
  // edges shared_boundaries compares grow about eightfold (64-fold when every tooth's edges
  // are compared with every other tooth's, as they were along y, and for shared boundaries
  // along x too).
  for (const bool sideways : {false, true}) {
    CAPTURE(sideways);
    std::size_t edge_pairs[2] = {}, triangulation_tests[2] = {}, boundary_pairs[2] = {};
    const int teeth[2] = {500, 4000};
    for (int size = 0; size < 2; ++size) {
      const PolygonRings polygon{comb(teeth[size], sideways), {}};
      Pieces pieces;
      std::string error;
      detail::PartitionWork work;
      REQUIRE_MESSAGE(partition_convex(polygon, pieces, error, &work), error);
      std::vector<Polygon> as_polygons;
      for (const auto& piece : pieces) as_polygons.push_back(Polygon{piece});
      std::vector<Segment> shared;
      detail::shared_boundaries(as_polygons, shared, &boundary_pairs[size]);
      edge_pairs[size] = work.edge_pairs;
      triangulation_tests[size] = work.triangulation_tests;
      // One piece per tooth and the base under them all, T-junctions with the base at each tooth.
      CHECK(pieces.size() == static_cast<std::size_t>(teeth[size]) + 1);
      CHECK(shared.size() == static_cast<std::size_t>(teeth[size]));
      if (size == 0) {
        std::mt19937_64 rng(static_cast<std::uint64_t>(teeth[size]) + sideways);
        check_partition(polygon, pieces, random_samples(rng, polygon.outer, 4000));
      }
    }
    MESSAGE("edge pairs " << edge_pairs[0] << " -> " << edge_pairs[1] << ", triangulation tests " << triangulation_tests[0] << " -> "
                          << triangulation_tests[1] << ", boundary pairs " << boundary_pairs[0] << " -> " << boundary_pairs[1]);
    CHECK(edge_pairs[1] <= 12 * edge_pairs[0]);
    CHECK(boundary_pairs[1] <= 12 * boundary_pairs[0]);
  }
}

TEST_CASE("partition_convex: a 65,534-vertex comb, the most a partition takes, along either axis") {
  for (const bool sideways : {false, true}) {
    CAPTURE(sideways);
    const PolygonRings polygon{comb(16383, sideways), {}};
    REQUIRE(polygon.outer.size() == 65534);
    Pieces pieces;
    std::string error;
    detail::PartitionWork work;
    REQUIRE_MESSAGE(partition_convex(polygon, pieces, error, &work), error);
    CHECK(pieces.size() == 16384);
    // Linear: a few pairs a vertex (every pair of teeth would be 5e8).
    CHECK(work.edge_pairs <= 8 * polygon.outer.size());
    std::vector<Polygon> as_polygons;
    for (const auto& piece : pieces) as_polygons.push_back(Polygon{piece});
    std::vector<Segment> shared;
    std::size_t pairs = 0;
    detail::shared_boundaries(as_polygons, shared, &pairs);
    CHECK(shared.size() == 16383);
    CHECK(pairs <= 8 * polygon.outer.size());
  }
}

// Whether closed segments ab and cd meet, exactly (the reference for the simplicity sweep).
bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within_box(a, b, c)) || (o2 == 0 && within_box(a, b, d)) || (o3 == 0 && within_box(c, d, a)) ||
         (o4 == 0 && within_box(c, d, b));
}

TEST_CASE("partition_convex: outlines whose edges' boxes all overlap (stars) are refused exactly when two edges meet") {
  // Stars on integer coordinates, their edges' boxes overlapping pairwise far more than the
  // edges are many (the validation then sweeps), each with one vertex moved: anywhere, onto
  // another vertex, onto the middle of another edge (exactly on it), or onto a hole's vertex.
  // The verdict must be the all-pairs check's.
  std::mt19937_64 rng(20261207);
  int refused = 0, accepted = 0;
  for (int trial = 0; trial < 120; ++trial) {
    CAPTURE(trial);
    PolygonRings polygon;
    const int n = 400 + static_cast<int>(rng() % 200);
    for (const Vec2 v : random_star(rng, n, {0, 0}, 1.0))
      polygon.outer.push_back({2.0 * std::round(v.x * 50000.0), 2.0 * std::round(v.y * 50000.0)});
    if (trial % 3 == 0) polygon.holes.push_back({{-2000, -2000}, {2000, -2000}, {2000, 2000}, {-2000, 2000}});
    const int i = static_cast<int>(rng() % static_cast<std::uint64_t>(n));
    const int j = (i + 2 + static_cast<int>(rng() % static_cast<std::uint64_t>(n - 3))) % n;  // not i, not next to it
    const Vec2 a = polygon.outer[static_cast<std::size_t>(j)], b = polygon.outer[static_cast<std::size_t>((j + 1) % n)];
    switch (trial % 4) {
      case 0: polygon.outer[static_cast<std::size_t>(i)] = {2.0 * static_cast<double>(rng() % 100000) - 1e5, 0.0}; break;
      case 1: polygon.outer[static_cast<std::size_t>(i)] = a; break;
      case 2: polygon.outer[static_cast<std::size_t>(i)] = {(a.x + b.x) / 2, (a.y + b.y) / 2}; break;
      default: if (!polygon.holes.empty()) polygon.outer[static_cast<std::size_t>(i)] = polygon.holes[0][rng() % 4];
    }
    // Leave out moves that made a vertex straight or repeated (cleaning would drop it).
    const auto& o = polygon.outer;
    const std::size_t u = static_cast<std::size_t>(i);
    const Vec2 prev = o[(u + o.size() - 1) % o.size()], next = o[(u + 1) % o.size()];
    if (orientation(prev, o[u], next) == 0) continue;
    struct RingEdge {
      Vec2 a, b;
      std::size_t ring, k, size;
    };
    std::vector<RingEdge> edges;
    for (std::size_t r = 0; r <= polygon.holes.size(); ++r) {
      const auto& ring = r == 0 ? polygon.outer : polygon.holes[r - 1];
      for (std::size_t k = 0; k < ring.size(); ++k) edges.push_back({ring[k], ring[(k + 1) % ring.size()], r, k, ring.size()});
    }
    bool meet = false;
    for (std::size_t e = 0; e < edges.size() && !meet; ++e)
      for (std::size_t f = e + 1; f < edges.size() && !meet; ++f) {
        const RingEdge &x = edges[e], &y = edges[f];
        if (x.ring == y.ring && ((x.k + 1) % x.size == y.k || (y.k + 1) % y.size == x.k)) continue;  // adjacent
        meet = segments_touch(x.a, x.b, y.a, y.b);
      }
    Pieces pieces;
    std::string error;
    detail::PartitionWork work;
    const bool ok = partition_convex(polygon, pieces, error, &work);
    CHECK(work.edge_pairs < 40 * edges.size());  // swept: nowhere near the pairs of overlapping boxes
    CHECK(ok == !meet);
    if (ok) {
      ++accepted;
      check_partition(polygon, pieces, random_samples(rng, polygon.outer, 300));
    } else {
      ++refused;
      CHECK((error.find("cross") != std::string::npos || error.find("touch") != std::string::npos));
    }
  }
  CHECK(refused > 40);
  CHECK(accepted > 10);
}

TEST_CASE("partition_convex: many holes, placed by the sweep: holes outside the outer boundary and nested holes are refused by name") {
  // A square with a 6 x 6 grid of holes (more hole pairs than vertices: the sweep places them),
  // every other one wound the other way and some of them triangles.
  std::mt19937_64 rng(36);
  const auto grid = [] {
    PolygonRings p{{{0, 0}, {19, 0}, {19, 19}, {0, 19}}, {}};
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) {
        const double x = 3.0 * a + 1, y = 3.0 * b + 1;
        std::vector<Vec2> hole{{x, y}, {x + 2, y}, {x + 2, y + 2}, {x, y + 2}};
        if ((a + b) % 3 == 0) hole.erase(hole.begin() + 2);
        if ((a + b) % 2 == 0) std::reverse(hole.begin(), hole.end());
        p.holes.push_back(hole);
      }
    return p;
  };
  const PolygonRings valid = grid();
  check_partition(valid, partition_ok(valid), random_samples(rng, valid.outer, 3000));
  for (int trial = 0; trial < 10; ++trial) {  // random stars with many small holes
    PolygonRings star{random_star(rng, 40, {0, 0}, 1.0), {}};
    add_random_holes(rng, star, 40, 0.02, 0.05);
    std::size_t total = star.outer.size();
    for (const auto& hole : star.holes) total += hole.size();
    REQUIRE(star.holes.size() * star.holes.size() > total);
    check_partition(star, partition_ok(star), random_samples(rng, star.outer, 1000));
  }
  const auto refused_with = [](const PolygonRings& p, const std::string& expected) {
    Pieces pieces;
    std::string error;
    CHECK_FALSE(partition_convex(p, pieces, error));
    CHECK(error == expected);
    CHECK(pieces.empty());
  };
  PolygonRings outside = grid();
  for (Vec2& v : outside.holes[7]) v.x += 100.0;
  refused_with(outside, "holes[7]: not inside the outer boundary");
  PolygonRings left_of_all = grid();
  for (Vec2& v : left_of_all.holes[20]) v.x -= 100.0;
  refused_with(left_of_all, "holes[20]: not inside the outer boundary");
  PolygonRings nested = grid();
  nested.holes[12] = {{4.5, 4.5}, {4.75, 4.5}, {4.75, 4.75}, {4.5, 4.75}};  // inside holes[7]'s square
  refused_with(nested, "holes[12] lies inside holes[7] (nested holes)");
  PolygonRings nested_deeper = nested;  // inside holes[12], itself inside holes[7]
  nested_deeper.holes[30] = {{4.6, 4.6}, {4.7, 4.6}, {4.7, 4.7}};
  refused_with(nested_deeper, "holes[12] lies inside holes[7] (nested holes)");
  PolygonRings in_outside = outside;  // inside holes[7], which lies outside the outer boundary
  in_outside.holes[13] = {{104.5, 4.5}, {104.75, 4.5}, {104.75, 4.75}};
  refused_with(in_outside, "holes[7]: not inside the outer boundary");
}

// Every stretch two pieces share, by comparing every pair of edges of different pieces: the
// reference for shared_boundaries, as sorted (from, to) pairs, each ordered lexicographically.
std::vector<std::array<double, 4>> all_pairs_shared(const std::vector<Polygon>& pieces) {
  const auto less = [](Vec2 p, Vec2 q) { return p.x < q.x || (p.x == q.x && p.y < q.y); };
  std::vector<std::array<double, 4>> out;
  for (std::size_t a = 0; a < pieces.size(); ++a)
    for (std::size_t b = a + 1; b < pieces.size(); ++b) {
      const auto& u = pieces[a].vertices;
      const auto& v = pieces[b].vertices;
      for (std::size_t i = 0; i < u.size(); ++i)
        for (std::size_t j = 0; j < v.size(); ++j) {
          Vec2 p = u[i], q = u[(i + 1) % u.size()], r = v[j], t = v[(j + 1) % v.size()];
          if (orientation(p, q, r) != 0 || orientation(p, q, t) != 0) continue;
          if (less(q, p)) std::swap(p, q);
          if (less(t, r)) std::swap(r, t);
          const Vec2 from = less(p, r) ? r : p, to = less(q, t) ? q : t;
          if (less(from, to)) out.push_back({from.x, from.y, to.x, to.y});
        }
    }
  std::sort(out.begin(), out.end());
  return out;
}

TEST_CASE("shared_boundaries: every stretch the pieces share, slanted ones included, comparing few pairs on stars") {
  std::mt19937_64 rng(314);
  for (int trial = 0; trial < 24; ++trial) {
    CAPTURE(trial);
    PolygonRings polygon;
    if (trial % 3 == 2) {
      // A comb slanted (its teeth's sides and the base's top on shared slanted lines), at
      // ordinary and at huge and tiny scales.
      polygon.outer = bench::comb_outline(20 + trial, false);
      const double scale = trial % 2 ? 1e300 : 1e-300;
      for (Vec2& v : polygon.outer) v = {(v.x - 0.75 * v.y) * (trial < 12 ? 1.0 : scale), (0.5 * v.x + v.y) * (trial < 12 ? 1.0 : scale)};
    } else {
      polygon.outer = random_star(rng, 300, {0, 0}, 1.0);
      if (trial % 3 == 1) add_random_holes(rng, polygon, 4);
    }
    const Pieces pieces = partition_ok(polygon);
    std::vector<Polygon> as_polygons;
    std::size_t piece_edges = 0;
    for (const auto& piece : pieces) {
      as_polygons.push_back(Polygon{piece});
      piece_edges += piece.size();
    }
    std::vector<Segment> shared;
    std::size_t pairs = 0;
    detail::shared_boundaries(as_polygons, shared, &pairs);
    std::vector<std::array<double, 4>> found;
    const auto less = [](Vec2 p, Vec2 q) { return p.x < q.x || (p.x == q.x && p.y < q.y); };
    for (const Segment& g : shared) {
      const Vec2 p = less(g.a, g.b) ? g.a : g.b, q = less(g.a, g.b) ? g.b : g.a;
      found.push_back({p.x, p.y, q.x, q.y});
    }
    std::sort(found.begin(), found.end());
    const auto expected = all_pairs_shared(as_polygons);
    CHECK(found == expected);
    CHECK(expected.size() + 1 >= pieces.size());  // the pieces are connected through them
    if (trial % 3 != 2) CHECK(pairs <= 4 * piece_edges);
  }
}

// Comb, slanted comb, star, spiral, and a square with a grid of holes, of about n vertices.
PolygonRings growth_shape(int kind, int n, std::mt19937_64& rng) {
  PolygonRings p;
  switch (kind) {
    case 0: p.outer = bench::comb_outline(n / 4, false); break;
    case 1: p.outer = bench::comb_outline(n / 4, true); break;
    case 2:
      p.outer = bench::comb_outline(n / 4, false);
      for (Vec2& v : p.outer) v = {v.x - 0.75 * v.y, 0.5 * v.x + v.y};
      break;
    case 3: p.outer = random_star(rng, n, {0, 0}, 1.0); break;
    case 4:
      for (int k = 0; k < n / 2; ++k) {
        const double t = 16.0 * 3.14159265358979323846 * k / (n / 2);
        p.outer.push_back({(1.0 + t) * std::cos(t), (1.0 + t) * std::sin(t)});
      }
      for (int k = n / 2 - 1; k >= 0; --k) {
        const double t = 16.0 * 3.14159265358979323846 * k / (n / 2);
        p.outer.push_back({(4.0 + t) * std::cos(t), (4.0 + t) * std::sin(t)});
      }
      break;
    default: {
      const int k = static_cast<int>(std::lround(std::sqrt(n / 4.0)));
      p.outer = {{0, 0}, {3.0 * k + 1, 0}, {3.0 * k + 1, 3.0 * k + 1}, {0, 3.0 * k + 1}};
      for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b)
          p.holes.push_back({{3.0 * a + 1, 3.0 * b + 1}, {3.0 * a + 3, 3.0 * b + 1}, {3.0 * a + 3, 3.0 * b + 3}, {3.0 * a + 1, 3.0 * b + 3}});
    }
  }
  return p;
}

TEST_CASE("partition_convex: its work grows as n log n on combs, stars, spirals and holed squares") {
  // The pairs of edges the validation compares plus the triangulation's orientation tests, at
  // about 4,000 and 16,000 vertices: n log n gives at most 4 x 1.2 = 4.8 times the work (the
  // log grows by 2 in 12), a quadratic part 16 times. Ear clipping scanned a comb's base fan
  // (16 times) and the validation compared every pair of a star's edges (16 times).
  for (int kind = 0; kind < 6; ++kind) {
    CAPTURE(kind);
    std::size_t total[2] = {};
    std::size_t vertices[2] = {};
    for (int size = 0; size < 2; ++size) {
      std::mt19937_64 rng(static_cast<std::uint64_t>(kind));
      const PolygonRings polygon = growth_shape(kind, size == 0 ? 4000 : 16000, rng);
      vertices[size] = polygon.outer.size();
      for (const auto& hole : polygon.holes) vertices[size] += hole.size();
      Pieces pieces;
      std::string error;
      detail::PartitionWork work;
      REQUIRE_MESSAGE(partition_convex(polygon, pieces, error, &work), error);
      total[size] = work.edge_pairs + work.triangulation_tests;
    }
    MESSAGE("kind " << kind << ": " << vertices[0] << " -> " << vertices[1] << " vertices, work " << total[0] << " -> "
                    << total[1]);
    CHECK(vertices[1] <= 4 * vertices[0] + 16);
    CHECK(total[1] <= 5 * total[0]);
  }
}

}  // namespace par2d::test
