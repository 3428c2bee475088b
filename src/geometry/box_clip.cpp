// Sutherland-Hodgman clipping of convex segments and polygons to an axis-aligned box. Each
// crossing point is computed from its edge's line rather than by interpolating along the
// edge: for an edge 1e30 long the interpolation's rounding (1e14) would exceed a box of 1e13.
// The line is held relative to the box center (unit normal n, offset n.(a - center)), the
// offset from an exact cross product: n.a itself rounds by ulps of the vertex coordinates,
// and for vertices 1e217 from a view at -110 that moved the line by 1e201.
#include "geometry/box_clip.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

namespace par2d::detail {
namespace {

void finish(ConvexShape& out) {
  out.bounds_min = out.bounds_max = out.vertices[0];
  Vec2 sum{0.0, 0.0};
  for (Vec2 v : out.vertices) {
    out.bounds_min = {std::min(out.bounds_min.x, v.x), std::min(out.bounds_min.y, v.y)};
    out.bounds_max = {std::max(out.bounds_max.x, v.x), std::max(out.bounds_max.y, v.y)};
    sum = sum + v;
  }
  out.centroid = (1.0 / static_cast<double>(out.vertices.size())) * sum;
}

// One side of the box: sign * coordinate[axis] <= limit keeps a point.
struct Side {
  int axis;
  double sign, value;  // value: the side's coordinate
  double level(Vec2 v) const noexcept { return sign * (axis == 0 ? v.x : v.y) - sign * value; }
};

Side side_of(int index, Vec2 center, double half) noexcept {
  const int axis = index / 2;
  const double sign = index % 2 == 0 ? 1.0 : -1.0;
  return {axis, sign, (axis == 0 ? center.x : center.y) + sign * half};
}

// The exact power of two that brings the largest coordinate of these points to 2^500 or below.
int shift_below_overflow(std::initializer_list<Vec2> points) noexcept {
  double big = 0.0;
  for (Vec2 v : points) big = std::max({big, std::abs(v.x), std::abs(v.y)});
  return big > 0x1p500 ? 500 - std::ilogb(big) : 0;
}

Vec2 scaled(Vec2 v, int shift) noexcept { return {std::ldexp(v.x, shift), std::ldexp(v.y, shift)}; }

// perp(b - a) / |b - a|, the convention of ConvexShape::edge_normals, without overflow.
Vec2 unit_normal(Vec2 a, Vec2 b) noexcept {
  const int shift = shift_below_overflow({a, b});
  const Vec2 e = scaled(b, shift) - scaled(a, shift);
  const double len = length(e);
  return {-e.y / len, e.x / len};
}

// n.(a - center) for the unit normal n = perp(b - a) / |b - a| of the line through a and b
// (the convention of ConvexShape::edge_normals), exact to a few ulps of the result however
// far a and b are from the center. The three points are first scaled by a power of two
// (exact) so that neither |b - a| nor the cross product can overflow.
double offset_from_center(Vec2 a, Vec2 b, Vec2 center) noexcept {
  const int shift = shift_below_overflow({a, b, center});
  const Vec2 sa = scaled(a, shift), sb = scaled(b, shift), sc = scaled(center, shift);
  // n.(a - c) = -cross(a - c, b - a) / |b - a|.
  return std::ldexp(-cross_from(sa, sb, sc) / length(sb - sa), -shift);
}

// Where the line n.(p - center) = offset crosses the side (the edge from `inside` to
// `outside` does).
Vec2 crossing(const Side& side, Vec2 center, Vec2 n, double offset, Vec2 inside, Vec2 outside) noexcept {
  if (side.axis == 0 && n.y != 0.0) {
    const double local = side.value - center.x;  // +-half, as the side was placed
    return {side.value, center.y + (offset - n.x * local) / n.y};
  }
  if (side.axis == 1 && n.x != 0.0) {
    const double local = side.value - center.y;
    return {center.x + (offset - n.y * local) / n.x, side.value};
  }
  const double li = side.level(inside), lo = side.level(outside);
  Vec2 x = inside + (li / (li - lo)) * (outside - inside);
  (side.axis == 0 ? x.x : x.y) = side.value;
  return x;
}

bool clip_segment(const ConvexShape& s, Vec2 center, double half, ConvexShape& out) {
  Vec2 p = s.vertices[0], q = s.vertices[1];
  const Vec2 n = unit_normal(p, q);
  const double offset = offset_from_center(p, q, center);
  for (int index = 0; index < 4; ++index) {
    const Side side = side_of(index, center, half);
    const double lp = side.level(p), lq = side.level(q);
    if (lp > 0.0 && lq > 0.0) return false;
    if (lp <= 0.0 && lq <= 0.0) continue;
    if (lp > 0.0) p = crossing(side, center, n, offset, q, p);
    else q = crossing(side, center, n, offset, p, q);
  }
  if (!(p.x != q.x || p.y != q.y)) return false;
  out.kind = ShapeKind::segment;
  out.radius = 0.0;
  out.edge_normals.clear();
  out.vertices.assign({p, q});
  finish(out);
  return true;
}

// Distance from p to the closed segment [a, b], to a few ulps of the result however far the
// ends are from p (the perpendicular part from an exact cross product).
double segment_distance(Vec2 a, Vec2 b, Vec2 p) noexcept {
  const int shift = shift_below_overflow({a, b, p});
  const Vec2 sa = scaled(a, shift), sb = scaled(b, shift), sp = scaled(p, shift);
  const Vec2 e = sb - sa;
  const double t = dot(sp - sa, e);
  if (t <= 0.0) return std::ldexp(length(sp - sa), -shift);
  if (t >= dot(e, e)) return std::ldexp(length(sp - sb), -shift);
  return std::ldexp(std::abs(cross_from(sa, sb, sp)) / length(e), -shift);
}

}  // namespace

double distance_to_shape(const ConvexShape& s, Vec2 p) noexcept {
  if (s.kind == ShapeKind::circle)
    return circle_power(s.vertices[0], s.radius, p) > 0.0 ? length(to_circle_boundary(s.vertices[0], s.radius, p)) : 0.0;
  if (s.kind == ShapeKind::segment) return segment_distance(s.vertices[0], s.vertices[1], p);
  const std::size_t n = s.vertices.size();
  bool inside = true;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = s.vertices[i], b = s.vertices[(i + 1) % n];
    if (offset_from_center(a, b, p) > 0.0) inside = false;  // p beyond this edge's line (normals point in)
    nearest = std::min(nearest, segment_distance(a, b, p));
  }
  return inside ? 0.0 : nearest;
}

bool clip_to_box(const ConvexShape& s, Vec2 center, double half, ConvexShape& out, std::vector<Vec2>& tmp) {
  if (s.kind == ShapeKind::segment) return clip_segment(s, center, half, out);
  if (s.kind != ShapeKind::polygon) return false;
  // Each vertex with the normal and offset of the edge that leaves it.
  std::vector<Vec2>& pts = out.vertices;
  std::vector<Vec2>& normals = out.edge_normals;
  pts.assign(s.vertices.begin(), s.vertices.end());
  normals.assign(s.edge_normals.begin(), s.edge_normals.end());
  std::vector<double> offsets(pts.size()), next_offsets;
  for (std::size_t i = 0; i < pts.size(); ++i) offsets[i] = offset_from_center(pts[i], pts[(i + 1) % pts.size()], center);
  std::vector<Vec2> next_normals;
  for (int index = 0; index < 4; ++index) {
    const Side side = side_of(index, center, half);
    const Vec2 inward = side.axis == 0 ? Vec2{-side.sign, 0.0} : Vec2{0.0, -side.sign};
    tmp.clear();
    next_normals.clear();
    next_offsets.clear();
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 v = pts[i], w = pts[(i + 1) % n];
      const double lv = side.level(v), lw = side.level(w);
      if (lv <= 0.0) {
        tmp.push_back(v);
        next_normals.push_back(normals[i]);
        next_offsets.push_back(offsets[i]);
      }
      if ((lv <= 0.0) != (lw <= 0.0)) {
        tmp.push_back(lv <= 0.0 ? crossing(side, center, normals[i], offsets[i], v, w)
                                : crossing(side, center, normals[i], offsets[i], w, v));
        // Leaving the box, the side's edge follows the exit point; entering, the edge's own.
        if (lv <= 0.0) {
          next_normals.push_back(inward);
          next_offsets.push_back(dot(inward, tmp.back() - center));
        } else {
          next_normals.push_back(normals[i]);
          next_offsets.push_back(offsets[i]);
        }
      }
    }
    pts.swap(tmp);
    normals.swap(next_normals);
    offsets.swap(next_offsets);
    if (pts.size() < 3) return false;
  }
  // Drop repeated points (a vertex on a side) and so zero-length edges.
  std::size_t m = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2 v = pts[i], w = pts[(i + 1) % pts.size()];
    if (v.x == w.x && v.y == w.y) continue;
    pts[m] = v;
    normals[m] = normals[i];
    ++m;
  }
  pts.resize(m);
  normals.resize(m);
  if (m < 3) return false;
  out.kind = ShapeKind::polygon;
  out.radius = 0.0;
  finish(out);
  return true;
}

}  // namespace par2d::detail
