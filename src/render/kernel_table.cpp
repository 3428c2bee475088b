// Kernel table (scalar first, upgraded to what the CPU has) and the SIMD render driver.
#include "render/kernel_table.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <memory>

#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "scalar/scalar_renderer.hpp"

namespace par2d::simd {
#define PAR2D_DECLARE_KERNELS(suffix)                                                                       \
  void render_tile_##suffix(const detail::TileWork&, float*, detail::TileResult&) noexcept;                \
  void union_measure_##suffix(float*, float*, std::size_t, const float*, const float*, float*) noexcept; \
  void atan2_##suffix(const float*, const float*, float*) noexcept;
PAR2D_DECLARE_KERNELS(sse4_2)
PAR2D_DECLARE_KERNELS(avx2)
PAR2D_DECLARE_KERNELS(avx512)
#undef PAR2D_DECLARE_KERNELS
}  // namespace par2d::simd

namespace par2d::detail {
namespace {

constexpr KernelSet kKernels[] = {
    {Isa::sse4_2, 4, simd::render_tile_sse4_2, simd::union_measure_sse4_2, simd::atan2_sse4_2},
    {Isa::avx2, 8, simd::render_tile_avx2, simd::union_measure_avx2, simd::atan2_avx2},
    {Isa::avx512, 16, simd::render_tile_avx512, simd::union_measure_avx512, simd::atan2_avx512},
};

// Everything one worker thread reuses from tile to tile.
struct ThreadState {
  TileWork work;
  TileSetupScratch setup;
  ScalarScratch scalar;
  std::unique_ptr<float[]> scratch;  // 64-byte aligned view into it via `aligned`
  std::size_t scratch_floats = 0;
  float* aligned = nullptr;
  TileResult result;

  float* kernel_scratch(std::size_t floats) {
    if (floats > scratch_floats) {
      scratch_floats = floats + floats / 2;
      scratch = std::make_unique<float[]>(scratch_floats + 16);
      const auto address = reinterpret_cast<std::uintptr_t>(scratch.get());
      aligned = scratch.get() + ((64 - address % 64) % 64) / sizeof(float);
    }
    return aligned;
  }
};

void render_tile_scalar(const PreparedScene& scene, const RenderOptions& options, const TileRect& tile,
                        ScalarScratch& scratch, const ImageView& image) {
  const double inv_spp = 1.0 / options.spp;
  for (int j = tile.y0; j < tile.y1; ++j) {
    for (int i = tile.x0; i < tile.x1; ++i) {
      Rgb sum{0.0, 0.0, 0.0};
      for (int k = 0; k < options.spp; ++k) {
        double sx, sy;
        sample_offset(k, options.spp, sx, sy);
        const Rgb e = scalar_irradiance(scene, sample_position(scene, i, j, sx, sy), scratch);
        for (int c = 0; c < 3; ++c) sum[c] += e[c];
      }
      float* p = image.data + static_cast<std::ptrdiff_t>(j) * image.row_stride + 3 * static_cast<std::ptrdiff_t>(i);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(sum[c] * inv_spp);
    }
  }
}

}  // namespace

const KernelSet* kernels_for(Isa isa) noexcept {
  for (const KernelSet& k : kKernels) {
    if (k.isa == isa) return &k;
  }
  return nullptr;
}

void render_simd(const PreparedScene& scene, const RenderOptions& options, Isa isa, int threads,
                 const ImageView& image) {
  const KernelSet* kernels = kernels_for(isa);
  tbb::enumerable_thread_specific<ThreadState> states;
  for_each_tile(TileGrid{scene.width, scene.height}, threads, [&](const TileRect& tile) {
    ThreadState& state = states.local();
    TileWork& work = state.work;
    if (work.sample_x.size() != static_cast<std::size_t>(options.spp)) {
      work.spp = options.spp;
      work.sample_x.resize(options.spp);
      work.sample_y.resize(options.spp);
      for (int k = 0; k < options.spp; ++k) {
        double sx, sy;
        sample_offset(k, options.spp, sx, sy);
        work.sample_x[k] = static_cast<float>(sx);
        work.sample_y[k] = static_cast<float>(sy);
      }
    }
    if (!build_tile_work(scene, tile, options.culling, work, state.setup)) {
      render_tile_scalar(scene, options, tile, state.scalar, image);
      return;
    }
    float* scratch = state.kernel_scratch(kernel_scratch_floats(work, kernels->lanes));
    kernels->render_tile(work, scratch, state.result);
    for (int j = tile.y0; j < tile.y1; ++j) {
      float* row = image.data + static_cast<std::ptrdiff_t>(j) * image.row_stride;
      const int local_row = (j - tile.y0) * kTileSize;
      for (int i = tile.x0; i < tile.x1; ++i) {
        const int local = local_row + (i - tile.x0);
        for (int c = 0; c < 3; ++c) row[3 * i + c] = state.result.rgb[c][local];
      }
    }
  });
}

}  // namespace par2d::detail
