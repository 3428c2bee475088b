// Whether a tile gets per-cell light lists or keeps the tile's own (and then is computed
// shape-major): decided once per tile, read by the tile setup and the cell lists alike.
#pragma once

#include <cstddef>

namespace par2d::detail {

// Tiles with fewer pairs keep their lists: cells cost setup per pair and cell, and save
// kernel work only where many pairs' shadows miss parts of the tile (small occluders). On
// tiles with a few pairs cells drop few of them and their setup costs more than it saves;
// from 16 pairs, tiles of rubble (hundreds of pairs each) all get cells while scenes of
// larger occluders keep their tile lists (docs/performance.md).
inline constexpr std::size_t kCellMinPairs = 16;

// Whether a tile with `pairs` pairs gets cells: only culled tiles (their lists are refined
// per cell) with many pairs.
inline bool tile_gets_cells(bool culled, std::size_t pairs) noexcept { return culled && pairs >= kCellMinPairs; }

// How the kernel walks a tile.
struct TilePlan {
  // Per-cell lists (build_cell_lists); else the tile's own lists (game-model tiles get them
  // as one cell over the whole tile).
  bool cells = false;
  // A plain one-sample tile without cells computes single-pair lights shape-major
  // (single_pair_light in simd/tile_work.hpp), with no arc for them or for the occluders
  // only they use.
  bool shape_major = false;
};

inline TilePlan plan_tile(bool culled, std::size_t pairs, int spp) noexcept {
  TilePlan plan;
  plan.cells = tile_gets_cells(culled, pairs);
  plan.shape_major = spp == 1 && !plan.cells;
  return plan;
}

}  // namespace par2d::detail
