// A light's emission e_L (docs/contract.md section 6): intensity * color, or with `normalize`
// scaled so that `intensity` is the irradiance at the reference distance whatever the light's
// size. One definition for validation, the World, the ray caster and every renderer.
#pragma once

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

}  // namespace par2d::detail
