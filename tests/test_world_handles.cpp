// Handles of the persistent world: a slot's generation at the end of its 32 bits retires the
// slot rather than wrapping, so no handle ever names a second object; erasing a light with many
// entries moves the entries after it, not its own.
#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

#include "comb_outline.hpp"
#include "world/world.hpp"

namespace par2d::detail {

// Ages a slot as 2^32 - 2 removals in it would (running them takes hours).
struct WorldTestAccess {
  static std::uint32_t generation(const World& w, std::uint64_t id) {
    return w.slots_[static_cast<std::size_t>((id & 0xffffffffu) - 1)].generation;
  }
  static void set_generation(World& w, std::uint64_t id, std::uint32_t generation) {
    w.slots_[static_cast<std::size_t>((id & 0xffffffffu) - 1)].generation = generation;
  }
};

}  // namespace par2d::detail

namespace par2d::test {
namespace {

constexpr std::uint32_t kLastGeneration = std::numeric_limits<std::uint32_t>::max();

Light lamp(double x) { return Light{Circle{{x, 8.0}, 1.0}, {1.0, 1.0, 1.0}, 1.0}; }
Occluder post(double x) { return Occluder{Circle{{x, 4.0}, 0.5}}; }

detail::World framed_world() {
  detail::World w;
  REQUIRE(w.set_frame(16, 16, View{0, 0, 16, 16}).ok());
  return w;
}

}  // namespace

TEST_CASE("a light slot at its last generation retires on removal: the old handle never names a new light") {
  detail::World w = framed_world();
  LightHandle first;
  REQUIRE(w.add_light(lamp(4.0), &first).ok());
  // The slot as it is after 2^32 - 2 add/remove cycles: this handle carries the last generation.
  detail::WorldTestAccess::set_generation(w, first.id, kLastGeneration);
  const LightHandle aged{(static_cast<std::uint64_t>(kLastGeneration) << 32) | (first.id & 0xffffffffu)};
  REQUIRE(w.find_light(aged.id) != nullptr);
  REQUIRE(w.remove_light(aged).ok());
  // Every add after it takes a fresh slot; no handle of any earlier generation of the old slot
  // (generations 1 .. 2^32 - 1) names anything.
  std::vector<LightHandle> added(4);
  for (LightHandle& h : added) REQUIRE(w.add_light(lamp(6.0), &h).ok());
  for (const LightHandle& h : added) CHECK((h.id & 0xffffffffu) != (first.id & 0xffffffffu));
  for (const std::uint64_t g : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{kLastGeneration}}) {
    CAPTURE(g);
    CHECK(w.find_light((g << 32) | (first.id & 0xffffffffu)) == nullptr);
  }
  CHECK(w.remove_light(aged).code() == StatusCode::invalid_argument);
  CHECK(w.light_count() == 4);
}

TEST_CASE("an occluder slot at its last generation retires on removal") {
  detail::World w = framed_world();
  OccluderHandle first;
  REQUIRE(w.add_occluder(post(4.0), &first).ok());
  detail::WorldTestAccess::set_generation(w, first.id, kLastGeneration);
  const OccluderHandle aged{(static_cast<std::uint64_t>(kLastGeneration) << 32) | (first.id & 0xffffffffu)};
  REQUIRE(w.remove_occluder(aged).ok());
  OccluderHandle next;
  REQUIRE(w.add_occluder(post(8.0), &next).ok());
  CHECK((next.id & 0xffffffffu) != (first.id & 0xffffffffu));
  CHECK(w.find_occluder((std::uint64_t{1} << 32) | (first.id & 0xffffffffu)) == nullptr);
  CHECK(w.find_occluder(next.id) != nullptr);
}

TEST_CASE("set_scene keeps retired slots retired and retires slots at their last generation") {
  detail::World w = framed_world();
  Scene scene;
  scene.width = scene.height = 16;
  scene.view = {0, 0, 16, 16};
  scene.lights = {lamp(2.0), lamp(6.0)};
  scene.occluders = {post(10.0)};
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(w.set_scene(scene, &lights, &occluders).ok());
  // The first light's slot at its last generation: the next set_scene must not reuse it.
  detail::WorldTestAccess::set_generation(w, lights[0].id, kLastGeneration);
  const std::uint64_t aged_slot = lights[0].id & 0xffffffffu;
  for (int round = 0; round < 3; ++round) {
    CAPTURE(round);
    std::vector<LightHandle> again;
    std::vector<OccluderHandle> again_occluders;
    REQUIRE(w.set_scene(scene, &again, &again_occluders).ok());
    for (const LightHandle& h : again) CHECK((h.id & 0xffffffffu) != aged_slot);
    for (const OccluderHandle& h : again_occluders) CHECK((h.id & 0xffffffffu) != aged_slot);
    CHECK(again.size() == 2);
    CHECK(again_occluders.size() == 1);
    for (const std::uint64_t g : {std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{kLastGeneration}})
      CHECK(w.find_light((g << 32) | aged_slot) == nullptr);
    CHECK(detail::WorldTestAccess::generation(w, (std::uint64_t{1} << 32) | aged_slot) == 0);
    // Adds after a set_scene never take the retired slot either.
    LightHandle extra;
    REQUIRE(w.add_light(lamp(12.0), &extra).ok());
    CHECK((extra.id & 0xffffffffu) != aged_slot);
  }
}

TEST_CASE("changing or removing a concave light moves each later entry once per entry erased, none of its own") {
  // A comb of 250 teeth is 501 entries (251 pieces and 250 shared boundaries); a lamp comes
  // after them. Erasing the comb's entries from the first up moved the rest of them each time
  // (125,000 moves); from the last down only the lamp moves, once per entry.
  detail::World w = framed_world();
  Light comb{Polygon{bench::comb_outline(250, false)}, {1.0, 1.0, 1.0}, 1.0};
  LightHandle comb_handle, lamp_handle;
  REQUIRE(w.add_light(comb, &comb_handle).ok());
  REQUIRE(w.add_light(lamp(4.0), &lamp_handle).ok());
  std::size_t moved = w.lit_entries_moved();
  for (Vec2& v : std::get<Polygon>(comb.shape).vertices) v.x += 0.5;
  REQUIRE(w.update_light(comb_handle, comb).ok());
  CHECK(w.lit_entries_moved() - moved <= 501);
  moved = w.lit_entries_moved();
  REQUIRE(w.remove_light(comb_handle).ok());
  CHECK(w.lit_entries_moved() - moved <= 501);
  const Scene snapshot = w.snapshot();
  REQUIRE(snapshot.lights.size() == 1);  // the lamp, untouched
  CHECK(std::get<Circle>(snapshot.lights[0].shape).center.x == 4.0);
}

}  // namespace par2d::test
