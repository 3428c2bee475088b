// Triangulation of a polygon with holes in O(n log n) (monotone_triangulation.cpp), for the
// convex partition (polygon_partition.hpp). Exact: every decision is an orientation sign or a
// comparison of coordinates.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// Triangulates the polygon whose rings lie in `points` one after another, `ring_sizes` long
// each: the outer ring counter-clockwise first, then the holes clockwise, all simple, pairwise
// disjoint, with no straight vertex. Appends counter-clockwise triangles of indices into
// `points` that tile the polygon (flat ones a run of collinear vertices would make are left
// out) and adds the orientation tests made to `tests`. False on a bug (valid input never).
bool triangulate_polygon(const std::vector<Vec2>& points, const std::vector<int>& ring_sizes,
                         std::vector<std::array<int, 3>>& triangles, std::size_t& tests);

// p and q lie on one line through apex and differ from it: whether on the same side of apex.
bool same_direction(Vec2 apex, Vec2 p, Vec2 q) noexcept;

}  // namespace par2d::detail
