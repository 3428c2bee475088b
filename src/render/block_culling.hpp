// Block culling: per block and light, the occluders that can block some ray from the block
// to the light (one spatial-index query), the lights hidden from the whole block, and the
// adaptive rule that decides which block and tile occlusion proofs are worth trying.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/occlusion_proof.hpp"
#include "culling/visible_light.hpp"
#include "render/frame_counters.hpp"
#include "render/scene_bounds.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Per-thread buffers of the block culling.
struct BlockCullingScratch {
  std::vector<Vec2> hull_points, hull;  // the hull of the block and a light
  // Occluders that may prove a light hidden (of a game-model scene: the opaque dark ones).
  std::vector<std::uint32_t> provers;
  std::vector<std::pair<double, std::uint32_t>> ordered_candidates;  // a light's block candidates, angular keys
  // Tile proofs tried and succeeded so far in the current block, per light and over all lights
  // (reset per block), for the adaptive rule (block_culling.cpp). A block's tiles are built by
  // one thread in a fixed order, so the rule decides the same way whatever the scheduling.
  struct TileProofRecord {
    std::uint32_t tried = 0, succeeded = 0;
  };
  std::vector<TileProofRecord> tile_proof_records;
  TileProofRecord block_proof_record;
  // Each light's part outside the occluder it sits in (filled by cull_block per block): the
  // shape the block and tile proofs and the pair separators see.
  VisibleLights visible;
  // Its counts (block_proofs_skipped, tile_proofs_skipped: proofs the adaptive rule did not
  // try), accumulated until the owner clears them.
  FrameCounters counts;

  // Reserves for a scene with these counts (allocates; when they change). The hull of a block
  // (4 corners) and a light (its vertices, a circle's 4 box corners) has at most 4 + max(4, V)
  // points, and hull_with_shape sizes its output 2 n + 1 first; the provers and a light's
  // ordered candidates are among its block candidates (distinct occluders).
  void reserve_for(const SceneBounds& bounds) {
    const std::size_t points = 4 + std::max<std::size_t>(4, bounds.max_vertices);
    hull_points.reserve(points);
    hull.reserve(2 * points + 1);
    provers.reserve(bounds.occluders);
    ordered_candidates.reserve(bounds.occluders);
    tile_proof_records.reserve(bounds.lights);
    visible.reserve_for(bounds.lights, bounds.max_vertices);
  }
  std::size_t reserved_bytes() const noexcept {
    return (hull_points.capacity() + hull.capacity()) * sizeof(Vec2) + provers.capacity() * sizeof(std::uint32_t) +
           ordered_candidates.capacity() * sizeof(std::pair<double, std::uint32_t>) +
           tile_proof_records.capacity() * sizeof(TileProofRecord) + visible.reserved_bytes();
  }

  void start_block(std::size_t lights) {
    tile_proof_records.assign(lights, TileProofRecord{});
    block_proof_record = TileProofRecord{};
  }
};

// Whether the culling's double-precision tests (light reach, occlusion proofs, umbra and
// behind tests on the whole shapes) can be trusted: not when some coordinate lies 2^40 pixels
// or more from the origin, where their rounding reaches pixels (a slanted wall 1e25 long
// let a proof hide a light in front of it). Such scenes render without culling (the same
// image, slower).
inline bool culling_trusted(const PreparedScene& scene) noexcept {
  const double pixel = std::max(std::abs(scene.view.x1 - scene.view.x0) / scene.width,
                                std::abs(scene.view.y1 - scene.view.y0) / scene.height);
  return scene.extent < 0x1p40 * pixel;
}

// Per light of the scene, the occluders that can block some ray from the block with these
// corners to the light, in `candidates` (in index order, or by direction when there are many:
// order_by_angle in block_culling.cpp); `shadowed` marks the lights that `reach` or a proof
// shows hidden from the whole block. Without `reach`: every (acting) occluder for every light.
// `skip` (per light, may be null): lights marked there are left out as if shadowed (the
// light-layer cache holds their share of the block).
void cull_block(const PreparedScene& scene, const std::array<Vec2, 4>& corners, const std::vector<LightReach>* reach,
                std::vector<std::vector<std::uint32_t>>& candidates, std::vector<unsigned char>& shadowed,
                BlockCullingScratch& scratch, OcclusionProofScratch& occlusion, const unsigned char* skip = nullptr);

// Occlusion proofs: the most strips one may use per block and light, and per tile and light.
// A tile tries one only for a light with at least kTileProofMinPairs occluders in front:
// with fewer, the kernel's merge costs less than a failed proof. Frame times depend little
// on the budgets (docs/performance.md).
inline constexpr int kBlockStripBudget = 64;
inline constexpr int kTileStripBudget = 16;
inline constexpr std::size_t kTileProofMinPairs = 8;

// Whether a tile proof, where the adaptive rule tries one, shows light l hidden over the tile
// `box` by the occluders of its pairs (work.pairs from `first_pair` on, at least
// kTileProofMinPairs of them).
bool tile_proof_hides_light(const PreparedScene& scene, std::size_t l, const Aabb& box, const TileWork& work,
                            std::uint32_t first_pair, BlockCullingScratch& scratch, OcclusionProofScratch& occlusion);

}  // namespace par2d::detail
