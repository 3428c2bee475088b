// The table of pixel formats and their tile stores: float RGB and RGBA, half RGBA, 8-bit sRGB
// RGBA and BGRA with exposure, plain or with an ordered dither.
#include "render/frame_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace par2d {
namespace detail {
namespace {


// Calls row(r, g, b, host, count) for each row of `part`: the tile's three channel rows from
// the part's first column, and the host row's first byte of the part.
template <int kChannels, class T, class Row>
void for_each_part_row(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                       const FrameTarget& target, Row&& row) noexcept {
  const int count = part.x1 - part.x0;
  const std::size_t first = static_cast<std::size_t>(part.x0 - tile_x0);
  for (int j = part.y0; j < part.y1; ++j) {
    const std::size_t base = static_cast<std::size_t>(j - tile_y0) * kTileSize + first;
    unsigned char* host = target.data + static_cast<std::ptrdiff_t>(j - target.region.y0) * target.row_stride +
                          static_cast<std::ptrdiff_t>(part.x0 - target.region.x0) * kChannels *
                              static_cast<std::ptrdiff_t>(sizeof(T));
    row(result.rgb[0] + base, result.rgb[1] + base, result.rgb[2] + base, host, count);
  }
}

// Interleaves each row of `part` into a small local buffer with put(dst, r, g, b) and
// copies it to the host row in one memcpy: host rows need not be aligned for float, and
// one copy per row is cheaper than one per pixel.
template <int kChannels, class T, class Put>
void store_rows(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part, const FrameTarget& target,
                Put&& put) noexcept {
  for_each_part_row<kChannels, T>(
      result, tile_x0, tile_y0, part, target,
      [&](const float* r, const float* g, const float* b, unsigned char* host, int count) {
        T row_buffer[kTileSize * kChannels];
        for (int i = 0; i < count; ++i) put(row_buffer + i * kChannels, r[i], g[i], b[i]);
        std::memcpy(host, row_buffer, static_cast<std::size_t>(count) * kChannels * sizeof(T));
      });
}

// Float rows (3 or 4 channels) written straight into the host row: an SSE2 transpose of 4
// pixels at a time (baseline on every x86-64), unaligned stores, a scalar tail. The stored
// floats are the kernel's own, so the bytes equal the per-channel copy's. A third of the
// instructions of a copy through a row buffer.
template <int kChannels>
void store_float_rows(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                      const FrameTarget& target) noexcept {
  for_each_part_row<kChannels, float>(
      result, tile_x0, tile_y0, part, target,
      [](const float* r, const float* g, const float* b, unsigned char* host, int count) {
        float* row = reinterpret_cast<float*>(host);
        int i = 0;
#if defined(__SSE2__)
        for (; i + 4 <= count; i += 4) {
          const __m128 vr = _mm_loadu_ps(r + i), vg = _mm_loadu_ps(g + i), vb = _mm_loadu_ps(b + i);
          float* p = row + i * kChannels;
          if constexpr (kChannels == 3) {
            const __m128 rg_lo = _mm_unpacklo_ps(vr, vg);                              // r0 g0 r1 g1
            const __m128 rg_hi = _mm_unpackhi_ps(vr, vg);                              // r2 g2 r3 g3
            const __m128 b0r1 = _mm_shuffle_ps(vb, vr, _MM_SHUFFLE(1, 1, 0, 0));      // b0 b0 r1 r1
            const __m128 g1b1 = _mm_shuffle_ps(vg, vb, _MM_SHUFFLE(1, 1, 1, 1));      // g1 g1 b1 b1
            const __m128 b2r3 = _mm_shuffle_ps(vb, vr, _MM_SHUFFLE(3, 3, 2, 2));      // b2 b2 r3 r3
            const __m128 g3b3 = _mm_shuffle_ps(vg, vb, _MM_SHUFFLE(3, 3, 3, 3));      // g3 g3 b3 b3
            _mm_storeu_ps(p, _mm_shuffle_ps(rg_lo, b0r1, _MM_SHUFFLE(2, 0, 1, 0)));      // r0 g0 b0 r1
            _mm_storeu_ps(p + 4, _mm_shuffle_ps(g1b1, rg_hi, _MM_SHUFFLE(1, 0, 2, 0)));  // g1 b1 r2 g2
            _mm_storeu_ps(p + 8, _mm_shuffle_ps(b2r3, g3b3, _MM_SHUFFLE(2, 0, 2, 0)));   // b2 r3 g3 b3
          } else {
            const __m128 va = _mm_set1_ps(1.0f);
            const __m128 rg_lo = _mm_unpacklo_ps(vr, vg), rg_hi = _mm_unpackhi_ps(vr, vg);
            const __m128 ba_lo = _mm_unpacklo_ps(vb, va), ba_hi = _mm_unpackhi_ps(vb, va);
            _mm_storeu_ps(p, _mm_movelh_ps(rg_lo, ba_lo));
            _mm_storeu_ps(p + 4, _mm_movehl_ps(ba_lo, rg_lo));
            _mm_storeu_ps(p + 8, _mm_movelh_ps(rg_hi, ba_hi));
            _mm_storeu_ps(p + 12, _mm_movehl_ps(ba_hi, rg_hi));
          }
        }
#endif
        for (; i < count; ++i) {
          float pixel[4] = {r[i], g[i], b[i], 1.0f};
          std::memcpy(row + i * kChannels, pixel, kChannels * sizeof(float));
        }
      });
}

// 8-bit sRGB rows through the scalar encoder, at the target's exposure; kBgra: bytes B, G, R,
// A; kDithered: the ordered dither of the pixel's place on the frame's pixel grid.
template <bool kBgra, bool kDithered>
void store_srgb8_rows(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                      const FrameTarget& target) noexcept {
  const double exposure = target.exposure;
  const std::size_t first = static_cast<std::size_t>(part.x0 - tile_x0);
  constexpr int kRed = kBgra ? 2 : 0, kBlue = kBgra ? 0 : 2;
  for (int y = part.y0; y < part.y1; ++y) {
    const std::size_t base = static_cast<std::size_t>(y - tile_y0) * kTileSize + first;
    unsigned char* host = target.data + static_cast<std::ptrdiff_t>(y - target.region.y0) * target.row_stride +
                          static_cast<std::ptrdiff_t>(part.x0 - target.region.x0) * 4;
    unsigned char row[kTileSize * 4];
    for (int i = 0; i < part.x1 - part.x0; ++i) {
      unsigned char* p = row + 4 * i;
      const double rgb[3] = {exposure * static_cast<double>(result.rgb[0][base + static_cast<std::size_t>(i)]),
                             exposure * static_cast<double>(result.rgb[1][base + static_cast<std::size_t>(i)]),
                             exposure * static_cast<double>(result.rgb[2][base + static_cast<std::size_t>(i)])};
      if constexpr (kDithered) {
        const int b = bayer8(target.dither_x + part.x0 + i, target.dither_y + y);
        p[kRed] = encode_srgb8_dithered(rgb[0], b);
        p[1] = encode_srgb8_dithered(rgb[1], b);
        p[kBlue] = encode_srgb8_dithered(rgb[2], b);
      } else {
        p[kRed] = encode_srgb8(rgb[0]);
        p[1] = encode_srgb8(rgb[1]);
        p[kBlue] = encode_srgb8(rgb[2]);
      }
      p[3] = 255;
    }
    std::memcpy(host, row, static_cast<std::size_t>(part.x1 - part.x0) * 4);
  }
}

// Half-float RGBA rows (alpha 1.0 = 0x3C00), in the host's byte order.
void store_half_rows(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part,
                     const FrameTarget& target) noexcept {
  store_rows<4, std::uint16_t>(result, tile_x0, tile_y0, part, target,
                               [](std::uint16_t* p, float r, float g, float b) {
                                 p[0] = half_of(r);
                                 p[1] = half_of(g);
                                 p[2] = half_of(b);
                                 p[3] = 0x3C00;
                               });
}

// Rows in PixelFormat's order, so that a format's row is found by its value.
constexpr PixelFormatInfo kPixelFormats[] = {
    {PixelFormat::rgb_f32, "rgb_f32", 12, 3, false, &VectorTileStores::rgb_f32, nullptr, store_float_rows<3>},
    {PixelFormat::rgba_f32, "rgba_f32", 16, 4, false, &VectorTileStores::rgba_f32, nullptr, store_float_rows<4>},
    {PixelFormat::rgba8_srgb, "rgba8_srgb", 4, 4, true, nullptr, &VectorTileStores::rgba8_srgb,
     store_srgb8_rows<false, false>},
    {PixelFormat::bgra8_srgb, "bgra8_srgb", 4, 4, true, nullptr, &VectorTileStores::bgra8_srgb,
     store_srgb8_rows<true, false>},
    {PixelFormat::rgba16f, "rgba16f", 8, 4, false, nullptr, nullptr, store_half_rows},
    {PixelFormat::rgba8_srgb_dithered, "rgba8_srgb_dithered", 4, 4, true, nullptr, nullptr, store_srgb8_rows<false, true>},
    {PixelFormat::bgra8_srgb_dithered, "bgra8_srgb_dithered", 4, 4, true, nullptr, nullptr, store_srgb8_rows<true, true>},
};
constexpr std::size_t kPixelFormatCount = sizeof(kPixelFormats) / sizeof(kPixelFormats[0]);

constexpr bool rows_in_enum_order() noexcept {
  for (std::size_t i = 0; i < kPixelFormatCount; ++i)
    if (static_cast<std::size_t>(kPixelFormats[i].format) != i) return false;
  return true;
}
static_assert(rows_in_enum_order(), "kPixelFormats lists the formats in PixelFormat's order");

}  // namespace

const PixelFormatInfo* pixel_format_info(PixelFormat format) noexcept {
  const auto index = static_cast<std::size_t>(format);
  return index < kPixelFormatCount ? &kPixelFormats[index] : nullptr;
}

void build_srgb_buckets(double exposure, SrgbBuckets& out) {
  out.exposure = exposure;
  out.valid = false;
  if (!(exposure >= 0x1p-20 && exposure <= 0x1p20)) return;
  // threshold[k]: the least non-negative float r with exposure * r (in double) >= the k-th
  // code's start, by bisection over the float bit patterns (ordered like the values for
  // r >= 0); the product is monotone in r, so r >= threshold[k] exactly when the scalar
  // encoder's value reaches that start.
  std::array<float, 255> threshold{};
  for (std::size_t k = 0; k < threshold.size(); ++k) {
    std::uint32_t lo = 0, hi = 0x7f800000u;  // +inf reaches every start
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      float r;
      std::memcpy(&r, &mid, sizeof r);
      if (exposure * static_cast<double>(r) >= srgb8_thresholds()[k]) hi = mid;
      else lo = mid + 1;
    }
    std::memcpy(&threshold[k], &lo, sizeof lo);
    if (!std::isfinite(threshold[k])) return;
  }
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < threshold.size(); ++k)
    closest = std::min(closest, static_cast<double>(threshold[k]) - static_cast<double>(threshold[k - 1]));
  if (!(closest > 0.0)) return;
  // The widest power-of-two bucket no wider than the closest pair: one threshold at most each.
  double scale = std::exp2(std::ceil(-std::log2(closest)));
  while (1.0 / scale > closest) scale *= 2.0;
  while (2.0 / scale <= closest) scale *= 0.5;
  const double last = std::floor(static_cast<double>(threshold.back()) * scale);  // exact: scale is a power of two
  if (!(last < 65536.0)) return;
  out.scale = static_cast<float>(scale);
  out.last = static_cast<int>(last);
  const std::size_t buckets = static_cast<std::size_t>(out.last) + 1;
  out.below.assign(buckets, 0.0f);
  out.inside.assign(buckets, std::numeric_limits<float>::infinity());
  std::size_t k = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    while (k < threshold.size() && static_cast<double>(threshold[k]) * scale < static_cast<double>(b)) ++k;
    out.below[b] = static_cast<float>(k);  // thresholds below the bucket's start
    if (k < threshold.size() && std::floor(static_cast<double>(threshold[k]) * scale) == static_cast<double>(b))
      out.inside[b] = threshold[k];
  }
  out.valid = true;
}

bool streams_float_frame(const FrameTarget& target) noexcept {
  const PixelFormatInfo& format = *pixel_format_info(target.format);
  if (!format.float_store) return false;
  const std::size_t frame_bytes = static_cast<std::size_t>(target.region.x1 - target.region.x0) *
                                  static_cast<std::size_t>(target.region.y1 - target.region.y0) *
                                  static_cast<std::size_t>(format.bytes_per_pixel);
  return frame_bytes >= kStreamingFrameBytes;
}

void shift_pixels(const FrameTarget& target, int dx, int dy) noexcept {
  const int width = target.region.x1 - target.region.x0, height = target.region.y1 - target.region.y0;
  const std::size_t pixel = static_cast<std::size_t>(pixel_format_info(target.format)->bytes_per_pixel);
  const std::size_t bytes = static_cast<std::size_t>(width - std::abs(dx)) * pixel;
  const std::size_t to = static_cast<std::size_t>(std::max(-dx, 0)) * pixel, from = static_cast<std::size_t>(std::max(dx, 0)) * pixel;
  const auto move_row = [&](int j) {
    std::memmove(target.data + static_cast<std::ptrdiff_t>(j) * target.row_stride + to,
                 target.data + static_cast<std::ptrdiff_t>(j + dy) * target.row_stride + from, bytes);
  };
  if (dy >= 0) {
    for (int j = 0; j + dy < height; ++j) move_row(j);
  } else {
    for (int j = height - 1; j + dy >= 0; --j) move_row(j);
  }
}

void store_tile(const TileResult& result, int tile_x0, int tile_y0, const TileRect& part, const FrameTarget& target,
                const VectorTileStores& vector_stores) noexcept {
  if (target.ring) {
    // Each piece as an ordinary store into a target whose region is moved so that the piece's
    // frame pixels land on their buffer pixels.
    for_each_ring_piece(target, part, [&](const TileRect& piece, int dx, int dy) {
      FrameTarget placed = target;
      placed.ring = false;
      placed.region = {target.region.x0 - dx, target.region.y0 - dy, target.region.x1 - dx, target.region.y1 - dy};
      store_tile(result, tile_x0, tile_y0, piece, placed, vector_stores);
    });
    return;
  }
  const PixelFormatInfo& format = *pixel_format_info(target.format);  // valid: checked at the API boundary
  const int count = part.x1 - part.x0, rows = part.y1 - part.y0;
  const int first_column = part.x0 - tile_x0, first_row = part.y0 - tile_y0;
  unsigned char* host = target.data + static_cast<std::ptrdiff_t>(part.y0 - target.region.y0) * target.row_stride +
                        static_cast<std::ptrdiff_t>(part.x0 - target.region.x0) * format.bytes_per_pixel;
  const FloatRowsStore float_store = format.float_store ? vector_stores.*format.float_store : nullptr;
  if (float_store) {
    float_store(result, first_column, first_row, rows, count, host, target.row_stride, streams_float_frame(target));
    return;
  }
  const Srgb8RowsStore srgb8_store = format.srgb8_store ? vector_stores.*format.srgb8_store : nullptr;
  if (srgb8_store && vector_stores.srgb && vector_stores.srgb->valid && vector_stores.srgb->exposure == target.exposure) {
    srgb8_store(result, first_column, first_row, rows, count, host, target.row_stride, *vector_stores.srgb);
    return;
  }
  format.generic_store(result, tile_x0, tile_y0, part, target);
}

}  // namespace detail

int bytes_per_pixel(PixelFormat format) noexcept {
  const detail::PixelFormatInfo* info = detail::pixel_format_info(format);
  return info ? info->bytes_per_pixel : 0;
}

}  // namespace par2d
