// Image tiles: the unit of parallel work and of per-tile culling.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace par2d::detail {

// 16 x 16 pixels: small enough that every thread gets many tiles (pbrt keeps tiles at
// most ~32 px), large enough to amortize per-tile culling; a multiple of every SIMD width.
inline constexpr int kTileSize = 16;
inline constexpr int kTilePixels = kTileSize * kTileSize;

struct TileGrid {
  int width = 0, height = 0;
  int columns() const noexcept { return (width + kTileSize - 1) / kTileSize; }
  int rows() const noexcept { return (height + kTileSize - 1) / kTileSize; }
  long long count() const noexcept { return static_cast<long long>(columns()) * rows(); }
};

struct TileRect {
  int x0, y0, x1, y1;  // pixel columns [x0, x1), rows [y0, y1)
};

inline TileRect tile_rect(const TileGrid& grid, long long index) noexcept {
  const int tx = static_cast<int>(index % grid.columns());
  const int ty = static_cast<int>(index / grid.columns());
  const int x0 = tx * kTileSize, y0 = ty * kTileSize;
  return {x0, y0, std::min(x0 + kTileSize, grid.width), std::min(y0 + kTileSize, grid.height)};
}

// Runs `render_tile(tile_rect)` for every tile on `threads` workers. Iterates tile
// indices, not pixel ranges (blocked_range splits at midpoints, which would not stay
// aligned to SIMD packets). Each tile writes only its own pixels, so the image does not
// depend on the thread count.
template <class Fn>
void for_each_tile(const TileGrid& grid, int threads, Fn&& render_tile) {
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<long long>(0, grid.count(), 1),
                      [&](const tbb::blocked_range<long long>& range) {
                        for (long long t = range.begin(); t != range.end(); ++t) render_tile(tile_rect(grid, t));
                      });
  });
}

}  // namespace par2d::detail
