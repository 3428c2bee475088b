// The boundaries a partition's pieces share (polygon_partition.hpp): where a concave light's
// pieces meet, which the World lights with negative emission.
#include <algorithm>
#include <utility>
#include <vector>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {

void shared_boundaries(const std::vector<Polygon>& pieces, std::vector<Segment>& out, std::size_t* pairs) {
  std::size_t compared = 0;
  // Two pieces with disjoint interiors meet along collinear edges of opposite direction; an
  // edge on the polygon's boundary has the outside on one side and meets no other piece's.
  struct Edge {
    Vec2 lo, hi;  // ordered along the edge's main axis
    bool by_x;    // the axis: x unless the edge is vertical
    std::size_t piece;
  };
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
  // x, then y; horizontal ones by y, then x; the rest by x. Pieces side by side along an axis
  // (a comb's teeth) then compare an edge with the edges on its own line only, not with every
  // edge whose range overlaps its own.
  const auto kind = [](const Edge& e) { return !e.by_x ? 0 : (e.lo.y == e.hi.y ? 1 : 2); };
  const auto line = [&kind](const Edge& e) { return kind(e) == 0 ? e.lo.x : (kind(e) == 1 ? e.lo.y : 0.0); };
  std::vector<std::size_t> order(edges.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Edge& e = edges[a];
    const Edge& f = edges[b];
    if (kind(e) != kind(f)) return kind(e) < kind(f);
    if (line(e) != line(f)) return line(e) < line(f);
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
      if (kind(f) != kind(e) || line(f) != line(e) || !(key(e, f.lo) < key(e, e.hi))) break;
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
