// The viewer's scene edits without any window code: pick, move, resize, add and delete lights.
#pragma once

#include <optional>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::viewer {

// Maps window pixels to world coordinates for a scene shown in a window of win_w x win_h
// (docs/contract.md section 2: pixel (i, j) samples x0 + (i + 0.5) * (x1 - x0) / width).
struct WindowMapping {
  View view;
  int win_w = 1;
  int win_h = 1;
  Vec2 to_world(double px, double py) const noexcept;
  // The inverse: window position (continuous, pixel (i, j) spans [i, i + 1) x [j, j + 1)) of a world point.
  Vec2 to_window(Vec2 world) const noexcept;
  // World length of one window pixel (the smaller axis's, as the contract's pixel width).
  double pixel_size() const noexcept;
  // World displacement of a mouse move of (dx, dy) window pixels.
  Vec2 delta_to_world(double dx, double dy) const noexcept;
};

// The light whose shape is nearest to `p` within `radius` (0 inside a shape), if any;
// among overlapping lights the last one, the one drawn "on top" in the file's order.
std::optional<std::size_t> pick_light(const Scene& scene, Vec2 p, double radius) noexcept;

// Points along the shape's outline (a closed loop for circles and polygons, the two ends of a
// segment), for drawing it; circles get `circle_points` points.
std::vector<Vec2> outline(const Shape& shape, int circle_points = 48);

// Moves a shape by `d`.
void translate(Shape& shape, Vec2 d) noexcept;

// Scales a shape by `factor` about its center (circle center, segment midpoint, vertex mean).
void scale(Shape& shape, double factor) noexcept;

// Edits that leave the scene valid: each applies the change to a copy, validates it and
// only then commits it to `scene`; they return whether it was applied (a light shrunk
// to nothing or moved to a non-finite place is refused and the scene is left as it was).
bool move_light(Scene& scene, std::size_t index, Vec2 d);
bool scale_light(Scene& scene, std::size_t index, double factor);
// A circle light of `radius` at `p`, with the color and intensity of `like` (if given).
bool add_light(Scene& scene, Vec2 p, double radius, const Light* like);
bool delete_light(Scene& scene, std::size_t index);

}  // namespace par2d::viewer
