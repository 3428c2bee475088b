// Cached light layers (opt-in, Renderer::set_light_layer_budget): per (block, light), the
// light's share of each of the block's tiles before its emission is applied, so that a frame
// in which a light only flickers (or changes colour) recombines the block from its layers
// instead of computing every light's visibility again.
//
// Why it is exact enough: a tile's irradiance is ambient + sum over its lights of emission x
// share, and a light's share (visible measure, cone, range window, transmittance, normals)
// depends on the light's geometry, its occluders and the pixel, never on any emission. A layer
// is the kernel's result for the tile with that light alone at unit emission; recombining
// multiplies it by the light's emission and adds, in float, in the order the kernel would.
// What differs from the kernel is float rounding (a product rounded once more per light), far
// inside 1e-6 of the brightest emission (docs/api.md states the bound; the tests check it).
//
// Who drops a layer: the change tracker (render/change_tracker.hpp), with the same rules that
// dirty blocks: a light whose geometry, reach or number changed loses every layer; an occluder
// change loses the layers of the blocks it meets and of the (block, light) pairs whose
// candidate query it meets; a new frame key, terms or world loses all. An emission change
// dirties the light's blocks but keeps its layers: that is what they are for.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/tiling.hpp"

namespace par2d::detail {

inline constexpr int kBlockTileCount = kBlockTiles * kBlockTiles;
// The most one layer holds: three planes for every tile of its block.
inline constexpr std::size_t kMaxLayerFloats = static_cast<std::size_t>(kBlockTileCount) * 3 * kTilePixels;

// One light's share of one block's tiles.
struct LightLayer {
  std::uint32_t light = 0;  // index into PreparedScene::lights
  // Per tile of the block (row by row): where its planes start in `data`, or -1 (not stored:
  // the light was not among the tile's lights when the layer was filled).
  std::int32_t offset[kBlockTileCount];
  // Bit t: tile t holds one plane, the same for all three channels (no coloured transmittance
  // in front of the light there), else three.
  std::uint32_t mono = 0;
  std::vector<float> data;

  LightLayer() { clear(0); }
  // Empty (every offset -1): the light takes part in the block but reaches none of its tiles.
  void clear(std::uint32_t l) noexcept;
  // Stores tile `t`'s planes (`planes` of them, kTilePixels floats each, from `rgb`) within the
  // capacity the plan reserved (LightLayerCache::layer_floats), growing only past it.
  void store(int t, const float* const rgb[3], int planes);
  std::size_t bytes() const noexcept { return sizeof(LightLayer) + data.capacity() * sizeof(float); }
};

// The most one layer holds, its bookkeeping included: `planes` planes (1, or 3 where coloured
// transmittance can tint a light's share) for every tile of its block.
constexpr std::size_t max_layer_bytes(int planes) noexcept {
  return sizeof(LightLayer) + static_cast<std::size_t>(kBlockTileCount) * static_cast<std::size_t>(planes) *
                                  kTilePixels * sizeof(float);
}

class LightLayerCache {
 public:
  // At most `bytes` of layers (0: no cache). Drops every layer.
  void set_budget(std::size_t bytes);
  std::size_t budget() const noexcept { return budget_; }
  // Bytes the layers hold now (as of the last finish_frame or drop).
  std::size_t bytes() const noexcept { return bytes_; }

  // Drops, called by the change tracker while it plans a frame.
  void clear() noexcept;                            // every layer
  void set_block_count(std::size_t blocks);         // a frame of another size: every layer
  // A view moved on its pixel grid: the layers of the blocks both grids hold follow them (new
  // block (bx, by) is `from`'s (bx + dbx, by + dby)); the others are dropped.
  void move_blocks(const BlockGrid& from, const BlockGrid& to, std::int64_t dbx, std::int64_t dby);
  void drop_light(std::size_t light) noexcept;      // light `light`'s layers, in every block
  void drop_lights_from(std::size_t count) noexcept;  // layers of lights numbered `count` or more
  // Light `light` was erased: its layers dropped, those of the lights above renumbered one lower.
  void erase_light(std::size_t light) noexcept;
  void drop_block(std::size_t block) noexcept;      // every layer of the block
  void drop(std::size_t block, std::size_t light) noexcept;
  bool has(std::size_t block, std::size_t light) const noexcept;

  // The plan of a frame, made by the change tracker before it (so that the image does not
  // depend on which thread reaches a block first): per block, the lights that take part in
  // it (`first[b]` .. `first[b + 1]` of `lights`, in number order; blocks not rendered: none)
  // and how many of them have no layer there. In block order, each block rendered whole
  // (`dirty` null: every block; else those marked kBlockWhole) whose missing layers, at max_layer_bytes(planes) each, fit in what
  // the budget leaves may store them; a block whose lights all have layers (and a scene
  // without directional lights, `directional`) is recombined from them alone, with no
  // culling and no kernel. `planes`: 3 when an occluder's transmittance differs between
  // channels (a light's share may then differ per channel), else 1.
  void plan_frame(const std::vector<std::uint8_t>* dirty, const std::vector<std::uint32_t>& first,
                  const std::vector<std::uint32_t>& lights, bool directional, int planes);
  // The floats a new layer reserves this frame (its planes for every tile of the block).
  std::size_t layer_floats() const noexcept {
    return static_cast<std::size_t>(kBlockTileCount) * static_cast<std::size_t>(planes_) * kTilePixels;
  }
  bool may_fill(std::size_t block) const noexcept { return block < fill_.size() && fill_[block] != 0; }
  bool recombine_only(std::size_t block) const noexcept { return block < whole_.size() && whole_[block] != 0; }
  // After a block rendered with may_fill: an empty layer for each light that takes part in it
  // but reached none of its tiles (so that the next frame knows every light is accounted
  // for), the layers' unused reserve given back, and the layers in light order (the order
  // tiles sum their lights in).
  void finish_block(std::size_t block);

  // The layers of `block`: only the thread rendering the block touches them during a frame.
  std::vector<LightLayer>& block(std::size_t b) noexcept { return blocks_[b]; }
  // After a frame: counts what the layers hold.
  void finish_frame() noexcept;

 private:
  void recount() noexcept;

  std::size_t budget_ = 0;
  std::size_t bytes_ = 0;
  std::vector<std::vector<LightLayer>> blocks_, spare_;
  std::vector<std::uint8_t> fill_, whole_;
  std::vector<std::uint32_t> first_, lights_;  // the plan's lists
  int planes_ = 3;
};

}  // namespace par2d::detail
