// Bodies of the per-ISA entry points: each tile_kernel_<isa>.cpp includes this with
// PAR2D_KERNEL_ARCH and PAR2D_KERNEL_SUFFIX defined, so the three files differ only in flags.
#include "simd/tile_kernel.hpp"
#include "simd/tile_store.hpp"

#define PAR2D_CONCAT_INNER(a, b) a##b
#define PAR2D_CONCAT(a, b) PAR2D_CONCAT_INNER(a, b)

namespace par2d::simd {

void PAR2D_CONCAT(render_tile_, PAR2D_KERNEL_SUFFIX)(const TileWork& work, float* scratch, TileResult& out) noexcept {
  render_tile<PAR2D_KERNEL_ARCH>(work, scratch, out);
}

void PAR2D_CONCAT(union_measure_, PAR2D_KERNEL_SUFFIX)(float* lo, float* hi, std::size_t count, const float* width,
                                                        const float* reach0, float* out) noexcept {
  using B = xsimd::batch<float, PAR2D_KERNEL_ARCH>;
  constexpr std::size_t W = B::size;
  const B w = B::load_unaligned(width);
  const std::size_t used = sort_slots<PAR2D_KERNEL_ARCH>(count);
  for (std::size_t p = count; p < used; ++p) {
    w.store_aligned(lo + p * W);
    w.store_aligned(hi + p * W);
  }
  sort_by_lo<PAR2D_KERNEL_ARCH>(lo, hi, used);
  sorted_union_measure<PAR2D_KERNEL_ARCH>(lo, hi, count, B::load_unaligned(reach0)).store_unaligned(out);
}

void PAR2D_CONCAT(atan2_, PAR2D_KERNEL_SUFFIX)(const float* y, const float* x, float* out, int domain) noexcept {
  using B = xsimd::batch<float, PAR2D_KERNEL_ARCH>;
  const B yb = B::load_unaligned(y), xb = B::load_unaligned(x);
  const B r = domain == 2   ? fast_atan2_first_quadrant<PAR2D_KERNEL_ARCH>(yb, xb)
              : domain == 1 ? fast_atan2_upper<PAR2D_KERNEL_ARCH>(yb, xb)
                            : fast_atan2<PAR2D_KERNEL_ARCH>(yb, xb);
  r.store_unaligned(out);
}

// out += emission x layer, per channel (one plane for all three when `mono`), with the
// kernel's own multiply-add: the light-layer cache's recombination (render/light_layers.hpp).
void PAR2D_CONCAT(add_light_layer_, PAR2D_KERNEL_SUFFIX)(const float* layer, bool mono, const float* emission,
                                                         detail::TileResult& out) noexcept {
  using B = xsimd::batch<float, PAR2D_KERNEL_ARCH>;
  constexpr std::size_t W = B::size;
  for (std::size_t c = 0; c < 3; ++c) {
    const float* plane = layer + (mono ? 0 : c * detail::kTilePixels);
    const B e(emission[c]);
    float* sum = out.rgb[c];
    for (std::size_t p = 0; p < detail::kTilePixels; p += W)
      xsimd::fma(e, B::load_unaligned(plane + p), B::load_aligned(sum + p)).store_aligned(sum + p);
  }
}

void PAR2D_CONCAT(store_rgb_f32_, PAR2D_KERNEL_SUFFIX)(const TileResult& tile, int first_column, int first_row, int rows,
                                                       int count, unsigned char* host, std::ptrdiff_t row_stride,
                                                       bool stream) noexcept {
  store_float_tile<PAR2D_KERNEL_ARCH, 3>(tile, first_column, first_row, rows, count, host, row_stride, stream);
}

void PAR2D_CONCAT(store_rgba_f32_, PAR2D_KERNEL_SUFFIX)(const TileResult& tile, int first_column, int first_row, int rows,
                                                        int count, unsigned char* host, std::ptrdiff_t row_stride,
                                                       bool stream) noexcept {
  store_float_tile<PAR2D_KERNEL_ARCH, 4>(tile, first_column, first_row, rows, count, host, row_stride, stream);
}

void PAR2D_CONCAT(store_rgba8_srgb_, PAR2D_KERNEL_SUFFIX)(const TileResult& tile, int first_column, int first_row,
                                                          int rows, int count, unsigned char* host,
                                                          std::ptrdiff_t row_stride,
                                                          const detail::SrgbBuckets& buckets) noexcept {
  store_srgb8_tile<PAR2D_KERNEL_ARCH>(tile, first_column, first_row, rows, count, host, row_stride, buckets);
}

void PAR2D_CONCAT(store_bgra8_srgb_, PAR2D_KERNEL_SUFFIX)(const TileResult& tile, int first_column, int first_row,
                                                          int rows, int count, unsigned char* host,
                                                          std::ptrdiff_t row_stride,
                                                          const detail::SrgbBuckets& buckets) noexcept {
  store_srgb8_tile<PAR2D_KERNEL_ARCH, true>(tile, first_column, first_row, rows, count, host, row_stride, buckets);
}

}  // namespace par2d::simd
