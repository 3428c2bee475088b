// Interval arithmetic on directions: clipping arcs to a light's arc and measuring unions.
#include "geometry/angular_intervals.hpp"

#include <algorithm>
#include <cmath>

namespace par2d::detail {

double angle_in_light_frame(const AngularSpan& light, double direction) noexcept {
  double a = std::fmod(direction - light.start, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  if (a >= kTwoPi) a -= kTwoPi;
  return a;
}

void clip_to_light_arc(const AngularSpan& light, const AngularSpan& span, std::vector<ArcInterval>& out) {
  const double w = light.width;
  if (span.full) {
    if (w > 0.0) out.push_back({0.0, w});
    return;
  }
  const double lo = angle_in_light_frame(light, span.start);
  const double hi = lo + span.width;
  if (lo < w) out.push_back({lo, std::min(hi, w)});
  if (hi > kTwoPi) {  // wraps past the light's start
    const double wrapped = std::min(hi - kTwoPi, w);
    if (wrapped > 0.0) out.push_back({0.0, wrapped});
  }
}

double union_measure(std::vector<ArcInterval>& intervals) noexcept {
  std::sort(intervals.begin(), intervals.end(),
            [](const ArcInterval& a, const ArcInterval& b) { return a.lo < b.lo; });
  double covered = 0.0, reach = 0.0;
  for (const ArcInterval& i : intervals) {
    const double lo = std::max(i.lo, reach);
    if (i.hi > lo) covered += i.hi - lo;
    reach = std::max(reach, i.hi);
  }
  return covered;
}

}  // namespace par2d::detail
