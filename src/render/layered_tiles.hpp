// A tile computed through the light-layer cache (render/light_layers.hpp): each of its lights'
// shares from the block's stored layer, or computed alone at unit emission and stored, and the
// rest (directional lights, lights with no room in the budget) by one kernel call with their
// real emissions and the ambient term; then the shares times their emissions added on.
#pragma once

#include <cstdint>
#include <vector>

#include "render/cell_lists.hpp"
#include "render/frame_counters.hpp"
#include "render/kernel_table.hpp"
#include "render/light_layers.hpp"
#include "render/tile_setup.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Runs the ISA's tile kernel on a work the layered path handed it (the frame driver's, with
// its scratch and counts).
class TileKernelRunner {
 public:
  virtual void run(const TileWork& work, TileResult& out) = 0;

 protected:
  ~TileKernelRunner() = default;
};

// Per-thread buffers of the layered path, reused from tile to tile.
struct LayeredTileScratch {
  std::vector<std::int32_t> layer_of;  // per scene light: its layer in the current block, or -1
  // Per scene light: 1 where a layer held the light's share of the whole block when it began
  // (left out of the block's culling and tile setup: nothing about it is computed).
  std::vector<unsigned char> skip;
  std::vector<KernelLight> all_lights;  // the tile's lights while parts of them are computed
  std::vector<KernelLightTerms> all_terms;
  std::vector<std::uint32_t> part_scene;  // scene index of each light handed to the kernel
  std::vector<std::uint32_t> rest;        // tile lights computed with their emissions
  TileResult single;
};

// Indexes the layers of the block about to be rendered by light, and marks them `skip`.
void start_layered_block(std::size_t scene_lights, const std::vector<LightLayer>& layers, LayeredTileScratch& scratch);

// Computes tile `tile`, number `t` of its block (row by row), into `out`: `work` as
// build_tile_work left it for the tile (its cell lists not yet built; the block's culling
// given `skip`), `layers` the block's. With `fill`, the work's lights are computed alone and
// stored (a new layer reserving `layer_floats`), else with their emissions in one kernel
// call; then every stored share of the tile is added, in light order.
void render_layered_tile(const PreparedScene& scene, const TileRect& tile, int t, const KernelSet& kernels,
                         bool fill, std::size_t layer_floats,
                         TileWork& work, const TileSetupScratch& setup, CellListScratch& cells,
                         std::vector<LightLayer>& layers, LayeredTileScratch& scratch, TileKernelRunner& runner,
                         TileResult& out, FrameCounters& counts);

// Tile `t` of a block whose lights all have layers: the ambient term plus each layer's share
// of the tile times its light's emission, in light order (what render_layered_tile computes
// there, without the culling that only confirms which lights reach the tile).
void recombine_tile(const PreparedScene& scene, const std::vector<LightLayer>& layers, int t, const KernelSet& kernels,
                    TileResult& out, FrameCounters& counts) noexcept;

}  // namespace par2d::detail
