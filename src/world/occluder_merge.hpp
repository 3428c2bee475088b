// Occluder merging for tilemaps: runs of equal axis-aligned wall boxes that share whole
// edges, each replaced by the one box that is their union. A pure function; the World keeps
// the groups behind its handles (world/world_merge.cpp).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// One occluder of the merged list: `occluder` is the exact union of the source occluders
// `sources` (indices into the list given, ascending); a group of one is the source as given.
struct MergedOccluder {
  Occluder occluder;
  std::vector<std::size_t> sources;
};

// Every occluder in exactly one group, groups in the order of their first source. A group of
// two or more holds axis-aligned rectangles (a polygon of 4 vertices on two x and two y
// values) with equal transmittance and mask, a dark interior, every transmittance channel 0
// or 1 (a translucent row crossed lengthwise multiplies one transmittance per box) and albedo
// 0 (a reflecting wall's boundary pieces follow its given vertices, docs/contract.md section
// 7), that a row
// (same y0 and y1, each box's x1 the next one's x0) or, for the boxes no row took, a column
// joins end to end. Coordinates are compared exactly, so the union is exactly the merged box
// and every renderer sees the same occluded set: merging changes no image beyond rounding.
// The groups depend on the boxes alone, not on their order in the list (a box given twice,
// same box and properties, joins nothing), so that any order of the same boxes merges alike.
std::vector<MergedOccluder> merge_tilemap_boxes(const std::vector<Occluder>& occluders);

// The same as runs only: each group of two or more boxes (sources ascending, runs in the order
// of their first source) and the box that is their union; `occluder(i)` gives the i-th of `n`.
struct BoxRun {
  Polygon shape;
  std::vector<std::size_t> sources;
};
// Whether `o` can join a run at all: a mergeable box (then a change to it can change runs).
bool mergeable_box(const Occluder& o);
// Whether two boxes can join end to end: both mergeable, equal properties, a whole edge shared.
// A box joinable with no other is in no run and changes none.
bool joinable(const Occluder& a, const Occluder& b);
std::vector<BoxRun> tilemap_box_runs(std::size_t n, const std::function<const Occluder&(std::size_t)>& occluder);

}  // namespace par2d::detail
