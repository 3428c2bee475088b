// The World's occluders: adding, updating and removing them (a concave one as its convex
// pieces under one handle), and what a change of one means for the lights' overlaps.
#include "world/world.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include "geometry/aabb.hpp"
#include "geometry/bounce_pieces.hpp"
#include "geometry/polygon_partition.hpp"
#include "lighting/light_emission.hpp"
#include "scene/same_values.hpp"
#include "scene/scene_validate.hpp"
#include "world/occluder_merge.hpp"
#include "world/world_support.hpp"

namespace par2d::detail {

using namespace world_support;

// Occluder k has a new shape (or is new): its overlaps with lights, its separators and the
// reach of lights whose proofs looked where it was or is.
void World::occluder_changed(std::size_t k, const Aabb* old_box) {
  const ConvexShape& occ = scene_.occluders[k];
  const Aabb box = bounds_of(occ);
  const auto index = static_cast<std::uint32_t>(k);
  reserve_overlaps(scene_, nullptr, &occ);
  std::vector<LightOverlap>& spares = scene_.spare_overlaps;
  for (PreparedLight& light : scene_.lights) {
    erase_overlap(light, index, spares);
    if (!boxes_meet(bounds_of(light.shape), box) || !meets_within_contact(light.shape, occ)) continue;
    LightOverlap overlap;
    if (!spares.empty()) {
      overlap = std::move(spares.back());
      spares.pop_back();
    }
    describe_overlap(light.shape, occ, overlap);
    insert_overlap(light, index, std::move(overlap));
  }
  scene_.separators.forget_occluder(k);
  if (observer_) {
    if (old_box) observer_->region_changed(*old_box);
    observer_->region_changed(box);
  }
}

Status World::add_occluder(const Occluder& occluder, OccluderHandle* handle) {
  if (handle == nullptr) return Status(StatusCode::invalid_argument, "add_occluder: handle is null");
  if (auto problem = check_occluder(occluder, std::string())) return refused("add_occluder", *problem);
  const double pieces = bounce_pieces_ + bounce_pieces_of(occluder);
  if (pieces > kMaxBouncePieces) return refused("add_occluder", {"albedo", bounce_pieces_text(pieces)});
  const std::uint32_t slot = new_slot(kOccluder, 0);
  bounce_pieces_ = pieces;
  push_occluder(occluder, slot);
  handle->id = make_handle(slot);
  if (may_join(occluder)) regroup();
  return {};
}

void World::push_occluder(const Occluder& occluder, std::uint32_t slot) {
  if (!needs_partition(occluder.shape)) return push_occluder_entry(occluder, slot);
  // One entry per convex piece: occlusion is a union, and a concave occluder is opaque and
  // dark inside (check_occluder), so its pieces shadow exactly what it does.
  compound_occluders_[slot] = occluder;
  std::string error;
  partition_polygon(std::get<Polygon>(occluder.shape), pieces_, error);  // validated: it exists
  Occluder entry = occluder;
  std::uint32_t last = slot;
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    entry.shape = pieces_[k];
    if (k > 0) last = chain_slot(kOccluder, last, slot);
    push_occluder_entry(entry, k == 0 ? slot : last);
  }
}

void World::push_occluder_entry(const Occluder& occluder, std::uint32_t slot) {
  const std::size_t k = occluder_sources_.size();
  slots_[slot].list = kOccluder;
  slots_[slot].where = static_cast<std::int32_t>(k);
  occluder_sources_.push_back(occluder);
  occluder_slots_.push_back(slot);
  scene_.occluders.emplace_back();
  scene_.occluder_terms.push_back(occluder_terms(occluder));
  update_model_flag(scene_);
  make_convex_shape(occluder.shape, scene_.occluders[k]);
  scale_shape(scene_.occluders[k], factor_);
  scene_.occluder_bvh.insert(bounds_of(scene_.occluders[k]));
  scene_.separators.resize(scene_.lights.size(), k + 1);
  occluder_changed(k, nullptr);
  ++stats_.index_updates;
}

void World::erase_occluder(std::uint32_t slot) {
  erase_chain(slot, &World::erase_occluder_entry, internal_occluders_);
  compound_occluders_.erase(slot);
}

Status World::update_occluder(OccluderHandle handle, const Occluder& occluder) {
  Slot* slot = find(handle.id, true);
  if (!slot) return unknown_handle("occluder", handle.id);
  // The values it holds (already checked): nothing changes, nothing is marked.
  if (same_occluder(user_occluder(static_cast<std::uint32_t>(slot - slots_.data())), occluder)) return {};
  if (auto problem = check_occluder(occluder, std::string())) return refused("occluder " + std::to_string(handle.id), *problem);
  const auto index = static_cast<std::uint32_t>(slot - slots_.data());
  const double pieces = bounce_pieces_ - bounce_pieces_of(user_occluder(index)) + bounce_pieces_of(occluder);
  if (pieces > kMaxBouncePieces) return refused("occluder " + std::to_string(handle.id), {"albedo", bounce_pieces_text(pieces)});
  bounce_pieces_ = pieces;
  // A merged tilemap box: its group is split into its boxes, this one changes, and the rest
  // (with this one, if it still joins) merge again.
  const bool boxes = slots_[index].group != kNoSlot || may_join(user_occluder(index)) || may_join(occluder);
  dissolve_group(index);
  update_entry(index, occluder);
  if (boxes) regroup();
  return {};
}

void World::update_entry(std::uint32_t index, const Occluder& occluder) {
  if (compound_occluders_.count(index) != 0 || needs_partition(occluder.shape)) {
    // A concave occluder's pieces change with it: taken out and put in again.
    erase_occluder(index);
    push_occluder(occluder, index);
    return;
  }
  const auto k = static_cast<std::size_t>(slots_[index].where);
  const Aabb old_box = bounds_of(scene_.occluders[k]);
  occluder_sources_[k] = occluder;
  scene_.occluder_terms[k] = occluder_terms(occluder);
  update_model_flag(scene_);
  make_convex_shape(occluder.shape, scene_.occluders[k]);
  scale_shape(scene_.occluders[k], factor_);
  scene_.occluder_bvh.update(static_cast<std::uint32_t>(k), bounds_of(scene_.occluders[k]));
  occluder_changed(k, &old_box);
  ++stats_.index_updates;
}

Status World::remove_occluder(OccluderHandle handle) {
  Slot* slot = find(handle.id, true);
  if (!slot) return unknown_handle("occluder", handle.id);
  const auto index = static_cast<std::uint32_t>(slot - slots_.data());
  bounce_pieces_ -= bounce_pieces_of(user_occluder(index));
  const bool box = slots_[index].group != kNoSlot || may_join(user_occluder(index));
  dissolve_group(index);
  erase_occluder(index);
  release_slot(&slots_[index]);
  if (box) regroup();
  return {};
}

void World::erase_occluder_entry(std::size_t k) {
  const std::size_t m = occluder_sources_.size() - 1;
  if (observer_) observer_->region_changed(bounds_of(scene_.occluders[k]));
  // Occluder m takes index k everywhere.
  for (PreparedLight& light : scene_.lights) {
    erase_overlap(light, static_cast<std::uint32_t>(k), scene_.spare_overlaps);
    if (k == m) continue;
    auto& list = light.overlapping_occluders;
    const auto it = std::lower_bound(list.begin(), list.end(), static_cast<std::uint32_t>(m));
    if (it == list.end() || *it != m) continue;
    LightOverlap overlap = std::move(light.overlaps[static_cast<std::size_t>(it - list.begin())]);
    erase_overlap(light, static_cast<std::uint32_t>(m), scene_.spare_overlaps);
    insert_overlap(light, static_cast<std::uint32_t>(k), std::move(overlap));
  }
  scene_.occluder_bvh.remove(static_cast<std::uint32_t>(k));
  if (k != m) {
    std::swap(occluder_sources_[k], occluder_sources_[m]);
    occluder_slots_[k] = occluder_slots_[m];
    std::swap(scene_.occluders[k], scene_.occluders[m]);
    std::swap(scene_.occluder_terms[k], scene_.occluder_terms[m]);
    scene_.separators.move_occluder(m, k);
    slots_[occluder_slots_[k]].where = static_cast<std::int32_t>(k);
    if (observer_) observer_->occluder_renumbered(bounds_of(scene_.occluders[k]));
  }
  occluder_sources_.pop_back();
  occluder_slots_.pop_back();
  scene_.occluders.pop_back();
  scene_.occluder_terms.pop_back();
  update_model_flag(scene_);
  scene_.separators.forget_occluder(m);
  scene_.separators.resize(scene_.lights.size(), m);
  ++stats_.index_updates;
}

}  // namespace par2d::detail
