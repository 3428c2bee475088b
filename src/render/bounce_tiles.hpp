// The bounce term (docs/contract.md section 7) of a tile, for the frame driver: the reflecting
// occluders that may reach the tile, each kept unless occlusion proofs show every segment from
// the tile to it blocked, then the scalar reference at each sample over those alone. Culling
// only skips sources that add exactly nothing, so the result equals the reference's.
#pragma once

#include <cstdint>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/occlusion_proof.hpp"
#include "render/frame_counters.hpp"
#include "render/tiling.hpp"
#include "scalar/bounce_reference.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Per-lane buffers, reused from tile to tile and frame to frame.
struct BounceTileScratch {
  BounceScratch reference;
  OcclusionProofScratch occlusion;
  // This tile's sources that may reach it, each with the occluders that may stand between
  // (BounceSourceSubset).
  std::vector<std::uint32_t> sources, first, blockers;
  std::vector<std::uint32_t> candidates, provers;
  std::vector<Vec2> hull_points, hull;
  // The coarse bounce: the occluders near a tile's nodes, and the nodes' values once computed.
  std::vector<std::uint32_t> near;
};

// The lights' reach as the frame proved it, as the piece radiances' test of hidden lights
// (bounce_radiances): a light hides a box beyond its reach in every sector the box spans.
class ReachHidesLights final : public LightHiddenTest {
 public:
  explicit ReachHidesLights(const LightReach* reach) noexcept : reach_(reach) {}
  bool hides(std::size_t light, const Aabb& box) const noexcept override { return reach_[light].hides(box); }

 private:
  const LightReach* reach_;  // per scene light
};

// The coarse bounce's nodes (docs/contract.md section 7, "Coarse bounce") that a frame's
// samples interpolate: node (c, r) is grid pixel (gx0 + c * step, gy0 + r * step), its value the
// exact bounce at that pixel's center. Computed once per frame before the tiles, in groups of
// group x group nodes culled together (about 32 pixels across: culling over much larger regions
// leaves more sources per node), so tiles sharing a node do not each compute it.
struct BounceNodes {
  int step = 1;
  int group = 1;  // nodes per group side
  std::int64_t gx0 = 0, gy0 = 0;
  int columns = 0, rows = 0;
  std::vector<Rgb> value;  // row by row
  const Rgb& at(std::int64_t gx, std::int64_t gy) const noexcept {
    return value[static_cast<std::size_t>((gy - gy0) / step) * static_cast<std::size_t>(columns) +
                 static_cast<std::size_t>((gx - gx0) / step)];
  }
};

// Sizes `nodes` for the samples of the frame pixels `area` at the scene's step (> 1), and
// returns how many groups compute_bounce_nodes has to compute.
int plan_bounce_nodes(const PreparedScene& scene, const TileRect& area, BounceNodes& nodes);

// Computes the nodes of group `group`: with `cull`, each over the sources that the occlusion
// proofs leave for the group's pixels (as a tile's), else over every lit source.
void compute_bounce_nodes(const PreparedScene& scene, const BounceFrame& bounce, bool shaded, bool cull,
                          BounceNodes& nodes, int group, BounceTileScratch& scratch, FrameCounters& counts);

// Adds the mean over each sample of the pixels `part` (within `tile`) of the bounce term to
// `out` (the tile's result, rows of kTileSize). With `cull`, sources proven hidden from the
// whole tile are skipped and the others' possible blockers are found once for the tile;
// without, every sample walks every lit source (the reference). Counts the work in `counts`.
// With `nodes` (a coarse step), the samples interpolate the nodes they see instead.
void add_bounce_tile(const PreparedScene& scene, const BounceFrame& bounce, const BounceNodes* nodes, int spp,
                     bool shaded, bool cull, const TileRect& tile, const TileRect& part, BounceTileScratch& scratch,
                     TileResult& out, FrameCounters& counts);

}  // namespace par2d::detail
