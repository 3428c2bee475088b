// Image tiles (the kernel's unit) grouped in blocks (the unit of parallel work and of
// spatial-index queries).
#pragma once

#include <algorithm>

#include "parallel/parallel_for.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

// Blocks of kBlockTiles x kBlockTiles tiles: one spatial-index query per block and light
// serves several tiles, and a 1920 x 1080 frame still has hundreds of blocks, so every
// one of 16 threads gets many (pbrt's rule of many small work items).
inline constexpr int kBlockTiles = 4;
inline constexpr int kBlockSize = kTileSize * kBlockTiles;

struct TileRect {
  int x0, y0, x1, y1;  // pixel columns [x0, x1), rows [y0, y1)
};

// Calls fn(rect) for the cells of `cell` pixels covering `area`, row by row.
template <class Fn>
void for_each_cell(const TileRect& area, int cell, Fn&& fn) {
  for (int y = area.y0; y < area.y1; y += cell) {
    for (int x = area.x0; x < area.x1; x += cell) fn(TileRect{x, y, std::min(x + cell, area.x1), std::min(y + cell, area.y1)});
  }
}

// Runs fn(block_rect, worker) for every block of the width x height image (see
// for_each_index). Iterates block indices, not pixel ranges (blocked_range splits at
// midpoints, which would not stay aligned to tiles and SIMD packets). Each block writes
// only its own pixels, so the image does not depend on the thread count.
template <class Fn>
void for_each_block(int width, int height, int threads, Fn&& fn) {
  const int columns = (width + kBlockSize - 1) / kBlockSize;
  const int rows = (height + kBlockSize - 1) / kBlockSize;
  for_each_index(columns * rows, threads, [&](int b, int worker) {
    const int x0 = (b % columns) * kBlockSize, y0 = (b / columns) * kBlockSize;
    fn(TileRect{x0, y0, std::min(x0 + kBlockSize, width), std::min(y0 + kBlockSize, height)}, worker);
  });
}

}  // namespace par2d::detail
