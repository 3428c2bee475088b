// The light-layer cache's bookkeeping: see light_layers.hpp.
#include "render/light_layers.hpp"

#include <algorithm>

namespace par2d::detail {

void LightLayer::clear(std::uint32_t l) noexcept {
  light = l;
  std::fill(std::begin(offset), std::end(offset), -1);
  mono = 0;
  data.clear();
}

void LightLayer::store(int t, const float* const rgb[3], int planes) {
  const std::size_t at = data.size(), need = at + static_cast<std::size_t>(planes) * kTilePixels;
  if (need > data.capacity()) data.reserve(std::max(need, std::min(2 * data.capacity(), kMaxLayerFloats)));
  for (int c = 0; c < planes; ++c) data.insert(data.end(), rgb[c], rgb[c] + kTilePixels);
  offset[t] = static_cast<std::int32_t>(at);
  if (planes == 1) mono |= 1u << t;
}

void LightLayerCache::set_budget(std::size_t bytes) {
  budget_ = bytes;
  clear();
}

void LightLayerCache::clear() noexcept {
  for (std::vector<LightLayer>& b : blocks_) b.clear();
  fill_.assign(fill_.size(), 0);
  bytes_ = 0;
}

void LightLayerCache::set_block_count(std::size_t blocks) {
  if (blocks_.size() == blocks) return;
  blocks_.clear();
  blocks_.resize(blocks);
  fill_.assign(blocks, 0);
  bytes_ = 0;
}

void LightLayerCache::move_blocks(const BlockGrid& from, const BlockGrid& to, std::int64_t dbx, std::int64_t dby) {
  // Into the spare list (its storage kept from move to move), then swapped in.
  std::vector<std::vector<LightLayer>>& moved = spare_;
  moved.clear();
  moved.resize(to.count());
  if (blocks_.size() == from.count()) {
    for (int by = 0; by < to.rows; ++by) {
      for (int bx = 0; bx < to.columns; ++bx) {
        const std::int64_t ox = bx + dbx, oy = by + dby;
        if (ox < 0 || oy < 0 || ox >= from.columns || oy >= from.rows) continue;
        moved[static_cast<std::size_t>(by) * static_cast<std::size_t>(to.columns) + static_cast<std::size_t>(bx)] =
            std::move(blocks_[static_cast<std::size_t>(oy) * static_cast<std::size_t>(from.columns) +
                              static_cast<std::size_t>(ox)]);
      }
    }
  }
  blocks_.swap(moved);
  spare_.clear();  // the layers of blocks left behind: dropped (the list's storage stays)
  fill_.assign(blocks_.size(), 0);
  recount();
}

void LightLayerCache::drop_light(std::size_t light) noexcept {
  for (std::size_t b = 0; b < blocks_.size(); ++b) drop(b, light);
}

void LightLayerCache::drop_lights_from(std::size_t count) noexcept {
  for (std::vector<LightLayer>& layers : blocks_)
    layers.erase(std::remove_if(layers.begin(), layers.end(), [&](const LightLayer& y) { return y.light >= count; }),
                 layers.end());
  recount();
}

void LightLayerCache::erase_light(std::size_t light) noexcept {
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    drop(b, light);
    for (LightLayer& y : blocks_[b])
      if (y.light > light) --y.light;
  }
}

void LightLayerCache::drop_block(std::size_t block) noexcept {
  if (block >= blocks_.size()) return;
  for (const LightLayer& y : blocks_[block]) bytes_ -= y.bytes();
  blocks_[block].clear();
}

void LightLayerCache::drop(std::size_t block, std::size_t light) noexcept {
  if (block >= blocks_.size()) return;
  std::vector<LightLayer>& layers = blocks_[block];
  for (std::size_t i = 0; i < layers.size(); ++i) {
    if (layers[i].light != light) continue;
    bytes_ -= layers[i].bytes();
    layers.erase(layers.begin() + static_cast<std::ptrdiff_t>(i));
    return;
  }
}

bool LightLayerCache::has(std::size_t block, std::size_t light) const noexcept {
  if (block >= blocks_.size()) return false;
  for (const LightLayer& y : blocks_[block])
    if (y.light == light) return true;
  return false;
}

void LightLayerCache::plan_frame(const std::vector<std::uint8_t>* dirty, const std::vector<std::uint32_t>& first,
                                 const std::vector<std::uint32_t>& lights, bool directional, int planes) {
  planes_ = planes;
  first_ = first;
  lights_ = lights;
  fill_.assign(blocks_.size(), 0);
  whole_.assign(blocks_.size(), 0);
  std::size_t planned = bytes_;
  for (std::size_t b = 0; b < blocks_.size() && b + 1 < first.size(); ++b) {
    if (dirty && (*dirty)[b] != kBlockWhole) continue;
    std::size_t missing = 0;
    for (std::uint32_t i = first[b]; i < first[b + 1]; ++i) missing += has(b, lights[i]) ? 0 : 1;
    if (missing == 0 && !directional) {
      whole_[b] = 1;
      continue;
    }
    const std::size_t need = missing * max_layer_bytes(planes);
    if (need > budget_ || planned > budget_ - need) continue;
    planned += need;
    fill_[b] = 1;
  }
}

void LightLayerCache::finish_block(std::size_t block) {
  std::vector<LightLayer>& layers = blocks_[block];
  if (block + 1 < first_.size()) {
    for (std::uint32_t i = first_[block]; i < first_[block + 1]; ++i) {
      if (has(block, lights_[i])) continue;
      layers.emplace_back();
      layers.back().clear(lights_[i]);
    }
  }
  for (LightLayer& layer : layers)
    if (layer.data.capacity() > layer.data.size()) layer.data.shrink_to_fit();
  std::sort(layers.begin(), layers.end(), [](const LightLayer& a, const LightLayer& b) { return a.light < b.light; });
}

void LightLayerCache::finish_frame() noexcept { recount(); }

void LightLayerCache::recount() noexcept {
  bytes_ = 0;
  for (const std::vector<LightLayer>& layers : blocks_)
    for (const LightLayer& y : layers) bytes_ += y.bytes();
}

}  // namespace par2d::detail
