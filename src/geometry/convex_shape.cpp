// Canonical convex shapes: their construction (make_convex_shape, centroid_radius) and the exact
// primitives every query builds on (length, cross_from, circle_power, to_circle_boundary). The
// queries themselves (containment, rays, arcs, distances, contacts) are in convex_shape_queries.cpp.
#include "geometry/convex_shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/exact_arithmetic.hpp"

namespace par2d::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// docs/contract.md section 3: a turn this small relative to its edges counts as straight.
constexpr double kStraightTurn = 1e-9;

}  // namespace

// cross(a - x, b - x) with each difference split exactly into a rounded part and its error,
// the eight products split exactly, all summed without error. Out of line: rarely needed.
double exact_cross_from(Vec2 a, Vec2 b, Vec2 x) noexcept {
  double ax, axe, ay, aye, bx, bxe, by, bye;
  two_sum(a.x, -x.x, ax, axe);
  two_sum(a.y, -x.y, ay, aye);
  two_sum(b.x, -x.x, bx, bxe);
  two_sum(b.y, -x.y, by, bye);
  ExactSum sum;
  sum.add_product(axe, bye);
  sum.add_product(-aye, bxe);
  sum.add_product(ax, bye);
  sum.add_product(axe, by);
  sum.add_product(-ay, bxe);
  sum.add_product(-aye, bx);
  sum.add_product(ax, by);
  sum.add_product(-ay, bx);
  return sum.value();
}

double cross_from(Vec2 a, Vec2 b, Vec2 x) noexcept { return side_of(a, b, x); }

namespace {

[[gnu::noinline]] double exact_circle_power(Vec2 center, double radius, Vec2 x) noexcept {
  double mx, mxe, my, mye;
  two_sum(x.x, -center.x, mx, mxe);
  two_sum(x.y, -center.y, my, mye);
  ExactSum sum;
  sum.add_product(mxe, mxe);
  sum.add_product(mye, mye);
  sum.add_product(2.0 * mx, mxe);
  sum.add_product(2.0 * my, mye);
  sum.add_product(-radius, radius);
  sum.add_product(mx, mx);
  sum.add_product(my, my);
  return sum.value();
}

}  // namespace

double circle_power(Vec2 center, double radius, Vec2 x) noexcept {
  const Vec2 m = x - center;
  const double mm = dot(m, m), rr = radius * radius;
  const double plain = mm - rr;
  if (std::abs(plain) > kPlainEnough * (mm + rr) || !(mm + rr < kInfinity)) return plain;
  return exact_circle_power(center, radius, x);
}

Vec2 to_circle_boundary(Vec2 center, double radius, Vec2 p) noexcept {
  const Vec2 d = center - p;
  const double len = length(d);
  if (!(len > 0.0)) return {radius, 0.0};
  // Signed distance to the circle (negative inside), then along the unit direction to the center.
  const double dist = circle_power(center, radius, p) / (len + radius);
  return dist * ((1.0 / len) * d);
}

double length(Vec2 a) noexcept {
  // sqrt of the squared length is as exact as hypot and much faster; hypot only where the
  // square would overflow or lose everything to underflow (coordinates may be any finite number).
  const double squared = a.x * a.x + a.y * a.y;
  if (squared > 1e-290 && squared < 1e290) return std::sqrt(squared);
  return std::hypot(a.x, a.y);
}

ConvexShape make_convex_shape(const Shape& shape) {
  ConvexShape s;
  make_convex_shape(shape, s);
  return s;
}

void make_convex_shape(const Shape& shape, ConvexShape& s) {
  s.vertices.clear();
  s.edge_normals.clear();
  s.radius = 0.0;
  if (const auto* circle = std::get_if<Circle>(&shape)) {
    s.kind = ShapeKind::circle;
    s.vertices.push_back(circle->center);
    s.radius = circle->radius;
  } else if (const auto* segment = std::get_if<Segment>(&shape)) {
    s.kind = ShapeKind::segment;
    s.vertices.push_back(segment->a);
    s.vertices.push_back(segment->b);
  } else {
    s.kind = ShapeKind::polygon;
    std::vector<Vec2>& v = s.vertices;
    for (Vec2 p : std::get<Polygon>(shape).vertices) {
      if (v.empty() || p.x != v.back().x || p.y != v.back().y) v.push_back(p);
    }
    while (v.size() > 1 && v.front().x == v.back().x && v.front().y == v.back().y) v.pop_back();
    // Winding, straightness and normals are decided on coordinates scaled by a power of two
    // (exact) into [-1, 1], as validation does: with coordinates near 1e160 and beyond, raw
    // cross products overflow to inf/NaN, which reversed nothing and erased every vertex as
    // "straight" (inf <= 1e-9 * inf). The tests are scale-invariant, so for ordinary
    // coordinates the verdicts are bit-for-bit those of the raw numbers.
    double max_abs = 0.0;
    for (Vec2 p : v) max_abs = std::max({max_abs, std::abs(p.x), std::abs(p.y)});
    int exponent = 0;
    std::frexp(max_abs, &exponent);
    const auto scaled = [exponent](Vec2 p) { return Vec2{std::ldexp(p.x, -exponent), std::ldexp(p.y, -exponent)}; };
    // The area is summed relative to the first vertex: with absolute coordinates, a small
    // polygon far from the origin (0.1 units at 1e7) loses the area's sign to cancellation.
    double area2 = 0.0;
    const Vec2 anchor = v.empty() ? Vec2{} : scaled(v[0]);
    for (size_t i = 0; i < v.size(); ++i)
      area2 += cross(scaled(v[i]) - anchor, scaled(v[(i + 1) % v.size()]) - anchor);
    if (area2 < 0.0) std::reverse(v.begin(), v.end());
    // Drop straight turns until none is left (each removal can straighten a neighbour). A
    // pass walks the ring once, compacting in place: a vertex's turn is taken from the last
    // vertex kept (the ring's last one while none is kept yet) to the next one not yet seen
    // (the first kept, for the last vertex), and the pass stops with 3 vertices left, so it
    // keeps exactly what erasing each straight vertex at once would keep, in linear time.
    for (bool removed = true; removed && v.size() > 3;) {
      removed = false;
      const std::size_t n = v.size();
      std::size_t kept = 0, i = 0;
      for (; i < n && kept + (n - i) > 3; ++i) {
        const Vec2 prev = scaled(kept > 0 ? v[kept - 1] : v[n - 1]), next = scaled(i + 1 < n ? v[i + 1] : v[0]);
        const Vec2 e1 = scaled(v[i]) - prev, e2 = next - scaled(v[i]);
        if (std::abs(cross(e1, e2)) <= kStraightTurn * length(e1) * length(e2)) {
          removed = true;
        } else {
          v[kept++] = v[i];
        }
      }
      for (; i < n; ++i) v[kept++] = v[i];
      v.resize(kept);
    }
    const std::size_t n = s.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 e = scaled(s.vertices[(i + 1) % n]) - scaled(s.vertices[i]);
      const double len = length(e);
      s.edge_normals.push_back({-e.y / len, e.x / len});
    }
  }
  s.bounds_min = {kInfinity, kInfinity};
  s.bounds_max = {-kInfinity, -kInfinity};
  // The vertex mean is summed at a power-of-two scale (exact) so that it cannot overflow.
  double max_abs = 0.0;
  for (Vec2 p : s.vertices) max_abs = std::max({max_abs, std::abs(p.x), std::abs(p.y)});
  int exponent = 0;
  std::frexp(max_abs, &exponent);
  Vec2 sum{0.0, 0.0};
  for (Vec2 p : s.vertices) {
    s.bounds_min = {std::min(s.bounds_min.x, p.x - s.radius), std::min(s.bounds_min.y, p.y - s.radius)};
    s.bounds_max = {std::max(s.bounds_max.x, p.x + s.radius), std::max(s.bounds_max.y, p.y + s.radius)};
    sum = sum + Vec2{std::ldexp(p.x, -exponent), std::ldexp(p.y, -exponent)};
  }
  const Vec2 mean = (1.0 / static_cast<double>(s.vertices.size())) * sum;
  s.centroid = {std::ldexp(mean.x, exponent), std::ldexp(mean.y, exponent)};
}

double centroid_radius(const ConvexShape& shape) noexcept {
  double farthest = 0.0;
  for (const Vec2 v : shape.vertices) farthest = std::max(farthest, dot(v - shape.centroid, v - shape.centroid));
  return std::sqrt(farthest) * (1.0 + 1e-12) + shape.radius;
}

}  // namespace par2d::detail
