// What the World's files share (world.cpp, world_occluders.cpp): emission and part terms of
// a user's light, the one-line refusals, and a light's sorted overlap list.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>

#include "lighting/light_emission.hpp"
#include "par2d/scene.hpp"
#include "par2d/status.hpp"
#include "scene/scene_validate.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail::world_support {

inline bool emits(const Light& light) noexcept {
  const double e = std::max({light.intensity * light.color[0], light.intensity * light.color[1],
                             light.intensity * light.color[2]});
  return e > 0.0;
}

// A part's terms: the light's, with no occluder acting on its unshadowed part.
inline LightTerms part_terms(const Light& light, LightPart part, double scale) noexcept {
  LightTerms terms = light_terms(light, scale);
  if (part == LightPart::unshadowed) terms.mask = 0;
  return terms;
}

// `who: place: what`, e.g. `light 4294967298: polygon: edges 1 and 3 cross`.
inline Status refused(const std::string& who, const SceneProblem& problem) {
  std::string message = who + ": ";
  if (!problem.place.empty()) {
    // Places come as ".polygon..." relative to the object.
    message += problem.place[0] == '.' ? problem.place.substr(1) : problem.place;
    message += ": ";
  }
  message += problem.what;
  return Status(StatusCode::invalid_scene, std::move(message));
}

inline Status unknown_handle(const char* kind, std::uint64_t id) {
  return Status(StatusCode::invalid_argument, std::string("unknown ") + kind + " handle " + std::to_string(id));
}

// Keeps a light's overlap list sorted by occluder, its overlaps in step.
// The overlap goes to `spares` with its buffer (the pool of find_light_overlaps).
inline void erase_overlap(PreparedLight& light, std::uint32_t k, std::vector<LightOverlap>& spares) {
  auto& list = light.overlapping_occluders;
  const auto it = std::lower_bound(list.begin(), list.end(), k);
  if (it == list.end() || *it != k) return;
  const auto i = it - list.begin();
  list.erase(it);
  std::rotate(light.overlaps.begin() + i, light.overlaps.begin() + i + 1, light.overlaps.end());
  spares.push_back(std::move(light.overlaps.back()));
  light.overlaps.pop_back();
}

inline void insert_overlap(PreparedLight& light, std::uint32_t k, LightOverlap overlap) {
  auto& list = light.overlapping_occluders;
  const auto it = std::lower_bound(list.begin(), list.end(), k);
  const auto i = it - list.begin();
  list.insert(it, k);
  light.overlaps.insert(light.overlaps.begin() + i, std::move(overlap));
}

}  // namespace par2d::detail::world_support
