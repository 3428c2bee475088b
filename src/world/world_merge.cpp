// Tilemap boxes merged behind the callers' handles. A row (or column) of touching wall boxes
// with the same properties is one occluder to every renderer (world/occluder_merge.hpp: its
// union, exactly, so no image changes), while each box keeps its handle: the group's first
// box (its leader) holds the entry, the others name it through Slot::group, and each box's
// occluder as given is kept for find_occluder and snapshot. Changing or removing a box splits
// its group into single boxes and applies the change; then the groups are made again what
// set_scene would make of the world's boxes as they now are (in snapshot order), so a frame
// stays bit for bit a one-shot render of the snapshot. Only changes to or from a box regroup.
#include <algorithm>
#include <unordered_map>

#include "geometry/aabb.hpp"
#include "world/occluder_merge.hpp"
#include "world/world.hpp"

namespace par2d::detail {

void World::push_loaded_occluders(const Scene& scene, const std::vector<std::pair<std::uint32_t, std::size_t>>& plain) {
  const std::vector<BoxRun> runs = tilemap_box_runs(
      plain.size(), [&](std::size_t i) -> const Occluder& { return scene.occluders[plain[i].second]; });
  std::vector<std::uint32_t> leader(plain.size(), kNoSlot);
  for (const BoxRun& run : runs)
    for (const std::size_t i : run.sources) leader[i] = plain[run.sources[0]].first;
  std::size_t run = 0;
  occluder_sources_.reserve(occluder_sources_.size() + plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    const auto [slot, index] = plain[i];
    Slot& s = slots_[slot];
    s.list = kOccluder;
    if (leader[i] == kNoSlot) {
      s.where = static_cast<std::int32_t>(occluder_sources_.size());
      occluder_sources_.push_back(scene.occluders[index]);
      occluder_slots_.push_back(slot);
      continue;
    }
    s.group = leader[i];
    merged_sources_.emplace(slot, scene.occluders[index]);
    if (leader[i] != slot) {
      s.where = 0;  // a handle to its group (never read: the group is split first)
      ++merged_followers_;
      continue;
    }
    // The leader: the first box of its run (runs come in the order of their first box).
    const BoxRun& r = runs[run++];
    std::vector<std::uint32_t>& members = merge_groups_[slot];
    for (const std::size_t k : r.sources) members.push_back(plain[k].first);
    Occluder merged = scene.occluders[index];
    merged.shape = r.shape;
    s.where = static_cast<std::int32_t>(occluder_sources_.size());
    occluder_sources_.push_back(std::move(merged));
    occluder_slots_.push_back(slot);
  }
}

std::vector<std::uint32_t> World::dissolve_group(std::uint32_t slot) {
  const std::uint32_t leader = slots_[slot].group;
  if (leader == kNoSlot) return {};
  auto node = merge_groups_.extract(leader);
  std::vector<std::uint32_t> members = std::move(node.mapped());
  erase_occluder_entry(static_cast<std::size_t>(slots_[leader].where));
  for (const std::uint32_t m : members) {
    auto source = merged_sources_.extract(m);
    slots_[m].group = kNoSlot;
    push_occluder_entry(source.mapped(), m);
  }
  merged_followers_ -= members.size() - 1;
  return members;
}

bool World::may_join(const Occluder& box) {
  if (!mergeable_box(box)) return false;
  const Polygon& p = std::get<Polygon>(box.shape);
  Aabb query = kEmptyBox;
  for (const Vec2 v : p.vertices)
    query = {std::min(query.min_x, v.x * factor_), std::min(query.min_y, v.y * factor_),
             std::max(query.max_x, v.x * factor_), std::max(query.max_y, v.y * factor_)};
  query_.clear();
  scene_.occluder_bvh.query_box(query, query_);
  for (const std::uint32_t k : query_) {
    const std::uint32_t slot = occluder_slots_[k];
    if (const auto group = merge_groups_.find(slot); group != merge_groups_.end()) {
      for (const std::uint32_t m : group->second)
        if (joinable(box, merged_sources_.at(m))) return true;
    } else if (joinable(box, occluder_sources_[k])) {
      return true;
    }
  }
  return false;
}

const Occluder& World::plain_source(std::uint32_t slot) const noexcept {
  if (const auto it = merged_sources_.find(slot); it != merged_sources_.end()) return it->second;
  return occluder_sources_[static_cast<std::size_t>(slots_[slot].where)];
}

void World::regroup() {
  // The plain occluders' slots in snapshot order (a group's boxes where its entry is).
  std::vector<std::uint32_t>& order = regroup_order_;
  order.clear();
  for (const std::uint32_t slot : occluder_slots_) {
    if (slots_[slot].internal || compound_occluders_.count(slot) != 0) continue;
    if (const auto group = merge_groups_.find(slot); group != merge_groups_.end()) {
      order.insert(order.end(), group->second.begin(), group->second.end());
    } else {
      order.push_back(slot);
    }
  }
  const std::vector<BoxRun> runs =
      tilemap_box_runs(order.size(), [&](std::size_t i) -> const Occluder& { return plain_source(order[i]); });
  // Groups that are still runs stay; the others are split, and new runs formed.
  std::unordered_map<std::uint32_t, std::size_t> run_of_leader;
  run_of_leader.reserve(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) run_of_leader.emplace(order[runs[r].sources[0]], r);
  auto same_members = [&](const BoxRun& run, const std::vector<std::uint32_t>& members) {
    if (run.sources.size() != members.size()) return false;
    for (std::size_t i = 0; i < members.size(); ++i)
      if (order[run.sources[i]] != members[i]) return false;
    return true;
  };
  std::vector<std::vector<std::uint32_t>> wanted;
  for (const BoxRun& run : runs) {
    const auto current = merge_groups_.find(order[run.sources[0]]);
    if (current != merge_groups_.end() && same_members(run, current->second)) continue;
    std::vector<std::uint32_t> members;
    for (const std::size_t i : run.sources) members.push_back(order[i]);
    wanted.push_back(std::move(members));
  }
  std::vector<std::uint32_t> stale;
  for (const auto& [leader, members] : merge_groups_) {
    const auto run = run_of_leader.find(leader);
    if (run == run_of_leader.end() || !same_members(runs[run->second], members)) stale.push_back(leader);
  }
  for (const std::uint32_t leader : stale) dissolve_group(leader);
  for (const std::vector<std::uint32_t>& members : wanted) form_group(members);
}

void World::form_group(const std::vector<std::uint32_t>& members) {
  // Their union: boxes joined end to end along one line.
  Vec2 lo = std::get<Polygon>(occluder_sources_[static_cast<std::size_t>(slots_[members[0]].where)].shape).vertices[0];
  Vec2 hi = lo;
  for (const std::uint32_t m : members) {
    const auto k = static_cast<std::size_t>(slots_[m].where);
    for (const Vec2 v : std::get<Polygon>(occluder_sources_[k].shape).vertices) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y)};
    }
  }
  const std::uint32_t leader = members[0];
  for (const std::uint32_t m : members) {
    const auto k = static_cast<std::size_t>(slots_[m].where);
    merged_sources_.emplace(m, occluder_sources_[k]);
    erase_occluder_entry(k);  // renumbers the last entry's slot
    slots_[m].group = leader;
    slots_[m].where = 0;
  }
  merge_groups_[leader] = members;
  Occluder merged = merged_sources_.at(leader);
  merged.shape = Polygon{{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}};
  push_occluder_entry(merged, leader);
  merged_followers_ += members.size() - 1;
}

}  // namespace par2d::detail
