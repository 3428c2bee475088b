// Per-tile work for the SIMD kernels: which lights and occluders matter to a tile, their
// depth order, and their float geometry relative to the tile origin.
#pragma once

#include <cstdint>
#include <vector>

#include "culling/occlusion_proof.hpp"
#include "culling/light_reach.hpp"
#include "world/prepared_scene.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

// Per-thread buffers reused from tile to tile.
struct TileSetupScratch {
  // Per light: occluders that can block some ray from the current block to the light
  // (sorted), from one spatial-index query per block and light.
  std::vector<std::vector<std::uint32_t>> block_candidates;
  std::vector<unsigned char> block_shadowed;  // per light: in one occluder's umbra over the whole block
  std::vector<std::int32_t> local_index;  // occluder -> index in TileWork::occluders, or -1
  std::vector<std::uint32_t> used;
  std::vector<unsigned char> used_whole;  // per entry of `used`: in a general pair (kernel shape kept whole)
  std::vector<Vec2> hull_points, hull;
  ConvexShape clipped, clipped_light;  // shapes reaching far from the tile, clipped to a box around it
  std::vector<std::uint32_t> pair_occluders;
  std::vector<std::uint32_t> directional;  // a directional light's candidate occluders
  OcclusionProofScratch occlusion;
  // The last tile built: the scene index of each TileWork::lights entry (plain scenes), and
  // whether its lists were culled (cell_lists.hpp refines only culled tiles).
  std::vector<std::uint32_t> tile_lights;
  bool tile_culled = false;
  // Counts for FrameStats, accumulated until the owner resets them.
  std::uint64_t umbra_tests = 0, umbra_hits = 0;
};

// Fills scratch.block_candidates for the pixel rectangle `block`, skipping the lights that
// `reach` or a proof shows hidden from the whole block. Without `reach` (culling off):
// every occluder for every light.
void gather_block_candidates(const PreparedScene& scene, const TileRect& block, const std::vector<LightReach>* reach,
                             TileSetupScratch& scratch);

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
