// Planning a frame: which blocks it computes, how, and which stages run around them.
#include "render/frame_plan.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/kernel_table.hpp"
#include "render/light_layers.hpp"

namespace par2d::detail {

TileRect uncovered_part(const TileRect& block, const UncoveredPixels& uncovered) noexcept {
  // Both bands meet a block at the frame's corner: their box.
  TileRect part{block.x1, block.y1, block.x0, block.y0};
  for (const TileRect& band : {uncovered.columns, uncovered.rows}) {
    const TileRect cut{std::max(band.x0, block.x0), std::max(band.y0, block.y0), std::min(band.x1, block.x1),
                       std::min(band.y1, block.y1)};
    if (cut.x0 >= cut.x1 || cut.y0 >= cut.y1) continue;
    part = {std::min(part.x0, cut.x0), std::min(part.y0, cut.y0), std::max(part.x1, cut.x1), std::max(part.y1, cut.y1)};
  }
  return part;
}

void plan_frame(const PreparedScene& scene, const FrameSettings& settings, const TileRect& region,
                const std::vector<LightReach>* reach, const std::vector<std::uint8_t>* dirty, LightLayerCache* layers,
                FramePlan& plan, const UncoveredPixels* uncovered) {
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
  const BlockGrid grid = frame_blocks(scene);
  const int bx0 = grid.column_of(region.x0), bx1 = grid.column_of(region.x1 - 1) + 1;
  const int by0 = grid.row_of(region.y0), by1 = grid.row_of(region.y1 - 1) + 1;
  plan.blocks.clear();
  plan.blocks.reserve(static_cast<std::size_t>(bx1 - bx0) * static_cast<std::size_t>(by1 - by0));
  plan.tiles = 0;
  for (int by = by0; by < by1; ++by) {
    for (int bx = bx0; bx < bx1; ++bx) {
      const std::size_t index = static_cast<std::size_t>(by) * static_cast<std::size_t>(grid.columns) +
                                static_cast<std::size_t>(bx);
      const std::uint8_t mark = dirty ? (*dirty)[index] : kBlockWhole;
      if (mark == kBlockClean) continue;
      PlannedBlock block;
      block.rect = grid.block(bx, by);
      block.part = block.rect;
      block.index = static_cast<std::uint32_t>(index);
      block.strategy = strategy;
      if (mark == kBlockUncovered && uncovered) {
        const TileRect part = uncovered_part(block.rect, *uncovered);
        if (part.x0 >= part.x1 || part.y0 >= part.y1) continue;
        block.part = part;
        if (strategy == BlockStrategy::layered) block.strategy = BlockStrategy::kernel;
      } else if (layers) {
        if (layers->recombine_only(index)) {
          block.strategy = BlockStrategy::recombine;
        } else {
          block.fill_layers = layers->may_fill(index);
        }
      }
      // The block's tiles that meet its part and the region.
      const int x0 = std::max(block.part.x0, region.x0), x1 = std::min(block.part.x1, region.x1);
      const int y0 = std::max(block.part.y0, region.y0), y1 = std::min(block.part.y1, region.y1);
      if (x0 >= x1 || y0 >= y1) continue;
      plan.blocks.push_back(block);
      const auto tile_of = [](int p, int origin) { return (p - origin) / kTileSize; };
      plan.tiles += static_cast<std::uint64_t>(tile_of(x1 - 1, block.rect.x0) - tile_of(x0, block.rect.x0) + 1) *
                    static_cast<std::uint64_t>(tile_of(y1 - 1, block.rect.y0) - tile_of(y0, block.rect.y0) + 1);
    }
  }
}

}  // namespace par2d::detail
