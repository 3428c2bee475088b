// Storing a tile's channel planes into host rows of the host's pixel format (float RGB,
// float RGBA, 8-bit sRGB RGBA), one vector register of pixels at a time, for each ISA's
// kernel table.
//
// The kernel leaves each channel in its own plane (TileResult); a float host row wants
// r g b (a) per pixel. Output register k of a row's interleaved stream holds, in lane j,
// element f = k * W + j: channel f % C of pixel f / C of the register's W pixels. Each
// output is the three channel registers permuted with one constant index (pixel f / C in
// every lane) and blended with constant masks (which lanes take which channel): three
// permutes and two blends (a third blend puts RGBA's constant alpha): fewer than half the
// instructions of the 4-pixel SSE2 transpose every x86-64 has (docs/performance.md). The
// stored floats are the kernel's own: the bytes equal the per-channel copy's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include <xsimd/xsimd.hpp>

#include "simd/tile_work.hpp"

// The 8-bit store packs a pixel's four bytes into one 32-bit lane, R in the low byte.
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "par2d's 8-bit sRGB tile store assumes a little-endian target"
#endif

// The row helpers are inlined into each store whatever the compiler's size estimate says:
// called, a whole row costs more than the stores themselves.
// Sanitizer builds leave it to the compiler (PAR2D_KERNEL_INLINE_HINTS, simd/tile_kernel.hpp).
#if defined(__GNUC__) && !defined(PAR2D_KERNEL_INLINE_HINTS)
#define PAR2D_STORE_INLINE inline __attribute__((always_inline))
#else
#define PAR2D_STORE_INLINE inline
#endif

namespace par2d::simd {
namespace tile_store_detail {

// Lane j of output register kOut: its pixel (the permute index, the same for every channel).
template <std::size_t kChannels, std::size_t kOut>
struct PixelOfLane {
  static constexpr std::uint32_t get(std::size_t j, std::size_t lanes) {
    return static_cast<std::uint32_t>((kOut * lanes + j) / kChannels);
  }
};

// Lane j of output register kOut: whether it holds channel kChannel.
template <std::size_t kChannels, std::size_t kOut, std::size_t kChannel>
struct LaneHoldsChannel {
  static constexpr bool get(std::size_t j, std::size_t lanes) { return (kOut * lanes + j) % kChannels == kChannel; }
};

template <class A, std::size_t kChannels, std::size_t kOut>
PAR2D_STORE_INLINE xsimd::batch<float, A> interleaved_register(const xsimd::batch<float, A>& r, const xsimd::batch<float, A>& g,
                                                   const xsimd::batch<float, A>& b) noexcept {
  using B = xsimd::batch<float, A>;
  using U = xsimd::batch<std::uint32_t, A>;
  // Integer permutes: every ISA's xsimd has them for 32-bit lanes (NEON's float swizzle is
  // missing); the bits are moved, never converted.
  constexpr auto pixel = xsimd::make_batch_constant<U, PixelOfLane<kChannels, kOut>>();
  auto permuted = [&](const B& plane) {
    return xsimd::bitwise_cast<B>(xsimd::swizzle(xsimd::bitwise_cast<U>(plane), pixel));
  };
  B out = permuted(b);
  if constexpr (kChannels == 4)
    out = xsimd::select(xsimd::make_batch_bool_constant<B, LaneHoldsChannel<kChannels, kOut, 3>>(), B(1.0f), out);
  out = xsimd::select(xsimd::make_batch_bool_constant<B, LaneHoldsChannel<kChannels, kOut, 1>>(), permuted(g), out);
  return xsimd::select(xsimd::make_batch_bool_constant<B, LaneHoldsChannel<kChannels, kOut, 0>>(), permuted(r), out);
}

// Row j of a part of the tile (from first_row, first_column): its three channel rows.
struct TileRowPlanes {
  const float* r;
  const float* g;
  const float* b;
};
inline TileRowPlanes tile_row_planes(const detail::TileResult& tile, int first_column, int first_row, int j) noexcept {
  const std::size_t base =
      static_cast<std::size_t>(first_row + j) * detail::kTileSize + static_cast<std::size_t>(first_column);
  return {tile.rgb[0] + base, tile.rgb[1] + base, tile.rgb[2] + base};
}

// A non-temporal store of one register to an address aligned to its width: the line is
// written without first being read into the cache (the store_float_tile `stream` case).
// ISAs without one (NEON) take an ordinary aligned store.
template <class A>
PAR2D_STORE_INLINE void stream_register(const xsimd::batch<float, A>& v, float* to) noexcept {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, A>::value) return _mm512_stream_ps(to, v);
#endif
#if defined(__AVX__)
  if constexpr (std::is_base_of<xsimd::avx, A>::value) return _mm256_stream_ps(to, v);
#endif
#if defined(__SSE2__)
  if constexpr (std::is_base_of<xsimd::sse2, A>::value) return _mm_stream_ps(to, v);
#endif
  v.store_aligned(to);
}

// Non-temporal stores are weakly ordered: fenced before the tile counts as written, so
// whichever thread reads the frame after the render's join sees every line.
inline void stream_fence() noexcept {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

template <class A, std::size_t kChannels, bool kStream, std::size_t... kOut>
PAR2D_STORE_INLINE void store_interleaved(const float* r, const float* g, const float* b, float* row,
                              std::index_sequence<kOut...>) noexcept {
  using B = xsimd::batch<float, A>;
  const B vr = B::load_unaligned(r), vg = B::load_unaligned(g), vb = B::load_unaligned(b);
  if constexpr (kStream)
    (stream_register<A>(interleaved_register<A, kChannels, kOut>(vr, vg, vb), row + kOut * B::size), ...);
  else
    (interleaved_register<A, kChannels, kOut>(vr, vg, vb).store_unaligned(row + kOut * B::size), ...);
}

// A whole tile row (kTileSize pixels) as kTileSize / W groups of kChannels registers.
template <class A, std::size_t kChannels, bool kStream>
PAR2D_STORE_INLINE void store_whole_row(const TileRowPlanes& planes, float* row) noexcept {
  constexpr int W = static_cast<int>(xsimd::batch<float, A>::size);
  for (int i = 0; i < detail::kTileSize; i += W)
    store_interleaved<A, kChannels, kStream>(planes.r + i, planes.g + i, planes.b + i,
                                             row + i * static_cast<int>(kChannels), std::make_index_sequence<kChannels>());
}

}  // namespace tile_store_detail

// Rows first_row .. first_row + rows - 1 of the tile, columns first_column .. + count - 1,
// into host rows `row_stride` bytes apart from `host` (which need not be float-aligned:
// unaligned stores, and memcpy for the last pixels of a row). kChannels: 3 (RGB) or 4
// (RGBA, alpha 1).
// `stream`: the frame is too large to stay cached until it is read (detail::store_tile
// decides), so whole rows that start on a register-width boundary are written with
// non-temporal stores. An ordinary store first reads each line it fills; a frame written
// whole does not need that read. Measured on paper at 1920x1080 (float RGB, 25 MB), AVX-512,
// 2 threads: see docs/performance.md. The bytes are the same either way.
template <class A, std::size_t kChannels>
void store_float_tile(const detail::TileResult& tile, int first_column, int first_row, int rows, int count,
                      unsigned char* host, std::ptrdiff_t row_stride, bool stream) noexcept {
  static_assert(kChannels == 3 || kChannels == 4, "float RGB or RGBA");
  constexpr int W = static_cast<int>(xsimd::batch<float, A>::size);
  static_assert(detail::kTileSize % W == 0, "whole tile rows are whole registers");
  const std::size_t register_bytes = W * sizeof(float);
  if (stream && count == detail::kTileSize && reinterpret_cast<std::uintptr_t>(host) % register_bytes == 0 &&
      static_cast<std::size_t>(row_stride) % register_bytes == 0) {
    // Every row starts on a register boundary (the usual whole tile of an aligned frame):
    // no test per row.
    for (int j = 0; j < rows; ++j)
      tile_store_detail::store_whole_row<A, kChannels, true>(
          tile_store_detail::tile_row_planes(tile, first_column, first_row, j),
          reinterpret_cast<float*>(host + j * row_stride));
    tile_store_detail::stream_fence();
    return;
  }
  bool streamed = false;
  for (int j = 0; j < rows; ++j) {
    const tile_store_detail::TileRowPlanes planes = tile_store_detail::tile_row_planes(tile, first_column, first_row, j);
    const auto [r, g, b] = planes;
    float* row = reinterpret_cast<float*>(host + j * row_stride);
    int i = 0;
    if (count == detail::kTileSize) {  // whole rows (most tiles): a constant trip count, unrolled
      // Every register of such a row is aligned when its first is (W pixels are kChannels * W floats).
      if (stream && reinterpret_cast<std::uintptr_t>(row) % (W * sizeof(float)) == 0) {
        tile_store_detail::store_whole_row<A, kChannels, true>(planes, row);
        streamed = true;
      } else {
        tile_store_detail::store_whole_row<A, kChannels, false>(planes, row);
      }
      continue;
    }
    for (; i + W <= count; i += W)
      tile_store_detail::store_interleaved<A, kChannels, false>(r + i, g + i, b + i, row + i * static_cast<int>(kChannels),
                                                                std::make_index_sequence<kChannels>());
    for (; i < count; ++i) {
      const float pixel[4] = {r[i], g[i], b[i], 1.0f};
      std::memcpy(row + i * static_cast<int>(kChannels), pixel, kChannels * sizeof(float));
    }
  }
  if (streamed) tile_store_detail::stream_fence();
}

namespace tile_store_detail {

// table[index] per lane. xsimd 8.1's batch<float>::gather never reaches its AVX2 or
// AVX-512 overloads (they take one template argument where the call passes two) and
// falls back to one load and insert per lane, ~4x the instructions; the gather
// instructions are called here directly. Other ISAs have none: per-lane loads.
template <class A>
inline xsimd::batch<float, A> gather(const float* table, const xsimd::batch<std::int32_t, A>& index) noexcept {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, A>::value) return _mm512_i32gather_ps(index, table, sizeof(float));
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, A>::value) return _mm256_i32gather_ps(table, index, sizeof(float));
#endif
  return xsimd::batch<float, A>::gather(table, index);
}

// The sRGB codes of one register of a channel (SrgbBuckets).
template <class A>
inline xsimd::batch<std::int32_t, A> srgb_codes(const float* channel, const detail::SrgbBuckets& buckets) noexcept {
  using B = xsimd::batch<float, A>;
  const B v = B::load_unaligned(channel);
  const B positive = xsimd::select(v > B(0.0f), v, B(0.0f));  // NaN and v <= 0: code 0
  // Truncation of a non-negative value is its floor; an infinite product clamps to `last`.
  const auto bucket = xsimd::to_int(xsimd::min(positive * B(buckets.scale), B(static_cast<float>(buckets.last))));
  const B below = gather<A>(buckets.below.data(), bucket);
  const B inside = gather<A>(buckets.inside.data(), bucket);
  return xsimd::to_int(below + xsimd::select(positive >= inside, B(1.0f), B(0.0f)));
}

}  // namespace tile_store_detail

// The same rows into 8-bit sRGB RGBA (alpha 255) through `buckets` (SrgbBuckets): per
// channel a multiply, a clamp, two gathers, a compare and a conversion; the three codes and
// alpha packed into one 32-bit pixel (bytes R, G, B, A in memory on little-endian targets,
// which are all the targets par2d builds for). NaN and values <= 0 encode as 0, as in the
// scalar encoder; the codes equal its codes (the thresholds carry its double product).
// kBgra: bytes B, G, R, A instead (the red and blue codes swap places).
template <class A, bool kBgra = false>
void store_srgb8_tile(const detail::TileResult& tile, int first_column, int first_row, int rows, int count,
                      unsigned char* host, std::ptrdiff_t row_stride, const detail::SrgbBuckets& buckets) noexcept {
  using B = xsimd::batch<float, A>;
  using I = xsimd::batch<std::int32_t, A>;
  constexpr int W = static_cast<int>(B::size);
  const float* below = buckets.below.data();
  const float* inside = buckets.inside.data();
  auto scalar_code = [&](float v) {
    const float positive = v > 0.0f ? v : 0.0f;
    const int bucket = static_cast<int>(std::min(positive * buckets.scale, static_cast<float>(buckets.last)));
    return static_cast<unsigned char>(below[bucket] + (positive >= inside[bucket] ? 1.0f : 0.0f));
  };
  const I alpha(-0x1000000);  // 0xFF000000: byte 3 of each pixel
  for (int j = 0; j < rows; ++j) {
    const tile_store_detail::TileRowPlanes planes = tile_store_detail::tile_row_planes(tile, first_column, first_row, j);
    const float* r = kBgra ? planes.b : planes.r;  // the plane whose codes go to byte 0
    const float* g = planes.g;
    const float* b = kBgra ? planes.r : planes.b;
    unsigned char* row = host + j * row_stride;
    int i = 0;
    for (; i + W <= count; i += W) {
      const I pixels = tile_store_detail::srgb_codes<A>(r + i, buckets) |
                       (tile_store_detail::srgb_codes<A>(g + i, buckets) << 8) |
                       (tile_store_detail::srgb_codes<A>(b + i, buckets) << 16) | alpha;
      pixels.store_unaligned(reinterpret_cast<std::int32_t*>(row + 4 * i));
    }
    for (; i < count; ++i) {
      const unsigned char pixel[4] = {scalar_code(r[i]), scalar_code(g[i]), scalar_code(b[i]), 255};
      std::memcpy(row + 4 * i, pixel, 4);
    }
  }
}

}  // namespace par2d::simd
