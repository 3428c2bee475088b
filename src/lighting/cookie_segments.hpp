// A light's cookie (docs/contract.md section 6) in the form the renderers integrate: the
// periodic piecewise-linear weight over ray directions, one linear segment per knot. Kept
// apart from the profile's closed forms (angular_profile.hpp) so the prepared scene holds it
// without the SIMD headers.
#pragma once

namespace par2d::detail {

// Segment k starts `offset[k]` radians past the first knot (offset[0] = 0, increasing; the
// first knot's ray direction is `first`, in [0, 2 pi)) with weight `value[k]` and runs
// `width[k]` radians (> 0; the widths sum to 2 pi) to weight value[k] + rise[k] (the next
// knot's). `area_before[k]` is the integral of the weight over the segments before k, `area`
// over the whole turn. A fixed array: a light's terms are copied without allocating.
inline constexpr int kMaxCookieSegments = 32;
struct CookieSegments {
  int count = 0;  // 0: no cookie
  double first = 0.0;
  double area = 0.0;
  double offset[kMaxCookieSegments] = {};
  double width[kMaxCookieSegments] = {};
  double value[kMaxCookieSegments] = {};
  double rise[kMaxCookieSegments] = {};
  double area_before[kMaxCookieSegments] = {};
  // rise / width as the double path takes it (profile_ramp_slope in angular_profile.hpp: 0
  // where the width is below what the number type resolves), worked out once here rather
  // than in every evaluation.
  double slope[kMaxCookieSegments] = {};
  // The same numbers rounded once for the float kernels (their slope by float's own rule),
  // so an evaluation broadcasts them instead of converting each.
  struct Floats {
    float area = 0.0f;
    float offset[kMaxCookieSegments] = {};
    float width[kMaxCookieSegments] = {};
    float value[kMaxCookieSegments] = {};
    float slope[kMaxCookieSegments] = {};
    float low[kMaxCookieSegments] = {};
    float high[kMaxCookieSegments] = {};
    float area_before[kMaxCookieSegments] = {};
  } floats;
};

}  // namespace par2d::detail
