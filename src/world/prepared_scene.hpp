// The validated scene in the form every renderer reads: canonical shapes, emissions,
// and which light/occluder pairs overlap (those need the general visibility test).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "world/occluder_bvh.hpp"
#include "par2d/scene.hpp"

namespace par2d::detail {

struct PreparedLight {
  ConvexShape shape;
  Rgb emission{};  // intensity * color
  // Occluders whose shape meets this light's (sorted). For such a pair the blocked
  // directions are not all-or-nothing per direction interval; see scalar_renderer.
  std::vector<std::uint32_t> overlapping_occluders;
  // For each of those, where the two boundaries meet: the only directions at which the
  // nearer of the two shapes can change.
  std::vector<std::vector<Vec2>> overlap_points;
};

// Separating lines of disjoint light/occluder pairs (occluder on the positive side),
// computed the first time a tile asks and then shared by every tile and thread: a pair
// matters to many tiles, and the exact closest-point computation costs more than a tile.
class PairSeparators {
 public:
  // All pairs unknown, for `lights` x `occluders`.
  void reset(std::size_t lights, std::size_t occluders);
  // Persistent worlds (single-threaded, between frames): room for `lights` x `occluders`
  // keeping what is known (grows capacity geometrically, so steady state never allocates);
  // forget a light's row or an occluder's column; move one (swap-removal).
  void resize(std::size_t lights, std::size_t occluders);
  void forget_light(std::size_t light) noexcept;
  void forget_occluder(std::size_t occluder) noexcept;
  void move_light(std::size_t from, std::size_t to) noexcept;
  void move_occluder(std::size_t from, std::size_t to) noexcept;
  // The line for (light, occluder), or empty when the shapes touch or overlap.
  std::optional<Line> get(std::size_t light, std::size_t occluder, const ConvexShape& light_shape,
                          const ConvexShape& occluder_shape) const noexcept;

 private:
  enum : std::uint8_t { kUnknown = 0, kComputing = 1, kSeparated = 2, kTouching = 3 };
  void copy_pair(std::size_t from, std::size_t to) noexcept;
  std::size_t lights_ = 0, occluders_ = 0;
  std::size_t rows_ = 0, stride_ = 0;  // capacity: lights x occluders
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
  std::unique_ptr<Line[]> lines_;
};

// Coordinates are the scene's times a power of two chosen in prepare_scene (exact, and
// irradiance does not depend on scale), so that no scene's products of coordinates
// underflow or overflow.
struct PreparedScene {
  int width = 0, height = 0;
  View view;
  std::vector<PreparedLight> lights;  // lights with non-zero emission only
  std::vector<ConvexShape> occluders;
  double e_max = 0.0;  // docs/contract.md section 5
  // Largest distance from the view's center to any point of the view or of a shape's box.
  double extent = 0.0;
  OccluderBvh occluder_bvh;  // over the occluders' bounding boxes
  PairSeparators separators;
};

// Builds the prepared form of a scene that passed validate_scene.
PreparedScene prepare_scene(const Scene& scene);

// The pieces prepare_scene is made of, for worlds that change shape by shape.
// The power of two all prepared coordinates are scaled by (see PreparedScene).
double scene_scale(const View& view, double largest_coordinate) noexcept;
void scale_shape(ConvexShape& shape, double factor) noexcept;
// e_max and extent of a prepared scene from its view, lights and occluders.
void update_scene_bounds(PreparedScene& scene) noexcept;
// light.overlapping_occluders / overlap_points from scratch, with the scene's index.
void find_light_overlaps(const PreparedScene& scene, PreparedLight& light, std::vector<std::uint32_t>& scratch);

// World position of sample (sx, sy) in [0,1)^2 of pixel (i, j) of a width x height
// image of `view` (docs/contract.md section 2).
inline Vec2 sample_position(const View& view, int width, int height, int i, int j, double sx, double sy) noexcept {
  return {view.x0 + (i + sx) * (view.x1 - view.x0) / width, view.y0 + (j + sy) * (view.y1 - view.y0) / height};
}

// The same in the prepared scene's (scaled) coordinates.
inline Vec2 sample_position(const PreparedScene& s, int i, int j, double sx, double sy) noexcept {
  return sample_position(s.view, s.width, s.height, i, j, sx, sy);
}

}  // namespace par2d::detail
