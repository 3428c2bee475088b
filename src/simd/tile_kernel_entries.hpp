// Declarations of the per-ISA entry points that tile_kernel_entry.hpp defines, for the
// kernel tables (render/kernel_table_<arch>.cpp): PAR2D_DECLARE_TILE_KERNELS(suffix).
#pragma once

#include <cstddef>

#include "simd/tile_work.hpp"

#define PAR2D_DECLARE_TILE_KERNELS(suffix)                                                                  \
  namespace par2d::simd {                                                                                  \
  void render_tile_##suffix(const detail::TileWork&, float*, detail::TileResult&) noexcept;                \
  void union_measure_##suffix(float*, float*, std::size_t, const float*, const float*, float*) noexcept; \
  void atan2_##suffix(const float*, const float*, float*, int) noexcept;                                   \
  void add_light_layer_##suffix(const float*, bool, const float*, detail::TileResult&) noexcept;           \
  void store_rgb_f32_##suffix(const detail::TileResult&, int, int, int, int, unsigned char*, std::ptrdiff_t, bool) noexcept; \
  void store_rgba_f32_##suffix(const detail::TileResult&, int, int, int, int, unsigned char*, std::ptrdiff_t, bool) noexcept; \
  void store_rgba8_srgb_##suffix(const detail::TileResult&, int, int, int, int, unsigned char*, std::ptrdiff_t,         \
                                 const detail::SrgbBuckets&) noexcept;                                                   \
  void store_bgra8_srgb_##suffix(const detail::TileResult&, int, int, int, int, unsigned char*, std::ptrdiff_t,         \
                                 const detail::SrgbBuckets&) noexcept;                                                   \
  }

// An ISA's VectorTileStores (render/frame_output.hpp), for its kernel table row.
#define PAR2D_TILE_STORES(suffix)                                                                      \
  {                                                                                                    \
    ::par2d::simd::store_rgb_f32_##suffix, ::par2d::simd::store_rgba_f32_##suffix,                    \
        ::par2d::simd::store_rgba8_srgb_##suffix, ::par2d::simd::store_bgra8_srgb_##suffix             \
  }
