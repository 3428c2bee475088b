// The game lighting model's share of a tile's work (docs/contract.md section 6): which
// occluders act on and shadow a light, range culling, the kernel's light and occluder terms,
// directional lights, ambient and per-pixel normals.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "render/kernel_shapes.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Whether occluder k may prove a shadow of a light with this mask: only opaque, dark-interior
// occluders acting on it hide what lies behind them.
inline bool proves_shadow(const PreparedScene& scene, std::uint32_t k, std::uint32_t light_mask) noexcept {
  const OccluderTerms& t = scene.occluder_terms[k];
  return t.opaque() && !t.lit_interior && t.acts_on(light_mask);
}

// Whether every point of `box` lies at least `range` from the light's shape (its box is
// nearer than the shape): the range window is 0 there.
inline bool beyond_range(const Aabb& box, const ConvexShape& light, const LightTerms& terms) noexcept {
  if (!terms.has_range()) return false;
  const double dx = std::max({light.bounds_min.x - box.max_x, 0.0, box.min_x - light.bounds_max.x});
  const double dy = std::max({light.bounds_min.y - box.max_y, 0.0, box.min_y - light.bounds_max.y});
  return std::hypot(dx, dy) >= terms.range;
}

inline KernelOccluderTerms kernel_occluder_terms(const OccluderTerms& t) noexcept {
  KernelOccluderTerms k;
  for (int c = 0; c < 3; ++c) k.transmittance[c] = static_cast<float>(t.transmittance[static_cast<std::size_t>(c)]);
  k.opaque = t.opaque();
  k.lit_interior = t.lit_interior;
  return k;
}

// A light's model terms for the kernel, past those its pairs set (KernelLightTerms::translucent).
// `ranged`: the light's range window applies (its kernel shape is then kept whole); `scale`:
// the tile frame's.
void finish_light_terms(const LightTerms& light, bool ranged, double scale, KernelLightTerms& terms) noexcept;

// Per-thread buffers of the directional lights.
struct DirectionalScratch {
  std::vector<Vec2> hull;               // one part of the tile's swept box
  std::vector<std::uint32_t> found;     // the index's answer for one part
  std::vector<std::uint32_t> occluders; // a directional light's candidate occluders
};

// Directional lights: tile lights whose pairs are every acting occluder a ray of their arc
// may meet from the tile (all are in front: the light is at infinity), appended to `work`
// with their terms; their occluders are interned into `occluders`.
void add_directional_lights(const PreparedScene& scene, const std::array<Vec2, 4>& corners, const Aabb& box,
                            DirectionalScratch& scratch, TileOccluders& occluders, TileWork& work);

// The tile's ambient term and, when `shaded` and the scene has a normal source, its normals.
void set_tile_shading(const PreparedScene& scene, const TileRect& tile, bool shaded, TileWork& work);

}  // namespace par2d::detail
