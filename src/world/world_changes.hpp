// What a World says when it changes, for the render-time caches kept beside it (the
// Renderer's per-block change tracking, render/change_tracker.hpp, which passes each event on
// to culling's light reach cache). The World holds no cache of its own: it tells one observer
// what changed, in the terms its PreparedScene uses, and the observer decides what that
// invalidates.
#pragma once

#include <cstddef>

#include "geometry/aabb.hpp"

namespace par2d::detail {

// Lights are numbered as in PreparedScene::lights (emitting lights only), the order a tile sums
// them in. Erasing a light renumbers the lights above it one lower, keeping their order (so a
// pixel none of them changed sums alike).
class WorldObserver {
 public:
  // Every light is new (the whole world was prepared again: a new scene, a new coordinate
  // scale); `count` lights. Must not throw: it is called after the new state is in place.
  virtual void lights_reset(std::size_t count) noexcept = 0;
  // A light was appended (number count - 1).
  virtual void light_added() = 0;
  // Light `p`'s shape or lighting-model terms changed (an emission change alone is not reported:
  // nothing geometric depends on it).
  virtual void light_changed(std::size_t p) noexcept = 0;
  // Light `p` was erased; the lights numbered above it now have the numbers one lower.
  virtual void light_erased(std::size_t p) noexcept = 0;
  // Occluders inside `box` (prepared coordinates) appeared, moved or disappeared.
  virtual void region_changed(const Aabb& box) noexcept = 0;
  // The frame's size or view changed (anything measured in pixels or bounded by the view).
  virtual void frame_changed() noexcept = 0;
  // The view moved by whole pixels on its pixel grid (PreparedScene::grid_x, grid_y): pixels
  // keep their positions on the grid, only the visible rectangle moved.
  virtual void frame_scrolled() noexcept = 0;
  // Light `p`'s emission (colour, intensity) changed and nothing else: nothing geometric
  // depends on it, so the reach ignores it; pixels do (render/change_tracker.hpp).
  virtual void light_emission_changed(std::size_t /*p*/) noexcept {}
  // An occluder inside `box` took another number (the last one takes a removed one's): its
  // shape is unchanged, but the order of a block's candidates may follow the numbers.
  virtual void occluder_renumbered(const Aabb& /*box*/) noexcept {}
  // The scene-wide terms (ambient, directional lights, normal source) were replaced.
  virtual void terms_changed() noexcept {}

 protected:
  ~WorldObserver() = default;
};

}  // namespace par2d::detail
