// Per-tile work for the SIMD kernels: which lights and occluders matter to a tile, their
// depth order, and their float geometry relative to the tile origin.
#pragma once

#include <cstdint>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/occlusion_proof.hpp"
#include "render/block_culling.hpp"
#include "render/frame_counters.hpp"
#include "render/kernel_shapes.hpp"
#include "render/model_terms.hpp"
#include "render/pair_setup.hpp"
#include "render/scene_bounds.hpp"
#include "render/tile_plan.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Per-thread buffers reused from tile to tile, one part per concern (each header says what
// its part holds).
struct TileSetupScratch {
  // What gather_block_candidates found for the current block, read by each of its tiles.
  // Per light: occluders that can block some ray from the block to the light (cull_block).
  std::vector<std::vector<std::uint32_t>> block_candidates;
  std::vector<unsigned char> block_shadowed;  // per light: hidden from the whole block
  BlockView block;

  BlockCullingScratch culling;  // block_culling.hpp
  OcclusionProofScratch occlusion;  // block and tile proofs alike
  PairSetupScratch pairs;  // pair_setup.hpp
  KernelShapeScratch shapes;  // kernel_shapes.hpp
  TileOccluders occluders;  // kernel_shapes.hpp
  DirectionalScratch directional;  // model_terms.hpp

  // The last tile built: its plan (tile_plan.hpp) and the scene index of each
  // TileWork::lights entry (plain scenes), for the cell lists.
  TilePlan plan;
  std::vector<std::uint32_t> tile_lights;
  // Occluders that meet the block and are at least a tile wide and high: those that may hold
  // a whole tile (build_tile_work), and scratch for the block's query.
  std::vector<std::uint32_t> block_enclosers, enclosers_query;

  // The scene counts its buffers are reserved for (reserve_for).
  SceneBounds reserved;

  // Reserves every buffer a block or tile of a scene with these counts can fill, so that
  // frames of that scene allocate nothing whatever its lights' places (allocates; called
  // when the counts change). Each bound is argued where it is reserved.
  void reserve_for(const SceneBounds& bounds);
  // Bytes reserved by reserve_for (and kept since).
  std::size_t reserved_bytes() const noexcept;

  // Clears the counts its parts keep (the proofs', umbra tests', skipped proofs', dropped
  // pairs'), which accumulate from block to block until then.
  void clear_counts() noexcept {
    occlusion.proofs_tried = occlusion.proofs_succeeded = 0;
    culling.counts = FrameCounters{};
    pairs.counts = FrameCounters{};
  }
  // What its parts counted since clear_counts.
  FrameCounters counts() const noexcept {
    FrameCounters sum = culling.counts;
    sum += pairs.counts;
    sum.proofs_tried += occlusion.proofs_tried;
    sum.proofs_succeeded += occlusion.proofs_succeeded;
    return sum;
  }
};

// Fills scratch.block_candidates for the pixel rectangle `block`, skipping the lights that
// `reach` or a proof shows hidden from the whole block. Without `reach` (culling off):
// every occluder for every light.
// `skip` (per light, may be null): lights left out as if shadowed (cull_block).
void gather_block_candidates(const PreparedScene& scene, const TileRect& block, const std::vector<LightReach>* reach,
                             TileSetupScratch& scratch, const unsigned char* skip = nullptr);

// Fills `work` for `tile` at `spp` samples per pixel, a tile of the block last given to gather_block_candidates.
// Every tile goes to the kernel: a light that overlaps or touches an occluder is clipped at
// one of the occluder's edges where its cap lies inside it, or else makes a general pair
// (simd/tile_work.hpp). With `culling`, occluders behind a light for the whole
// tile are dropped, and lights in the umbra of one occluder over the whole tile, or
// proven hidden by several (culling/occlusion_proof.hpp), are skipped; the image is the
// same either way.
// Scenes with the game lighting model (PreparedScene::model) get the model's work: range
// culling, pairs only for occluders acting on each light, directional lights as tile lights,
// ambient, and per-pixel normals when `shaded` and the scene has a normal source.
void build_tile_work(const PreparedScene& scene, const TileRect& tile, int spp, bool culling, TileWork& work,
                     TileSetupScratch& scratch, bool shaded = false);

}  // namespace par2d::detail
