// The bounce term (docs/contract.md section 7) of a tile, for the frame driver: the reflecting
// occluders that may reach the tile, each kept unless occlusion proofs show every segment from
// the tile to it blocked, then the scalar reference at each sample over those alone. Culling
// only skips sources that add exactly nothing, so the result equals the reference's.
#pragma once

#include <cstdint>
#include <vector>

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
  std::vector<Rgb> node_value;
  std::vector<unsigned char> node_done;
};

// Adds the mean over each sample of the pixels `part` (within `tile`) of the bounce term to
// `out` (the tile's result, rows of kTileSize). With `cull`, sources proven hidden from the
// whole tile are skipped and the others' possible blockers are found once for the tile;
// without, every sample walks every lit source (the reference). Counts the work in `counts`.
void add_bounce_tile(const PreparedScene& scene, const BounceFrame& bounce, int spp, bool shaded, bool cull,
                     const TileRect& tile, const TileRect& part, BounceTileScratch& scratch, TileResult& out,
                     FrameCounters& counts);

}  // namespace par2d::detail
