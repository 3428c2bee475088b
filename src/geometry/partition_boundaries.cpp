// The boundaries a partition's pieces share (polygon_partition.hpp): where a concave light's
// pieces meet, which the World lights with negative emission.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {

namespace {

struct Edge {
  Vec2 lo, hi;  // ordered along the edge's main axis
  bool by_x;    // the axis: x unless the edge is vertical
  std::size_t piece;
};

// For each slanted edge (neither vertical nor horizontal) a group number such that collinear
// edges share theirs (others may too); 0 for the rest. Collinear edges' direction angles and
// distances of their line from the origin, computed in doubles, differ by rounding only: at
// most about 1e-15 radians and 1e-15 of the largest coordinate. So edges sorted by angle are
// chained into a group while neighbours lie within 1e-12 of each other, then each group by
// distance alike; a pair exactly collinear never falls apart, and a star's edges, whose
// directions all differ, form groups of one or two instead of one group of all.
std::vector<double> slanted_lines(const std::vector<Edge>& edges) {
  std::vector<double> group(edges.size(), 0.0);
  std::vector<std::size_t> slanted;
  std::vector<double> angle(edges.size()), distance(edges.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (!e.by_x || e.lo.y == e.hi.y) continue;
    const double dx = e.hi.x - e.lo.x, dy = e.hi.y - e.lo.y, length = std::hypot(dx, dy);
    angle[i] = std::atan2(dy, dx);
    distance[i] = (dx * e.lo.y - dy * e.lo.x) / length;
    // Overflowed or underflowed far: one group for all, as a sweep by x alone.
    if (!std::isfinite(angle[i]) || !std::isfinite(distance[i]) || !std::isfinite(length) || length == 0.0) return group;
    largest = std::max({largest, std::abs(e.lo.x), std::abs(e.lo.y), std::abs(e.hi.x), std::abs(e.hi.y)});
    slanted.push_back(i);
  }
  const double angle_gap = 1e-12, distance_gap = 1e-12 * largest;
  std::sort(slanted.begin(), slanted.end(), [&](std::size_t a, std::size_t b) { return angle[a] < angle[b]; });
  double next = 1.0;
  for (std::size_t first = 0; first < slanted.size();) {
    std::size_t last = first + 1;
    while (last < slanted.size() && angle[slanted[last]] - angle[slanted[last - 1]] <= angle_gap) ++last;
    const auto begin = slanted.begin() + static_cast<std::ptrdiff_t>(first), end = slanted.begin() + static_cast<std::ptrdiff_t>(last);
    std::sort(begin, end, [&](std::size_t a, std::size_t b) { return distance[a] < distance[b]; });
    for (auto it = begin; it != end; ++it) {
      if (it != begin && distance[*it] - distance[*(it - 1)] > distance_gap) next += 1.0;
      group[*it] = next;
    }
    next += 1.0;
    first = last;
  }
  return group;
}

}  // namespace

void shared_boundaries(const std::vector<Polygon>& pieces, std::vector<Segment>& out, std::size_t* pairs) {
  std::size_t compared = 0;
  // Two pieces with disjoint interiors meet along collinear edges of opposite direction; an
  // edge on the polygon's boundary has the outside on one side and meets no other piece's.
  std::vector<Edge> edges;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const std::vector<Vec2>& v = pieces[p].vertices;
    for (std::size_t i = 0; i < v.size(); ++i) {
      Vec2 a = v[i], b = v[(i + 1) % v.size()];
      const bool by_x = a.x != b.x;
      if (by_x ? b.x < a.x : b.y < a.y) std::swap(a, b);
      edges.push_back({a, b, by_x, p});
    }
  }
  const auto key = [](const Edge& e, Vec2 v) { return e.by_x ? v.x : v.y; };
  // The stretches come out in the order of a sweep over every edge sorted by its main axis
  // (vertical edges first, by y; then the rest by x), pair by pair, the earlier edge first.
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    if (a.by_x != b.by_x) return a.by_x < b.by_x;
    return a.by_x ? a.lo.x < b.lo.x : a.lo.y < b.lo.y;
  });
  // But collinear edges share their line, so the sweep runs within classes: vertical edges by
  // x, then y; horizontal ones by y, then x; the rest by x within groups that hold every
  // collinear pair (slanted_lines). Pieces side by side along an axis
  // (a comb's teeth) then compare an edge with the edges on its own line only, not with every
  // edge whose range overlaps its own.
  const auto kind = [](const Edge& e) { return !e.by_x ? 0 : (e.lo.y == e.hi.y ? 1 : 2); };
  const std::vector<double> slanted_line = slanted_lines(edges);
  const auto line = [&](std::size_t i) {
    const Edge& e = edges[i];
    return kind(e) == 0 ? e.lo.x : (kind(e) == 1 ? e.lo.y : slanted_line[i]);
  };
  std::vector<std::size_t> order(edges.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Edge& e = edges[a];
    const Edge& f = edges[b];
    if (kind(e) != kind(f)) return kind(e) < kind(f);
    if (line(a) != line(b)) return line(a) < line(b);
    return key(e, e.lo) < key(f, f.lo) || (key(e, e.lo) == key(f, f.lo) && a < b);
  });
  struct Found {
    std::size_t first, second;  // the pair's places in the sweep's order
    Segment stretch;
  };
  std::vector<Found> found;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Edge& e = edges[order[i]];
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const Edge& f = edges[order[j]];
      if (kind(f) != kind(e) || line(order[j]) != line(order[i]) || !(key(e, f.lo) < key(e, e.hi))) break;
      ++compared;
      // Vertical and horizontal edges on one line are collinear exactly; the rest are tested.
      if (f.piece == e.piece || (kind(e) == 2 && (orientation(e.lo, e.hi, f.lo) != 0 || orientation(e.lo, e.hi, f.hi) != 0)))
        continue;
      // Collinear and overlapping along the axis: the stretch from the later start to the
      // earlier end (both piece vertices).
      const Vec2 from = key(e, f.lo) < key(e, e.lo) ? e.lo : f.lo;
      const Vec2 to = key(e, f.hi) < key(e, e.hi) ? f.hi : e.hi;
      if (key(e, from) < key(e, to)) found.push_back({std::min(order[i], order[j]), std::max(order[i], order[j]), Segment{from, to}});
    }
  }
  std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  for (const Found& f : found) out.push_back(f.stretch);
  if (pairs != nullptr) *pairs = compared;
}

}  // namespace par2d::detail
