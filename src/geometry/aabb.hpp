// Axis-aligned boxes: the one copy of the box type and its helpers (bounds of a shape, meet,
// union, growth) that the occluder index, the world and the culling share.
#pragma once

#include <algorithm>
#include <limits>

#include "geometry/convex_shape.hpp"
#include "geometry/vec2.hpp"

namespace par2d::detail {

// Axis-aligned box, closed on every side. Precondition everywhere: finite, min <= max
// (except kEmptyBox, the start of a growth).
struct Aabb {
  double min_x, min_y, max_x, max_y;
};

// The box that grows into exactly what is added to it (min > max until then).
inline constexpr Aabb kEmptyBox{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};

inline Aabb bounds_of(const ConvexShape& s) noexcept {
  return {s.bounds_min.x, s.bounds_min.y, s.bounds_max.x, s.bounds_max.y};
}

// Whether two closed boxes share a point.
inline bool boxes_meet(const Aabb& a, const Aabb& b) noexcept {
  return a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y && b.min_y <= a.max_y;
}

// The least box holding both.
inline Aabb box_union(const Aabb& a, const Aabb& b) noexcept {
  return {std::min(a.min_x, b.min_x), std::min(a.min_y, b.min_y), std::max(a.max_x, b.max_x),
          std::max(a.max_y, b.max_y)};
}

// Grows `a` to hold `b`, or the point `p`.
inline void grow(Aabb& a, const Aabb& b) noexcept { a = box_union(a, b); }
inline void grow(Aabb& a, Vec2 p) noexcept {
  a = {std::min(a.min_x, p.x), std::min(a.min_y, p.y), std::max(a.max_x, p.x), std::max(a.max_y, p.y)};
}

}  // namespace par2d::detail
