// Per-tile work for the SIMD kernels: which lights and occluders matter to a tile, their
// depth order, and their float geometry relative to the tile origin.
#pragma once

#include <cstdint>
#include <vector>

#include "render/prepared_scene.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

// Per-thread buffers reused from tile to tile.
struct TileSetupScratch {
  std::vector<std::int32_t> local_index;  // occluder -> index in TileWork::occluders, or -1
  std::vector<std::uint32_t> candidates;
  std::vector<std::uint32_t> used;
  std::vector<Vec2> hull_points;
};

// Fills `work` for `tile`. Returns false when the tile must be computed by the scalar
// reference instead (a light that overlaps an occluder matters to it: the separating-line
// depth test the kernel uses needs disjoint shapes). With `culling`, occluders behind a
// light for the whole tile are dropped and lights in the umbra of one occluder over the
// whole tile are skipped; the image is the same either way.
bool build_tile_work(const PreparedScene& scene, const TileRect& tile, bool culling, TileWork& work,
                     TileSetupScratch& scratch);

}  // namespace par2d::detail
