// The part of a light outside the occluder it sits in: what reach, proofs and pair separators
// use for a light poking into a wall, since the cap inside the wall reaches no one.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// The one clip every renderer stage uses for `light`: the first of its overlaps (in the order
// of overlapping_occluders) whose occluder cuts off a cap of the light (LightOverlap::clips)
// and hides what lies behind it for this light (opaque, dark inside, acting on its mask: the
// cap then reaches no point outside the occluder, and a point inside sees nothing).
// An index into light.overlaps, or -1.
int designated_clip(const PreparedScene& scene, const PreparedLight& light) noexcept;

// A convex polygon P with (light minus the clip's cap) inside P inside the clip line's closed
// negative side: the light clipped at the line, a circle as its circumscribed 16-gon first.
// Every segment from a point outside the occluder to a light point outside P ends in the cap,
// inside the occluder: so a proof that P is hidden hides the light, and a line separating P
// from another occluder separates every light point that the kernel's clipped light keeps.
// False (out untouched) for a segment light or when nothing of the light is left.
bool visible_part(const ConvexShape& light, const LightClip& clip, ConvexShape& out, std::vector<Vec2>& scratch);

// Per block and thread: each light's visible part when it has a designated clip.
struct VisibleLights {
  struct Entry {
    int clip = -1;               // designated_clip, or -1: the light is used whole
    std::uint32_t occluder = 0;  // the clipping occluder when clip >= 0
    Line line;                   // its clip line (the light's kept part on side <= 0)
    ConvexShape shape;           // visible_part when clip >= 0
    // What `shape` was made from (the light's vertices and radius, the clip line): kept from
    // block to block and frame to frame while they stay, so it is made again only when
    // one of them changes, not per block.
    std::vector<Vec2> made_from;
    double made_radius = -1.0;
    Line made_line{};
  };
  std::vector<Entry> entries;
  std::vector<Vec2> points;

  // Reserves an entry per light with room for a visible part of a light of up to
  // `max_vertices` vertices (allocates; when the counts change). visible_part cuts a convex
  // polygon of n points (a light's vertices, or a circle's kCircleSides) by one line: n + 1
  // points at most.
  void reserve_for(std::size_t lights, std::size_t max_vertices);
  std::size_t reserved_bytes() const noexcept;

  // Fills entries for every light of the scene (cheap for lights without overlaps).
  void update(const PreparedScene& scene);
  // The shape stages after the overlap test see: the visible part, or the light itself.
  const ConvexShape& shape(const PreparedScene& scene, std::size_t l) const noexcept {
    return l < entries.size() && entries[l].clip >= 0 ? entries[l].shape : scene.lights[l].shape;
  }
  const Entry* clipped(std::size_t l) const noexcept {
    return l < entries.size() && entries[l].clip >= 0 ? &entries[l] : nullptr;
  }
};

}  // namespace par2d::detail
