// Liang-Barsky for segments and Sutherland-Hodgman for convex polygons, in coordinates
// relative to the box center (so that the clip points keep the precision the box needs).
#include "geometry/box_clip.hpp"

#include <algorithm>
#include <cmath>

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

// One side at a time, each crossing point interpolated from the end inside that side (a
// parameter along the whole segment would round away a box 1e-30 of its length).
bool clip_segment(const ConvexShape& s, Vec2 center, double half, ConvexShape& out) {
  Vec2 p = s.vertices[0] - center, q = s.vertices[1] - center;
  bool p_moved = false, q_moved = false;
  for (int side = 0; side < 4; ++side) {
    const int axis = side / 2;
    const double sign = side % 2 == 0 ? 1.0 : -1.0;
    auto level = [&](Vec2 v) { return sign * (axis == 0 ? v.x : v.y) - half; };  // <= 0 inside
    const double lp = level(p), lq = level(q);
    if (lp > 0.0 && lq > 0.0) return false;
    if (lp <= 0.0 && lq <= 0.0) continue;
    Vec2& outside = lp > 0.0 ? p : q;
    const Vec2 inside = lp > 0.0 ? q : p;
    const double li = lp > 0.0 ? lq : lp, lo = lp > 0.0 ? lp : lq;
    Vec2 x = inside + (li / (li - lo)) * (outside - inside);
    if (axis == 0) x.x = sign * half;
    else x.y = sign * half;
    outside = x;
    (lp > 0.0 ? p_moved : q_moved) = true;
  }
  out.kind = ShapeKind::segment;
  out.radius = 0.0;
  out.edge_normals.clear();
  out.vertices.resize(2);
  // An end kept whole stays exactly as it was.
  out.vertices[0] = p_moved ? center + p : s.vertices[0];
  out.vertices[1] = q_moved ? center + q : s.vertices[1];
  if (!(out.vertices[0].x != out.vertices[1].x || out.vertices[0].y != out.vertices[1].y)) return false;
  finish(out);
  return true;
}

}  // namespace

bool clip_to_box(const ConvexShape& s, Vec2 center, double half, ConvexShape& out, std::vector<Vec2>& tmp) {
  if (s.kind == ShapeKind::segment) return clip_segment(s, center, half, out);
  if (s.kind != ShapeKind::polygon) return false;
  // Vertices relative to the center, each with the normal of the edge that leaves it.
  std::vector<Vec2>& pts = out.vertices;
  std::vector<Vec2>& normals = out.edge_normals;
  pts.clear();
  normals.clear();
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    pts.push_back(s.vertices[i] - center);
    normals.push_back(s.edge_normals[i]);
  }
  // Sides as (axis, sign): keep sign * coordinate <= half.
  std::vector<Vec2> next_normals;
  for (int side = 0; side < 4; ++side) {
    const int axis = side / 2;
    const double sign = side % 2 == 0 ? 1.0 : -1.0;
    const Vec2 inward = axis == 0 ? Vec2{-sign, 0.0} : Vec2{0.0, -sign};
    auto level = [&](Vec2 v) { return sign * (axis == 0 ? v.x : v.y) - half; };  // <= 0 inside
    tmp.clear();
    next_normals.clear();
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 v = pts[i], w = pts[(i + 1) % n];
      const double lv = level(v), lw = level(w);
      if (lv <= 0.0) {
        tmp.push_back(v);
        // Leaving the box along this edge: the edge keeps its normal up to the exit point,
        // then the box side's edge follows.
        next_normals.push_back(normals[i]);
      }
      if ((lv <= 0.0) != (lw <= 0.0)) {
        // Crossing point, interpolated from the inside end.
        Vec2 x = lv <= 0.0 ? v + (lv / (lv - lw)) * (w - v) : w + (lw / (lw - lv)) * (v - w);
        if (axis == 0) x.x = sign * half;
        else x.y = sign * half;
        tmp.push_back(x);
        next_normals.push_back(lv <= 0.0 ? inward : normals[i]);
      }
    }
    pts.swap(tmp);
    normals.swap(next_normals);
    if (pts.size() < 3) return false;
  }
  // Drop repeated points (a vertex on a side) and zero-length edges.
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
  for (Vec2& v : pts) v = center + v;
  out.kind = ShapeKind::polygon;
  out.radius = 0.0;
  finish(out);
  return true;
}

}  // namespace par2d::detail
