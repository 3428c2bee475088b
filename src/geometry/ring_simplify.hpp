// Simplifies many rings together within a distance tolerance, never letting any two meet.
#pragma once

#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// Removes vertices from `rings` (closed, the first vertex not repeated) while every removed
// original vertex stays within `tolerance` of the edge that replaces it, the smallest such
// distance first. Input: rings that are each simple and pairwise apart (no two edges of any
// rings meet but adjacent ones at their shared vertex), finite coordinates. A vertex V between
// P and N goes only where the closed triangle P, V, N holds no other vertex of any ring, which
// keeps that input condition (an edge that would cross or touch the new edge P-N must have an
// end inside the triangle), and where its ring keeps 3 vertices; every orientation test is
// exact. Vertices exactly on the line between their neighbours go first, whatever the tolerance.
// A vertex blocked by another is tried again after a pass that removed something (at most 16
// passes). Every kept vertex is an input vertex, bit for bit. O(n log n) a pass for n vertices
// when the triangles each cover few of a uniform grid's cells, plus the original vertices each
// replaced edge spans.
void simplify_rings(std::vector<std::vector<Vec2>>& rings, double tolerance);

}  // namespace par2d::detail
