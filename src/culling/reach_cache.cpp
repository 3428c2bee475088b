// The light reach cache: change events mark lights stale, update proves them again.
#include "culling/reach_cache.hpp"

#include <algorithm>
#include <utility>

namespace par2d::detail {

void ReachCache::lights_reset(std::size_t count) noexcept {
  reset_pending_ = true;
  reset_count_ = count;
}

void ReachCache::light_added() {
  if (reset_pending_) {
    ++reset_count_;
    return;
  }
  reach_.emplace_back();
  depends_.push_back(kEmptyBox);
  stale_.push_back(1);
  farthest_low_.push_back(0.0);
  farthest_high_.push_back(0.0);
}

void ReachCache::light_changed(std::size_t p) noexcept {
  if (!reset_pending_) stale_[p] = 1;
}

void ReachCache::light_erased(std::size_t p) noexcept {
  if (reset_pending_) {
    --reset_count_;
    return;
  }
  const auto at = static_cast<std::ptrdiff_t>(p);
  reach_.erase(reach_.begin() + at);
  depends_.erase(depends_.begin() + at);
  stale_.erase(stale_.begin() + at);
  farthest_low_.erase(farthest_low_.begin() + at);
  farthest_high_.erase(farthest_high_.begin() + at);
}

void ReachCache::region_changed(const Aabb& box) noexcept {
  if (reset_pending_) return;
  for (std::size_t p = 0; p < stale_.size(); ++p) {
    if (!stale_[p] && boxes_meet(depends_[p], box)) stale_[p] = 1;
  }
}

void ReachCache::frame_changed() noexcept { std::fill(stale_.begin(), stale_.end(), 1); }

void ReachCache::frame_scrolled() noexcept { scrolled_ = true; }

std::size_t ReachCache::update(const PreparedScene& scene, const Scheduler& scheduler) {
  if (reset_pending_) {
    reach_.assign(reset_count_, LightReach{});
    depends_.assign(reset_count_, kEmptyBox);
    stale_.assign(reset_count_, 1);
    farthest_low_.assign(reset_count_, 0.0);
    farthest_high_.assign(reset_count_, 0.0);
    reset_pending_ = false;
  }
  if (scrolled_) {
    // The radii end at the farthest view corner: a proof stands while their number does.
    for (std::size_t p = 0; p < stale_.size(); ++p) {
      if (stale_[p]) continue;
      const double farthest = reach_farthest(scene, p, reach_[p].center, reach_[p].radius);
      if (!(farthest_low_[p] <= farthest && farthest < farthest_high_[p])) stale_[p] = 1;
    }
    scrolled_ = false;
  }
  stale_list_.clear();
  for (std::size_t p = 0; p < stale_.size(); ++p) {
    if (stale_[p]) stale_list_.push_back(static_cast<std::uint32_t>(p));
  }
  if (stale_list_.empty()) return 0;
  std::size_t max_vertices = 0;
  for (const PreparedLight& l : scene.lights) max_vertices = std::max(max_vertices, l.shape.vertices.size());
  for (const ConvexShape& o : scene.occluders) max_vertices = std::max(max_vertices, o.vertices.size());
  const auto workers = static_cast<std::size_t>(scheduler.workers());
  if (scratch_.size() < workers || reserved_occluders_ < scene.occluders.size() || reserved_vertices_ < max_vertices) {
    reserved_occluders_ = std::max(reserved_occluders_, scene.occluders.size());
    reserved_vertices_ = std::max(reserved_vertices_, max_vertices);
    if (scratch_.size() < workers) scratch_.resize(workers);
    for (LightReachScratch& s : scratch_) s.reserve_for(reserved_occluders_, reserved_vertices_);
  }
  scheduler.for_each_index(static_cast<int>(stale_list_.size()), [&](int i, int worker) {
    const std::uint32_t p = stale_list_[static_cast<std::size_t>(i)];
    LightReachScratch& scratch = scratch_[static_cast<std::size_t>(worker)];
    reach_[p] = compute_light_reach(scene, p, scratch);
    depends_[p] = scratch.depends_on;
    farthest_low_[p] = scratch.farthest_low;
    farthest_high_[p] = scratch.farthest_high;
  });
  std::fill(stale_.begin(), stale_.end(), 0);
  return stale_list_.size();
}

}  // namespace par2d::detail
