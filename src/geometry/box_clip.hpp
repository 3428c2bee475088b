// Clipping of convex segments and polygons to an axis-aligned box, so that shapes far larger
// than a tile reach the float kernels as the part of them that lies near the tile.
#pragma once

#include <vector>

#include "geometry/convex_shape.hpp"

namespace par2d::detail {

// The part of segment or polygon `s` inside the box |x - center.x| <= half,
// |y - center.y| <= half, into `out` (its buffers reused): new points lie on the shape's
// edge lines up to double rounding, a polygon keeps the normals of its own edges and gets
// the box's (inward, axis-aligned) for edges along the box. `tmp` is scratch. False when no
// piece with extent remains (a segment that misses the box or only touches it, a polygon
// whose remainder has no area); `out` is then unspecified.
// Euclidean distance from p to the closed shape (0 inside it), to a few ulps however far the
// shape's vertices are from p: for a polygon 1e217 across whose edge passes 100 units from p.
double distance_to_shape(const ConvexShape& s, Vec2 p) noexcept;

bool clip_to_box(const ConvexShape& s, Vec2 center, double half, ConvexShape& out, std::vector<Vec2>& tmp);

}  // namespace par2d::detail
