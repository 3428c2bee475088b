// Tile stores into each pixel format against a pixel-by-pixel reference: every part shape of a
// tile, through the generic store and through each ISA's vector stores of the float formats.
#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "render/frame_output.hpp"
#include "render/kernel_table.hpp"
#include "support/random_scenes.hpp"

using namespace par2d;
using par2d::detail::FrameTarget;
using par2d::detail::kTileSize;
using par2d::detail::TileRect;
using par2d::detail::TileResult;
using par2d::test::simd_isas_here;

namespace {

// What the store must write for tile pixel (i, j) of `result`, in `format`.
void reference_pixel(const TileResult& result, int i, int j, PixelFormat format, double exposure, unsigned char* out) {
  const std::size_t k = static_cast<std::size_t>(j) * kTileSize + static_cast<std::size_t>(i);
  const float rgb[3] = {result.rgb[0][k], result.rgb[1][k], result.rgb[2][k]};
  if (format == PixelFormat::rgba8_srgb) {
    for (int c = 0; c < 3; ++c) out[c] = detail::encode_srgb8(exposure * static_cast<double>(rgb[c]));
    out[3] = 255;
    return;
  }
  const float pixel[4] = {rgb[0], rgb[1], rgb[2], 1.0f};
  std::memcpy(out, pixel, static_cast<std::size_t>(bytes_per_pixel(format)));
}

}  // namespace

TEST_CASE("tile store: every format, every part of a tile, at odd offsets and strides, equals the pixel-by-pixel reference") {
  // The generic store, then each ISA's vector stores of the float formats (the ones the
  // frame driver uses with that ISA's kernel).
  std::vector<std::pair<std::string, detail::FloatTileStores>> stores{{"generic", {}}};
  for (Isa isa : simd_isas_here()) {
    const detail::KernelSet* kernels = detail::kernels_for(isa);
    REQUIRE(kernels != nullptr);
    const bool has_float_stores =
        kernels->float_stores.rgb_f32 != nullptr && kernels->float_stores.rgba_f32 != nullptr;
    REQUIRE(has_float_stores);
    stores.emplace_back(std::string(isa_name(isa)), kernels->float_stores);
  }
  for (const auto& [store_name, store] : stores) {
    INFO("store ", store_name);
    auto result = std::make_unique<TileResult>();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(-0.25f, 1.5f);
    for (auto& plane : result->rgb)
      for (float& v : plane) v = value(rng);
    result->rgb[1][5] = -0.0f;  // signs and special values pass through the float formats unchanged
    result->rgb[2][17] = 1e-40f;

    const int tile_x0 = 32, tile_y0 = 48;  // the tile's top-left pixel in the frame
    for (PixelFormat format : {PixelFormat::rgb_f32, PixelFormat::rgba_f32, PixelFormat::rgba8_srgb}) {
      const int bpp = bytes_per_pixel(format);
      int mismatches = 0, padding_changed = 0, parts = 0;
      for (int trial = 0; trial < 400; ++trial) {
        TileRect part;
        part.x0 = tile_x0 + static_cast<int>(rng() % kTileSize);
        part.x1 = part.x0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(tile_x0 + kTileSize - part.x0));
        part.y0 = tile_y0 + static_cast<int>(rng() % kTileSize);
        part.y1 = part.y0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(tile_y0 + kTileSize - part.y0));
        if (trial < kTileSize) part = {tile_x0 + trial, tile_y0, tile_x0 + kTileSize, tile_y0 + kTileSize};  // every start
        if (trial == kTileSize) part = {tile_x0, tile_y0, tile_x0 + kTileSize, tile_y0 + kTileSize};       // whole tile
        // The region starts left of and above the part by a few pixels; rows are padded by an
        // odd byte count, and the buffer starts one byte past an allocation, so rows are never
        // float-aligned.
        FrameTarget target;
        target.format = format;
        target.exposure = 0.8;
        target.region = {part.x0 - 3, part.y0 - 1, part.x1 + 2, part.y1 + 1};
        const int rw = target.region.x1 - target.region.x0, rh = target.region.y1 - target.region.y0;
        target.row_stride = static_cast<std::ptrdiff_t>(rw) * bpp + 5;
        std::vector<unsigned char> storage(static_cast<std::size_t>(target.row_stride) * rh + 1, 0xAB);
        target.data = storage.data() + 1;
        detail::store_tile(*result, tile_x0, tile_y0, part, target, store);
        ++parts;
        for (int y = target.region.y0; y < target.region.y1; ++y) {
          const unsigned char* row = target.data + static_cast<std::ptrdiff_t>(y - target.region.y0) * target.row_stride;
          for (std::ptrdiff_t b = 0; b < target.row_stride; ++b) {
            const int x = target.region.x0 + static_cast<int>(b / bpp);
            const bool in_part = b < static_cast<std::ptrdiff_t>(rw) * bpp && x >= part.x0 && x < part.x1 &&
                                 y >= part.y0 && y < part.y1;
            if (!in_part) {
              padding_changed += row[b] != 0xAB;
              continue;
            }
            if (b % bpp != 0) continue;
            unsigned char expected[16];
            reference_pixel(*result, x - tile_x0, y - tile_y0, format, target.exposure, expected);
            mismatches += std::memcmp(row + b, expected, static_cast<std::size_t>(bpp)) != 0;
          }
        }
        padding_changed += storage[0] != 0xAB;
      }
      INFO("format ", static_cast<int>(format), " parts ", parts);
      CHECK(mismatches == 0);
      CHECK(padding_changed == 0);
    }
  }
}
