// A light's emission e_L (docs/contract.md section 6): intensity * color, or with `normalize`
// scaled so that `intensity` is the irradiance at the reference distance whatever the light's
// size. One definition for validation, the World, the ray caster and every renderer.
#pragma once

#include <cstdint>

#include "par2d/scene.hpp"

namespace par2d::detail {

// The light's reference radius rho: the largest distance from its centre (a circle's center, a
// segment's midpoint, the mean of a polygon's vertices) to a point of the shape.
double reference_radius(const Shape& shape) noexcept;

// The factor `normalize` multiplies intensity * color by: pi / asin(min(1, rho / D)) for
// reference distance D (1 without normalize). A circle light then gives exactly `intensity`
// (times color) at distance D >= radius from its center, with nothing in front and the range
// window, cone and shading aside. +infinity where rho / D rounds to 0.
double emission_scale(const Light& light) noexcept;

// e_L = intensity * color * scale per channel; a dark channel stays 0 whatever the scale.
Rgb light_emission(const Rgb& color, double intensity, double scale) noexcept;
inline Rgb light_emission(const Light& light) noexcept {
  return light_emission(light.color, light.intensity, emission_scale(light));
}

// A light whose shadow removes less than all of it (Light::shadow) is rendered as two parts
// (docs/contract.md section 6): the part occluders act on, emitting e * k, and the part no
// occluder acts on (mask 0), emitting e * (1 - k), k = strength * (1 - shadow color) per channel;
// their sum is (1 - k) U + k S exactly. A light with k = 1 wherever it emits is one part,
// `whole` (itself); one with k = 0 wherever it emits is one part, `unshadowed`.
enum class LightPart : std::uint8_t { whole, shadowed, unshadowed };

// The parts an emitting light is rendered as: `first` always, `second` only for a split light
// (first shadowed, second unshadowed).
struct LightParts {
  LightPart first = LightPart::whole;
  bool split = false;
};
LightParts light_parts(const Light& light) noexcept;

// The emission of one part of `light`: light_emission(light) for `whole`, times k or 1 - k.
Rgb part_emission(const Light& light, LightPart part) noexcept;

}  // namespace par2d::detail
