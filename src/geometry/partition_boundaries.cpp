// The boundaries a partition's pieces share (polygon_partition.hpp): where a concave light's
// pieces meet, which the World lights with negative emission.
#include <algorithm>
#include <utility>
#include <vector>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {

void shared_boundaries(const std::vector<Polygon>& pieces, std::vector<Segment>& out) {
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
  // Vertical edges only overlap vertical ones, and those only in y; the rest in x.
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    if (a.by_x != b.by_x) return a.by_x < b.by_x;
    return a.by_x ? a.lo.x < b.lo.x : a.lo.y < b.lo.y;
  });
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    for (std::size_t j = i + 1; j < edges.size() && edges[j].by_x == e.by_x && key(e, edges[j].lo) < key(e, e.hi); ++j) {
      const Edge& f = edges[j];
      if (f.piece == e.piece || orientation(e.lo, e.hi, f.lo) != 0 || orientation(e.lo, e.hi, f.hi) != 0) continue;
      // Collinear and overlapping along the axis: the stretch from the later start to the
      // earlier end (both piece vertices).
      const Vec2 from = f.lo;  // f starts no earlier than e (sorted)
      const Vec2 to = key(e, f.hi) < key(e, e.hi) ? f.hi : e.hi;
      if (key(e, from) < key(e, to)) out.push_back(Segment{from, to});
    }
  }
}

}  // namespace par2d::detail
