// The persistent world behind par2d::Renderer: a PreparedScene kept up to date shape by shape,
// with stable handles and an occluder index updated in place. Render-time caches live with
// their rooms (culling's ReachCache) and follow the World's change events (world_changes.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "par2d/scene.hpp"
#include "par2d/status.hpp"
#include "par2d/types.hpp"
#include "lighting/light_emission.hpp"
#include "world/prepared_scene.hpp"
#include "world/world_changes.hpp"
#include "scene/scene_validate.hpp"

namespace par2d::detail {

class World {
 public:
  World();

  // The one observer told of every change from now on (nullptr: none); it is told
  // lights_reset at once. Kept across set_scene.
  void observe(WorldObserver* observer) noexcept;

  // The frame and its pixel grid (the image of `view` extended past its edges); the view
  // offset starts at 0, 0.
  Status set_frame(int width, int height, const View& view);
  // Shows the grid's pixels (x + i, y + j) as pixel (i, j): the view moved by whole pixels.
  // |x|, |y| <= kMaxViewOffset, and the moved view must be valid (docs/contract.md section 3).
  Status set_view_offset(std::int64_t x, std::int64_t y);
  std::int64_t view_offset_x() const noexcept { return scene_.grid_x; }
  std::int64_t view_offset_y() const noexcept { return scene_.grid_y; }
  Status set_scene(const Scene& scene, std::vector<LightHandle>* lights, std::vector<OccluderHandle>* occluders);

  Status add_light(const Light& light, LightHandle* handle);
  Status update_light(LightHandle handle, const Light& light);
  Status set_light_emission(LightHandle handle, const Rgb& color, double intensity);
  Status remove_light(LightHandle handle);
  // Lit entries moved down a place by erasures over the World's life (each erasure moves the
  // entries after it): for tests of what removing a light with many entries costs.
  std::size_t lit_entries_moved() const noexcept { return lit_entries_moved_; }
  Status add_occluder(const Occluder& occluder, OccluderHandle* handle);
  Status update_occluder(OccluderHandle handle, const Occluder& occluder);
  Status remove_occluder(OccluderHandle handle);

  // The scene-wide lighting-model terms (ambient, directional lights, normal source) of
  // `terms` replace the world's, validated first (`who` prefixes messages); shapes are untouched.
  Status set_model_terms(const char* who, const Scene& terms);
  // The one-bounce piece length (docs/contract.md section 7), validated like a scene's; refused
  // where the reflecting occluders would be cut into more than kMaxBouncePieces pieces.
  Status set_bounce(const Bounce& bounce);
  // The scene-wide terms as given (for the Renderer's setters, which change one at a time).
  const Scene& model_terms() const noexcept { return globals_; }

  // The light or occluder a handle names as last given (nullptr: no such handle).
  const Light* find_light(std::uint64_t id) const noexcept;
  const Occluder* find_occluder(std::uint64_t id) const noexcept;

  bool has_frame() const noexcept { return scene_.width > 0; }
  // The view set_frame gave (the grid), and the rectangle the frame shows (it moved by the offset).
  const View& grid_view() const noexcept { return view_; }
  const View& view() const noexcept { return visible_view_; }
  std::size_t light_count() const noexcept {
    return light_sources_.size() - internal_lights_ + dark_sources_.size();
  }
  std::size_t occluder_count() const noexcept {
    return occluder_sources_.size() - internal_occluders_ + merged_followers_;
  }

  // Brings everything derived up to date for a frame: coordinate scale, bounds and the index
  // (rebuilt only when refits have degraded it). Allocates nothing in steady state.
  const PreparedScene& commit();
  const PreparedScene& prepared() const noexcept { return scene_; }
  // The prepared scene, moved out (the World is left empty).
  PreparedScene take_prepared() noexcept { return std::move(scene_); }

  Scene snapshot() const;
  RendererStats& stats() noexcept { return stats_; }
  const RendererStats& stats() const noexcept { return stats_; }

 private:
  friend struct WorldTestAccess;  // tests/test_world_handles.cpp: ages a slot without 2^32 removals

  // A handle's slot: which array its object lives in and where.
  struct Slot {
    std::uint32_t generation = 1;  // 0: retired (see release_slot)
    std::int32_t where = -1;  // index into the owning array, -1 when free
    std::uint8_t list = 0;    // kLit / kDark / kOccluder
    // One user object can be several entries: a light split by its shadow (light_emission.hpp's
    // LightPart) and a concave occluder (one entry per convex piece). The
    // user's slot holds the first entry and starts a chain, through `next`, of internal slots
    // (no handle names them), one per further entry; `owner` is the user's slot.
    // A concave light is one entry (or two, split by its shadow) per convex piece and per
    // boundary two pieces share, the latter emitting -e: a direction crossing from one piece
    // into the next is counted by both and taken back once (push_light).
    bool internal = false;
    bool negative = false;  // lit entries: a shared boundary of a concave light's pieces
    LightPart part = LightPart::whole;  // lit entries: which part of the light this one renders
    std::uint32_t next = kNoSlot;
    std::uint32_t owner = kNoSlot;
    // A tilemap box merged with its row or column into one entry (world_merge.cpp): the
    // group's leader slot, which holds the entry.
    std::uint32_t group = kNoSlot;
  };
  LightPart part_of(std::size_t p) const noexcept { return slots_[light_slots_[p]].part; }
  static constexpr std::uint32_t kNoSlot = 0xffffffffu;
  // A new internal slot of `list` chained after `last`, owned by `owner`.
  std::uint32_t chain_slot(std::uint8_t list, std::uint32_t last, std::uint32_t owner);
  // Erases every entry of a user slot's chain with `erase_entry` (an index into its list),
  // releasing the internal slots (`internal` counts them) and keeping the user's.
  void erase_chain(std::uint32_t slot, void (World::*erase_entry)(std::size_t), std::size_t& internal);

  // A problem when a light emitting `emission` in all (entries_emission: its emission times
  // the most times a ray enters it), in place of the light in `replaced` (nullptr: added),
  // would take the lights' total emission past kMaxTotalEmission.
  std::optional<SceneProblem> emission_total_problem(const Rgb& emission, const Slot* replaced) const;
  static Rgb entries_emission(const Light& light);
  enum : std::uint8_t { kLit = 1, kDark = 2, kOccluder = 3 };

  // Frees a slot for reuse under its next generation. A slot whose generation would wrap past
  // 2^32 - 1 is retired instead (generation 0, never reused): reusing it would give a new object
  // the handle of one removed 2^32 generations ago.
  void release_slot(Slot* slot);
  std::uint64_t make_handle(std::uint32_t slot) const noexcept;
  Slot* find(std::uint64_t id, bool occluder) noexcept;
  std::uint32_t new_slot(std::uint8_t list, std::int32_t where);

  void prepare_lit(std::size_t p, const Light& light);
  // update_model_flag reads every light and occluder: while a user light's entries are pushed
  // or erased together (a concave light's pieces), it runs once at the end instead of per entry.
  class ModelFlagBatch;
  bool model_flag_deferred_ = false;
  // A user's light into the lists: dark, or lit as its one or two parts (a new internal slot
  // for the second), appended together; erase_light takes them all out again, keeping the
  // user's slot. `prepare` false: the entries are only laid out (set_scene prepares them all).
  void push_light(const Light& light, std::uint32_t slot, bool prepare = true);
  void erase_light(std::uint32_t slot);
  // One convex element of a user's light (the light itself, or a piece or shared boundary of
  // a concave one) as its parts, chained after `last` (`first`: into the user's slot `owner`);
  // returns the last slot used.
  std::uint32_t push_light_element(const Light& element, std::uint32_t owner, std::uint32_t last, bool first,
                                   bool negative, bool prepare);
  // The same for occluders: one entry, or one per convex piece of a concave one.
  void push_occluder(const Occluder& occluder, std::uint32_t slot);
  void erase_occluder(std::uint32_t slot);
  void push_occluder_entry(const Occluder& occluder, std::uint32_t slot);
  void erase_occluder_entry(std::size_t k);
  // A user's occluder (in no group) given a new shape or properties.
  void update_entry(std::uint32_t slot, const Occluder& occluder);
  // The user's light or occluder behind a user slot's first entry (a concave one as given).
  const Light& user_light(std::uint32_t slot) const noexcept;
  const Occluder& user_occluder(std::uint32_t slot) const noexcept;
  bool same_parts(const Slot& slot, const Light& light) const noexcept;
  // Lit entry p's emission and e_max share from its source and part.
  void set_part_emission(std::size_t p) noexcept;
  void push_lit(const Light& light, std::uint32_t slot, LightPart part, bool prepare);
  void push_dark(const Light& light, std::uint32_t slot);
  // Erases lit entry p; the entries above take the numbers one lower, in the same order.
  void erase_lit(std::size_t p);
  void erase_dark(std::size_t q);
  void occluder_changed(std::size_t k, const Aabb* old_box);
  void refresh_light_overlaps_for(std::size_t k);
  // `converted`: the normal map already converted for the view (see set_scene), if any.
  void reprepare_all(std::shared_ptr<const WorldNormals> converted = nullptr);
  void rebuild_index();
  double largest_coordinate() const noexcept;

  PreparedScene scene_;
  View view_{};        // unscaled: set_frame's, the pixel grid's
  View visible_view_{};  // unscaled: view_ moved by the offset (scene_.grid_x, grid_y)
  double factor_ = 1.0;  // scene_ coordinates = world coordinates * factor_

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_slots_;
  // Emitting lights, parallel to scene_.lights; dark (zero emission) lights aside.
  std::vector<Light> light_sources_;
  std::vector<std::uint32_t> light_slots_;
  std::size_t internal_lights_ = 0;  // lit entries in internal slots (not the user's first)
  std::size_t internal_occluders_ = 0;
  // Concave occluders and lights as given, by user slot (their entries hold the pieces).
  std::unordered_map<std::uint32_t, Occluder> compound_occluders_;
  std::unordered_map<std::uint32_t, Light> compound_lights_;
  std::vector<Polygon> pieces_;   // scratch for partitions
  std::vector<Segment> shared_;   // scratch: the boundaries a partition's pieces share
  // Tilemap boxes merged into one entry per group (world_merge.cpp): per leader slot the
  // group's user slots (leader first), per member slot its box as given.
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> merge_groups_;
  std::unordered_map<std::uint32_t, Occluder> merged_sources_;
  std::size_t merged_followers_ = 0;  // group members that are not its leader
  // The group of user slot `slot`, if any, split back into one entry per box; its members
  // (empty: it was in none).
  std::vector<std::uint32_t> dissolve_group(std::uint32_t slot);
  // The groups made again what merging the world's boxes now gives (after a box changed).
  void regroup();
  // Whether `box` (world coordinates) shares a whole edge with a box it could join (through
  // the index; no allocation): if neither a box's old nor new shape may join and it was in no
  // group, the groups cannot change.
  bool may_join(const Occluder& box);
  // These user slots (each one plain box entry, in no group, in snapshot order) as one group.
  void form_group(const std::vector<std::uint32_t>& members);
  // A plain occluder as given, in a group or not.
  const Occluder& plain_source(std::uint32_t slot) const noexcept;
  std::vector<std::uint32_t> regroup_order_;  // scratch
  std::vector<std::uint32_t> chain_scratch_;  // scratch: a light's entry slots, for erase_light
  std::size_t lit_entries_moved_ = 0;
  // set_scene: the plain occluders (user slot, index in `scene`) into the lists, merged.
  void push_loaded_occluders(const Scene& scene, const std::vector<std::pair<std::uint32_t, std::size_t>>& plain);
  std::vector<Light> dark_sources_;
  std::vector<std::uint32_t> dark_slots_;
  // The scene-wide game-model terms as given (ambient, directional lights, normal source);
  // its shapes and size are unused.
  Scene globals_;
  // Parallel to scene_.occluders.
  std::vector<Occluder> occluder_sources_;
  // How many bounce pieces the reflecting occluders are cut into (integers, exact in a
  // double), kept with every occluder change so that additions past kMaxBouncePieces are refused.
  double bounce_pieces_ = 0.0;
  double bounce_pieces_of(const Occluder& occluder) const noexcept;
  std::vector<std::uint32_t> occluder_slots_;

  WorldObserver* observer_ = nullptr;

  std::vector<std::uint32_t> query_;  // scratch for index queries
  std::vector<Aabb> boxes_;          // scratch for index builds
  ConvexShape shape_scratch_;
  RendererStats stats_;
};

// The prepared form of a scene as a World prepares it for a frame (set_scene, then commit):
// for tests and benchmarks that call the renderers' lower rooms directly, so they check the
// path the library runs. Throws std::invalid_argument when the scene does not validate.
PreparedScene prepare_scene(const Scene& scene);

}  // namespace par2d::detail
