// Light lists per cell of a tile (a rectangle of its SIMD packets): each light keeps only the
// pairs whose occluder can stand between the cell and the light.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/tile_plan.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"
#include "world/occluder_bvh.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

struct TileSetupScratch;  // render/tile_setup.hpp

// Per-thread buffers reused from tile to tile.
struct CellListScratch {
  struct Disc {
    Vec2 center;
    double radius = 0.0;
  };
  std::vector<Aabb> cell_boxes;
  std::vector<Vec2> cell_centers;
  std::vector<Disc> occluder_discs;       // per tile occluder
  std::vector<unsigned> occluder_cells;   // per tile occluder: bit c, cell c needs its arc
  std::vector<unsigned> pair_cells;       // per pair of the current light: bit c, cell c keeps it
  std::vector<KernelPair> pair_buffer;    // the cells' pairs before they are copied into the work
};

// Fills work's cells (TileWork::cells) for `tile`, the tile that build_tile_work last built
// into `work` with `setup`, for a kernel of `lanes` lanes. Tiles whose plan (TilePlan, made by
// build_tile_work) has cells get them (plain and game-model scenes alike); other plain tiles
// keep the tile's lists, other game-model tiles get them as one cell over the whole tile (the
// model kernel reads only cells). The image is the same either way: a pair an occluder
// cannot form over the cell blocks nothing there.
// `tile_lights`: the scene index of each of work.lights (null: setup.tile_lights, the tile's
// own; the light-layer path hands the kernel a part of the tile's lights at a time).
void build_cell_lists(const PreparedScene& scene, const TileRect& tile, int lanes, const TileSetupScratch& setup,
                      TileWork& work, CellListScratch& scratch, const std::uint32_t* tile_lights = nullptr);

}  // namespace par2d::detail
