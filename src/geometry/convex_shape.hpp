// Canonical convex shapes in double precision and the exact scalar geometry every path shares:
// containment, ray entry distance, angular span seen from a point, separation of two shapes.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/vec2.hpp"
#include "par2d/scene.hpp"

namespace par2d::detail {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

enum class ShapeKind : std::uint8_t { polygon, circle, segment };

// A validated shape in canonical form. Polygons have positive signed area (cross of
// consecutive edges > 0), no repeated and no collinear vertices. A segment keeps its two
// end points in `vertices`; a circle keeps its center there and its radius in `radius`.
// Every kind is thus "convex hull of `vertices`, grown by `radius`".
struct ConvexShape {
  ShapeKind kind = ShapeKind::polygon;
  std::vector<Vec2> vertices;
  // Polygons: unit normal of edge i (vertex i to i+1), pointing inside.
  std::vector<Vec2> edge_normals;
  double radius = 0.0;
  Vec2 bounds_min, bounds_max;  // axis-aligned bounding box
  Vec2 centroid;                // an interior point (vertex mean; the center for circles)
};

// Canonical form of a shape that passed validate_scene.
ConvexShape make_convex_shape(const Shape& shape);
// The same into `out`, reusing its buffers (no allocation once they have grown).
void make_convex_shape(const Shape& shape, ConvexShape& out);

// Whether x lies in the closed shape.
bool contains(const ConvexShape& shape, Vec2 x) noexcept;

// Radius of a disc about the centroid that holds the closed shape (the hull of the vertices
// grown by `radius`), rounded up past the rounding of its own few operations.
double centroid_radius(const ConvexShape& shape) noexcept;

// t_S(theta) of docs/contract.md section 1 along the unit direction `dir`: 0 when x is in the
// shape, +infinity when the ray misses it.
double ray_entry(const ConvexShape& shape, Vec2 x, Vec2 dir) noexcept;

// The set of directions in which the shape is seen from x: the arc
// [start, start + width] (radians, start in (-pi, pi]). `full` (width 2*pi) when x is in
// the shape. Outside a convex shape the arc is narrower than pi.
struct AngularSpan {
  double start = 0.0;
  double width = 0.0;
  bool full = false;
};
AngularSpan angular_span(const ConvexShape& shape, Vec2 x) noexcept;

// The two tangent directions (not normalized) bounding the shape's arc seen from x, found
// with pseudo-cross products only: `cw` is the clockwise-most in angle order (the arc's
// start), `ccw` the other. False when x is in the shape (the arc is the full circle).
bool tangent_directions(const ConvexShape& shape, Vec2 x, Vec2& cw, Vec2& ccw) noexcept;

// For a polygon or segment and x outside it: indices of the vertices giving the two
// tangent directions of tangent_directions (ties go to the lowest index).
void tangent_vertices(const ConvexShape& shape, Vec2 x, int& cw, int& ccw) noexcept;

// Whether `outer`'s arc from x contains `inner`'s whole arc (x outside both; arcs < pi).
bool arc_contains(Vec2 outer_cw, Vec2 outer_ccw, Vec2 inner_cw, Vec2 inner_ccw) noexcept;

// cross(a - x, b - a), which equals cross(a - x, b - x): twice the signed area of x, a, b,
// positive when x lies left of the line a -> b in a y-up frame. Correct to a few ulps of the
// result and exact in sign wherever the plain formula cancels: for a segment 1e17 long and x
// a unit from its line, the plain products (~1e34) round by more than the result (~1e17).
// Where the plain value is well away from its rounding bound it is returned as is; otherwise
// the differences and products are expanded without error and summed exactly.
double cross_from(Vec2 a, Vec2 b, Vec2 x) noexcept;

// |x - center|^2 - radius^2 (the power of x with respect to the circle), correct to a few ulps
// of the result: negative inside, and divided by |x - center| + radius, the distance to the
// circle, which the plain |x - center| - radius loses entirely for radii of 1e17 and beyond.
double circle_power(Vec2 center, double radius, Vec2 x) noexcept;

// The vector from p to the point of the circle nearest p, exact to rounding relative to its
// own length (not to the center's coordinates): for a circle of radius 1e17 whose boundary
// passes p, center + radius * unit vector would be off by units.
Vec2 to_circle_boundary(Vec2 center, double radius, Vec2 p) noexcept;

// Distance between the closed shapes (0 when they intersect or touch).
double shape_distance(const ConvexShape& a, const ConvexShape& b) noexcept;

// Distance from p to the closed shape (0 inside it).
double point_distance(const ConvexShape& shape, Vec2 p) noexcept;

// Relative size of a contact: a light point this close to an occluder (times the largest
// coordinate involved) lies on it. Where a light's boundary runs along an occluder's
// boundary, docs/contract.md gives t_occ == t_L there (the light is not visible), but the
// two distances come from different edges and round apart by a few ulps; without a
// tolerance such pixels flicker between 0 and the full arc. 2^-40 is ~4000 ulps: far above
// rounding, far below any gap a scene can mean.
inline constexpr double kContactTolerance = 0x1p-40;

// Whether all of `inner` lies in the closed `outer` (points within kContactTolerance of it,
// relative to `inner`'s coordinates, counting as on it). A light so contained in an occluder is
// hidden from every point: a ray to any of its points meets the occluder no later.
bool contained_within_contact(const ConvexShape& inner, const ConvexShape& outer) noexcept;

// Whether `light` meets the closed `occluder` or comes within kContactTolerance of it
// (relative to the light's coordinates, as above): the pairs whose depth order the reference
// decides by contact, which a fast path must not take for disjoint. A segment light cut from
// an occluder's edge lies off the edge's line by rounding, on either side.
bool meets_within_contact(const ConvexShape& light, const ConvexShape& occluder) noexcept;

// Polygon edges where the last rays entered the two shapes (-1: none yet). Rays cast in
// angular order from one point enter a convex polygon along its near chain in order, so
// starting from the last entry edge and walking finds the next in O(1) amortized, where a
// scan of every edge made two overlapping 7000-gons cost O(n^2) per pixel.
struct EntryHints {
  int light = -1;
  int occluder = -1;
};

// Whether the occluder is hit no later than the light along the unit direction `dir` from x
// (docs/contract.md: the light is visible only when t_L < t_occ), ties decided as contacts:
// a light entry point within kContactTolerance of the occluder is behind it. x must lie in
// neither shape.
bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, Vec2 dir) noexcept;
bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, Vec2 dir,
                    EntryHints& hints) noexcept;

// A line through `point` with unit normal n that strictly separates two disjoint shapes:
// n.(p - point) > 0 on all of `positive`, < 0 on all of `negative`. Empty when they touch
// or overlap. Kept as a point, not an offset n.point, so that sides can be tested with
// differences of nearby coordinates (no cancellation far from the origin).
struct Line {
  Vec2 normal;
  Vec2 point;
  // Signed distance of p from the line, positive on the `positive` shape's side.
  double side(Vec2 p) const noexcept { return dot(normal, p - point); }
};
std::optional<Line> separating_line(const ConvexShape& positive, const ConvexShape& negative) noexcept;

// Points where the boundaries of two shapes meet (for shapes that overlap). Where
// boundaries share a piece of line, the end points of the shared piece.
void boundary_intersections(const ConvexShape& a, const ConvexShape& b, std::vector<Vec2>& out);


}  // namespace par2d::detail
