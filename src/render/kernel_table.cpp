// Kernel lookup (the tables are per architecture: kernel_table_<arch>.cpp) and the SIMD render driver.
#include "render/kernel_table.hpp"

#include <memory>
#include <vector>

#include "render/light_reach.hpp"
#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "render/scalar_tiles.hpp"

namespace par2d::detail {
namespace {

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

}  // namespace

const KernelSet* kernels_for(Isa isa) noexcept {
  const CompiledKernels compiled = compiled_kernels();
  for (std::size_t i = 0; i < compiled.count; ++i) {
    if (compiled.kernels[i].isa == isa) return &compiled.kernels[i];
  }
  return nullptr;
}

void render_simd(const PreparedScene& scene, const RenderOptions& options, Isa isa, int threads,
                 const ImageView& image) {
  const KernelSet* kernels = kernels_for(isa);
  std::vector<ThreadState> states(static_cast<std::size_t>(threads));
  // Each light's reach first (a few proofs per light), so that blocks far from a light it
  // cannot reach skip it before any spatial query.
  std::vector<LightReach> reach;
  if (options.culling) {
    reach.resize(scene.lights.size());
    std::vector<LightReachScratch> reach_scratch(static_cast<std::size_t>(threads));
    for_each_index(static_cast<int>(scene.lights.size()), threads, [&](int l, int worker) {
      reach[static_cast<std::size_t>(l)] =
          compute_light_reach(scene, static_cast<std::size_t>(l), reach_scratch[static_cast<std::size_t>(worker)]);
    });
  }
  for_each_block(scene.width, scene.height, threads, [&](const TileRect& block, int worker) {
    ThreadState& state = states[static_cast<std::size_t>(worker)];
    TileWork& work = state.work;
    gather_block_candidates(scene, block, options.culling ? &reach : nullptr, state.setup);
    for_each_cell(block, kTileSize, [&](const TileRect& tile) {
      if (!build_tile_work(scene, tile, options.spp, options.culling, work, state.setup)) {
        render_rect_scalar(scene, options.spp, tile, state.scalar, image);
        return;
      }
      float* scratch = state.kernel_scratch(kernel_scratch_floats(work, kernels->lanes));
      kernels->render_tile(work, scratch, state.result);
      for (int j = tile.y0; j < tile.y1; ++j) {
        float* row = image.data + static_cast<std::ptrdiff_t>(j) * image.row_stride;
        const float* r = state.result.rgb[0] + (j - tile.y0) * kTileSize - tile.x0;
        const float* g = state.result.rgb[1] + (j - tile.y0) * kTileSize - tile.x0;
        const float* b = state.result.rgb[2] + (j - tile.y0) * kTileSize - tile.x0;
        for (int i = tile.x0; i < tile.x1; ++i) {
          row[3 * i] = r[i];
          row[3 * i + 1] = g[i];
          row[3 * i + 2] = b[i];
        }
      }
    });
  });
}

}  // namespace par2d::detail
