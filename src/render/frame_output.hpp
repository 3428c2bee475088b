// Storing finished tiles straight into the host's buffer in its pixel format (no second pass).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "io/pixel_encoding.hpp"
#include "par2d/types.hpp"
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
  // The frame's first pixel on the pixel grid (PreparedScene::grid_x, grid_y) modulo 8: the
  // ordered dither follows the grid, so a pixel kept by a scrolled view keeps its bytes.
  int dither_x = 0, dither_y = 0;
  // BufferLayout::ring: the region is the whole frame and frame pixel (x, y) lives at buffer
  // pixel ((ring_x + x) mod width, (ring_y + y) mod height), the grid pixel's place on a ring
  // of the frame's size; stores split a tile's part where the ring wraps.
  bool ring = false;
  int ring_x = 0, ring_y = 0;
};

// Calls fn(piece, dx, dy) for the pieces of `rect` (frame pixels of a ring target) that stay
// contiguous on the ring, at most four: the piece's pixels live at buffer pixels (x + dx, y + dy).
template <class Fn>
void for_each_ring_piece(const FrameTarget& target, const TileRect& rect, Fn&& fn) {
  const int w = target.region.x1 - target.region.x0, h = target.region.y1 - target.region.y0;
  const int seam_x = w - target.ring_x, seam_y = h - target.ring_y;
  const int xs[3] = {rect.x0, std::clamp(seam_x, rect.x0, rect.x1), rect.x1};
  const int ys[3] = {rect.y0, std::clamp(seam_y, rect.y0, rect.y1), rect.y1};
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      const TileRect piece{xs[b], ys[a], xs[b + 1], ys[a + 1]};
      if (piece.x0 >= piece.x1 || piece.y0 >= piece.y1) continue;
      fn(piece, piece.x0 < seam_x ? target.ring_x : target.ring_x - w, piece.y0 < seam_y ? target.ring_y : target.ring_y - h);
    }
  }
}

// Moves a whole frame's pixels (`target`, its region the frame) so that pixel (i, j) holds
// what pixel (i + dx, j + dy) held, for every pixel whose source is in the frame (|dx| < width,
// |dy| < height); the others keep stale values for the frame to overwrite. Row by row in the
// order that reads each row before it is overwritten.
void shift_pixels(const FrameTarget& target, int dx, int dy) noexcept;

// Rows first_row .. + rows - 1, columns first_column .. + count - 1 of a tile's result
// interleaved into host rows `row_stride` bytes apart starting at `host`: one ISA's vector
// stores (simd/tile_store.hpp).
// `stream`: write whole, aligned rows with non-temporal stores (kStreamingFrameBytes).
using FloatRowsStore = void (*)(const TileResult& result, int first_column, int first_row, int rows, int count,
                                unsigned char* host, std::ptrdiff_t row_stride, bool stream) noexcept;
using Srgb8RowsStore = void (*)(const TileResult& result, int first_column, int first_row, int rows, int count,
                                unsigned char* host, std::ptrdiff_t row_stride, const SrgbBuckets& buckets) noexcept;
struct VectorTileStores {
  FloatRowsStore rgb_f32 = nullptr;
  FloatRowsStore rgba_f32 = nullptr;
  Srgb8RowsStore rgba8_srgb = nullptr;
  Srgb8RowsStore bgra8_srgb = nullptr;
  const SrgbBuckets* srgb = nullptr;  // the target's exposure's buckets (rgba8_srgb needs valid ones)
};

// A store any ISA can run: the scalar path's, and the fallback of a kernel without a vector
// store for the format.
using GenericTileStore = void (*)(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                                  const FrameTarget& target) noexcept;

// The one table of pixel formats (frame_output.cpp), a row per PixelFormat. A new format is a
// row there with its generic store, a VectorTileStores member with each ISA's store
// (simd/tile_kernel_entry.hpp, declared and listed in simd/tile_kernel_entries.hpp), and the
// enum value (par2d/types.hpp).
struct PixelFormatInfo {
  PixelFormat format;
  const char* name;  // the enum value's name
  int bytes_per_pixel;
  int channels;  // stored per pixel, alpha included
  bool srgb8;    // 8-bit sRGB with exposure: an ISA store needs the frame's SrgbBuckets; never streamed
  FloatRowsStore VectorTileStores::*float_store;  // the ISA's vector store of a float format, else null
  Srgb8RowsStore VectorTileStores::*srgb8_store;  // the ISA's vector store of an 8-bit format, else null
  GenericTileStore generic_store;  // every ISA's store where it has no vector store: the same bytes
};

// The row of `format`, or null for a value outside the enum.
const PixelFormatInfo* pixel_format_info(PixelFormat format) noexcept;

// Float frames of at least this many bytes (over the target's region) are written with
// non-temporal stores wherever a tile row starts on a vector-register boundary: such a
// frame (1920x1080 float RGB is 25 MB) does not stay in a last-level cache from one frame
// to the next, so reading each line into the cache before filling it is wasted memory
// traffic. Smaller frames keep ordinary stores: their lines may still be cached, and
// whoever reads the frame next wants them there. 8-bit frames (a quarter of the bytes)
// always use ordinary stores.
inline constexpr std::size_t kStreamingFrameBytes = std::size_t{16} << 20;

// Whether `target`'s float stores stream (kStreamingFrameBytes over its region).
bool streams_float_frame(const FrameTarget& target) noexcept;

// Stores pixels `part` (inside the target's region) of the tile whose top-left pixel is
// (tile_x0, tile_y0), from its kernel result. `vector_stores`: the kernel ISA's stores; a
// missing one (and the scalar path) takes the generic store here: a 4-pixel SSE2 transpose
// for the float formats (a pixel-by-pixel copy where SSE2 is missing), the scalar encoder
// for 8-bit sRGB. Every store writes the same bytes.
void store_tile(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part, const FrameTarget& target,
                const VectorTileStores& vector_stores = {}) noexcept;

// The buckets of the vector 8-bit sRGB store for `exposure` (SrgbBuckets); valid is false
// (and the scalar encoder is used) for an exposure outside [2^-20, 2^20].
void build_srgb_buckets(double exposure, SrgbBuckets& out);


}  // namespace par2d::detail
