// The counts of a prepared scene that bound every per-thread buffer of a frame: buffers are
// reserved by them when they change (render/frame_driver.cpp), so that moving existing lights
// anywhere never makes a frame allocate.
#pragma once

#include <algorithm>
#include <cstddef>

#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

struct SceneBounds {
  std::size_t lights = 0, occluders = 0, directionals = 0;
  std::size_t max_vertices = 0;  // the most vertices of a light or an occluder
  // Room for boundary meeting points in the scene's overlaps, in use or spare: at least the
  // points of all overlaps, which a tile copies at most once each (TileWork::point_x). Not
  // compared: it only grows with the overlaps' buffers.
  std::size_t overlap_points = 0;

  // Light-occluder pairs a tile may hold: each light (scene or directional) pairs with each
  // occluder at most once. Buffers of pairs are reserved for at most kReservedTilePairs of
  // them (tiles with more, in levels of many lights and thousands of occluders, grow them).
  static constexpr std::size_t kReservedTilePairs = 4096;
  std::size_t tile_pairs() const noexcept {
    return std::min((lights + directionals) * occluders, kReservedTilePairs);
  }

  // A light's block candidates and the occluders one occlusion proof holds are reserved for
  // at most kReservedCandidates per lane (a block of a dense level that sees more grows them):
  // lights x occluders per lane would be megabytes in levels of thousands of occluders.
  static constexpr std::size_t kReservedCandidates = 512;
  std::size_t candidates() const noexcept { return std::min(occluders, kReservedCandidates); }

  bool operator==(const SceneBounds& o) const noexcept {
    return lights == o.lights && occluders == o.occluders && directionals == o.directionals &&
           max_vertices == o.max_vertices;
  }
  bool operator!=(const SceneBounds& o) const noexcept { return !(*this == o); }
};

// Cells a tile may be split into (cell_lists.hpp): at least kCellPixels pixels each.
inline constexpr std::size_t kMaxTileCells = kTilePixels / kCellPixels;

inline SceneBounds scene_bounds(const PreparedScene& scene) noexcept {
  SceneBounds b;
  b.lights = scene.lights.size();
  b.occluders = scene.occluders.size();
  b.directionals = scene.directionals.size();
  for (const PreparedLight& l : scene.lights) {
    b.max_vertices = std::max(b.max_vertices, l.shape.vertices.size());
    for (const LightOverlap& o : l.overlaps) b.overlap_points += o.points.capacity();
  }
  for (const LightOverlap& o : scene.spare_overlaps) b.overlap_points += o.points.capacity();
  for (const ConvexShape& o : scene.occluders) b.max_vertices = std::max(b.max_vertices, o.vertices.size());
  return b;
}

}  // namespace par2d::detail
