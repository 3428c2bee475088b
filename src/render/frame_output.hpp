// Storing finished tiles straight into the host's buffer in its pixel format (no second pass).
#pragma once

#include <cstddef>

#include "par2d/renderer.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

// Where a frame goes: `region` (pixels of the whole frame) is stored with its top-left pixel
// at `data`, rows `row_stride` bytes apart.
struct FrameTarget {
  unsigned char* data = nullptr;
  PixelFormat format = PixelFormat::rgb_f32;
  std::ptrdiff_t row_stride = 0;
  double exposure = 1.0;
  TileRect region{0, 0, 0, 0};
};

// Rows first_row .. + rows - 1, columns first_column .. + count - 1 of a tile's result
// interleaved into host rows `row_stride` bytes apart starting at `host`: one ISA's vector
// store for the float formats (simd/tile_store.hpp).
using FloatRowsStore = void (*)(const TileResult& result, int first_column, int first_row, int rows, int count,
                                unsigned char* host, std::ptrdiff_t row_stride) noexcept;
struct FloatTileStores {
  FloatRowsStore rgb_f32 = nullptr;
  FloatRowsStore rgba_f32 = nullptr;
};

// Stores pixels `part` (inside the target's region) of the tile whose top-left pixel is
// (tile_x0, tile_y0), from its kernel result. `vector_stores`: the kernel ISA's float
// stores; a null one (and the scalar path) takes the 4-pixel SSE2 transpose here (a
// pixel-by-pixel copy where SSE2 is missing). Every store writes the same bytes.
void store_tile(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part, const FrameTarget& target,
                const FloatTileStores& vector_stores = {}) noexcept;

// round(255 * srgb(clamp(v, 0, 1))), NaN and negatives to 0, from a table (no pow per channel).
unsigned char encode_srgb8(double linear) noexcept;
// The same by a binary search over the 255 thresholds: the table's reference in tests.
unsigned char encode_srgb8_search(double linear) noexcept;

}  // namespace par2d::detail
