// Plane vector arithmetic in double precision: the one copy every room uses (sums, dot, cross, length).
#pragma once

#include "par2d/scene.hpp"

namespace par2d::detail {

inline Vec2 operator+(Vec2 a, Vec2 b) noexcept { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) noexcept { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) noexcept { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) noexcept { return a.x * b.x + a.y * b.y; }
// Pseudo-cross product: > 0 when b is counter-clockwise of a in a y-up frame
// (clockwise on screen, where y points down). The signed area of o, a, b (twice) is
// cross(a - o, b - o).
inline double cross(Vec2 a, Vec2 b) noexcept { return a.x * b.y - a.y * b.x; }
// |a| without overflow or underflow for any finite coordinates.
double length(Vec2 a) noexcept;

}  // namespace par2d::detail
