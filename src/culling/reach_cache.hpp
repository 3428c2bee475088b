// Each light's reach (light_reach.hpp) kept from frame to frame: proven again only for the
// lights the World's change events say may have changed it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "culling/light_reach.hpp"
#include "parallel/scheduler.hpp"
#include "world/prepared_scene.hpp"
#include "world/world_changes.hpp"

namespace par2d::detail {

// A light's reach is stale when the light changed, when the frame changed (reach radii are
// in pixels and end at the view's corners), when the view moved on its pixel grid far enough
// to change how many radii are tried (LightReachScratch::farthest_low/high) or when an
// occluder changed inside the box its proofs looked at (LightReachScratch::depends_on);
// nothing else can change it.
class ReachCache final : public WorldObserver {
 public:
  // Proves the reach of every stale light of `scene` (the World this cache observes), in
  // parallel; returns how many were proven. Allocates nothing in steady state.
  std::size_t update(const PreparedScene& scene, const Scheduler& scheduler);
  // Per light of the scene last passed to update.
  const std::vector<LightReach>& reach() const noexcept { return reach_; }

  void lights_reset(std::size_t count) noexcept override;
  void light_added() override;
  void light_changed(std::size_t p) noexcept override;
  void light_erased(std::size_t p) noexcept override;
  void region_changed(const Aabb& box) noexcept override;
  void frame_changed() noexcept override;
  void frame_scrolled() noexcept override;

 private:
  // Set by lights_reset (which may not allocate): the arrays are resized to `reset_count_` and
  // every light proven at the next update; events until then only count lights.
  bool reset_pending_ = false;
  std::size_t reset_count_ = 0;

  // Parallel, per light.
  std::vector<LightReach> reach_;
  std::vector<Aabb> depends_;
  std::vector<std::uint8_t> stale_;
  std::vector<double> farthest_low_, farthest_high_;
  bool scrolled_ = false;  // the view moved on its grid since the last update
  // Scratch per worker, reserved for any light of the scene (LightReachScratch::reserve_for)
  // whenever the scene's occluder count or largest vertex count grows, so that moving lights
  // anywhere allocates nothing.
  std::vector<LightReachScratch> scratch_;
  std::size_t reserved_occluders_ = 0, reserved_vertices_ = 0;
  std::vector<std::uint32_t> stale_list_;
};

}  // namespace par2d::detail
