// Exact decomposition of a simple polygon with holes into convex pieces: a PARTITION (pieces
// with disjoint interiors whose union is the polygon exactly), so that concave lights and
// occluders can be made of par2d's convex shapes. Lights add, so the pieces must not overlap
// and must not leave gaps; every piece vertex is an input vertex (no new points are computed)
// and every decision is an exact-sign orientation test or a comparison of coordinates, so
// nothing depends on rounding.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// A polygon with holes: `outer` is its boundary, each entry of `holes` the boundary of a hole.
// Either winding is accepted for every ring (they are normalized); the closing edge is implied
// (do not repeat the first vertex at the end, though a repeat is tolerated).
struct PolygonRings {
  std::vector<Vec2> outer;
  std::vector<std::vector<Vec2>> holes;
};

// The most vertices partition_convex accepts over all rings together: the work is O(n log n)
// (65,536 vertices take a few tenths of a second), and the bound keeps one shape's pieces, and
// the memory the renderers give each, in reach; 65536 covers any hand-made or tile-derived
// outline.
inline constexpr std::size_t kMaxPartitionVertices = 65536;

// What a partition looked at, for tests of how its work grows: the pairs of edges its
// validation sweep compared, and the orientation tests its triangulation made (the sweep's
// comparisons of an edge with a vertex, and the monotone pieces' triangle tests).
struct PartitionWork {
  std::size_t edge_pairs = 0;
  std::size_t triangulation_tests = 0;
};

// Decomposes `polygon` into convex pieces.
//
// On success returns true and fills `pieces` (cleared first) with convex polygons that
// partition the polygon exactly: interiors pairwise disjoint, union = outer region minus the
// holes' regions. Each piece has at least 3 vertices, positive signed area (counter-clockwise
// in a y-up frame, the winding of ConvexShape), no repeated and no collinear vertices (every
// turn strictly convex), and every vertex is one of the input vertices, bit for bit. Pieces may
// meet in T-junctions (a vertex of one piece on an edge of another): harmless for a partition.
// The piece count is at most 2r + 1 - h (r: vertices with an interior angle above 180 degrees,
// h: holes), the Hertel-Mehlhorn bound; for a polygon without holes that is at most 4 times the
// fewest convex pieces possible.
//
// Accepted input: finite coordinates; consecutive repeated vertices and vertices exactly on
// the straight line between their neighbours are dropped first. Every ring must then be simple
// (no two non-adjacent edges meet, not even at a point; adjacent edges do not fold back onto
// each other) and enclose positive area; every hole must lie strictly inside the outer ring
// (not touching it), and holes must be pairwise disjoint (not touching, not nested).
//
// On failure returns false, leaves `pieces` empty and writes a one-line reason into `error`
// naming the ring ("outer", "holes[2]") and the input vertex or edge (edge k is the edge that
// starts at input vertex k of that ring), for example "outer: edges 2 and 5 cross",
// "holes[1]: not inside the outer boundary", "holes[0] and holes[2] overlap (edges 1 and 3
// cross)", "holes[2] lies inside holes[0] (nested holes)", "outer: fewer than 3 distinct
// vertices", "outer: zero area (all vertices on one line)", "outer: vertex 3 is not finite".
// `error` is left as it was on success.
//
// Cost: O(n log n) for n vertices in all rings, whatever the shape. Validation compares the
// pairs of edges whose x-ranges overlap (or y-ranges, where that makes far fewer: a comb's teeth
// side by side along either axis) while those are at most 16 an edge; past that (a star's
// edges around its centre) a sweep (Shamos-Hoey) checks them, and places the holes where they
// have more pairs than there are vertices. The triangulation (a sweep that cuts the polygon into
// monotone pieces, holes included, then one pass down each piece) is O(n log n), and merging
// the triangles costs O(1) a diagonal. `work`, when given, receives the pairs of edges compared
// and the triangulation's orientation tests. No input makes it crash, loop or produce
// non-finite output.
bool partition_convex(const PolygonRings& polygon, std::vector<std::vector<Vec2>>& pieces, std::string& error,
                      PartitionWork* work = nullptr);

// The same for a scene Polygon (its outline and holes), its pieces as Polygons. The second form only
// checks that a partition exists (validation), reusing per-thread buffers.
bool partition_polygon(const Polygon& polygon, std::vector<Polygon>& pieces, std::string& error);
bool partition_polygon(const Polygon& polygon, std::string& error);

// The boundaries that pieces of a partition (as partition_polygon makes them) share: where a
// straight path passes from one piece into another without leaving the polygon. Appends each
// shared stretch once, as a segment of positive length between two piece vertices (`out` is
// not cleared). Exact: collinearity by `orientation`, order along the line by coordinates.
// O(e log e + s) for e piece edges and s pairs of edges that overlap along their axis and lie
// on one vertical or horizontal line, or, for slanted edges, overlap in x and fall in one
// group of directions and distances from the origin chained 1e-12 apart (relative to the
// largest coordinate); `pairs`, when given, receives s.
void shared_boundaries(const std::vector<Polygon>& pieces, std::vector<Segment>& out, std::size_t* pairs = nullptr);

// How many pairs of the closed intervals `spans` (low, high) overlap as a sweep sees them: for
// each interval, those starting no earlier and no later than its high end. Sorts `spans`;
// O(n log n).
std::size_t sweep_pairs(std::vector<std::pair<double, double>>& spans);
// Whether a sweep over `count` items should run along y: only where the sweep along x would
// compare over 16 pairs an item and the one along y four times fewer, so that outlines of
// ordinary shape keep the x sweep (and the order in which it finds things).
inline bool sweep_along_y(std::size_t count, std::size_t x_pairs, std::size_t y_pairs) noexcept {
  return x_pairs > 16 * count && y_pairs < x_pairs / 4;
}

// The exact sign of cross(b - a, c - a) (twice the signed area of a, b, c): +1 when c lies
// strictly left of the line a -> b in a y-up frame, -1 strictly right, 0 exactly on it. Exact
// for all finite coordinates (no overflow or underflow assumption): a floating-point filter
// decides almost every call, and the rest are summed exactly in wide integers. Exposed for
// the tests, which check the pieces with the same exact predicate.
int orientation(Vec2 a, Vec2 b, Vec2 c) noexcept;

}  // namespace par2d::detail
