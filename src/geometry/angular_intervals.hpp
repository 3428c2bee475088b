// Sets of directions as intervals measured from the start of a light's arc (double precision).
#pragma once

#include <vector>

#include "geometry/convex_shape.hpp"

namespace par2d::detail {

// [lo, hi] in radians after the light's arc start; 0 <= lo <= hi <= light width.
struct ArcInterval {
  double lo = 0.0;
  double hi = 0.0;
};

// Appends the part of `span` that falls inside the light arc [light.start, light.start +
// light.width], in the light's frame: up to two pieces (an arc can wrap past the light's
// start). Empty pieces are not appended.
void clip_to_light_arc(const AngularSpan& light, const AngularSpan& span, std::vector<ArcInterval>& out);

// Measure of the union of the intervals (merged, never summed). Sorts them.
double union_measure(std::vector<ArcInterval>& intervals) noexcept;

// Angle of `direction` in the light's frame, in [0, 2*pi).
double angle_in_light_frame(const AngularSpan& light, double direction) noexcept;

}  // namespace par2d::detail
