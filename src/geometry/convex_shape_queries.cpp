// Queries on canonical convex shapes, exact in double precision (the reference every faster path
// is held to): containment, ray entry, angular span and tangents, distances, contacts, separating
// lines and boundary intersections. Construction and the exact primitives are in convex_shape.cpp.
#include "geometry/convex_shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/exact_arithmetic.hpp"

namespace par2d::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double wrap_angle(double a) noexcept {  // into (-pi, pi]
  while (a > kPi) a -= kTwoPi;
  while (a <= -kPi) a += kTwoPi;
  return a;
}

double point_segment_distance(Vec2 p, Vec2 a, Vec2 b, Vec2* closest = nullptr) noexcept {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  double s = len2 > 0.0 ? dot(p - a, ab) / len2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  Vec2 q = a + s * ab;
  if (s > 0.0 && s < 1.0 && len2 < kInfinity) {
    // The foot lies inside: a + s * ab is rounded to the end points' magnitude (16 units on
    // an edge 1e17 long), so it is found from p instead, along the normal, by the exact cross
    // product (p's signed distance to the left of a -> b, times |ab|).
    const double c = side_of(a, b, p);
    q = p - (c / len2) * Vec2{-ab.y, ab.x};
  }
  // Callers of closest points (separating lines) need the distance to be |p - q| itself.
  if (closest) *closest = q;
  return length(p - q);
}

// Whether closed segments [a,b] and [c,d] share a point.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) noexcept {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto on_segment = [](Vec2 p, Vec2 q, Vec2 r) {  // r collinear with pq: within its box?
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  return (d1 == 0 && on_segment(a, b, c)) || (d2 == 0 && on_segment(a, b, d)) ||
         (d3 == 0 && on_segment(c, d, a)) || (d4 == 0 && on_segment(c, d, b));
}

// Number of edges of the shape's core (the convex hull of its vertices).
int core_edge_count(const ConvexShape& s) noexcept {
  const int n = static_cast<int>(s.vertices.size());
  return n >= 3 ? n : n - 1;  // segment: one edge; point (circle center): none
}

void core_edge(const ConvexShape& s, int i, Vec2& a, Vec2& b) noexcept {
  const int n = static_cast<int>(s.vertices.size());
  a = s.vertices[i];
  b = s.vertices[(i + 1) % n];
}

bool core_contains(const ConvexShape& s, Vec2 p) noexcept {
  const int n = static_cast<int>(s.vertices.size());
  if (n < 3) return false;  // points and segments have no interior; distance covers them
  if (p.x < s.bounds_min.x || p.x > s.bounds_max.x || p.y < s.bounds_min.y || p.y > s.bounds_max.y) return false;
  for (int i = 0; i < n; ++i) {
    if (side_of(s.vertices[i], s.vertices[(i + 1) % n], p) < 0.0) return false;
  }
  return true;
}

// Distance from p to the shape's core, and the closest core point.
double point_core_distance(const ConvexShape& s, Vec2 p, Vec2& closest) noexcept {
  if (s.vertices.size() == 1) {
    closest = s.vertices[0];
    return length(p - closest);
  }
  if (core_contains(s, p)) {
    closest = p;
    return 0.0;
  }
  double best = kInfinity;
  for (int i = 0, n = core_edge_count(s); i < n; ++i) {
    Vec2 a, b, q;
    core_edge(s, i, a, b);
    const double d = point_segment_distance(p, a, b, &q);
    if (d < best) {
      best = d;
      closest = q;
    }
  }
  return best;
}

struct CoreBox {
  Vec2 lo{kInfinity, kInfinity}, hi{-kInfinity, -kInfinity};
};

CoreBox core_box(const ConvexShape& s) noexcept {
  CoreBox box;
  for (Vec2 v : s.vertices) {
    box.lo = {std::min(box.lo.x, v.x), std::min(box.lo.y, v.y)};
    box.hi = {std::max(box.hi.x, v.x), std::max(box.hi.y, v.y)};
  }
  return box;
}

// Whether the closed segment's box meets the closed box (else the segment meets nothing in it).
bool segment_meets_box(Vec2 a, Vec2 b, const CoreBox& box) noexcept {
  return std::min(a.x, b.x) <= box.hi.x && std::max(a.x, b.x) >= box.lo.x && std::min(a.y, b.y) <= box.hi.y &&
         std::max(a.y, b.y) >= box.lo.y;
}

// Calls fn(a0, a1, b0, b1) for the pairs of core edges of a and b that can share a point,
// in row order (edges of a outer); stops when fn returns true. Edges meet only inside both
// cores' boxes, so an edge of a outside b's box skips its whole row: two polygons of
// thousands of vertices that are apart cost n + m box tests, not n * m.
//
// Two many-gons whose boxes overlap would still pair every edge with every other; there the
// edges of b are indexed by runs monotone in x (a convex polygon has at most three: its
// lower and upper chains, one split where the vertex list starts), in which the edges' x
// ranges follow each other, so each edge of a visits, by binary search, only the edges of b
// whose x range meets its own: O((n + m) log m) for two overlapping 7000-gons instead of
// n * m. Edges with disjoint x ranges share no point, so fn sees every pair that can meet;
// only the order of the pairs within a row changes (callers depend on the row order alone).
template <class Fn>
bool any_edge_pair(const ConvexShape& a, const ConvexShape& b, Fn&& fn) {
  const CoreBox box_a = core_box(a), box_b = core_box(b);
  const int n = core_edge_count(a), m = core_edge_count(b);
  // Each run: edges of b in increasing x, as indices into `order`, from run_start[r].
  thread_local std::vector<int> order;
  thread_local std::vector<int> run_start;
  bool indexed = false;
  if (static_cast<long long>(n) * m > 4096) {
    order.clear();
    run_start.clear();
    int sign = 0;  // of dx along the current run: +1, -1, or 0 while only vertical edges
    std::size_t first = 0;
    auto close_run = [&]() {
      if (sign < 0) std::reverse(order.begin() + static_cast<std::ptrdiff_t>(first), order.end());
      run_start.push_back(static_cast<int>(first));
    };
    for (int j = 0; j < m; ++j) {
      Vec2 b0, b1;
      core_edge(b, j, b0, b1);
      const int s = b1.x > b0.x ? 1 : (b1.x < b0.x ? -1 : 0);
      if (s != 0 && sign != 0 && s != sign) {
        close_run();
        first = order.size();
        sign = 0;
      }
      if (s != 0) sign = s;
      order.push_back(j);
    }
    close_run();
    run_start.push_back(static_cast<int>(order.size()));
    indexed = run_start.size() <= 9;  // at most 8 runs (convex cores have 3)
  }
  for (int i = 0; i < n; ++i) {
    Vec2 a0, a1;
    core_edge(a, i, a0, a1);
    if (!segment_meets_box(a0, a1, box_b)) continue;
    if (!indexed) {
      for (int j = 0; j < m; ++j) {
        Vec2 b0, b1;
        core_edge(b, j, b0, b1);
        if (segment_meets_box(b0, b1, box_a) && fn(a0, a1, b0, b1)) return true;
      }
      continue;
    }
    const double x0 = std::min(a0.x, a1.x), x1 = std::max(a0.x, a1.x);
    const CoreBox edge_box{{x0, std::min(a0.y, a1.y)}, {x1, std::max(a0.y, a1.y)}};
    for (std::size_t r = 0; r + 1 < run_start.size(); ++r) {
      const auto begin = order.begin() + run_start[r], end = order.begin() + run_start[r + 1];
      // The first edge of the run whose x range reaches x0 (their right ends increase).
      auto it = std::partition_point(begin, end, [&](int j) {
        Vec2 b0, b1;
        core_edge(b, j, b0, b1);
        return std::max(b0.x, b1.x) < x0;
      });
      for (; it != end; ++it) {
        Vec2 b0, b1;
        core_edge(b, *it, b0, b1);
        if (std::min(b0.x, b1.x) > x1) break;  // this and every later edge lie right of the edge
        if (segment_meets_box(b0, b1, box_a) && segment_meets_box(b0, b1, edge_box) && fn(a0, a1, b0, b1))
          return true;
      }
    }
  }
  return false;
}

// The vertices of `from` nearest the core of `to`, as core_distance's loops over them would
// pick them: calls pick(d, v, q) for every vertex v whose distance d (closest point q) may be
// at most `limit`, in vertex order. A vertex farther from `to`'s bounding circle than `limit`
// is skipped: its distance is larger still. Returns the smallest distance seen.
template <class Pick>
double near_vertices(const ConvexShape& from, const ConvexShape& to, Vec2 center, double radius, double limit,
                     Pick&& pick) noexcept {
  double best = kInfinity;
  for (Vec2 v : from.vertices) {
    const double far = length(v - center);
    // The bound is rounded; the margin keeps every vertex whose true distance could be <= limit.
    if (far - radius - 1e-9 * (far + radius) > limit) continue;
    Vec2 q;
    const double d = point_core_distance(to, v, q);
    best = std::min(best, d);
    pick(d, v, q);
  }
  return best;
}

// Distance between the cores of two shapes with the closest points (pa on a, pb on b): the
// first crossing edge pair, else the first vertex (of a, then of b) at the least distance.
// Both searches skip what cannot matter (edge pairs outside the cores' boxes, vertices
// beyond the reach of the other's bounding circle), so polygons of thousands of vertices that
// are apart cost about n + m distance tests instead of n * m; the result is the one the full
// double loop gives.
double core_distance(const ConvexShape& a, const ConvexShape& b, Vec2& pa, Vec2& pb) noexcept {
  const bool crossing = any_edge_pair(a, b, [&](Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
    if (!segments_intersect(a0, a1, b0, b1)) return false;
    pa = pb = a0;
    return true;
  });
  if (crossing) return 0.0;
  // Without crossings, one core inside the other (a many-gon light nested in a many-gon
  // occluder) is at distance 0: found at once, where the vertex loops below would measure
  // every vertex of one against every edge of the other, n * m.
  for (const auto& [inner, outer] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    if (core_contains(*outer, inner->vertices[0])) {
      pa = pb = inner->vertices[0];
      return 0.0;
    }
  }
  // Bounding circles of the cores about their centroids (inside them).
  auto bounding_radius = [](const ConvexShape& s) {
    double r = 0.0;
    for (Vec2 v : s.vertices) r = std::max(r, length(v - s.centroid));
    return r;
  };
  const double radius_a = bounding_radius(a), radius_b = bounding_radius(b);
  // First the least distance, visiting likely vertices first so the bound tightens at once;
  // then the first pair at that distance in the full loops' order.
  double least = kInfinity;
  {
    auto none = [](double, Vec2, Vec2) {};
    // The vertex of a nearest b's centroid, then all (pruned by what it found), then b's.
    Vec2 seed_q;
    double seed = kInfinity;
    double nearest = kInfinity;
    for (Vec2 v : a.vertices) nearest = std::min(nearest, length(v - b.centroid));
    for (Vec2 v : a.vertices)
      if (length(v - b.centroid) == nearest) {
        seed = point_core_distance(b, v, seed_q);
        break;
      }
    least = std::min(seed, near_vertices(a, b, b.centroid, radius_b, seed, none));
    least = std::min(least, near_vertices(b, a, a.centroid, radius_a, least, none));
  }
  double best = kInfinity;
  near_vertices(a, b, b.centroid, radius_b, least, [&](double d, Vec2 v, Vec2 q) {
    if (d < best) best = d, pa = v, pb = q;
  });
  near_vertices(b, a, a.centroid, radius_a, least, [&](double d, Vec2 v, Vec2 q) {
    if (d < best) best = d, pa = q, pb = v;
  });
  return best;
}

// Ray x + t*dir against the closed segment [a, b]; +infinity when it misses.
double ray_segment(Vec2 x, Vec2 dir, Vec2 a, Vec2 b) noexcept {
  const Vec2 e = b - a, w = a - x;
  const double denom = cross(dir, e);
  if (denom != 0.0) {
    const double t = side_of(a, b, x) / denom;
    const double s = cross(w, dir) / denom;
    return (t >= 0.0 && s >= 0.0 && s <= 1.0) ? t : kInfinity;
  }
  if (cross(w, dir) != 0.0) return kInfinity;  // parallel, not on the ray's line
  const double ta = dot(a - x, dir), tb = dot(b - x, dir);
  if (ta <= 0.0 && tb >= 0.0) return 0.0;  // x lies on the segment
  if (tb <= 0.0 && ta >= 0.0) return 0.0;
  const double t = std::min(ta, tb);
  return t >= 0.0 ? t : kInfinity;
}

void circle_segment_points(Vec2 c, double r, Vec2 a, Vec2 b, std::vector<Vec2>& out) {
  const Vec2 d = b - a, f = a - c;
  const double qa = dot(d, d), qb = 2.0 * dot(f, d), qc = dot(f, f) - r * r;
  const double disc = qb * qb - 4.0 * qa * qc;
  if (qa == 0.0 || disc < 0.0) return;
  const double root = std::sqrt(disc);
  for (double s : {(-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)}) {
    if (s >= 0.0 && s <= 1.0) out.push_back(a + s * d);
  }
}

void segment_segment_points(Vec2 a, Vec2 b, Vec2 c, Vec2 d, std::vector<Vec2>& out) {
  const Vec2 e = b - a, f = d - c;
  const double denom = cross(e, f);
  if (denom != 0.0) {
    const double s = cross(c - a, f) / denom, t = cross(c - a, e) / denom;
    if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0) out.push_back(a + s * e);
    return;
  }
  if (cross(c - a, e) != 0.0) return;  // parallel lines apart
  // Collinear: the shared piece's end points are those end points lying on the other segment.
  const double len2 = dot(e, e);
  for (Vec2 p : {c, d}) {
    const double s = dot(p - a, e) / len2;
    if (s >= 0.0 && s <= 1.0) out.push_back(p);
  }
  const double flen2 = dot(f, f);
  for (Vec2 p : {a, b}) {
    const double t = dot(p - c, f) / flen2;
    if (t >= 0.0 && t <= 1.0) out.push_back(p);
  }
}

}  // namespace

bool contains(const ConvexShape& s, Vec2 x) noexcept {
  switch (s.kind) {
    case ShapeKind::circle: return circle_power(s.vertices[0], s.radius, x) <= 0.0;
    case ShapeKind::segment: {
      const Vec2 a = s.vertices[0], b = s.vertices[1];
      return side_of(a, b, x) == 0.0 && dot(x - a, b - a) >= 0.0 && dot(x - b, a - b) >= 0.0;
    }
    case ShapeKind::polygon: return core_contains(s, x);
  }
  return false;
}

double ray_entry(const ConvexShape& s, Vec2 x, Vec2 dir) noexcept {
  switch (s.kind) {
    case ShapeKind::circle: {
      const Vec2 m = x - s.vertices[0];
      const double c = circle_power(s.vertices[0], s.radius, x);
      if (c <= 0.0) return 0.0;
      const double b = dot(m, dir);
      const double disc = b * b - c;
      if (b > 0.0 || disc < 0.0) return kInfinity;  // pointing away, or passing by
      // -b - sqrt(disc) without its cancellation (a point near a circle of radius 1e17).
      return c / (-b + std::sqrt(disc));
    }
    case ShapeKind::segment: return ray_segment(x, dir, s.vertices[0], s.vertices[1]);
    case ShapeKind::polygon: {
      if (core_contains(s, x)) return 0.0;
      double t = kInfinity;
      const size_t n = s.vertices.size();
      for (size_t i = 0; i < n; ++i) t = std::min(t, ray_segment(x, dir, s.vertices[i], s.vertices[(i + 1) % n]));
      return t;
    }
  }
  return kInfinity;
}

AngularSpan angular_span(const ConvexShape& s, Vec2 x) noexcept {
  AngularSpan span;
  if (contains(s, x)) {
    span.full = true;
    span.start = -kPi;
    span.width = kTwoPi;
    return span;
  }
  if (s.kind == ShapeKind::circle) {
    const Vec2 d = s.vertices[0] - x;
    // asin(r / |d|) loses everything where r / |d| rounds to 1 (x near a huge circle); the
    // tangent length sqrt(|d|^2 - r^2) keeps the angle exact.
    const double half = std::atan2(s.radius, std::sqrt(std::max(0.0, circle_power(s.vertices[0], s.radius, x))));
    span.start = wrap_angle(std::atan2(d.y, d.x) - half);
    span.width = 2.0 * half;
    return span;
  }
  // Outside a convex shape every vertex lies within less than pi of the direction to an
  // interior point, so angles relative to that direction order the vertices exactly (relative
  // to a vertex instead, a half-plane-like polygon seen from near its edge puts the other end
  // near +-pi, where the sign of a cancelling cross product decides). The span is the range
  // of the vertices' angles alone.
  auto measure = [&](Vec2 ref, double& lo, double& hi) {
    lo = kInfinity;
    hi = -kInfinity;
    for (Vec2 v : s.vertices) {
      const Vec2 d = v - x;
      const double a = std::atan2(cross(ref, d), dot(ref, d));
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
  };
  Vec2 ref = s.centroid - x;
  double lo, hi;
  measure(ref, lo, hi);
  if (!(lo <= 0.0 && hi >= 0.0) || (ref.x == 0.0 && ref.y == 0.0)) {
    // The stored centroid is rounded to its coordinates' ulp: for a shape a few ulps across
    // (a segment 5 ulps long at 1e15) it can fall off the shape, outside the span (or onto x).
    // The sum of the vertices' offsets from x points to the centroid without that rounding
    // wherever the shape is near x; far from x the stored centroid was inside already.
    ref = {0.0, 0.0};
    for (Vec2 v : s.vertices) ref = ref + (v - x);
    measure(ref, lo, hi);
  }
  span.start = wrap_angle(std::atan2(ref.y, ref.x) + lo);
  span.width = hi - lo;
  return span;
}

bool tangent_directions(const ConvexShape& s, Vec2 x, Vec2& cw, Vec2& ccw) noexcept {
  if (contains(s, x)) return false;
  if (s.kind == ShapeKind::circle) {
    // Rotate the center direction by +-asin(r/d): cos = t/d, sin = r/d with t the tangent
    // length; scaled by d, no trigonometry needed.
    const Vec2 d = s.vertices[0] - x;
    const double t = std::sqrt(std::max(0.0, circle_power(s.vertices[0], s.radius, x)));
    const double r = s.radius;
    cw = {d.x * t + d.y * r, -d.x * r + d.y * t};
    ccw = {d.x * t - d.y * r, d.x * r + d.y * t};
    return true;
  }
  cw = ccw = s.vertices[0] - x;
  for (std::size_t i = 1; i < s.vertices.size(); ++i) {
    const Vec2 d = s.vertices[i] - x;
    if (cross(cw, d) < 0.0) cw = d;
    if (cross(ccw, d) > 0.0) ccw = d;
  }
  return true;
}

void tangent_vertices(const ConvexShape& s, Vec2 x, int& cw, int& ccw) noexcept {
  cw = ccw = 0;
  Vec2 cw_dir = s.vertices[0] - x, ccw_dir = cw_dir;
  for (std::size_t i = 1; i < s.vertices.size(); ++i) {
    const Vec2 d = s.vertices[i] - x;
    if (cross(cw_dir, d) < 0.0) cw_dir = d, cw = static_cast<int>(i);
    if (cross(ccw_dir, d) > 0.0) ccw_dir = d, ccw = static_cast<int>(i);
  }
}

bool arc_contains(Vec2 outer_cw, Vec2 outer_ccw, Vec2 inner_cw, Vec2 inner_ccw) noexcept {
  // Arcs narrower than pi: containment is both inner ends inside the outer cone.
  return cross(outer_cw, inner_cw) >= 0.0 && cross(inner_ccw, outer_ccw) >= 0.0 &&
         cross(outer_cw, inner_ccw) >= 0.0 && cross(inner_cw, outer_ccw) >= 0.0;
}

double shape_distance(const ConvexShape& a, const ConvexShape& b) noexcept {
  Vec2 pa, pb;
  return std::max(0.0, core_distance(a, b, pa, pb) - a.radius - b.radius);
}

double point_distance(const ConvexShape& s, Vec2 p) noexcept {
  if (s.kind == ShapeKind::polygon && core_contains(s, p)) return 0.0;
  if (s.kind == ShapeKind::circle) {
    const double power = circle_power(s.vertices[0], s.radius, p);
    return power <= 0.0 ? 0.0 : power / (length(p - s.vertices[0]) + s.radius);
  }
  Vec2 closest;
  return std::max(0.0, point_core_distance(s, p, closest) - s.radius);
}

namespace {

// t_S along dir from x outside the shape; for polygons the entry edge is found by walking
// from `hint` (updated; -1 when the ray misses).
double entry_with_hint(const ConvexShape& s, Vec2 x, Vec2 dir, int& hint) noexcept {
  if (s.kind != ShapeKind::polygon) return ray_entry(s, x, dir);
  const int n = static_cast<int>(s.vertices.size());
  if (hint >= 0 && hint < n) {
    for (int i = hint, from = -1, steps = 0; steps < n; ++steps) {
      const Vec2 a = s.vertices[i], e = s.vertices[(i + 1) % n] - a, w = a - x;
      const double denom = cross(dir, e);
      if (denom == 0.0) break;
      const double u = cross(w, dir) / denom;
      if (u >= 0.0 && u <= 1.0) {
        const double side = side_of(a, s.vertices[(i + 1) % n], x);  // cross(w, e) = cross(e, x - a)
        const double t = side / denom;
        // The entry is on a front-facing edge (x outside it); a back edge means a scan is needed.
        if (t >= 0.0 && side < 0.0) {
          hint = i;
          return t;
        }
        break;
      }
      const int next = u > 1.0 ? (i + 1) % n : (i + n - 1) % n;
      if (next == from) break;  // rounding at a vertex: let the scan settle it
      from = i;
      i = next;
    }
  }
  double best = kInfinity;
  hint = -1;
  for (int i = 0; i < n; ++i) {
    const double t = ray_segment(x, dir, s.vertices[i], s.vertices[(i + 1) % n]);
    if (t < best) best = t, hint = i;
  }
  return best;
}

}  // namespace

namespace {

// kContactTolerance relative to the shape's coordinates, as occluder_first's tolerance is
// relative to the light point's: a huge other shape must not widen what counts as a contact.
double contact_tolerance_of(const ConvexShape& s) noexcept {
  return kContactTolerance *
         std::max({std::abs(s.bounds_min.x), std::abs(s.bounds_min.y), std::abs(s.bounds_max.x), std::abs(s.bounds_max.y)});
}

}  // namespace

bool meets_within_contact(const ConvexShape& light, const ConvexShape& occluder) noexcept {
  return shape_distance(light, occluder) <= contact_tolerance_of(light);
}

bool contained_within_contact(const ConvexShape& inner, const ConvexShape& outer) noexcept {
  const double tolerance = contact_tolerance_of(inner);
  if (inner.kind != ShapeKind::circle) {
    // Convex: the hull of the vertices lies in the (grown) convex outer shape with them.
    for (Vec2 v : inner.vertices)
      if (!(point_distance(outer, v) <= tolerance)) return false;
    return true;
  }
  const Vec2 c = inner.vertices[0];
  const double r = inner.radius;
  switch (outer.kind) {
    case ShapeKind::circle:
      return length(c - outer.vertices[0]) + r <= outer.radius + tolerance;
    case ShapeKind::polygon:
      // The disc is inside when its center is at least r inside every edge line.
      for (std::size_t i = 0; i < outer.vertices.size(); ++i)
        if (!(dot(outer.edge_normals[i], c - outer.vertices[i]) >= r - tolerance)) return false;
      return true;
    case ShapeKind::segment:
      return false;  // a disc of radius > 0 has area
  }
  return false;
}

bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, Vec2 dir) noexcept {
  EntryHints hints;
  return occluder_first(occluder, light, x, dir, hints);
}

bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, Vec2 dir,
                    EntryHints& hints) noexcept {
  const double t_light = entry_with_hint(light, x, dir, hints.light);
  const double t_occluder = entry_with_hint(occluder, x, dir, hints.occluder);
  if (t_occluder <= t_light) return true;
  if (!(t_light < kInfinity)) return false;
  const Vec2 entry = x + t_light * dir;
  const double scale = std::max({std::abs(x.x), std::abs(x.y), std::abs(entry.x), std::abs(entry.y), t_light});
  const double tolerance = kContactTolerance * scale;
  if (occluder.kind != ShapeKind::polygon || hints.occluder < 0) return point_distance(occluder, entry) <= tolerance;
  // The light's entry point lies before the occluder along the ray, so outside it; where it
  // touches the occluder, the ray enters the occluder there too (a grazing ray that does not
  // is a zero-measure case): the entry edge and its neighbours are the only edges to check.
  const int n = static_cast<int>(occluder.vertices.size());
  for (int k = -1; k <= 1; ++k) {
    const int i = (hints.occluder + k + n) % n;
    if (point_segment_distance(entry, occluder.vertices[i], occluder.vertices[(i + 1) % n]) <= tolerance) return true;
  }
  return false;
}

std::optional<Line> separating_line(const ConvexShape& positive, const ConvexShape& negative) noexcept {
  Vec2 pn, pp;  // closest core points on `negative` and `positive`
  const double core = core_distance(negative, positive, pn, pp);
  if (!(core - negative.radius - positive.radius > 0.0)) return std::nullopt;
  const Vec2 n = (1.0 / core) * (pp - pn);
  // The perpendicular bisector of the closest points of two disjoint convex sets separates them.
  const Vec2 on_negative = pn + negative.radius * n;
  const Vec2 on_positive = pp - positive.radius * n;
  return Line{n, 0.5 * (on_negative + on_positive)};
}

void boundary_intersections(const ConvexShape& a, const ConvexShape& b, std::vector<Vec2>& out) {
  const bool a_circle = a.kind == ShapeKind::circle, b_circle = b.kind == ShapeKind::circle;
  if (a_circle && b_circle) {
    const Vec2 c0 = a.vertices[0], c1 = b.vertices[0];
    const Vec2 d = c1 - c0;
    const double dist = length(d);
    const double r0 = a.radius, r1 = b.radius;
    if (dist == 0.0 || dist > r0 + r1 || dist < std::abs(r0 - r1)) return;
    const double along = (dist * dist + r0 * r0 - r1 * r1) / (2.0 * dist);
    const double h = std::sqrt(std::max(0.0, r0 * r0 - along * along));
    const Vec2 u = (1.0 / dist) * d, perp{-u.y, u.x};
    const Vec2 mid = c0 + along * u;
    out.push_back(mid + h * perp);
    out.push_back(mid - h * perp);
    return;
  }
  if (a_circle || b_circle) {
    const ConvexShape& circle = a_circle ? a : b;
    const ConvexShape& other = a_circle ? b : a;
    for (int i = 0, n = core_edge_count(other); i < n; ++i) {
      Vec2 e0, e1;
      core_edge(other, i, e0, e1);
      circle_segment_points(circle.vertices[0], circle.radius, e0, e1, out);
    }
    return;
  }
  any_edge_pair(a, b, [&](Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
    segment_segment_points(a0, a1, b0, b1, out);
    return false;
  });
}

}  // namespace par2d::detail
