// The frame driver: renders a prepared scene's frame (or a region of it) into a host
// buffer, tile by tile, with the kernels of kernel_table.hpp or the scalar reference.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "culling/light_reach.hpp"
#include "par2d/isa.hpp"
#include "par2d/render.hpp"
#include "render/frame_counters.hpp"
#include "render/frame_output.hpp"
#include "parallel/scheduler.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

struct BounceFrame;
class LightLayerCache;

// What one frame computes: samples per pixel, culling, and the kernel ISA (Isa::scalar:
// the reference path, pixel by pixel).
struct FrameSettings {
  int spp = 1;
  bool culling = true;
  Isa isa = Isa::scalar;
  bool shaded = false;  // RenderOptions::shaded (docs/contract.md section 6)
  bool sample_needs = false;  // fill FrameStats' sampled counts (one exact pixel per tile)
  BounceTerm bounce = BounceTerm::included;  // RenderOptions::bounce (docs/contract.md section 7)
};

// Watching and stopping a frame (docs/api.md, "Long renders"): tiles are counted as they
// finish, `progress` is called on the thread that called render (which takes part in the
// frame's loop) after each of its tiles and once at the end, and once `cancel` is set or
// `progress` returns false, tiles not yet begun are skipped.
struct FrameControl {
  const ProgressFunction* progress = nullptr;  // null or empty: none
  const std::atomic<bool>* cancel = nullptr;
};

// Renders frames of prepared scenes into host buffers, tile by tile, keeping every
// per-thread buffer from frame to frame: after the first frame at a size (and worker
// count) a frame allocates nothing.
class FrameEngine {
 public:
  FrameEngine();
  ~FrameEngine();
  FrameEngine(FrameEngine&&) noexcept;
  FrameEngine& operator=(FrameEngine&&) noexcept;

  // The pixels of target.region, each tile computed whole and stored straight into the
  // target's format. Tiles and blocks are those of the whole frame, so a region's pixels
  // equal the same pixels of a whole frame bit for bit. `reach` (with culling): per light.
  // `counts`, when given, receives the frame's counts (render/frame_counters.hpp).
  // `dirty`, when given: one flag per kBlockSize block of the whole frame, row by row; only the
  // flagged blocks are computed and stored, the rest of the target is not touched.
  // `layers`, when given (a whole frame with culling and a SIMD ISA): tiles are computed
  // through the light-layer cache (render/layered_tiles.hpp), as its plan allows.
  // `control`, when given: progress and cancellation. Returns false when a cancelled frame
  // skipped tiles (the target then holds part of the frame and `counts` is left as it was).
  bool render(const PreparedScene& scene, const std::vector<LightReach>* reach, const FrameSettings& settings,
              const Scheduler& scheduler, const FrameTarget& target, FrameCounters* counts = nullptr,
              const std::vector<std::uint8_t>* dirty = nullptr, LightLayerCache* layers = nullptr,
              const FrameControl* control = nullptr);

 private:
  struct ThreadState;
  std::vector<ThreadState> states_;
  // One bounce (docs/contract.md section 7): the pieces and their radiances, made each frame of
  // a scene with a reflecting occluder.
  std::unique_ptr<BounceFrame> bounce_;
  std::vector<int> block_list_;  // the blocks of a frame with `dirty` flags, relative to the region's
  SrgbBuckets srgb_;  // the last 8-bit sRGB target's exposure's, rebuilt when it changes
};

}  // namespace par2d::detail
