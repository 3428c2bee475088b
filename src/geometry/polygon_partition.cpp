// Convex partition of a polygon with holes (polygon_partition.hpp): clean and validate the
// rings, bridge the holes into the outer ring, clip ears, then merge triangles across
// diagonals while the merged piece stays convex (Hertel-Mehlhorn). Every decision is an exact
// orientation sign or a comparison of input coordinates; no point is ever computed.
#include "geometry/polygon_partition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace par2d::detail {
namespace {

bool same_point(Vec2 p, Vec2 q) noexcept { return p.x == q.x && p.y == q.y; }
bool lex_less(Vec2 p, Vec2 q) noexcept { return p.x < q.x || (p.x == q.x && p.y < q.y); }

// p and q lie on one line through apex and differ from it: whether on the same side of apex.
bool same_direction(Vec2 apex, Vec2 p, Vec2 q) noexcept {
  if (p.x != apex.x) return (p.x > apex.x) == (q.x > apex.x);
  return (p.y > apex.y) == (q.y > apex.y);  // a vertical line
}

// Whether the direction d - apex lies in the closed wedge swept counter-clockwise from s - apex
// to e - apex. When s and e point the same way the wedge is the full turn: the tip of a
// zero-width slit (a hole's bridge) has polygon on both sides.
bool in_wedge(Vec2 apex, Vec2 s, Vec2 e, Vec2 d) noexcept {
  const int se = orientation(apex, s, e);
  if (se > 0) return orientation(apex, s, d) >= 0 && orientation(apex, d, e) >= 0;
  if (se < 0) return !(orientation(apex, e, d) > 0 && orientation(apex, d, s) > 0);
  if (same_direction(apex, s, e)) return true;
  return orientation(apex, s, d) >= 0;  // a straight angle: the closed left half-plane
}

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
  const bool along_y = sweep_along_y(edges.size(), sweep_pairs(x_spans), sweep_pairs(y_spans));
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
      const bool cross = meet == Meet::cross;
      const EdgeBox& first = (e.ring < f.ring || (e.ring == f.ring && e.k < f.k)) ? e : f;
      const EdgeBox& second = &first == &e ? f : e;
      const std::string k1 = std::to_string(rings[first.ring].input_index[first.k]);
      const std::string k2 = std::to_string(rings[second.ring].input_index[second.k]);
      if (first.ring == second.ring) {
        error = rings[first.ring].name + ": edges " + k1 + " and " + k2 + (cross ? " cross" : " touch");
      } else if (first.ring == 0) {
        error = rings[second.ring].name + (cross ? " crosses" : " touches") + " the outer boundary (its edge " + k2 +
                " and outer edge " + k1 + ")";
      } else {
        error = rings[first.ring].name + " and " + rings[second.ring].name +
                (cross ? " overlap (edges " + k1 + " and " + k2 + " cross)" : " touch (edges " + k1 + " and " + k2 + ")");
      }
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
// The ring being triangulated: nodes in a doubly linked list, each naming a vertex id. A
// bridge visits its two end points twice, so one vertex can have several nodes ("copies"),
// each with its own wedge of the polygon.

struct Mesh {
  std::vector<Vec2> points;  // by vertex id
  std::vector<int> vertex, prev, next;  // by node

  Vec2 at(int node) const noexcept { return points[static_cast<std::size_t>(vertex[node])]; }
  int add_node(int vertex_id) {
    vertex.push_back(vertex_id);
    prev.push_back(-1);
    next.push_back(-1);
    return static_cast<int>(vertex.size()) - 1;
  }
  // Whether the direction from node x toward d lies in the polygon's (closed) wedge at x: from
  // the outgoing edge counter-clockwise to the incoming one (the interior lies left of edges).
  bool wedge_holds(int x, Vec2 d) const noexcept { return in_wedge(at(x), at(next[x]), at(prev[x]), d); }
};

// Which of two ray hits (the ray from m toward +x) is nearer. A hit is a vertex on the ray or
// an edge crossing it strictly between its end points (lo below the ray, hi above).
struct RayHit {
  bool is_vertex = false;
  int node = -1;  // the vertex's node, or the node starting the edge
  Vec2 point, lo, hi;
};

// Sign of x2 - x1 where edges 1 and 2 (lo below, hi above the ray's line) cross that line. The
// edges of a valid ring never cross, so on their common y-range one stays on one side of the
// other: the sign is read at the range's lower end, or at its upper end where they meet below.
int crossing_order(const RayHit& e1, const RayHit& e2) noexcept {
  int s = e2.lo.y >= e1.lo.y ? -orientation(e1.lo, e1.hi, e2.lo) : orientation(e2.lo, e2.hi, e1.lo);
  if (s != 0) return s;
  s = e2.hi.y <= e1.hi.y ? -orientation(e1.lo, e1.hi, e2.hi) : orientation(e2.lo, e2.hi, e1.hi);
  return s;
}

// Whether hit a is strictly nearer to the ray's origin than hit b.
bool nearer(const RayHit& a, const RayHit& b) noexcept {
  if (a.is_vertex && b.is_vertex) return a.point.x < b.point.x;
  if (a.is_vertex) return orientation(b.lo, b.hi, a.point) > 0;  // left of b's crossing
  if (b.is_vertex) return orientation(a.lo, a.hi, b.point) < 0;
  return crossing_order(a, b) > 0;
}

// The node of the ring visible from m (a hole's lexicographically largest vertex; every vertex
// of the holes not yet bridged is lexicographically smaller, so only the ring can block) that
// the bridge goes to, or -1. Eberly's choice, made exactly: the nearest hit of the ray m + t
// (1, 0); a vertex hit is visible; for an edge hit, its end point P of larger x is visible
// unless ring vertices lie in the closed triangle (m, crossing, P), and then the one among them
// at the smallest angle from the ray (the nearest on ties) is.
int find_bridge(const Mesh& mesh, const std::vector<int>& ring_nodes, Vec2 m) {
  RayHit best;
  bool found = false;
  for (const int n : ring_nodes) {
    const Vec2 p = mesh.at(n), q = mesh.at(mesh.next[n]);
    if (p.y == m.y && p.x > m.x) {
      RayHit hit;
      hit.is_vertex = true;
      hit.node = n;
      hit.point = p;
      if (!found || nearer(hit, best)) best = hit;
      found = true;
    }
    if ((p.y < m.y && q.y > m.y) || (p.y > m.y && q.y < m.y)) {
      RayHit hit;
      hit.node = n;
      hit.lo = p.y < q.y ? p : q;
      hit.hi = p.y < q.y ? q : p;
      if (orientation(hit.lo, hit.hi, m) > 0) {  // m left of the upward edge: the crossing is right of m
        if (!found || nearer(hit, best)) best = hit;
        found = true;
      }
    }
  }
  if (!found) return -1;
  Vec2 target = best.point;
  if (!best.is_vertex) {
    const bool hi_is_p = best.hi.x >= best.lo.x;
    const Vec2 p = hi_is_p ? best.hi : best.lo, q = hi_is_p ? best.lo : best.hi;
    const bool above = p.y > m.y;
    bool have = false;
    Vec2 choice{};
    for (const int n : ring_nodes) {
      const Vec2 r = mesh.at(n);
      if (same_point(r, p)) continue;
      // In the closed triangle (m, crossing, p): on p's side of the ray's line, on m's side of
      // the edge's line, on the crossing's side of the line m p.
      const bool inside = above ? (r.y >= m.y && orientation(q, p, r) >= 0 && orientation(p, m, r) >= 0)
                                : (r.y <= m.y && orientation(p, q, r) >= 0 && orientation(m, p, r) >= 0);
      if (!inside) continue;
      if (!have) {
        choice = r;
        have = true;
        continue;
      }
      const int o = orientation(m, r, choice);
      if ((above ? o > 0 : o < 0) || (o == 0 && r.x < choice.x)) choice = r;
    }
    target = have ? choice : p;
  }
  // The copy of the target point whose wedge holds the direction to m.
  for (const int n : ring_nodes)
    if (same_point(mesh.at(n), target) && mesh.wedge_holds(n, m)) return n;
  return -1;
}

// ---------------------------------------------------------------------------------------------
// Ear clipping on the bridged ring (counter-clockwise). Node v with neighbours u, w is an ear
// when (1) u v w turns strictly left, (2) the triangle's corners at u and w lie in the ring's
// wedges there (so the copies of u and w, whose wedges are elsewhere, cannot reach into it),
// (3) no vertex other than copies of u, v, w lies in the closed triangle. Then no boundary
// meets the triangle's interior and it lies in the polygon. If any vertex lies in the triangle
// then a non-convex one does (the one nearest v sees open polygon toward v), so (3) scans the
// non-convex nodes only; a node's turn only grows more convex as ears are clipped beside it.
// (2) is implied by (3) on a weakly simple ring as far as the tests reach (dropping it fails
// none); it is kept because it is local and cheap, and it only ever refuses an ear whose
// triangle would leave the polygon at u or w.

class EarClipper {
 public:
  EarClipper(Mesh& mesh, const std::vector<int>& ring_nodes, std::size_t& scanned)
      : mesh_(mesh), nodes_(ring_nodes), scanned_(scanned) {
    const std::size_t total = mesh.vertex.size();
    alive_.assign(total, 0);
    reflex_.assign(total, 0);
    for (const int n : nodes_) {
      alive_[n] = 1;
      if (!convex(n)) {
        reflex_[n] = 1;
        reflex_by_x_.push_back(n);
      }
    }
    // By x and by y, so that an ear test scans only the nodes within its triangle's x-range or
    // its y-range, whichever holds fewer (a comb's teeth lie side by side along one axis).
    std::sort(reflex_by_x_.begin(), reflex_by_x_.end(), [&](int a, int b) { return mesh_.at(a).x < mesh_.at(b).x; });
    reflex_by_y_ = reflex_by_x_;
    std::sort(reflex_by_y_.begin(), reflex_by_y_.end(), [&](int a, int b) { return mesh_.at(a).y < mesh_.at(b).y; });
  }

  // Appends the triangles (vertex ids, counter-clockwise). False when clipping stalls on a ring
  // that still has area (a bug; valid input never gets here).
  bool run(std::vector<std::array<int, 3>>& triangles) {
    std::vector<int> work(nodes_.rbegin(), nodes_.rend());
    int count = static_cast<int>(nodes_.size());
    bool clipped_since_fill = false;
    // Clipping v changes the ring only at u and w, so only u, w, prev(u) (whose corner test
    // reads u's wedge) and next(w) change ear status: a node whose triangle held v also held
    // another vertex, which stays. The refill below is therefore a safety net (the tests
    // never reach it), and the work is O(n) ear tests of O(reflex vertices) each.
    while (count >= 3) {
      if (work.empty()) {
        if (!clipped_since_fill) break;
        clipped_since_fill = false;
        for (const int n : nodes_)
          if (alive_[n]) work.push_back(n);
        continue;
      }
      const int v = work.back();
      work.pop_back();
      if (!alive_[v] || !is_ear(v)) continue;
      const int u = mesh_.prev[v], w = mesh_.next[v];
      triangles.push_back({mesh_.vertex[u], mesh_.vertex[v], mesh_.vertex[w]});
      mesh_.next[u] = w;
      mesh_.prev[w] = u;
      alive_[v] = 0;
      --count;
      clipped_since_fill = true;
      for (const int x : {u, w})
        if (reflex_[x] && convex(x)) {
          reflex_[x] = 0;
          ++stale_;
        }
      if (reflex_[v]) ++stale_;  // cannot be: an ear tip is convex
      if (stale_ * 2 > reflex_by_x_.size()) compact();
      work.push_back(mesh_.next[w]);
      work.push_back(mesh_.prev[u]);
      work.push_back(w);
      work.push_back(u);
    }
    if (count < 3) return true;
    // Stalled: fine only if what is left has no area (a slit traced both ways).
    for (const int n : nodes_)
      if (alive_[n] && orientation(mesh_.at(mesh_.prev[n]), mesh_.at(n), mesh_.at(mesh_.next[n])) != 0) return false;
    return true;
  }

 private:
  bool convex(int n) const noexcept {
    return orientation(mesh_.at(mesh_.prev[n]), mesh_.at(n), mesh_.at(mesh_.next[n])) > 0;
  }

  void compact() {
    for (std::vector<int>* list : {&reflex_by_x_, &reflex_by_y_}) {
      std::size_t kept = 0;
      for (const int n : *list)
        if (alive_[n] && reflex_[n]) (*list)[kept++] = n;
      list->resize(kept);
    }
    stale_ = 0;
  }

  bool is_ear(int v) noexcept {
    const int u = mesh_.prev[v], w = mesh_.next[v];
    const Vec2 a = mesh_.at(u), b = mesh_.at(v), c = mesh_.at(w);
    if (orientation(a, b, c) <= 0) return false;
    if (!in_wedge(a, b, mesh_.at(mesh_.prev[u]), c)) return false;  // corner at u: from u->v to u->w
    if (!in_wedge(c, mesh_.at(mesh_.next[w]), b, a)) return false;  // corner at w: from w->u to w->v
    const double min_x = std::min({a.x, b.x, c.x}), max_x = std::max({a.x, b.x, c.x});
    const double min_y = std::min({a.y, b.y, c.y}), max_y = std::max({a.y, b.y, c.y});
    const auto by_x_first = std::lower_bound(reflex_by_x_.begin(), reflex_by_x_.end(), min_x,
                                             [&](int r, double x) { return mesh_.at(r).x < x; });
    const auto by_x_last = std::upper_bound(by_x_first, reflex_by_x_.end(), max_x,
                                            [&](double x, int r) { return x < mesh_.at(r).x; });
    const auto by_y_first = std::lower_bound(reflex_by_y_.begin(), reflex_by_y_.end(), min_y,
                                             [&](int r, double y) { return mesh_.at(r).y < y; });
    const auto by_y_last = std::upper_bound(by_y_first, reflex_by_y_.end(), max_y,
                                            [&](double y, int r) { return y < mesh_.at(r).y; });
    const bool by_x = by_x_last - by_x_first <= by_y_last - by_y_first;
    for (auto it = by_x ? by_x_first : by_y_first, end = by_x ? by_x_last : by_y_last; it != end; ++it) {
      ++scanned_;
      const int r = *it;
      const Vec2 p = mesh_.at(r);
      if (!alive_[r] || !reflex_[r] || p.x < min_x || p.x > max_x || p.y < min_y || p.y > max_y) continue;
      if (same_point(p, a) || same_point(p, b) || same_point(p, c)) continue;
      if (orientation(a, b, p) >= 0 && orientation(b, c, p) >= 0 && orientation(c, a, p) >= 0) return false;
    }
    return true;
  }

  Mesh& mesh_;
  const std::vector<int>& nodes_;
  std::size_t& scanned_;
  std::vector<char> alive_, reflex_;
  std::vector<int> reflex_by_x_, reflex_by_y_;  // the reflex nodes by x and by y
  std::size_t stale_ = 0;
};

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
  // Boundaries are now pairwise disjoint, so one vertex tells where a whole ring lies.
  for (std::size_t h = 1; h <= hole_count; ++h)
    if (!inside_ring(rings[0].points, rings[h].points[0])) {
      error = rings[h].name + ": not inside the outer boundary";
      return false;
    }
  for (std::size_t i = 1; i <= hole_count; ++i)
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

  Mesh mesh;
  std::vector<int> ring_nodes;
  std::vector<int> hole_start(hole_count + 1, 0);  // node of each hole's lexicographically largest vertex
  for (std::size_t r = 0; r <= hole_count; ++r) {
    const auto& pts = rings[r].points;
    const int first = static_cast<int>(mesh.vertex.size());
    const int n = static_cast<int>(pts.size());
    for (int k = 0; k < n; ++k) {
      mesh.points.push_back(pts[k]);
      const int node = mesh.add_node(static_cast<int>(mesh.points.size()) - 1);
      mesh.prev[node] = first + (k + n - 1) % n;
      mesh.next[node] = first + (k + 1) % n;
      if (r == 0) ring_nodes.push_back(node);
      if (k == 0 || lex_less(mesh.at(hole_start[r]), pts[k])) hole_start[r] = node;
    }
  }
  // Holes by decreasing largest vertex: each one's bridge runs where no later hole reaches.
  std::vector<std::size_t> order;
  for (std::size_t h = 1; h <= hole_count; ++h) order.push_back(h);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return lex_less(mesh.at(hole_start[b]), mesh.at(hole_start[a])); });
  for (const std::size_t h : order) {
    const int m = hole_start[h];
    const int r = find_bridge(mesh, ring_nodes, mesh.at(m));
    if (r < 0) {
      error = "internal error: no bridge found for " + rings[h].name;
      return false;
    }
    // r -> m -> (around the hole) -> m' -> r' -> old next of r.
    const int r_next = mesh.next[r], m_prev = mesh.prev[m];
    const int m_copy = mesh.add_node(mesh.vertex[m]);
    const int r_copy = mesh.add_node(mesh.vertex[r]);
    int x = m;
    do {
      ring_nodes.push_back(x);
      x = mesh.next[x];
    } while (x != m);
    mesh.next[r] = m;
    mesh.prev[m] = r;
    mesh.next[m_prev] = m_copy;
    mesh.prev[m_copy] = m_prev;
    mesh.next[m_copy] = r_copy;
    mesh.prev[r_copy] = m_copy;
    mesh.next[r_copy] = r_next;
    mesh.prev[r_next] = r_copy;
    ring_nodes.push_back(m_copy);
    ring_nodes.push_back(r_copy);
  }

  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(ring_nodes.size());
  if (!EarClipper(mesh, ring_nodes, counted.ear_scans).run(triangles)) {
    error = "internal error: ear clipping stalled";
    return false;
  }
  std::vector<std::vector<int>> merged;
  merge_pieces(mesh.points, triangles, merged);
  for (const auto& piece : merged) {
    if (piece.empty()) continue;
    std::vector<Vec2> out;
    const std::size_t n = piece.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 p = mesh.points[piece[(k + n - 1) % n]], v = mesh.points[piece[k]], q = mesh.points[piece[(k + 1) % n]];
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
