// The pieces occluder boundaries are cut into for one bounce of indirect light
// (docs/contract.md section 7): one function shared by the reference, the ray caster and the
// scene checks, so every path agrees on where each piece is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// One piece of an occluder's boundary. Straight pieces run from `a` to `b`; an arc runs
// counter-clockwise in angle (from `angle0` to `angle1`, radians, on the circle `center`,
// `radius`), `a` and `b` its end points. `normal` is the outward unit normal (for an arc, at
// `mid`); `mid` is the midpoint (for an arc, the point at its middle angle).
struct BouncePiece {
  Vec2 a, b;
  Vec2 mid;
  Vec2 normal;
  bool arc = false;
  Vec2 center;
  double radius = 0.0;
  double angle0 = 0.0, angle1 = 0.0;
};

// How many pieces `shape` is cut into at piece length h (> 0): per polygon edge (as given,
// zero-length edges none) ceil(length / h); a segment twice ceil(length / h); a circle
// ceil(2 pi r / h). As a double, so that absurd counts (a 1e300-long edge) are reported, not
// wrapped; counting stops once it passes `stop_after`.
double bounce_piece_count(const Shape& shape, double h, double stop_after = 1e300) noexcept;

// Appends the pieces of `shape` to `out`, in this order: a polygon's edges as given (vertex i
// to i + 1, each from its first vertex to its second), a segment's face with normal
// perp = (e.y, -e.x) / |e| (e = b - a) then the face with -perp, each from a to b; a circle's
// arcs from angle 0 up. The count must have been checked (bounce_piece_count).
void bounce_pieces(const Shape& shape, double h, std::vector<BouncePiece>& out);

// The same with every point scaled by `factor` (a power of two: exact), h in the shape's units.
void bounce_pieces(const Shape& shape, double h, double factor, std::vector<BouncePiece>& out);

}  // namespace par2d::detail
