// How far each light shines past the occluders around it, per direction: blocks beyond that
// distance skip the light without a spatial query or a proof of their own.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "culling/occlusion_proof.hpp"
#include "world/occluder_bvh.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// For one light: in each of kSectors equal angular sectors around `center`, a distance
// beyond which no point of the sector sees any of the light (+infinity where none was proven).
struct LightReach {
  // 32 sectors of 11.25 degrees: a doorway leaves only the narrower sectors it opens to at
  // infinity, so more blocks skip the light without a query and a proof than with 16.
  static constexpr int kSectors = 32;
  Vec2 center;
  double radius = 0.0;  // every light point lies within this distance of the center
  std::array<double, kSectors> reach{};
  // The least and the largest of `reach` (set by compute_light_reach; a box beyond the
  // largest is hidden whatever sectors it spans, one short of the least is not).
  double nearest = 0.0, farthest = 0.0;

  // Whether every point of `box` lies beyond the reach of the sectors it spans.
  bool hides(const Aabb& box) const noexcept;
};

// Per-thread buffers for compute_light_reach.
struct LightReachScratch {
  std::vector<Vec2> hull_points, hull;
  std::vector<std::uint32_t> candidates;
  OcclusionProofScratch proof;
  // Room for any light of a scene of `occluders` occluders, lights and occluders of at most
  // `max_vertices` vertices.
  void reserve_for(std::size_t occluders, std::size_t max_vertices);
  // After compute_light_reach: a box holding every region whose occluders the proofs
  // looked at (empty when none). Occluders changing outside it cannot change the reach.
  Aabb depends_on{};
  // After compute_light_reach: the reach is the same for every frame whose reach_farthest
  // lies in [farthest_low, farthest_high) (it only decides how many radii are tried), so a
  // view moved by whole pixels proves it again only when that leaves the range.
  double farthest_low = 0.0, farthest_high = 0.0;
};

// The farthest a light's reach is proven to: the farthest corner of the frame's visible view
// from `center`, or less for a ranged light (radius + range, radius the largest distance from
// `center` to the light's shape).
double reach_farthest(const PreparedScene& scene, std::size_t light, Vec2 center, double radius) noexcept;

// The reach of scene light `light`, proven for radii of the form radius + 8 px * 2^j, each
// sector's smallest found by bisection (a proof for a radius holds for every larger one),
// up to the farthest view corner.
LightReach compute_light_reach(const PreparedScene& scene, std::size_t light, LightReachScratch& scratch);

}  // namespace par2d::detail
