// The persistent world: validated, prepared shape by shape; the occluder index follows each
// change incrementally, and the observer hears of every change (docs/contract.md describes
// what is computed).
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
#include "world/world_support.hpp"

namespace par2d::detail {

using namespace world_support;

World::World() { scene_.separators.reset(0, 0); }

class World::ModelFlagBatch {
 public:
  explicit ModelFlagBatch(World& world) noexcept : world_(world), outer_(!world.model_flag_deferred_) {
    world_.model_flag_deferred_ = true;
  }
  ~ModelFlagBatch() {
    if (!outer_) return;
    world_.model_flag_deferred_ = false;
    update_model_flag(world_.scene_);
  }
  ModelFlagBatch(const ModelFlagBatch&) = delete;
  ModelFlagBatch& operator=(const ModelFlagBatch&) = delete;

 private:
  World& world_;
  bool outer_;
};

void World::observe(WorldObserver* observer) noexcept {
  observer_ = observer;
  if (observer_) observer_->lights_reset(scene_.lights.size());
}

std::uint64_t World::make_handle(std::uint32_t slot) const noexcept {
  return (static_cast<std::uint64_t>(slots_[slot].generation) << 32) | (static_cast<std::uint64_t>(slot) + 1);
}

World::Slot* World::find(std::uint64_t id, bool occluder) noexcept {
  const std::uint64_t low = id & 0xffffffffu;
  if (low == 0 || low > slots_.size()) return nullptr;
  Slot& slot = slots_[static_cast<std::size_t>(low - 1)];  // low <= slots_.size()
  if (slot.where < 0 || slot.internal || slot.generation != (id >> 32)) return nullptr;
  if ((slot.list == kOccluder) != occluder) return nullptr;
  return &slot;
}

void World::release_slot(Slot* slot) {
  slot->where = -1;
  if (slot->generation == std::numeric_limits<std::uint32_t>::max()) {
    slot->generation = 0;
    return;
  }
  ++slot->generation;
  free_slots_.push_back(static_cast<std::uint32_t>(slot - slots_.data()));
}

std::uint32_t World::new_slot(std::uint8_t list, std::int32_t where) {
  std::uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  slots_[slot].list = list;
  slots_[slot].where = where;
  slots_[slot].internal = false;
  slots_[slot].next = kNoSlot;
  slots_[slot].owner = kNoSlot;
  slots_[slot].group = kNoSlot;
  return slot;
}

std::uint32_t World::chain_slot(std::uint8_t list, std::uint32_t last, std::uint32_t owner) {
  const std::uint32_t slot = new_slot(list, 0);
  slots_[slot].internal = true;
  slots_[slot].owner = owner;
  slots_[last].next = slot;
  ++(list == kOccluder ? internal_occluders_ : internal_lights_);
  return slot;
}

const Light& World::user_light(std::uint32_t slot) const noexcept {
  if (const auto it = compound_lights_.find(slot); it != compound_lights_.end()) return it->second;
  const Slot& s = slots_[slot];
  return s.list == kLit ? light_sources_[static_cast<std::size_t>(s.where)] : dark_sources_[static_cast<std::size_t>(s.where)];
}

const Occluder& World::user_occluder(std::uint32_t slot) const noexcept {
  if (const auto it = compound_occluders_.find(slot); it != compound_occluders_.end()) return it->second;
  if (const auto it = merged_sources_.find(slot); it != merged_sources_.end()) return it->second;
  return occluder_sources_[static_cast<std::size_t>(slots_[slot].where)];
}

Status World::set_frame(int width, int height, const View& view) {
  if (auto problem = check_image_size(width, height)) return scene_error("set_frame", *problem);
  if (auto problem = check_view(view, width, height)) return scene_error("set_frame", *problem);
  // The same grid: back to offset 0 (whole pixels, as set_view_offset moves).
  if (width == scene_.width && height == scene_.height && same_view(view, view_)) return set_view_offset(0, 0);
  if (globals_.normal_map && (globals_.normal_map->width != width || globals_.normal_map->height != height))
    return Status(StatusCode::invalid_argument,
                  "set_frame: the normal map is " + std::to_string(globals_.normal_map->width) + "x" +
                      std::to_string(globals_.normal_map->height) + " but the frame would be " +
                      std::to_string(width) + "x" + std::to_string(height));
  const bool flips = (view.x1 > view.x0) != (view_.x1 > view_.x0) || (view.y1 > view.y0) != (view_.y1 > view_.y0);
  scene_.width = width;
  scene_.height = height;
  view_ = view;
  visible_view_ = view;
  scene_.grid_x = scene_.grid_y = 0;
  scene_.view = {view.x0 * factor_, view.y0 * factor_, view.x1 * factor_, view.y1 * factor_};
  // A mirrored view mirrors the map's normals with the image.
  if (flips && globals_.normal_map && scene_.normal_source == NormalSource::map) {
    auto mirrored = world_normals(*globals_.normal_map, view_);
    if (!mirrored) return Status(StatusCode::invalid_scene, "set_frame: normal_map: a normal does not convert to unit length");
    scene_.normal_map = std::move(mirrored);
  }
  if (observer_) observer_->frame_changed();
  return {};
}

Status World::set_view_offset(std::int64_t x, std::int64_t y) {
  if (!has_frame()) return Status(StatusCode::invalid_argument, "set_view_offset: no frame size (call set_frame or set_scene first)");
  if (x == scene_.grid_x && y == scene_.grid_y) return {};  // nothing moves
  if (!(-kMaxViewOffset <= x && x <= kMaxViewOffset && -kMaxViewOffset <= y && y <= kMaxViewOffset))
    return Status(StatusCode::invalid_argument, "set_view_offset: (" + std::to_string(x) + ", " + std::to_string(y) +
                                                    ") is farther than 2^40 pixels from the frame's view");
  const View moved = offset_view(view_, scene_.width, scene_.height, x, y);
  if (auto problem = check_view(moved, scene_.width, scene_.height))
    return Status(StatusCode::invalid_argument, "set_view_offset: the moved " + problem->place + " " + problem->what);
  visible_view_ = moved;
  scene_.grid_x = x;
  scene_.grid_y = y;
  // A normal map holds a normal per frame pixel: it does not move with the world, so every
  // pixel's normal changes.
  if (observer_) {
    if (globals_.normal_map) {
      observer_->frame_changed();
    } else {
      observer_->frame_scrolled();
    }
  }
  return {};
}

double World::bounce_pieces_of(const Occluder& occluder) const noexcept {
  if (occluder.albedo == Rgb{0.0, 0.0, 0.0}) return 0.0;
  return bounce_piece_count(occluder.shape, globals_.bounce.piece, 2.0 * kMaxBouncePieces);
}

Status World::set_bounce(const Bounce& bounce) {
  if (auto problem = check_bounce(bounce)) return refused("set_bounce", *problem);
  if (same_value(bounce.piece, globals_.bounce.piece) && bounce.step == globals_.bounce.step) return {};  // unchanged
  double pieces = 0.0;
  for (const Occluder& o : occluder_sources_) {
    if (o.albedo == Rgb{0.0, 0.0, 0.0}) continue;
    pieces += bounce_piece_count(o.shape, bounce.piece, 2.0 * kMaxBouncePieces);
    if (pieces > kMaxBouncePieces) return refused("set_bounce", {"bounce.piece", bounce_pieces_text(pieces)});
  }
  globals_.bounce = bounce;
  scene_.bounce_piece = bounce.piece;
  scene_.bounce_step = bounce.step;
  bounce_pieces_ = pieces;
  if (observer_) observer_->terms_changed();
  return {};
}

Status World::set_scene(const Scene& scene, std::vector<LightHandle>* lights, std::vector<OccluderHandle>* occluders) {
  // A normal map of the image's size is converted first: that pass checks every normal too,
  // so validation then checks only its size (a bad normal leaves `converted` null, and the
  // full check words the problem).
  std::shared_ptr<const WorldNormals> converted;
  if (scene.normal_map && !check_normal_map(*scene.normal_map, scene.width, scene.height, NormalsCheck::size_only))
    converted = world_normals(*scene.normal_map, scene.view);
  if (Status s = validate_scene(scene, "scene", converted ? NormalsCheck::size_only : NormalsCheck::each); !s.ok())
    return s;
  // Build the new state aside, so that a failure (out of memory) keeps the old one.
  World next;
  next.stats_ = stats_;
  next.scene_.width = scene.width;
  next.scene_.height = scene.height;
  next.view_ = scene.view;
  next.visible_view_ = scene.view;
  // Generations continue from this world's, so no old handle names a new object; retired slots
  // stay retired, and one whose generation would wrap retires now (see release_slot).
  next.slots_.resize(slots_.size());
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const std::uint32_t g = slots_[i].generation;
    next.slots_[i].generation = g == 0 || g == std::numeric_limits<std::uint32_t>::max() ? 0 : g + 1;
  }
  std::uint32_t cursor = 0;  // the next slot to consider for a new object
  const auto take_slot = [&next, &cursor]() -> std::uint32_t {
    while (cursor < next.slots_.size() && next.slots_[cursor].generation == 0) ++cursor;
    if (cursor == next.slots_.size()) next.slots_.emplace_back();
    return cursor++;
  };
  std::vector<LightHandle> light_handles;
  std::vector<OccluderHandle> occluder_handles;
  // Lights and plain occluders go into the lists (prepared together below); a concave occluder
  // (several entries) is added once the rest is prepared. Internal slots (a light's further
  // entries, a concave occluder's pieces) are taken after every handle's, so handles do not
  // depend on them.
  std::vector<std::pair<std::uint32_t, std::size_t>> lights_in, later_occluders;  // user slot, index
  std::vector<std::pair<std::uint32_t, std::size_t>> plain_occluders;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const std::uint32_t slot = take_slot();
    lights_in.emplace_back(slot, i);
    light_handles.push_back({next.make_handle(slot)});
  }
  for (std::size_t i = 0; i < scene.occluders.size(); ++i) {
    const Occluder& occluder = scene.occluders[i];
    const std::uint32_t slot = take_slot();
    (needs_partition(occluder.shape) ? later_occluders : plain_occluders).emplace_back(slot, i);
    occluder_handles.push_back({next.make_handle(slot)});
  }
  next.push_loaded_occluders(scene, plain_occluders);
  for (std::size_t i = next.slots_.size(); i-- > cursor;)
    if (next.slots_[i].generation != 0) next.free_slots_.push_back(static_cast<std::uint32_t>(i));
  // Each light's entries together, in the scene's order: as push_light appends a light's and
  // erase_lit keeps the others' order, so that a World and a fresh load of its snapshot hold
  // the same entries in the same order (and sum every pixel's lights alike).
  {
    const ModelFlagBatch batch(next);
    for (const auto& [slot, i] : lights_in) next.push_light(scene.lights[i], slot, false);
  }
  next.globals_.ambient = scene.ambient;
  next.globals_.directional_lights = scene.directional_lights;
  next.globals_.normal = scene.normal;
  next.globals_.normal_map = scene.normal_map;
  next.globals_.bounce = scene.bounce;
  for (const Occluder& o : scene.occluders) next.bounce_pieces_ += next.bounce_pieces_of(o);
  next.reprepare_all(std::move(converted));
  for (const auto& [slot, i] : later_occluders) next.push_occluder(scene.occluders[i], slot);
  next.observer_ = observer_;
  *this = std::move(next);
  if (observer_) observer_->lights_reset(scene_.lights.size());
  if (lights) *lights = std::move(light_handles);
  if (occluders) *occluders = std::move(occluder_handles);
  return {};
}

double World::largest_coordinate() const noexcept {
  double largest = 0.0;
  auto grow = [&](const ConvexShape& s) {
    largest = std::max({largest, std::abs(s.bounds_min.x), std::abs(s.bounds_min.y), std::abs(s.bounds_max.x),
                        std::abs(s.bounds_max.y)});
  };
  for (const PreparedLight& l : scene_.lights) grow(l.shape);
  for (const ConvexShape& o : scene_.occluders) grow(o);
  return largest;
}

// Everything from the sources, for a whole scene (set_scene) or a new coordinate scale (commit).
void World::reprepare_all(std::shared_ptr<const WorldNormals> converted) {
  scene_.lights.resize(light_sources_.size());
  scene_.occluders.resize(occluder_sources_.size());
  for (std::size_t p = 0; p < light_sources_.size(); ++p) {
    const Light& l = light_sources_[p];
    make_convex_shape(l.shape, scene_.lights[p].shape);
    set_part_emission(p);
  }
  for (std::size_t k = 0; k < occluder_sources_.size(); ++k) make_convex_shape(occluder_sources_[k].shape, scene_.occluders[k]);
  const double largest = std::max({largest_coordinate(), std::abs(visible_view_.x0), std::abs(visible_view_.x1),
                                   std::abs(visible_view_.y0), std::abs(visible_view_.y1)});
  factor_ = scene_scale(view_, largest);
  scene_.view = {view_.x0 * factor_, view_.y0 * factor_, view_.x1 * factor_, view_.y1 * factor_};
  scene_.scale = factor_;
  for (PreparedLight& l : scene_.lights) scale_shape(l.shape, factor_);
  for (ConvexShape& o : scene_.occluders) scale_shape(o, factor_);
  for (std::size_t p = 0; p < light_sources_.size(); ++p)
    scene_.lights[p].terms = part_terms(light_sources_[p], part_of(p), factor_);
  scene_.occluder_terms.resize(occluder_sources_.size());
  for (std::size_t k = 0; k < occluder_sources_.size(); ++k) scene_.occluder_terms[k] = occluder_terms(occluder_sources_[k]);
  globals_.view = view_;
  prepare_model_terms(globals_, scene_, std::move(converted));
  rebuild_index();
  reserve_overlaps(scene_, nullptr, nullptr);
  for (PreparedLight& l : scene_.lights) find_light_overlaps(scene_, l, query_, scene_.spare_overlaps);
  scene_.separators.reset(scene_.lights.size(), scene_.occluders.size());
  update_scene_bounds(scene_);
  ++stats_.full_prepares;
  if (observer_) observer_->lights_reset(scene_.lights.size());
}

void World::rebuild_index() {
  std::vector<Aabb>& boxes = boxes_;
  boxes.clear();
  for (const ConvexShape& o : scene_.occluders) boxes.push_back(bounds_of(o));
  scene_.occluder_bvh.build(boxes);
  ++stats_.index_builds;
}

void World::prepare_lit(std::size_t p, const Light& light) {
  PreparedLight& prepared = scene_.lights[p];
  make_convex_shape(light.shape, prepared.shape);
  scale_shape(prepared.shape, factor_);
  set_part_emission(p);
  prepared.terms = part_terms(light, part_of(p), factor_);
  if (!model_flag_deferred_) update_model_flag(scene_);
  reserve_overlaps(scene_, &prepared.shape, nullptr);
  find_light_overlaps(scene_, prepared, query_, scene_.spare_overlaps);
  scene_.separators.forget_light(p);
  if (observer_) observer_->light_changed(p);
}

void World::set_part_emission(std::size_t p) noexcept {
  // The e_max share goes to the user's first entry only.
  const Slot& slot = slots_[light_slots_[p]];
  const Light& light = light_sources_[p];
  PreparedLight& prepared = scene_.lights[p];
  prepared.emission = part_emission(light, slot.part);
  if (slot.negative)
    for (double& e : prepared.emission) e = -e;
  const Rgb whole = light_emission(light);
  prepared.e_max_share = slot.internal ? 0.0 : std::max({whole[0], whole[1], whole[2]});
}

void World::push_light(const Light& light, std::uint32_t slot, bool prepare) {
  if (!emits(light)) return push_dark(light, slot);
  if (!needs_partition(light.shape)) {
    push_light_element(light, slot, slot, true, false, prepare);
    return;
  }
  // A concave light: its convex pieces emit like lights, which count a direction once per
  // piece it meets; where a direction passes from one piece into the next across their shared
  // boundary, that boundary (a segment light emitting -e, seen with the same visibility as the
  // piece entered there) takes the second count back. So every direction counts once for
  // each time it enters the light from outside (docs/contract.md section 3).
  compound_lights_[slot] = light;
  const ModelFlagBatch batch(*this);
  std::string error;
  partition_polygon(std::get<Polygon>(light.shape), pieces_, error);  // check_light found it partitions
  shared_.clear();
  shared_boundaries(pieces_, shared_);
  Light element = light;
  std::uint32_t last = slot;
  bool first = true;
  for (Polygon& piece : pieces_) {
    element.shape = std::move(piece);
    last = push_light_element(element, slot, last, first, false, prepare);
    first = false;
  }
  for (const Segment& boundary : shared_) {
    element.shape = boundary;
    last = push_light_element(element, slot, last, false, true, prepare);
  }
}

std::uint32_t World::push_light_element(const Light& element, std::uint32_t owner, std::uint32_t last, bool first,
                                        bool negative, bool prepare) {
  const LightParts parts = light_parts(element);
  const LightPart kinds[2] = {parts.first, LightPart::unshadowed};
  const int part_count = parts.split ? 2 : 1;
  for (int part = 0; part < part_count; ++part) {
    if (!(first && part == 0)) last = chain_slot(kLit, last, owner);
    slots_[last].negative = negative;
    push_lit(element, last, kinds[part], prepare);
  }
  return last;
}

void World::erase_chain(std::uint32_t slot, void (World::*erase_entry)(std::size_t), std::size_t& internal) {
  for (std::uint32_t s = slots_[slot].next; s != kNoSlot;) {
    const std::uint32_t next = slots_[s].next;
    (this->*erase_entry)(static_cast<std::size_t>(slots_[s].where));
    release_slot(&slots_[s]);
    --internal;
    s = next;
  }
  slots_[slot].next = kNoSlot;
  (this->*erase_entry)(static_cast<std::size_t>(slots_[slot].where));
}

void World::erase_light(std::uint32_t slot) {
  if (slots_[slot].list == kDark) return erase_dark(static_cast<std::size_t>(slots_[slot].where));
  const ModelFlagBatch batch(*this);
  // A concave light's entries lie together; erased from the last down, no erase moves an entry
  // erased after it (from the first up, each moved all the rest: quadratic in the pieces). The
  // slots are released in the chain's order, as erase_chain does.
  chain_scratch_.clear();
  for (std::uint32_t s = slots_[slot].next; s != kNoSlot; s = slots_[s].next) chain_scratch_.push_back(s);
  for (auto it = chain_scratch_.rbegin(); it != chain_scratch_.rend(); ++it)
    erase_lit(static_cast<std::size_t>(slots_[*it].where));
  for (const std::uint32_t s : chain_scratch_) {
    release_slot(&slots_[s]);
    --internal_lights_;
  }
  slots_[slot].next = kNoSlot;
  erase_lit(static_cast<std::size_t>(slots_[slot].where));
  compound_lights_.erase(slot);
}

void World::push_lit(const Light& light, std::uint32_t slot, LightPart part, bool prepare) {
  const std::size_t p = light_sources_.size();
  light_sources_.push_back(light);
  light_slots_.push_back(slot);
  slots_[slot].part = part;
  slots_[slot].list = kLit;
  slots_[slot].where = static_cast<std::int32_t>(p);
  if (!prepare) return;
  scene_.lights.emplace_back();
  if (observer_) observer_->light_added();
  scene_.separators.resize(p + 1, scene_.occluders.size());
  prepare_lit(p, light);
}

void World::push_dark(const Light& light, std::uint32_t slot) {
  slots_[slot].list = kDark;
  slots_[slot].where = static_cast<std::int32_t>(dark_sources_.size());
  dark_sources_.push_back(light);
  dark_slots_.push_back(slot);
}

void World::erase_lit(std::size_t p) {
  // The entries above take the numbers one lower, in the same order: each user light's entries
  // stay together and in the order set_scene lays them out, so a one-shot render of the
  // snapshot sums every pixel's lights in this world's order (see snapshot).
  const std::size_t m = light_sources_.size() - 1;
  const auto at = static_cast<std::ptrdiff_t>(p);
  // Its overlaps go back to the pool (reserve_overlaps).
  for (LightOverlap& o : scene_.lights[p].overlaps) scene_.spare_overlaps.push_back(std::move(o));
  lit_entries_moved_ += m - p;
  light_sources_.erase(light_sources_.begin() + at);
  light_slots_.erase(light_slots_.begin() + at);
  scene_.lights.erase(scene_.lights.begin() + at);
  for (std::size_t i = p; i < m; ++i) slots_[light_slots_[i]].where = static_cast<std::int32_t>(i);
  if (!model_flag_deferred_) update_model_flag(scene_);
  if (observer_) observer_->light_erased(p);
  scene_.separators.erase_light(p);
  scene_.separators.resize(m, scene_.occluders.size());
}

void World::erase_dark(std::size_t q) {
  const std::size_t m = dark_sources_.size() - 1;
  if (q != m) {
    std::swap(dark_sources_[q], dark_sources_[m]);
    dark_slots_[q] = dark_slots_[m];
    slots_[dark_slots_[q]].where = static_cast<std::int32_t>(q);
  }
  dark_sources_.pop_back();
  dark_slots_.pop_back();
}

// A light's emission times the most times a ray enters it (light_entries_bound).
Rgb World::entries_emission(const Light& light) {
  Rgb emission = light_emission(light);
  const double entries = light_entries_bound(light);
  for (double& e : emission) e *= entries;
  return emission;
}

// The lights' total emission with `light` added (in place of lit light `replaced`, if any)
// must stay within what float32 output can hold, as for scenes (check_emission_total).
std::optional<SceneProblem> World::emission_total_problem(const Rgb& emission, const Slot* replaced) const {
  // The lit entries of the replaced light are left out.
  const std::uint32_t replaced_slot =
      replaced != nullptr ? static_cast<std::uint32_t>(replaced - slots_.data()) : kNoSlot;
  // Ambient and directional lights add to E too (check_scene_terms); lit lights as prepared,
  // but a concave light as a whole: its entries' emissions (pieces, and shared boundaries that
  // take counts back) sum to about one emission, while a ray can enter it up to
  // concave_entries_bound times.
  Rgb total = emission;
  for (std::size_t c = 0; c < 3; ++c) {
    total[c] += globals_.ambient[c];
    for (const DirectionalLight& d : globals_.directional_lights) total[c] += d.intensity * d.color[c];
  }
  for (std::size_t i = 0; i < light_sources_.size(); ++i) {
    const Slot& entry = slots_[light_slots_[i]];
    const std::uint32_t owner = entry.internal ? entry.owner : light_slots_[i];
    if (owner == replaced_slot || (!compound_lights_.empty() && compound_lights_.count(owner) != 0)) continue;
    for (std::size_t c = 0; c < 3; ++c) total[c] += scene_.lights[i].emission[c];
  }
  for (const auto& [owner, light] : compound_lights_) {
    if (owner == replaced_slot) continue;
    const Rgb whole = light_emission(light);
    const double entries = concave_entries_bound(std::get<Polygon>(light.shape));
    for (std::size_t c = 0; c < 3; ++c) total[c] += entries * whole[c];
  }
  for (std::size_t c = 0; c < 3; ++c) {
    if (!(total[c] <= kMaxTotalEmission))
      return SceneProblem{std::string(), "emission too large: the lights' total intensity * color reaches " +
                                             format_number(total[c]) + " (at most 1e38, so that float32 output stays finite)"};
  }
  return std::nullopt;
}

Status World::set_model_terms(const char* who, const Scene& terms) {
  MaybeProblem problem = check_ambient(terms.ambient);
  for (std::size_t i = 0; !problem && i < terms.directional_lights.size(); ++i)
    problem = check_directional(terms.directional_lights[i], "directional_lights[" + std::to_string(i) + "]");
  if (!problem && terms.normal) problem = check_normal(*terms.normal);
  if (!problem && terms.normal && terms.normal_map)
    problem = SceneProblem{"normal_map", "the scene has both normal and normal_map (at most one normal source)"};
  // Before the first frame the map is checked against its own size; set_frame then refuses
  // a frame of any other size.
  // The conversion checks every normal (see set_scene); the full check only words a problem.
  std::shared_ptr<const WorldNormals> converted;
  if (!problem && terms.normal_map) {
    const int width = has_frame() ? scene_.width : terms.normal_map->width;
    const int height = has_frame() ? scene_.height : terms.normal_map->height;
    problem = check_normal_map(*terms.normal_map, width, height, NormalsCheck::size_only);
    if (!problem) {
      converted = world_normals(*terms.normal_map, view_);
      if (!converted) problem = check_normal_map(*terms.normal_map, width, height);
    }
  }
  if (!problem) {
    Scene total;  // the emission total over lights, directional lights and ambient
    for (std::size_t p = 0; p < light_sources_.size(); ++p)
      if (!slots_[light_slots_[p]].internal) total.lights.push_back(user_light(light_slots_[p]));
    total.ambient = terms.ambient;
    total.directional_lights = terms.directional_lights;
    if (auto p = check_scene_terms(total)) problem = p;
  }
  if (problem) return refused(who, *problem);
  // Everything is built aside and then moved in (no throw), so that running out of memory
  // keeps the old terms; no shape is re-prepared.
  Scene next;
  next.ambient = terms.ambient;
  next.directional_lights = terms.directional_lights;
  next.normal = terms.normal;
  next.normal_map = terms.normal_map;
  next.view = view_;
  next.bounce = globals_.bounce;  // not one of the terms set here (docs/contract.md section 7)
  PreparedScene staged;
  prepare_model_terms(next, staged, std::move(converted));
  globals_ = std::move(next);
  scene_.ambient = staged.ambient;
  scene_.directionals = std::move(staged.directionals);
  scene_.normal_source = staged.normal_source;
  scene_.normal = staged.normal;
  scene_.normal_map = std::move(staged.normal_map);
  update_model_flag(scene_);
  update_scene_bounds(scene_);
  if (observer_) observer_->terms_changed();
  return {};
}

Status World::add_light(const Light& light, LightHandle* handle) {
  if (handle == nullptr) return Status(StatusCode::invalid_argument, "add_light: handle is null");
  if (auto problem = check_light(light, std::string())) return refused("add_light", *problem);
  if (auto problem = emission_total_problem(entries_emission(light), nullptr)) return refused("add_light", *problem);
  const std::uint32_t slot = new_slot(0, 0);
  push_light(light, slot);
  handle->id = make_handle(slot);
  return {};
}

// Whether `light` renders as the same entries the light in `slot` has now (lit, same parts),
// so that it can be prepared in place: a moving light keeps its index and caches.
bool World::same_parts(const Slot& slot, const Light& light) const noexcept {
  if (slot.list != kLit || !emits(light)) return false;
  // A concave light's entries follow its pieces: it is laid out anew.
  if (compound_lights_.count(static_cast<std::uint32_t>(&slot - slots_.data())) != 0 || needs_partition(light.shape))
    return false;
  const LightParts parts = light_parts(light);
  return parts.first == slot.part && parts.split == (slot.next != kNoSlot);
}

Status World::update_light(LightHandle handle, const Light& light) {
  Slot* slot = find(handle.id, false);
  if (!slot) return unknown_handle("light", handle.id);
  // The values it holds (already checked): nothing changes, nothing is marked.
  if (same_light(user_light(static_cast<std::uint32_t>(slot - slots_.data())), light)) return {};
  if (auto problem = check_light(light, std::string())) return refused("light " + std::to_string(handle.id), *problem);
  const std::uint32_t index = static_cast<std::uint32_t>(slot - slots_.data());
  if (auto problem = emission_total_problem(entries_emission(light), slot))
    return refused("light " + std::to_string(handle.id), *problem);
  if (same_parts(*slot, light)) {
    for (const std::uint32_t s : {index, slot->next}) {
      if (s == kNoSlot) continue;
      const auto where = static_cast<std::size_t>(slots_[s].where);
      light_sources_[where] = light;
      prepare_lit(where, light);
    }
  } else if (slot->list == kDark && !emits(light)) {
    dark_sources_[static_cast<std::size_t>(slot->where)] = light;
  } else {
    erase_light(index);
    push_light(light, index);
  }
  return {};
}

Status World::set_light_emission(LightHandle handle, const Rgb& color, double intensity) {
  Slot* slot = find(handle.id, false);
  if (!slot) return unknown_handle("light", handle.id);
  for (std::size_t c = 0; c < 3; ++c) {
    if (!(std::isfinite(color[c]) && color[c] >= 0.0))
      return Status(StatusCode::invalid_scene, "light " + std::to_string(handle.id) + ": color[" + std::to_string(c) +
                                                   "]: must be a finite number >= 0");
  }
  if (!(std::isfinite(intensity) && intensity >= 0.0))
    return Status(StatusCode::invalid_scene,
                  "light " + std::to_string(handle.id) + ": intensity: must be a finite number >= 0");
  const std::uint32_t index = static_cast<std::uint32_t>(slot - slots_.data());
  const auto where = static_cast<std::size_t>(slot->where);
  const auto compound = compound_lights_.find(index);
  Light& source = compound != compound_lights_.end() ? compound->second
                  : slot->list == kLit                ? light_sources_[where]
                                                      : dark_sources_[where];
  if (same_rgb(source.color, color) && same_value(source.intensity, intensity)) return {};  // unchanged
  Rgb emission = light_emission(color, intensity, emission_scale(source));
  if (compound != compound_lights_.end()) {
    const double entries = concave_entries_bound(std::get<Polygon>(source.shape));
    for (double& e : emission) e *= entries;
  }
  if (auto problem = emission_total_problem(emission, slot)) return refused("light " + std::to_string(handle.id), *problem);
  // The new light, built in place (its shape's storage is not copied).
  const Rgb old_color = source.color;
  const double old_intensity = source.intensity;
  source.color = color;
  source.intensity = intensity;
  const bool in_place = same_parts(*slot, source);
  source.color = old_color;
  source.intensity = old_intensity;
  if (in_place) {
    // Only the emission changes: shape, overlaps, separators and reach all stay.
    for (const std::uint32_t s : {index, slot->next}) {
      if (s == kNoSlot) continue;
      const auto p = static_cast<std::size_t>(slots_[s].where);
      light_sources_[p].color = color;
      light_sources_[p].intensity = intensity;
      set_part_emission(p);
      if (observer_) observer_->light_emission_changed(p);
    }
  } else if (slot->list == kDark && !(emission[0] > 0.0 || emission[1] > 0.0 || emission[2] > 0.0)) {
    source.color = color;
    source.intensity = intensity;
  } else {
    Light copy = source;
    copy.color = color;
    copy.intensity = intensity;
    erase_light(index);
    push_light(copy, index);
  }
  return {};
}

Status World::remove_light(LightHandle handle) {
  Slot* slot = find(handle.id, false);
  if (!slot) return unknown_handle("light", handle.id);
  erase_light(static_cast<std::uint32_t>(slot - slots_.data()));
  release_slot(slot);
  return {};
}

const PreparedScene& World::commit() {
  // The coordinate scale follows the view and the largest coordinate (scene_scale); when
  // it changes, everything is prepared again (a zoom by a power of two, far-flung shapes).
  const double largest = std::max({largest_coordinate() / factor_, std::abs(visible_view_.x0),
                                   std::abs(visible_view_.x1), std::abs(visible_view_.y0), std::abs(visible_view_.y1)});
  if (scene_scale(view_, largest) != factor_) reprepare_all();
  update_scene_bounds(scene_);
  if (scene_.occluder_bvh.needs_rebuild()) rebuild_index();
  return scene_;
}

const Light* World::find_light(std::uint64_t id) const noexcept {
  const Slot* slot = const_cast<World*>(this)->find(id, false);
  return slot == nullptr ? nullptr : &user_light(static_cast<std::uint32_t>(slot - slots_.data()));
}

const Occluder* World::find_occluder(std::uint64_t id) const noexcept {
  const Slot* slot = const_cast<World*>(this)->find(id, true);
  return slot == nullptr ? nullptr : &user_occluder(static_cast<std::uint32_t>(slot - slots_.data()));
}

Scene World::snapshot() const {
  Scene out;
  out.width = scene_.width;
  out.height = scene_.height;
  out.view = visible_view_;
  for (std::size_t p = 0; p < light_sources_.size(); ++p)
    if (!slots_[light_slots_[p]].internal) out.lights.push_back(user_light(light_slots_[p]));
  out.lights.insert(out.lights.end(), dark_sources_.begin(), dark_sources_.end());
  for (std::size_t k = 0; k < occluder_sources_.size(); ++k) {
    const std::uint32_t slot = occluder_slots_[k];
    if (slots_[slot].internal) continue;
    if (const auto group = merge_groups_.find(slot); group != merge_groups_.end()) {
      for (const std::uint32_t member : group->second) out.occluders.push_back(merged_sources_.at(member));
    } else {
      out.occluders.push_back(user_occluder(slot));
    }
  }
  out.ambient = globals_.ambient;
  out.directional_lights = globals_.directional_lights;
  out.normal = globals_.normal;
  out.normal_map = globals_.normal_map;
  out.bounce = globals_.bounce;
  return out;
}

PreparedScene prepare_scene(const Scene& scene) {
  World world;
  if (Status s = world.set_scene(scene, nullptr, nullptr); !s.ok()) throw std::invalid_argument(s.message());
  world.commit();
  return world.take_prepared();
}

}  // namespace par2d::detail
