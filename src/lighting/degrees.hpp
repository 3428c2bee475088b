// Angles as scene files give them (degrees, any finite size), reduced before they become
// radians. One helper for every backend: the prepared terms of the scalar and SIMD paths and
// the ray caster's own.
#pragma once

#include <cmath>

namespace par2d::detail {

// `degrees` modulo 360, exactly: the remainder of two doubles is always representable, so
// std::fmod returns it without rounding. A direction of 1e20 degrees and its residue then
// become the same radians bit for bit; multiplying the raw angle by pi / 180 first would
// round it to a multiple of its ulp (16 degrees near 1e17), far off the direction meant. The
// sign is kept (the result lies in (-360, 360)), so an angle within a turn either way comes
// back unchanged.
inline double reduce_degrees(double degrees) noexcept { return std::fmod(degrees, 360.0); }

}  // namespace par2d::detail
