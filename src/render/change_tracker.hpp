// Frames that cost what changed: which blocks of the frame a Renderer must compute again,
// from the World's change events and what the last frame's lights reached.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "culling/light_reach.hpp"
#include "par2d/isa.hpp"
#include "par2d/types.hpp"
#include "render/frame_plan.hpp"
#include "render/light_layers.hpp"
#include "world/prepared_scene.hpp"
#include "world/world_changes.hpp"

namespace par2d::detail {

// Everything outside the shapes a block's pixels depend on; any difference: a full frame.
// The view offset on the pixel grid is not part of it: a frame at another offset keeps the
// pixels both show (ChangeTracker::plan).
struct FrameKey {
  int width = 0, height = 0;
  View view{};  // the pixel grid's (PreparedScene::view)
  std::int64_t grid_x = 0, grid_y = 0;  // the offset on it (compared by plan, not ==)
  double scale = 0.0;
  // What the scene's extent decides for every pixel: kernel coordinates clipped near the tile
  // (TileFrame::far) and trusted culling; the extent itself only where directional lights
  // sweep it (0 otherwise).
  bool far = false, trusted = false;
  double extent = 0.0;
  bool model = false, bounce = false;
  bool scrolls = false;  // a frame at another offset may keep pixels (no bounce, directional light or normal map)
  bool ring = false;     // BufferLayout::ring
  const void* data = nullptr;
  PixelFormat format = PixelFormat::rgb_f32;
  std::ptrdiff_t row_stride = 0;
  double exposure = 0.0;
  FrameSettings settings{};

  bool operator==(const FrameKey& o) const noexcept;
};

// Observes a World (forwarding every event to `next`, the reach cache) and decides, at each
// whole-frame render, which 64x64 blocks must be computed again. Exact-conservative: a block
// is skipped only when nothing its pixels are computed from changed:
//  - the frame key (size, view, coordinate scale, extent, the model flag, the host buffer,
//    the output format and exposure, spp, ISA, culling, shading), the scene-wide terms and a
//    reset of the world: every block;
//  - without culling (the scalar reference, culling off, untrusted culling) or with one
//    bounce, every light sees every pixel: any change is every block;
//  - with culling, light l takes part in block B only where its reach does not hide B and
//    B is within its range: the box I_l (reach's farthest distance, cut by the range's box).
//    A light added, changed, re-emitting, renumbered or erased, or whose reach changed,
//    dirties the blocks meeting its old and new I_l. An occluder appearing, moving,
//    disappearing or renumbered inside box R dirties the blocks meeting R and, for each
//    light whose old or new Q_l meets R, the blocks meeting its old and new I_l; Q_l holds
//    every hull of a block meeting I_l with the light's shape (I_l grown by a block, and the
//    shape's box): the only place a block's candidate query looks.
// Directional lights are unbounded: with any, an occluder change is every block.
// With a light-layer cache (set_layers, budget above 0) and culling, plan also drops the layers
// those rules make stale (light_layers.hpp: an emission change dirties blocks but keeps them)
// and decides which dirty blocks may store new ones.
class ChangeTracker final : public WorldObserver {
 public:
  // The observer events are passed on to (the reach cache); set before the World observes this.
  void forward_to(WorldObserver* next) noexcept { next_ = next; }
  // The next whole frame computes every block.
  void force_full() noexcept { full_ = true; }
  // The light-layer cache plan keeps (may be null).
  void set_layers(LightLayerCache* layers) noexcept { layers_ = layers; }
  // Whether the frame last planned may use the layers (a budget, culling, no bounce).
  bool layered() const noexcept { return layered_; }

  // For a whole-frame render of `scene` with `key`: returns the mask of blocks to compute
  // (frame_blocks, row by row; kBlockWhole or kBlockUncovered), or nullptr for every block;
  // fills `rects` with the rectangles those blocks cover, merged. `reach`: the reach the
  // frame culls with (nullptr without culling). Then records this frame as the one the host's
  // buffer holds.
  // A frame whose view moved by whole pixels on the same grid (key equal but for the offset,
  // key.scrolls, less than a frame each way) keeps what both frames show: shift() then says
  // how far the buffer's pixels move, and uncovered() what the move shows for the first time.
  const std::vector<std::uint8_t>* plan(const PreparedScene& scene, const std::vector<LightReach>* reach,
                                        const FrameKey& key, std::vector<PixelRect>& rects);
  // After plan: new pixel (i, j) is the last frame's pixel (i + dx, j + dy) (0, 0: no move).
  int shift_x() const noexcept { return shift_x_; }
  int shift_y() const noexcept { return shift_y_; }
  const UncoveredPixels& uncovered() const noexcept { return uncovered_; }

  void lights_reset(std::size_t count) noexcept override;
  void light_added() override;
  void light_changed(std::size_t p) noexcept override;
  void light_erased(std::size_t p) noexcept override;
  void region_changed(const Aabb& box) noexcept override;
  void frame_changed() noexcept override;
  void frame_scrolled() noexcept override;
  void light_emission_changed(std::size_t p) noexcept override;
  void occluder_renumbered(const Aabb& box) noexcept override;
  void terms_changed() noexcept override;

 private:
  static constexpr std::size_t kMaxRegions = 64;  // more changes in a frame: every block

  // What decides whether a light takes part in a block, as of one frame: cull_block skips the
  // light where `reach` hides the block or the block is beyond `range` of `bounds`.
  struct Footprint {
    Aabb influence = kEmptyBox;  // I_l (empty: no light)
    Aabb query = kEmptyBox;      // Q_l
    LightReach reach;
    Aabb bounds = kEmptyBox;     // the shape's box
    double range = 0.0;          // infinity: none
    // Whether the light takes part in the block with box `box` (the frame's model flag given).
    bool takes_part(const Aabb& box, bool model) const noexcept;
  };

  void region(const Aabb& box) noexcept;
  // Marks the blocks meeting `box` (and drops their layers).
  void mark(const PreparedScene& scene, const Aabb& box);
  // For a move by (dx, dy) pixels: the uncovered bands, their blocks marked kBlockUncovered
  // (their layers, which lack those tiles, dropped) and the layers of the blocks both frames
  // hold renumbered.
  void plan_scroll(const PreparedScene& scene, int dx, int dy);
  // Marks the blocks where `f` takes part and (when given) whose box joined with the light's
  // meets `region`: where an occluder in `region` may be one of the light's candidates; there,
  // light `light`'s layers are dropped.
  void mark_light(const PreparedScene& scene, const Footprint& f, const Aabb* region, std::size_t light);
  // Per rendered block, the lights that take part in it: the layer cache's plan_frame.
  void plan_layer_fills(const PreparedScene& scene, bool full);

  // changed_ flags: the light's geometry, terms or number changed (its layers are stale), or
  // only its emission (they stay).
  static constexpr std::uint8_t kChanged = 1, kEmission = 2;

  WorldObserver* next_ = nullptr;
  LightLayerCache* layers_ = nullptr;
  bool layered_ = false;
  std::vector<std::uint32_t> part_first_, part_lights_;  // per block, the lights taking part
  bool full_ = true;  // every block at the next frame
  bool any_ = false;  // some change since the last frame
  bool have_key_ = false;
  FrameKey key_{};
  // Per light, as of the last frame (kept parallel to PreparedScene::lights by the events).
  std::vector<Footprint> old_;
  std::vector<std::uint8_t> changed_;
  // Erased lights' footprints and occluder regions since the last frame.
  std::vector<Footprint> erased_;
  std::vector<Aabb> regions_;
  std::vector<std::uint8_t> mask_;
  std::vector<Aabb> block_boxes_;  // each block's box as cull_block sees it
  double pixel_ = 0.0;             // a pixel's larger side, prepared units
  std::vector<Footprint> new_;
  int shift_x_ = 0, shift_y_ = 0;
  UncoveredPixels uncovered_;
};

}  // namespace par2d::detail
