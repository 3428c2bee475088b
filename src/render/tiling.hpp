// Image tiles (the kernel's unit) grouped in blocks (the unit of parallel work and of
// spatial-index queries).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

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

// A frame's blocks, placed on its pixel grid (PreparedScene::grid_x, grid_y): block (bx, by)
// holds the frame's pixels [bx * kBlockSize - ax, +kBlockSize) x [by * kBlockSize - ay,
// +kBlockSize). Blocks and their tiles are whole even where the frame's edges cut them (the
// pixels outside are computed and dropped), so which tile and block a pixel is computed in,
// and with it every bit of its value, depends on its place on the grid alone: a view moved by
// whole pixels finds the pixels it keeps exactly as a frame rendered there would compute them.
struct BlockGrid {
  int ax = 0, ay = 0;  // block (0, 0)'s corner is frame pixel (-ax, -ay); 0 <= ax, ay < kBlockSize
  int columns = 0, rows = 0;

  // Blocks of a width x height frame whose top-left pixel is grid pixel (grid_x, grid_y).
  BlockGrid(int width, int height, std::int64_t grid_x, std::int64_t grid_y) noexcept
      : ax(static_cast<int>(((grid_x % kBlockSize) + kBlockSize) % kBlockSize)),
        ay(static_cast<int>(((grid_y % kBlockSize) + kBlockSize) % kBlockSize)),
        columns((width + ax + kBlockSize - 1) / kBlockSize),
        rows((height + ay + kBlockSize - 1) / kBlockSize) {}

  std::size_t count() const noexcept { return static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows); }
  TileRect block(int bx, int by) const noexcept {
    const int x0 = bx * kBlockSize - ax, y0 = by * kBlockSize - ay;
    return {x0, y0, x0 + kBlockSize, y0 + kBlockSize};
  }
  TileRect block(std::size_t index) const noexcept {
    return block(static_cast<int>(index % static_cast<std::size_t>(columns)),
                 static_cast<int>(index / static_cast<std::size_t>(columns)));
  }
  // The column (row) of the block holding frame column x (row y), for -ax <= x.
  int column_of(int x) const noexcept { return (x + ax) / kBlockSize; }
  int row_of(int y) const noexcept { return (y + ay) / kBlockSize; }
};

// A dirty-block mask's values (one per block of a BlockGrid, row by row).
inline constexpr std::uint8_t kBlockClean = 0;
inline constexpr std::uint8_t kBlockWhole = 1;      // every pixel of the block
inline constexpr std::uint8_t kBlockUncovered = 2;  // only the tiles a scrolled view shows anew

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
