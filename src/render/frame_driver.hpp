// The frame driver: runs a frame's plan (render/frame_plan.hpp) into a host buffer, block by
// block, each block's tiles by its strategy.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "par2d/render.hpp"
#include "render/frame_counters.hpp"
#include "render/frame_output.hpp"
#include "render/frame_plan.hpp"
#include "parallel/scheduler.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

struct BounceFrame;
struct BounceNodes;
struct LightReach;
struct FrameLane;
struct FrameRun;

// Watching and stopping a frame (docs/api.md, "Long renders"): tiles are counted as they
// finish, `progress` is called on the thread that called render (which takes part in the
// frame's loop) after each of its tiles and once at the end, and once `cancel` is set or
// `progress` returns false, tiles not yet begun are skipped.
struct FrameControl {
  const ProgressFunction* progress = nullptr;  // null or empty: none
  const std::atomic<bool>* cancel = nullptr;
};

// Runs frame plans of prepared scenes into host buffers, tile by tile, keeping every
// per-lane buffer from frame to frame: after the first frame at a size (and worker count) a
// frame allocates nothing. It decides nothing about what a frame computes: the plan does.
class FrameEngine {
 public:
  FrameEngine();
  ~FrameEngine();
  FrameEngine(FrameEngine&&) noexcept;
  FrameEngine& operator=(FrameEngine&&) noexcept;

  // Runs `plan` (made by plan_frame for `scene` and target.region): the pixels of its blocks
  // within the region, each tile computed whole by its block's strategy and stored straight
  // into the target's format; the rest of the target is not touched. Tiles and blocks are
  // those of the whole frame, so a region's pixels equal the same pixels of a whole frame bit
  // for bit. `counts`, when given, receives the frame's counts (render/frame_counters.hpp).
  // `control`, when given: progress and cancellation. Returns false when a cancelled frame
  // skipped tiles (the target then holds part of the frame and `counts` is left as it was).
  bool run(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler, const FrameTarget& target,
           FrameCounters* counts = nullptr, const FrameControl* control = nullptr);

 private:
  // The frame's stages, in the order run calls them.
  int reserve_lanes(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler);
  VectorTileStores stores_for(const FramePlan& plan, const FrameTarget& target);
  void run_bounce_stage(const PreparedScene& scene, const Scheduler& scheduler, int lanes, bool cull,
                        const LightReach* reach);
  void run_bounce_nodes(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler, int lanes);
  void run_lanes(const FrameRun& run, const Scheduler& scheduler, int lanes);
  FrameCounters sum_counters(const FramePlan& plan, int lanes) const;

  std::vector<FrameLane> lanes_;  // one per worker, each with its own buffers; blocks are dealt to them as they finish
  // One bounce (docs/contract.md section 7): the pieces and their radiances, made each frame of
  // a scene with a reflecting occluder.
  std::unique_ptr<BounceFrame> bounce_;
  // The coarse bounce's nodes (a step above 1), computed after the radiances, before the tiles;
  // what computing them counted, added to the frame's counts.
  std::unique_ptr<BounceNodes> bounce_nodes_;
  FrameCounters node_counts_;
  SrgbBuckets srgb_;  // the last 8-bit sRGB target's exposure's, rebuilt when it changes
};

}  // namespace par2d::detail
