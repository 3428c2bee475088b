// Planning a frame: which blocks it computes, how, and which stages run around them.
#include "render/frame_plan.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/kernel_table.hpp"
#include "render/light_layers.hpp"

namespace par2d::detail {

void plan_frame(const PreparedScene& scene, const FrameSettings& settings, const TileRect& region,
                const std::vector<LightReach>* reach, const std::vector<std::uint8_t>* dirty, LightLayerCache* layers,
                FramePlan& plan) {
  plan.region = region;
  plan.spp = settings.spp;
  plan.shaded = settings.shaded;
  plan.sample_needs = settings.sample_needs;
  plan.kernels = kernels_for(settings.isa);
  plan.cull_reach = settings.culling ? reach : nullptr;
  // RenderOptions::bounce: the bounce term where the scene has one and the options want it;
  // the direct light (kernel or reference, with the ambient) unless only the bounce is asked.
  plan.bounce.run = scene.bounce && settings.bounce != BounceTerm::excluded;
  plan.bounce.cull = settings.culling && plan.kernels != nullptr;
  const bool direct = settings.bounce != BounceTerm::only;
  // Layers hold what a kernel computes: the scalar reference computes every light itself, and
  // a frame of the bounce term alone computes no light.
  if (!plan.kernels || !direct) layers = nullptr;
  plan.layers = layers;
  BlockStrategy strategy = BlockStrategy::kernel;
  if (!direct) {
    strategy = BlockStrategy::no_direct;
  } else if (!plan.kernels) {
    strategy = BlockStrategy::scalar_reference;
  } else if (layers) {
    strategy = BlockStrategy::layered;
  }

  // The blocks of the whole frame that meet the region, row by row.
  const int bx0 = region.x0 / kBlockSize, bx1 = (region.x1 - 1) / kBlockSize + 1;
  const int by0 = region.y0 / kBlockSize, by1 = (region.y1 - 1) / kBlockSize + 1;
  const int frame_columns = (scene.width + kBlockSize - 1) / kBlockSize;
  plan.blocks.clear();
  plan.blocks.reserve(static_cast<std::size_t>(bx1 - bx0) * static_cast<std::size_t>(by1 - by0));
  plan.tiles = 0;
  for (int by = by0; by < by1; ++by) {
    for (int bx = bx0; bx < bx1; ++bx) {
      const std::size_t index = static_cast<std::size_t>(by) * static_cast<std::size_t>(frame_columns) +
                                static_cast<std::size_t>(bx);
      if (dirty && !(*dirty)[index]) continue;
      PlannedBlock block;
      block.rect = TileRect{bx * kBlockSize, by * kBlockSize, std::min((bx + 1) * kBlockSize, scene.width),
                            std::min((by + 1) * kBlockSize, scene.height)};
      block.index = static_cast<std::uint32_t>(index);
      block.strategy = strategy;
      if (layers) {
        if (layers->recombine_only(index)) {
          block.strategy = BlockStrategy::recombine;
        } else {
          block.fill_layers = layers->may_fill(index);
        }
      }
      plan.blocks.push_back(block);
      // The block's tiles that meet the region.
      const int x0 = std::max(block.rect.x0, region.x0), x1 = std::min(block.rect.x1, region.x1);
      const int y0 = std::max(block.rect.y0, region.y0), y1 = std::min(block.rect.y1, region.y1);
      plan.tiles += static_cast<std::uint64_t>((x1 - 1) / kTileSize - x0 / kTileSize + 1) *
                    static_cast<std::uint64_t>((y1 - 1) / kTileSize - y0 / kTileSize + 1);
    }
  }
}

}  // namespace par2d::detail
