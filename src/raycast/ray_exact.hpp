// The ray caster's exact predicates and distances (raycast_renderer.cpp): written apart from
// src/geometry's, so that a bug in those cannot hide in the check that PAR is tested against.
#pragma once

#include "geometry/vec2.hpp"

namespace par2d::detail::ray_exact {

// cross(b - a, x - a) with its sign exact (twice the signed area of a, b, x).
double side_of(Vec2 a, Vec2 b, Vec2 x) noexcept;
// |x - c|^2 - r^2 with its sign exact: <= 0 where x lies in the closed disc.
double power_of(Vec2 c, double r, Vec2 x) noexcept;
// Smallest t >= 0 with x + t*d on the closed segment [a, b], or +inf.
double ray_segment(Vec2 x, Vec2 d, Vec2 a, Vec2 b) noexcept;

}  // namespace par2d::detail::ray_exact
