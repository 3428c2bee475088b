// Proofs that a union of occluders hides a light from a whole region (from-region
// visibility), so that a block or tile can skip the light without changing the image.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/convex_shape.hpp"

namespace par2d::detail {

// Reused buffers for the proofs (one per thread).
struct OcclusionProofScratch {
  std::vector<double> light_u, light_v;            // light points in the slab frame
  std::vector<double> viewer_gain, viewer_offset;  // viewer point i projects to gain * q + offset
  std::vector<double> light_gain, light_offset;    // light points beyond the slab, likewise
  std::vector<double> light_on_side;               // heights of light points on the slab's far side
  std::vector<double> blocker_a, blocker_c;        // occluder point i projects to a - c * q
  std::vector<std::uint32_t> blocker_first;        // blocker k: points [first[k], first[k + 1])
  std::vector<std::uint32_t> blocker_occluder;     // blocker k's occluder
  // Joining blockers that touch (see segments_blocked): box blockers by their left edge, a
  // union-find forest over the blockers, and the regrouped point runs.
  std::vector<std::uint32_t> box_order, group_parent, group_first;
  std::vector<double> grouped_a, grouped_c;
  std::vector<double> clip_u, clip_v, half_u, half_v;
  std::vector<std::pair<double, double>> intervals;
  std::vector<std::pair<double, double>> strips;
  // Room for every proof over at most `occluders` occluders of at most `max_vertices`
  // vertices, against a light of at most `max_vertices` + 1 (a light's visible part,
  // visible_light.hpp), with at most 4 viewer points and `strip_budget` strips.
  void reserve_for(std::size_t occluders, std::size_t max_vertices, int strip_budget);
  std::size_t reserved_bytes() const noexcept;
  // Counts for FrameStats, accumulated over calls until the owner resets them.
  std::uint64_t proofs_tried = 0, proofs_succeeded = 0;
  // Proofs refused before their setup by a segment to the light that passes every occluder.
  std::uint64_t proofs_probed_out = 0;
};

// Whether every segment from a point of the convex hull of `viewer[0..viewer_count)` to a point
// of `light` meets one of the occluders `ids[0..count)` strictly between the two. Then the
// light's visible arc is empty at every point of the viewer region, whatever the occluders'
// depth order elsewhere.
//
// `axis` (a unit vector) points from the viewer toward the light, and the light must start
// beyond the viewer's end along it: the open slab between them is crossed by every such
// segment from side to side, and only the occluders' parts inside the slab are used. A
// segment's line is fixed by its heights p and q on the slab's viewer and light sides. For
// a strip [q0, q1] of light-side heights, the lines through one occluder (clipped to the
// slab) form an interval of p, the occluder's shadow cast from the light side of the slab
// onto the viewer side: projected from height q1 for its top, from q0 for its bottom, it
// blocks every line of the strip with p in between. The strip is proven when the
// intervals together cover every p of a line meeting both the viewer and the light. A
// strip that is not proven is split; a single line (p, q) at a strip's middle height that
// meets both shapes and passes every occluder ends the search.
//
// Occluders that are axis-aligned boxes and touch or overlap inside the slab (closed boxes:
// a shared edge or corner counts) are joined into one blocker first: from any point, the
// directions toward a connected union of convex sets form one interval, bounded by its
// points' extreme projections, so the joined shadow is exact where the separate shadows
// would meet with no slack at all (a tilemap wall face running into the next box's face).
//
// Before any of that, segments from the viewer points and their mean to the light's centroid:
// one that passes every occluder shows the light seen, and refuses the proof cheaply.
//
// Conservative: false means "not proven" (the light may be hidden all the same), also when
// more than `strip_budget` strips would be needed, and when the proof would hang on less
// than ~1e-12 of the coordinates' magnitude (or the slab is narrower than 1e-9 of it). Circle occluders count as inscribed 12-gons,
// circle lights as circumscribed octagons.
bool segments_blocked(const Vec2* viewer, int viewer_count, Vec2 axis, const ConvexShape& light,
                      const std::vector<ConvexShape>& occluders, const std::uint32_t* ids, std::size_t count,
                      int strip_budget, OcclusionProofScratch& scratch);

// Whether the segment [a, b] certainly meets none of the occluders `ids[0..count)` (closed
// shapes; a touch counts as a meeting). Then no proof that they hide b from a can succeed.
bool segment_passes(Vec2 a, Vec2 b, const std::vector<ConvexShape>& occluders, const std::uint32_t* ids,
                    std::size_t count) noexcept;

// The same for the rectangle [lo, hi] as the viewer, across the side with the widest gap
// to the light's box (false when the boxes' projections overlap on both axes).
bool rect_hidden_from_light(Vec2 lo, Vec2 hi, const ConvexShape& light, const std::vector<ConvexShape>& occluders,
                            const std::uint32_t* ids, std::size_t count, int strip_budget,
                            OcclusionProofScratch& scratch);

}  // namespace par2d::detail
