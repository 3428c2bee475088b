// What a frame computes, decided before it runs: the blocks, each block's strategy and the
// frame's stages, as data the frame engine (render/frame_driver.hpp) executes.
#pragma once

#include <cstdint>
#include <vector>

#include "culling/light_reach.hpp"
#include "par2d/isa.hpp"
#include "par2d/types.hpp"
#include "render/tiling.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

struct KernelSet;
class LightLayerCache;

// What one frame computes: samples per pixel, culling, and the kernel ISA (Isa::scalar:
// the reference path, pixel by pixel).
struct FrameSettings {
  int spp = 1;
  bool culling = true;
  Isa isa = Isa::scalar;
  bool shaded = false;  // RenderOptions::shaded (docs/contract.md section 6)
  bool sample_needs = false;  // fill FrameStats' sampled counts (one exact pixel per tile)
  BounceTerm bounce = BounceTerm::included;  // RenderOptions::bounce (docs/contract.md section 7)
};

// How a block's direct light (the ambient term included) is computed, tile by tile. Every
// strategy leaves the tile's result for the frame's later stages (the bounce term, the store).
enum class BlockStrategy : std::uint8_t {
  kernel,            // block culling (with the plan's reach), tile setup, cell lists, the ISA's kernel
  layered,           // as `kernel`, through the light-layer cache (render/layered_tiles.hpp)
  recombine,         // every light from its stored layer: no culling, no kernel
  scalar_reference,  // the double-precision reference, pixel by pixel
  no_direct,         // none (RenderOptions::bounce == only): the result starts at zero
};

// The frame's blocks on its pixel grid (BlockGrid), whole past the frame's edges; with a
// normal map (one normal per frame pixel, padded to whole blocks) they start at the frame's
// corner instead.
inline BlockGrid frame_blocks(const PreparedScene& scene) noexcept {
  if (scene.normal_source == NormalSource::map) return BlockGrid(scene.width, scene.height, 0, 0);
  return BlockGrid(scene.width, scene.height, scene.grid_x, scene.grid_y);
}

// The pixels a view moved by whole pixels shows for the first time: a band of columns at one
// side and a band of rows at one side (either empty).
struct UncoveredPixels {
  TileRect columns{0, 0, 0, 0}, rows{0, 0, 0, 0};
};

// The pixels of `block` to compute for a move's uncovered bands: the box of the bands' parts
// in it (empty, x0 >= x1 or y0 >= y1, where they miss it). Tile-aligned where the bands are.
TileRect uncovered_part(const TileRect& block, const UncoveredPixels& uncovered) noexcept;

// One block of the frame to compute.
struct PlannedBlock {
  TileRect rect;             // the block's pixels (kBlockSize square, whole past the frame's edges)
  TileRect part;             // the pixels to compute: the tiles meeting it (and the region)
  std::uint32_t index = 0;   // its number among the whole frame's blocks, row by row
  BlockStrategy strategy = BlockStrategy::kernel;
  bool fill_layers = false;  // `layered`: the block may store the layers it lacks
};

// The bounce term (docs/contract.md section 7) as a stage of its own: the pieces' radiances
// computed once before the blocks, then added to every tile after its direct light.
struct BounceStage {
  bool run = false;   // the scene has a reflecting occluder and the options want its term
  bool cull = false;  // skip sources proven hidden from a whole tile (add_bounce_tile)
};

// A frame as data: plan_frame decides it, FrameEngine::run executes it. Its storage is kept
// from frame to frame (a plan of no more blocks than before allocates nothing).
struct FramePlan {
  TileRect region{0, 0, 0, 0};       // the pixels of the frame that are stored
  std::vector<PlannedBlock> blocks;  // in frame order (row by row); only these are computed
  std::uint64_t tiles = 0;           // tiles of the blocks that meet the region (progress)
  int spp = 1;
  bool shaded = false;
  bool sample_needs = false;
  // The ISA's kernels and pixel stores; null (Isa::scalar): the generic stores, and no block
  // may use a kernel strategy. Lanes reserve kernel buffers when set.
  const KernelSet* kernels = nullptr;
  // The reach `kernel` and `layered` blocks cull with; null: no culling.
  const std::vector<LightReach>* cull_reach = nullptr;
  // The cache `layered` and `recombine` blocks use, finished after the frame; null: none.
  LightLayerCache* layers = nullptr;
  BounceStage bounce;
};

// Plans a frame of `scene` with `settings` storing `region` (pixels of the whole frame):
//  - the blocks meeting the region, in frame order; with `dirty` (a value per block of
//    frame_blocks, row by row) only those not kBlockClean;
//  - `reach`: per light, what blocks cull with when the settings cull;
//  - `layers` (the light-layer cache, when the change tracker planned it for this frame): used
//    only when the block's direct light is computed by a kernel (not by the scalar reference,
//    not with the bounce term alone); then a block whose lights all have layers is
//    recombined, the others are layered, filling layers where the cache's plan lets them;
//  - the bounce stage, where the scene has a bounce term and the settings include it.
//  - with `uncovered` (a view moved by whole pixels), blocks marked kBlockUncovered compute
//    only their tiles meeting it, by the kernel (their layers, missing those tiles, are not used).
void plan_frame(const PreparedScene& scene, const FrameSettings& settings, const TileRect& region,
                const std::vector<LightReach>* reach, const std::vector<std::uint8_t>* dirty, LightLayerCache* layers,
                FramePlan& plan, const UncoveredPixels* uncovered = nullptr);

}  // namespace par2d::detail
