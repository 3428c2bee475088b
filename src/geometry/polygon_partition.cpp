// Convex partition of a polygon with holes (polygon_partition.hpp): clean and validate the
// rings, triangulate them by a monotone decomposition (holes need no bridges), then merge
// triangles across diagonals while the merged piece stays convex (Hertel-Mehlhorn). Every
// decision is an exact orientation sign or a comparison of input coordinates; no point is ever
// computed.
#include "geometry/polygon_partition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>

#include "geometry/monotone_triangulation.hpp"

namespace par2d::detail {
namespace {

bool same_point(Vec2 p, Vec2 q) noexcept { return p.x == q.x && p.y == q.y; }
bool lex_less(Vec2 p, Vec2 q) noexcept { return p.x < q.x || (p.x == q.x && p.y < q.y); }

bool in_box(Vec2 a, Vec2 b, Vec2 p) noexcept {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

enum class Meet { none, cross, touch };

// How the closed segments ab and cd meet: not at all, crossing at one point interior to both,
// or touching (an end point on the other segment, or a shared piece of line).
Meet segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) noexcept {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  if (o1 != 0 && o1 == o2) return Meet::none;
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o3 != 0 && o3 == o4) return Meet::none;
  if (o1 != 0 && o2 != 0 && o3 != 0 && o4 != 0) return Meet::cross;
  if ((o1 == 0 && in_box(a, b, c)) || (o2 == 0 && in_box(a, b, d)) || (o3 == 0 && in_box(c, d, a)) ||
      (o4 == 0 && in_box(c, d, b)))
    return Meet::touch;
  return Meet::none;
}

// Even-odd containment of p, which must not lie on the ring (half-open rule on the horizontal
// line through p; the crossing side decided by orientation).
bool inside_ring(const std::vector<Vec2>& ring, Vec2 p) noexcept {
  bool inside = false;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = ring[i], b = ring[i + 1 == n ? 0 : i + 1];
    if ((a.y > p.y) != (b.y > p.y)) {
      const Vec2 lo = a.y < b.y ? a : b, hi = a.y < b.y ? b : a;
      if (orientation(lo, hi, p) > 0) inside = !inside;
    }
  }
  return inside;
}

// A ring after cleaning: its points and, for each, the index of the input vertex it came from.
struct Ring {
  std::string name;
  std::vector<Vec2> points;
  std::vector<int> input_index;
  Vec2 box_min, box_max;
};

// Drops repeated and straight vertices; refuses fewer than 3 distinct points, no area, folds.
bool clean_ring(const std::vector<Vec2>& input, Ring& ring, std::string& error) {
  {
    std::vector<Vec2> sorted = input;
    std::sort(sorted.begin(), sorted.end(), lex_less);
    const auto end = std::unique(sorted.begin(), sorted.end(), same_point);
    if (end - sorted.begin() < 3) {
      error = ring.name + ": fewer than 3 distinct vertices";
      return false;
    }
    // Some three points are not on one line: with a the first point and b another, some c is off ab.
    const Vec2 a = sorted[0], b = sorted[1];
    bool area = false;
    for (auto it = sorted.begin() + 2; it != end && !area; ++it) area = orientation(a, b, *it) != 0;
    if (!area) {
      error = ring.name + ": zero area (all vertices on one line)";
      return false;
    }
  }
  // Consecutive repeats (the closing edge included).
  std::vector<Vec2> pts;
  std::vector<int> index;
  for (std::size_t i = 0; i < input.size(); ++i) {
    if (!pts.empty() && same_point(pts.back(), input[i])) continue;
    pts.push_back(input[i]);
    index.push_back(static_cast<int>(i));
  }
  while (pts.size() > 1 && same_point(pts.back(), pts.front())) {
    pts.pop_back();
    index.pop_back();
  }
  // Straight vertices, in a linked ring so that a removal re-examines both neighbours.
  const int n = static_cast<int>(pts.size());
  std::vector<int> prev(n), next(n), work(n);
  std::vector<char> alive(n, 1);
  for (int i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
    work[i] = n - 1 - i;
  }
  int count = n;
  while (!work.empty() && count >= 3) {
    const int v = work.back();
    work.pop_back();
    if (!alive[v]) continue;
    const int p = prev[v], q = next[v];
    if (orientation(pts[p], pts[v], pts[q]) != 0) continue;
    if (same_direction(pts[v], pts[p], pts[q])) {
      error = ring.name + ": the edges at vertex " + std::to_string(index[v]) + " fold back onto each other";
      return false;
    }
    alive[v] = 0;
    next[p] = q;
    prev[q] = p;
    --count;
    work.push_back(p);
    work.push_back(q);
  }
  if (count < 3) {  // cannot happen with three points off one line; kept as a guard
    error = ring.name + ": zero area (all vertices on one line)";
    return false;
  }
  int start = 0;
  while (!alive[start]) ++start;
  ring.points.clear();
  ring.input_index.clear();
  int v = start;
  do {
    ring.points.push_back(pts[v]);
    ring.input_index.push_back(index[v]);
    v = next[v];
  } while (v != start);
  ring.box_min = ring.box_max = ring.points[0];
  for (const Vec2 p : ring.points) {
    ring.box_min = {std::min(ring.box_min.x, p.x), std::min(ring.box_min.y, p.y)};
    ring.box_max = {std::max(ring.box_max.x, p.x), std::max(ring.box_max.y, p.y)};
  }
  return true;
}

// +1 for a counter-clockwise simple ring, -1 clockwise: the turn at its lexicographically
// smallest vertex, which is strictly convex (no straight vertices remain).
int ring_orientation(const std::vector<Vec2>& ring) noexcept {
  const std::size_t n = ring.size();
  std::size_t m = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (lex_less(ring[i], ring[m])) m = i;
  return orientation(ring[(m + n - 1) % n], ring[m], ring[(m + 1) % n]);
}

struct EdgeBox {
  double min_x, max_x, min_y, max_y;
  int ring, k;
};

}  // namespace

std::size_t sweep_pairs(std::vector<std::pair<double, double>>& spans) {
  std::sort(spans.begin(), spans.end());
  std::vector<double> lows(spans.size());
  for (std::size_t i = 0; i < spans.size(); ++i) lows[i] = spans[i].first;
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < spans.size(); ++i) {
    const auto later = lows.begin() + static_cast<std::ptrdiff_t>(i + 1);
    pairs += static_cast<std::size_t>(std::upper_bound(later, lows.end(), spans[i].second) - later);
  }
  return pairs;
}

namespace {

// The error for edge k of ring r and edge l of ring q meeting (crossing or touching).
void report_meeting(const std::vector<Ring>& rings, int r, int k, int q, int l, bool cross, std::string& error) {
  if (q < r || (q == r && l < k)) {
    std::swap(r, q);
    std::swap(k, l);
  }
  const std::string k1 = std::to_string(rings[r].input_index[k]);
  const std::string k2 = std::to_string(rings[q].input_index[l]);
  if (r == q) {
    error = rings[r].name + ": edges " + k1 + " and " + k2 + (cross ? " cross" : " touch");
  } else if (r == 0) {
    error = rings[q].name + (cross ? " crosses" : " touches") + " the outer boundary (its edge " + k2 +
            " and outer edge " + k1 + ")";
  } else {
    error = rings[r].name + " and " + rings[q].name +
            (cross ? " overlap (edges " + k1 + " and " + k2 + " cross)" : " touch (edges " + k1 + " and " + k2 + ")");
  }
}

// The same check as check_edges by a sweep (Shamos and Hoey) in O(n log n) for any shape, for
// outlines whose edges' boxes overlap pairwise along both axes (a star's edges around its
// centre). The sweep runs along x, then y (lexicographic order of the end points); the edges
// it crosses are kept ordered bottom to top, and only edges next to each other there are
// compared. At each end point p it first checks that exactly the two edges of one vertex end
// there and that no other edge passes through p; with no meeting before p the order is
// strict, and the first meeting (lexicographically) is found when the sweep reaches it or as
// two edges become neighbours before it.
class SimplicitySweep {
 public:
  SimplicitySweep(const std::vector<Ring>& rings, std::size_t& pairs)
      : rings_(rings), pairs_(pairs), status_(Below{this}) {
    for (int r = 0; r < static_cast<int>(rings.size()); ++r) {
      const int n = static_cast<int>(rings[r].points.size());
      for (int k = 0; k < n; ++k) {
        Vec2 a = rings[r].points[k], b = rings[r].points[(k + 1) % n];
        const bool forward = !lex_less(b, a);
        if (!forward) std::swap(a, b);
        edges_.push_back({a, b, r, k, forward});
      }
      ccw_.push_back(ring_orientation(rings[r].points) > 0);
    }
    parent_.assign(rings.size(), -1);
  }

  // After a successful run: the ring whose region immediately encloses ring r's, or -1.
  int parent(int r) const noexcept { return parent_[static_cast<std::size_t>(r)]; }

  // True when no two edges meet but adjacent ones at their vertex; else false with `error`.
  bool run(std::string& error) {
    struct Event {
      Vec2 p;
      int edge;
      bool start;
    };
    std::vector<Event> events;
    events.reserve(2 * edges_.size());
    for (int e = 0; e < static_cast<int>(edges_.size()); ++e) {
      events.push_back({edges_[e].lo, e, true});
      events.push_back({edges_[e].hi, e, false});
    }
    std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return lex_less(a.p, b.p); });
    where_.resize(edges_.size());
    seen_.assign(rings_.size(), 0);
    std::vector<int> starting, ending;
    for (std::size_t i = 0; i < events.size();) {
      const Vec2 p = events[i].p;
      starting.clear();
      ending.clear();
      for (; i < events.size() && same_point(events[i].p, p); ++i)
        (events[i].start ? starting : ending).push_back(events[i].edge);
      // Exactly the two edges of one vertex end at p.
      std::vector<int>& at_p = ending;
      for (const int e : ending) status_.erase(where_[static_cast<std::size_t>(e)]);
      at_p.insert(at_p.end(), starting.begin(), starting.end());
      for (std::size_t x = 0; x < at_p.size(); ++x)
        for (std::size_t y = x + 1; y < at_p.size(); ++y)
          if (!adjacent(at_p[x], at_p[y])) return meeting(at_p[x], at_p[y], error);
      // No other edge passes through p; the edges just below and above it.
      auto above = status_.lower_bound(p);
      if (above != status_.end() && side(*above, p) == 0) return meeting(*above, at_p.front(), error);
      // A ring's first point: the edge just below it tells the ring around it. Left of an edge
      // (above it, as it runs lo -> hi) lies inside a counter-clockwise ring.
      const int r = edges_[static_cast<std::size_t>(at_p.front())].ring;
      if (!seen_[static_cast<std::size_t>(r)] && above != status_.begin()) {
        const Edge& below = edges_[static_cast<std::size_t>(*std::prev(above))];
        const bool inside = below.forward == ccw_[static_cast<std::size_t>(below.ring)];
        parent_[static_cast<std::size_t>(r)] = inside ? below.ring : parent_[static_cast<std::size_t>(below.ring)];
      }
      seen_[static_cast<std::size_t>(r)] = 1;
      if (starting.empty()) {
        if (above != status_.end() && above != status_.begin() && !check(*std::prev(above), *above, error)) return false;
        continue;
      }
      for (const int e : starting) where_[static_cast<std::size_t>(e)] = status_.insert(e).first;
      for (const int e : starting) {
        const auto it = where_[static_cast<std::size_t>(e)];
        if (it != status_.begin() && !check(*std::prev(it), e, error)) return false;
        if (std::next(it) != status_.end() && !check(e, *std::next(it), error)) return false;
      }
    }
    return true;
  }

 private:
  struct Edge {
    Vec2 lo, hi;  // lexicographically ordered end points
    int ring, k;
    bool forward;  // lo is the ring's vertex k (the ring runs lo -> hi)
  };
  // Orders the edges the sweep line crosses bottom to top. Of two edges, the one that entered
  // later has its start within the other's span: compared by the side of the other it starts
  // on, or, for two edges from one point, by their directions.
  struct Below {
    using is_transparent = void;
    const SimplicitySweep* sweep;
    bool operator()(int a, int b) const noexcept {
      if (a == b) return false;
      const Edge& ea = sweep->edges_[static_cast<std::size_t>(a)];
      const Edge& eb = sweep->edges_[static_cast<std::size_t>(b)];
      ++sweep->pairs_;
      if (same_point(ea.lo, eb.lo)) return orientation(ea.lo, ea.hi, eb.hi) > 0;
      if (lex_less(eb.lo, ea.lo)) return sweep->side(b, ea.lo) < 0;
      return sweep->side(a, eb.lo) > 0;
    }
    bool operator()(int e, Vec2 p) const noexcept { return sweep->side(e, p) > 0; }  // e passes below p
    bool operator()(Vec2 p, int e) const noexcept { return sweep->side(e, p) < 0; }
  };

  int side(int e, Vec2 p) const noexcept {
    const Edge& edge = edges_[static_cast<std::size_t>(e)];
    return orientation(edge.lo, edge.hi, p);
  }
  bool adjacent(int a, int b) const noexcept {
    const Edge& ea = edges_[static_cast<std::size_t>(a)];
    const Edge& eb = edges_[static_cast<std::size_t>(b)];
    if (ea.ring != eb.ring) return false;
    const int n = static_cast<int>(rings_[static_cast<std::size_t>(ea.ring)].points.size());
    return (ea.k + 1) % n == eb.k || (eb.k + 1) % n == ea.k;
  }
  bool meeting(int a, int b, std::string& error) const {
    const Edge& ea = edges_[static_cast<std::size_t>(a)];
    const Edge& eb = edges_[static_cast<std::size_t>(b)];
    report_meeting(rings_, ea.ring, ea.k, eb.ring, eb.k, segments_meet(ea.lo, ea.hi, eb.lo, eb.hi) == Meet::cross,
                   error);
    return false;
  }
  // Two edges next to each other on the sweep line: false (with `error`) if they meet.
  bool check(int a, int b, std::string& error) const {
    ++pairs_;
    if (adjacent(a, b)) return true;  // they share one vertex only: no fold survives cleaning
    const Edge& ea = edges_[static_cast<std::size_t>(a)];
    const Edge& eb = edges_[static_cast<std::size_t>(b)];
    if (segments_meet(ea.lo, ea.hi, eb.lo, eb.hi) == Meet::none) return true;
    return meeting(a, b, error);
  }

  const std::vector<Ring>& rings_;
  std::size_t& pairs_;
  std::vector<Edge> edges_;
  std::set<int, Below> status_;
  std::vector<std::set<int, Below>::iterator> where_;
  std::vector<char> ccw_, seen_;  // by ring
  std::vector<int> parent_;       // by ring
};

// No two edges of all rings meet, except adjacent edges of one ring at their shared vertex.
// Edges sorted by their smallest x (or y); each is compared with those whose x-range (y-range)
// starts before its own ends, along y where that makes far fewer pairs: a comb's teeth side by
// side along y would make every pair of them a pair in x.
bool check_edges(const std::vector<Ring>& rings, std::string& error, std::size_t& pairs) {
  std::vector<EdgeBox> edges;
  for (int r = 0; r < static_cast<int>(rings.size()); ++r) {
    const auto& pts = rings[r].points;
    const int n = static_cast<int>(pts.size());
    for (int k = 0; k < n; ++k) {
      const Vec2 a = pts[k], b = pts[(k + 1) % n];
      edges.push_back({std::min(a.x, b.x), std::max(a.x, b.x), std::min(a.y, b.y), std::max(a.y, b.y), r, k});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeBox& a, const EdgeBox& b) { return a.min_x < b.min_x; });
  std::vector<std::pair<double, double>> x_spans(edges.size()), y_spans(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    x_spans[i] = {edges[i].min_x, edges[i].max_x};
    y_spans[i] = {edges[i].min_y, edges[i].max_y};
  }
  const std::size_t x_pairs = sweep_pairs(x_spans), y_pairs = sweep_pairs(y_spans);
  // Pairs in both axes far beyond the edges: the sweep, whose cost does not depend on them.
  if (std::min(x_pairs, y_pairs) > 16 * edges.size()) return SimplicitySweep(rings, pairs).run(error);
  const bool along_y = sweep_along_y(edges.size(), x_pairs, y_pairs);
  if (along_y)
    std::sort(edges.begin(), edges.end(), [](const EdgeBox& a, const EdgeBox& b) { return a.min_y < b.min_y; });
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const EdgeBox& e = edges[i];
    for (std::size_t j = i + 1; j < edges.size() && (along_y ? edges[j].min_y <= e.max_y : edges[j].min_x <= e.max_x); ++j) {
      const EdgeBox& f = edges[j];
      ++pairs;
      if (f.max_y < e.min_y || f.min_y > e.max_y || f.max_x < e.min_x || f.min_x > e.max_x) continue;
      if (e.ring == f.ring) {
        const int n = static_cast<int>(rings[e.ring].points.size());
        if ((e.k + 1) % n == f.k || (f.k + 1) % n == e.k) continue;  // adjacent: share one vertex only
      }
      const auto& pe = rings[e.ring].points;
      const auto& pf = rings[f.ring].points;
      const int ne = static_cast<int>(pe.size()), nf = static_cast<int>(pf.size());
      const Meet meet = segments_meet(pe[e.k], pe[(e.k + 1) % ne], pf[f.k], pf[(f.k + 1) % nf]);
      if (meet == Meet::none) continue;
      report_meeting(rings, e.ring, e.k, f.ring, f.k, meet == Meet::cross, error);
      return false;
    }
  }
  return true;
}

bool box_inside(const Ring& inner, const Ring& outer) noexcept {
  return outer.box_min.x <= inner.box_min.x && inner.box_max.x <= outer.box_max.x &&
         outer.box_min.y <= inner.box_min.y && inner.box_max.y <= outer.box_max.y;
}

// ---------------------------------------------------------------------------------------------
// Hertel-Mehlhorn: remove each diagonal (an edge two triangles share) whose removal leaves a
// convex piece, i.e. the merged angles at both its ends are at most 180 degrees. A diagonal
// kept is needed at one of its ends, which is then a reflex vertex of the polygon, and a
// reflex vertex needs at most two (two disjoint pairs of neighbouring sectors, each over 180
// degrees, would sum past 360): at most 2r diagonals stay, and by Euler's formula a partition
// of a polygon with h holes by d diagonals has d + 1 - h pieces.

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

void merge_pieces(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                  std::vector<std::vector<int>>& pieces) {
  const int t_count = static_cast<int>(triangles.size());
  // Each piece is a ring of corners: corner 3t + k is vertex triangles[t][k] of triangle t and
  // starts the piece's edge to the next corner. A merge across a diagonal unlinks the two
  // corners that start its half-edges, so every edge left keeps its corner and a merge costs
  // O(1) (copying the pieces made merging into a long piece cost its length each time).
  const auto corners = static_cast<std::size_t>(3 * t_count);
  std::vector<int> next(corners), prev(corners), first(triangles.size()), parent(triangles.size());
  const auto vertex_of = [&triangles](int c) { return triangles[static_cast<std::size_t>(c / 3)][static_cast<std::size_t>(c % 3)]; };
  struct HalfEdge {
    std::uint64_t key;
    int triangle, from, corner;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(triangles.size() * 3);
  for (int t = 0; t < t_count; ++t) {
    parent[t] = t;
    first[t] = 3 * t;
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      next[3 * t + k] = 3 * t + (k + 1) % 3;
      prev[3 * t + k] = 3 * t + (k + 2) % 3;
      const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      half_edges.push_back({(lo << 32) | hi, t, a, 3 * t + k});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key < y.key || (x.key == y.key && x.triangle < y.triangle);
  });
  const auto angle_ok = [&](int x, int a, int y) {
    const Vec2 px = points[x], pa = points[a], py = points[y];
    const int o = orientation(px, pa, py);
    return o > 0 || (o == 0 && !same_direction(pa, px, py));
  };
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i;
    while (j < half_edges.size() && half_edges[j].key == half_edges[i].key) ++j;
    if (j - i == 2 && half_edges[i].from != half_edges[i + 1].from) {
      const int a = half_edges[i].from;
      const int b = half_edges[i + 1].from;
      const int p = find_root(parent, half_edges[i].triangle), q = find_root(parent, half_edges[i + 1].triangle);
      if (p != q) {
        // Piece p runs x, a, b, s and piece q runs z, b, a, y; merged: x, a, y ... z, b, s.
        const int ab = half_edges[i].corner, ba = half_edges[i + 1].corner;
        const int qa = next[ba], pb = next[ab];  // a starting a -> y, b starting b -> s
        const int xc = prev[ab], zc = prev[ba];
        const int x = vertex_of(xc), s = vertex_of(next[pb]), y = vertex_of(next[qa]), z = vertex_of(zc);
        if (angle_ok(x, a, y) && angle_ok(z, b, s)) {
          next[xc] = qa;
          prev[qa] = xc;
          next[zc] = pb;
          prev[pb] = zc;
          first[p] = pb;  // the merged piece starts at b
          parent[q] = p;
        }
      }
    }
    i = j;
  }
  pieces.assign(triangles.size(), {});
  for (int t = 0; t < t_count; ++t) {
    if (parent[t] != t) continue;
    int c = first[t];
    do {
      pieces[t].push_back(vertex_of(c));
      c = next[c];
    } while (c != first[t]);
  }
}

}  // namespace

bool partition_convex(const PolygonRings& polygon, std::vector<std::vector<Vec2>>& pieces, std::string& error,
                      PartitionWork* work) {
  pieces.clear();
  PartitionWork scratch;
  PartitionWork& counted = work != nullptr ? *work : scratch;
  const std::size_t hole_count = polygon.holes.size();
  std::vector<Ring> rings(hole_count + 1);
  rings[0].name = "outer";
  for (std::size_t h = 0; h < hole_count; ++h) rings[h + 1].name = "holes[" + std::to_string(h) + "]";

  std::size_t total = polygon.outer.size();
  for (const auto& hole : polygon.holes) total += hole.size();
  if (total > kMaxPartitionVertices) {
    error = "too many vertices: " + std::to_string(total) + " in all rings (at most " +
            std::to_string(kMaxPartitionVertices) + ")";
    return false;
  }
  for (std::size_t r = 0; r <= hole_count; ++r) {
    const auto& input = r == 0 ? polygon.outer : polygon.holes[r - 1];
    for (std::size_t i = 0; i < input.size(); ++i)
      if (!std::isfinite(input[i].x) || !std::isfinite(input[i].y)) {
        error = rings[r].name + ": vertex " + std::to_string(i) + " is not finite";
        return false;
      }
  }
  for (std::size_t r = 0; r <= hole_count; ++r)
    if (!clean_ring(r == 0 ? polygon.outer : polygon.holes[r - 1], rings[r], error)) return false;
  if (!check_edges(rings, error, counted.edge_pairs)) return false;
  // Boundaries are now pairwise disjoint, so one vertex tells where a whole ring lies. Many
  // holes (where testing every pair would cost more than the vertices) are placed by a sweep.
  if (hole_count * hole_count > total) {
    std::size_t compared = 0;
    SimplicitySweep sweep(rings, compared);
    if (!sweep.run(error)) return false;  // cannot be: check_edges passed
    const auto inside_outer = [&](int r) {
      while (r > 0) r = sweep.parent(r);
      return r == 0;
    };
    for (std::size_t h = 1; h <= hole_count; ++h)
      if (!inside_outer(static_cast<int>(h))) {
        error = rings[h].name + ": not inside the outer boundary";
        return false;
      }
    for (std::size_t h = 1; h <= hole_count; ++h)
      if (sweep.parent(static_cast<int>(h)) != 0) {
        error = rings[h].name + " lies inside " + rings[static_cast<std::size_t>(sweep.parent(static_cast<int>(h)))].name +
                " (nested holes)";
        return false;
      }
  }
  for (std::size_t h = 1; h <= hole_count && hole_count * hole_count <= total; ++h)
    if (!inside_ring(rings[0].points, rings[h].points[0])) {
      error = rings[h].name + ": not inside the outer boundary";
      return false;
    }
  for (std::size_t i = 1; i <= hole_count && hole_count * hole_count <= total; ++i)
    for (std::size_t j = 1; j <= hole_count; ++j)
      if (i != j && box_inside(rings[j], rings[i]) && inside_ring(rings[i].points, rings[j].points[0])) {
        error = rings[j].name + " lies inside " + rings[i].name + " (nested holes)";
        return false;
      }

  // Outer counter-clockwise, holes clockwise: the polygon lies left of every edge.
  for (std::size_t r = 0; r <= hole_count; ++r) {
    const int want = r == 0 ? 1 : -1;
    if (ring_orientation(rings[r].points) != want) std::reverse(rings[r].points.begin(), rings[r].points.end());
  }

  std::vector<Vec2> points;
  std::vector<int> ring_sizes;
  points.reserve(total);
  for (std::size_t r = 0; r <= hole_count; ++r) {
    points.insert(points.end(), rings[r].points.begin(), rings[r].points.end());
    ring_sizes.push_back(static_cast<int>(rings[r].points.size()));
  }
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(points.size() + 2 * hole_count);
  if (!triangulate_polygon(points, ring_sizes, triangles, counted.triangulation_tests)) {
    error = "internal error: the triangulation found no edge where one must be";
    return false;
  }
  std::vector<std::vector<int>> merged;
  merge_pieces(points, triangles, merged);
  for (const auto& piece : merged) {
    if (piece.empty()) continue;
    std::vector<Vec2> out;
    const std::size_t n = piece.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 p = points[piece[(k + n - 1) % n]], v = points[piece[k]], q = points[piece[(k + 1) % n]];
      if (orientation(p, v, q) != 0) out.push_back(v);  // drop straight vertices
    }
    if (out.size() >= 3) pieces.push_back(std::move(out));
  }
  return true;
}

bool partition_polygon(const Polygon& polygon, std::vector<Polygon>& pieces, std::string& error) {
  thread_local std::vector<std::vector<Vec2>> raw;
  pieces.clear();
  thread_local PolygonRings rings;
  rings.outer = polygon.vertices;
  rings.holes.assign(polygon.holes.begin(), polygon.holes.end());
  if (!partition_convex(rings, raw, error)) return false;
  pieces.resize(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    pieces[k].vertices = raw[k];
  }
  return true;
}

bool partition_polygon(const Polygon& polygon, std::string& error) {
  thread_local PolygonRings rings;
  thread_local std::vector<std::vector<Vec2>> raw;
  rings.outer = polygon.vertices;
  rings.holes.assign(polygon.holes.begin(), polygon.holes.end());
  return partition_convex(rings, raw, error);
}

}  // namespace par2d::detail
