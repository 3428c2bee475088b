// Tile stores for each pixel format: float RGB, float RGBA, 8-bit sRGB RGBA with exposure.
#include "render/frame_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace par2d {

int bytes_per_pixel(PixelFormat format) noexcept {
  switch (format) {
    case PixelFormat::rgb_f32: return 12;
    case PixelFormat::rgba_f32: return 16;
    case PixelFormat::rgba8_srgb: return 4;
  }
  return 0;
}

namespace detail {
namespace {

// Linear values at which the rounded 8-bit sRGB code steps from k-1 to k, k = 1..255: the
// inverse transfer function at (k - 0.5) / 255 (the PNG writer encodes the same way).
struct SrgbThresholds {
  std::array<double, 255> t{};
  SrgbThresholds() {
    for (int k = 1; k <= 255; ++k) {
      const double s = (k - 0.5) / 255.0;
      t[static_cast<std::size_t>(k - 1)] = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    }
  }
};
const SrgbThresholds kSrgb;

template <class Put>
void for_each_pixel(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part, const FrameTarget& target,
                    Put&& put) noexcept {
  const int size = bytes_per_pixel(target.format);
  for (int j = part.y0; j < part.y1; ++j) {
    unsigned char* row = target.data + static_cast<std::ptrdiff_t>(j - target.region.y0) * target.row_stride;
    const std::size_t base = static_cast<std::size_t>(j - tile_y0) * kTileSize;
    for (int i = part.x0; i < part.x1; ++i) {
      const std::size_t at = base + static_cast<std::size_t>(i - tile_x0);
      put(row + static_cast<std::ptrdiff_t>(i - target.region.x0) * size, result.rgb[0][at], result.rgb[1][at],
          result.rgb[2][at]);
    }
  }
}

}  // namespace

unsigned char encode_srgb8(double linear) noexcept {
  if (!(linear > 0.0)) return 0;
  if (linear >= 1.0) return 255;
  return static_cast<unsigned char>(std::upper_bound(kSrgb.t.begin(), kSrgb.t.end(), linear) - kSrgb.t.begin());
}

void store_tile(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                const FrameTarget& target) noexcept {
  // memcpy: host buffers need not be aligned for float.
  switch (target.format) {
    case PixelFormat::rgb_f32:
      for_each_pixel(result, tile_x0, tile_y0, part, target, [](unsigned char* p, float r, float g, float b) {
        const float v[3] = {r, g, b};
        std::memcpy(p, v, sizeof v);
      });
      break;
    case PixelFormat::rgba_f32:
      for_each_pixel(result, tile_x0, tile_y0, part, target, [](unsigned char* p, float r, float g, float b) {
        const float v[4] = {r, g, b, 1.0f};
        std::memcpy(p, v, sizeof v);
      });
      break;
    case PixelFormat::rgba8_srgb: {
      const double exposure = target.exposure;
      for_each_pixel(result, tile_x0, tile_y0, part, target, [exposure](unsigned char* p, float r, float g, float b) {
        p[0] = encode_srgb8(exposure * static_cast<double>(r));
        p[1] = encode_srgb8(exposure * static_cast<double>(g));
        p[2] = encode_srgb8(exposure * static_cast<double>(b));
        p[3] = 255;
      });
      break;
    }
  }
}

}  // namespace detail
}  // namespace par2d
