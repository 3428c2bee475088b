// Whether two scene values are the same bit for bit: an update that re-sends what an item
// already holds (an engine syncing every light from its entities each frame) changes nothing,
// so it must mark nothing dirty. Numbers compare by their bits, not by `==`: -0.0 and 0.0 are
// different values (they can take different branches in angle code), so only a value that
// cannot render differently counts as unchanged.
#pragma once

#include "par2d/scene.hpp"

namespace par2d::detail {

bool same_value(double a, double b) noexcept;
bool same_rgb(const Rgb& a, const Rgb& b) noexcept;
bool same_view(const View& a, const View& b) noexcept;
bool same_shape(const Shape& a, const Shape& b) noexcept;
bool same_light(const Light& a, const Light& b) noexcept;
bool same_occluder(const Occluder& a, const Occluder& b) noexcept;
bool same_directional_lights(const std::vector<DirectionalLight>& a, const std::vector<DirectionalLight>& b) noexcept;

}  // namespace par2d::detail
