// The game lighting model's direction weights in closed form (docs/contract.md section 6):
// a spot light's cone profile c(theta) and the clamped-cosine shading s(theta), and their
// integral over any interval of directions. Written once over the number type: `double` for
// the scalar reference, an xsimd float batch for the tile kernels (one lane per pixel).
//
// Frame: u = theta - origin, where `origin` is the start of the arc being integrated (a light's
// clockwise tangent, a directional light's first angle), so the arc is u in [0, width],
// width <= 2 pi. profile_cumulative(p, u) is an antiderivative of c(u) * s(u) on [0, 2 pi]; the
// weight of a visible piece [a, b] is profile_cumulative(p, b) - profile_cumulative(p, a).
// Antiderivatives are taken piece by piece relative to each piece's own center (the cone's
// axis, the lobe's peak), so float keeps its precision however far the arc is from 0.
#pragma once

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "lighting/cookie_segments.hpp"

namespace par2d::detail {

inline constexpr double kProfilePi = 3.14159265358979323846;
inline constexpr double kProfileTwoPi = 2.0 * kProfilePi;

// The few operations that differ between double and a batch.
inline double profile_select(bool m, double a, double b) noexcept { return m ? a : b; }
inline double profile_min(double a, double b) noexcept { return std::min(a, b); }
inline double profile_max(double a, double b) noexcept { return std::max(a, b); }
inline double profile_wrap(double a) noexcept {  // into [0, 2 pi)
  a -= kProfileTwoPi * std::floor(a / kProfileTwoPi);
  return a < kProfileTwoPi ? a : 0.0;
}
inline void profile_sincos(double a, double& s, double& c) noexcept {
  s = std::sin(a);
  c = std::cos(a);
}
inline double profile_acos(double a) noexcept { return std::acos(a); }
inline double profile_atan2(double y, double x) noexcept { return std::atan2(y, x); }
inline double profile_sqrt(double a) noexcept { return std::sqrt(a); }

// The batch forms, where xsimd has a vector architecture: a file compiled without one (the
// scalar reference of a WebAssembly build without SIMD128) gets only the double forms above.
#if !defined(XSIMD_NO_SUPPORTED_ARCHITECTURE)
template <class A>
xsimd::batch<float, A> profile_select(const xsimd::batch_bool<float, A>& m, const xsimd::batch<float, A>& a,
                                      const xsimd::batch<float, A>& b) noexcept {
  return xsimd::select(m, a, b);
}
template <class A>
xsimd::batch<float, A> profile_min(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) noexcept {
  return xsimd::min(a, b);
}
template <class A>
xsimd::batch<float, A> profile_max(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) noexcept {
  return xsimd::max(a, b);
}
template <class A>
xsimd::batch<float, A> profile_wrap(const xsimd::batch<float, A>& a) noexcept {
  using B = xsimd::batch<float, A>;
  const B w = a - B(static_cast<float>(kProfileTwoPi)) * xsimd::floor(a * B(static_cast<float>(1.0 / kProfileTwoPi)));
  return xsimd::select(w < B(static_cast<float>(kProfileTwoPi)), w, B(0.0f));
}
template <class A>
void profile_sincos(const xsimd::batch<float, A>& a, xsimd::batch<float, A>& s, xsimd::batch<float, A>& c) noexcept {
  const auto sc = xsimd::sincos(a);
  s = sc.first;
  c = sc.second;
}
template <class A>
xsimd::batch<float, A> profile_acos(const xsimd::batch<float, A>& a) noexcept {
  return xsimd::acos(a);
}
template <class A>
xsimd::batch<float, A> profile_atan2(const xsimd::batch<float, A>& y, const xsimd::batch<float, A>& x) noexcept {
  return xsimd::atan2(y, x);
}
template <class A>
xsimd::batch<float, A> profile_sqrt(const xsimd::batch<float, A>& a) noexcept {
  return xsimd::sqrt(a);
}
#endif

// A double constant as T (float batches round it to float explicitly).
template <class T>
T profile_constant(double v) noexcept {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else {
    return T(static_cast<float>(v));
  }
}

template <class T>
T profile_clamp(const T& v, const T& lo, const T& hi) noexcept {
  return profile_min(profile_max(v, lo), hi);
}

// c(u) * s(u) for one light at one point. `cone` and `shading` are the same for every lane
// (a light has a cone or not; a scene has a normal source or not), so they are plain bools.
template <class T>
struct AngularProfile {
  bool cone = false;
  bool shading = false;
  // Cone (a trapezoid over u): weight 1 within `plateau` of `cone_center`, 0 beyond `half`,
  // linear between (slope `inv_fade`, 0 when the fade is 0: no ramp).
  T cone_center{}, plateau{}, half{}, inv_fade{};
  // Shading: s(u) = max(0, amplitude * cos(u - lobe_center) + offset), positive on
  // |u - lobe_center| < lobe_half (lobe_half in [0, pi]).
  T lobe_center{}, lobe_half{}, amplitude{}, offset{};
  // A cookie instead of the cone (never both): its segments, shared by every lane, and how far
  // the frame's start lies past the cookie's first knot (in [0, 2 pi), per lane).
  const CookieSegments* cookie = nullptr;
  T cookie_shift{};
};

// The slope 1 / fade of a cone's ramps, as the number type holds them; 0 (a hard edge) for a
// ramp too narrow to resolve. The ramp's width is taken as T stores the cone (half minus
// plateau), so slope and width agree. Float angles near 2 pi are 5e-7 rad apart: a ramp
// narrower than kNarrowestRamp (2^-20 rad, about 5.5e-5 degree) is a few of those steps, and as
// a hard edge at its middle it is off by at most a quarter of its width in any integral
// (2.4e-7 rad of 2 pi: far inside the SIMD bound). Double keeps every ramp whose slope is
// finite (a fade below ~1e-308 rad has none; 0 * inf would be NaN).
template <class T>
double profile_ramp_slope(double half, double fade) noexcept {
  if constexpr (std::is_same_v<T, double>) {
    const double width = half - (half - fade);
    const double slope = width > 0.0 ? 1.0 / width : 0.0;
    return std::isfinite(slope) ? slope : 0.0;
  } else {
    constexpr float kNarrowestRamp = 1.0f / (1 << 20);
    const float width = static_cast<float>(half) - static_cast<float>(half - fade);
    return width >= kNarrowestRamp ? 1.0 / static_cast<double>(width) : 0.0;
  }
}

// A cone whose axis is the ray direction `center` (radians, any value), half angle `half`
// and fade `fade` (radians, 0 <= fade <= half <= pi), in the frame starting at `origin`.
template <class T>
void set_profile_cone(AngularProfile<T>& p, const T& origin, double center, double half, double fade) noexcept {
  p.cone = true;
  p.cone_center = profile_wrap(profile_constant<T>(center) - origin);
  const double slope = profile_ramp_slope<T>(half, fade);
  // An unresolved ramp becomes a hard edge at its middle (off by at most a quarter of its width).
  const double edge = slope > 0.0 ? half : half - 0.5 * fade;
  p.half = profile_constant<T>(edge);
  p.plateau = profile_constant<T>(slope > 0.0 ? half - fade : edge);
  p.inv_fade = profile_constant<T>(slope);
}

// Fills the cookie's slopes and its float copy (after its offsets, widths, values, rises and
// areas).
inline void finish_cookie_segments(CookieSegments& c) noexcept {
  CookieSegments::Floats& f = c.floats;
  f.area = static_cast<float>(c.area);
  for (int k = 0; k < c.count; ++k) {
    c.slope[k] = c.rise[k] * profile_ramp_slope<double>(c.width[k], c.width[k]);
    f.offset[k] = static_cast<float>(c.offset[k]);
    f.width[k] = static_cast<float>(c.width[k]);
    f.value[k] = static_cast<float>(c.value[k]);
    f.slope[k] = static_cast<float>(c.rise[k] * profile_ramp_slope<float>(c.width[k], c.width[k]));
    f.low[k] = static_cast<float>(std::min(c.value[k], c.value[k] + c.rise[k]));
    f.high[k] = static_cast<float>(std::max(c.value[k], c.value[k] + c.rise[k]));
    f.area_before[k] = static_cast<float>(c.area_before[k]);
  }
}

// A cookie in the frame starting at `origin`.
template <class T>
void set_profile_cookie(AngularProfile<T>& p, const T& origin, const CookieSegments* cookie) noexcept {
  p.cookie = cookie;
  p.cookie_shift = profile_wrap(origin - profile_constant<T>(cookie->first));
}

// Shading by the unit surface normal (nx, ny, nz) for light from elevation angle alpha
// (sin_el = sin alpha, cos_el = cos alpha): s(theta) = max(0, n . (cos_el cos theta,
// cos_el sin theta, sin_el)) = max(0, A cos(theta - beta) + C) with A = cos_el |n_xy|,
// beta = atan2(ny, nx), C = sin_el nz. `beta` is passed in (it is the same for every light).
template <class T>
void set_profile_shading(AngularProfile<T>& p, const T& origin, const T& beta, const T& normal_xy,
                         const T& nz, double sin_el, double cos_el) noexcept {
  p.shading = true;
  p.amplitude = profile_constant<T>(cos_el) * normal_xy;
  p.offset = profile_constant<T>(sin_el) * nz;
  p.lobe_center = profile_wrap(beta - origin);
  // s > 0 where cos(u - beta) > -C / A. A = 0: s is the constant max(0, C).
  const auto flat = p.amplitude <= T(0.0);
  const T ratio = profile_select(flat, profile_select(p.offset > T(0.0), T(-1.0), T(1.0)),
                                 -p.offset / profile_select(flat, T(1.0), p.amplitude));
  p.lobe_half = profile_acos(profile_clamp(ratio, T(-1.0), T(1.0)));
}

namespace profile_detail {

// Integral of the unit trapezoid (1 on |v| <= plateau, 0 beyond half) from -infinity to v.
template <class T>
T trapezoid_cumulative(const AngularProfile<T>& p, const T& v) noexcept {
  const T fade = p.half - p.plateau;
  const T rise = profile_clamp(v + p.half, T(0.0), fade);
  const T fall = profile_clamp(v - p.plateau, T(0.0), fade);
  const T half_slope = T(0.5) * p.inv_fade;
  return rise * rise * half_slope + profile_clamp(v + p.plateau, T(0.0), p.plateau + p.plateau) + fall -
         fall * fall * half_slope;
}

// Integral of max(0, A cos t + C) over t from -lobe_half to v, for the lobe centered at 0.
template <class T>
T lobe_cumulative(const AngularProfile<T>& p, const T& v) noexcept {
  const T t = profile_clamp(v, -p.lobe_half, p.lobe_half);
  T s, c;
  profile_sincos(t, s, c);
  return p.amplitude * s + p.offset * t;
}

// Integral over v in [lo, hi] (relative to the lobe's center) of (value_lo + slope (v - lo)) *
// (A cos v + C). Written around the piece's middle m and half width h (sin hi - sin lo =
// 2 cos m sin h, cos hi - cos lo = -2 sin m sin h), so no term is a difference of nearly equal
// numbers: each is off by about an ulp times the piece's width, and the slope times the width
// is at most 1. (The form around the lobe's center, c0 * base + slope * ramp with c0 = value at
// the center, cancelled catastrophically for steep ramps: c0 ~ pi / fade.)
template <class T>
T linear_times_lobe(const AngularProfile<T>& p, const T& value_lo, const T& slope, const T& lo, const T& hi) noexcept {
  const T h = T(0.5) * (hi - lo);
  const T w = h + h;
  T sm, cm, sh, ch;
  profile_sincos(lo + h, sm, cm);
  profile_sincos(h, sh, ch);
  const T& a = p.amplitude;
  const T& c = p.offset;
  const T base = T(2.0) * a * cm * sh + c * w;
  // Integral of (v - lo)(A cos v + C) = A (w sin hi + cos hi - cos lo) + C w^2 / 2.
  const T sin_hi = sm * ch + cm * sh;
  const T ramp = a * (w * sin_hi - T(2.0) * sm * sh) + c * T(0.5) * w * w;
  return value_lo * base + slope * ramp;
}

// A cookie segment in the number type: its width and slope, the weights at its two ends in
// order. A segment narrower than float resolves (profile_ramp_slope) keeps its start weight
// over its width: off by at most width * |rise|, below 2^-20 rad of 2 pi.
template <class T>
struct CookiePiece {
  T width, value, slope, low, high;
};
// One of the cookie's numbers as T: the double, or its float copy broadcast.
template <class T>
T cookie_number(const double* d, const float* f, int k) noexcept {
  if constexpr (std::is_same_v<T, double>) {
    return d[k];
  } else {
    return T(f[k]);
  }
}

template <class T>
CookiePiece<T> cookie_piece(const CookieSegments& c, int k) noexcept {
  const CookieSegments::Floats& f = c.floats;
  CookiePiece<T> piece;
  piece.width = cookie_number<T>(c.width, f.width, k);
  piece.value = cookie_number<T>(c.value, f.value, k);
  piece.slope = cookie_number<T>(c.slope, f.slope, k);
  if constexpr (std::is_same_v<T, double>) {
    piece.low = std::min(c.value[k], c.value[k] + c.rise[k]);
    piece.high = std::max(c.value[k], c.value[k] + c.rise[k]);
  } else {
    piece.low = T(f.low[k]);
    piece.high = T(f.high[k]);
  }
  return piece;
}

// The cookie's antiderivative (no shading), measured from its first knot: the point's offset
// r past that knot (one turn's area added where u + shift passes a turn), the segment holding
// r found by comparisons (no branch per lane), then the areas before it plus its own part up
// to r, relative to its start so float keeps its precision.
template <class T>
T cookie_cumulative(const AngularProfile<T>& p, const T& u) noexcept {
  const CookieSegments& c = *p.cookie;
  const CookieSegments::Floats& f = c.floats;
  const T turn = profile_constant<T>(kProfileTwoPi);
  const T d = u + p.cookie_shift;
  const auto past = d >= turn;
  const T r = profile_select(past, d - turn, d);
  T start(0.0), before(0.0);
  T width = cookie_number<T>(c.width, f.width, 0), value = cookie_number<T>(c.value, f.value, 0);
  T slope = cookie_number<T>(c.slope, f.slope, 0);
  for (int k = 1; k < c.count; ++k) {
    const T offset = cookie_number<T>(c.offset, f.offset, k);
    const auto in = r >= offset;
    start = profile_select(in, offset, start);
    before = profile_select(in, cookie_number<T>(c.area_before, f.area_before, k), before);
    width = profile_select(in, cookie_number<T>(c.width, f.width, k), width);
    value = profile_select(in, cookie_number<T>(c.value, f.value, k), value);
    slope = profile_select(in, cookie_number<T>(c.slope, f.slope, k), slope);
  }
  T area;
  if constexpr (std::is_same_v<T, double>) {
    area = c.area;
  } else {
    area = T(f.area);
  }
  const T t = profile_clamp(r - start, T(0.0), width);
  return profile_select(past, area, T(0.0)) + before + t * (value + T(0.5) * slope * t);
}

// The cookie times the lobe: every segment copy (the two that can meet [0, 2 pi]: a segment
// starts in [0, 2 pi) and is at most 2 pi wide) against every lobe copy that can overlap,
// integrated from -infinity (a constant that differences cancel) to u, as for the cone.
template <class T>
T cookie_lobe_cumulative(const AngularProfile<T>& p, const T& u) noexcept {
  T sum(0.0);
  const CookieSegments& c = *p.cookie;
  for (int k = 0; k < c.count; ++k) {
    const CookiePiece<T> piece = cookie_piece<T>(c, k);
    // Where segment k starts in the frame, in [0, 2 pi).
    const T first = profile_wrap(cookie_number<T>(c.offset, c.floats.offset, k) - p.cookie_shift);
    for (int copy = -1; copy <= 0; ++copy) {
      const T start = first + profile_constant<T>(copy * kProfileTwoPi);
      const T end = start + piece.width;
      for (int j = -1; j <= 1; ++j) {
        const T lobe = p.lobe_center + profile_constant<T>(j * kProfileTwoPi);
        const T lo = profile_max(start, lobe - p.lobe_half);
        const T hi = profile_min(end, profile_min(lobe + p.lobe_half, u));
        const auto some = hi > lo;
        const T value_lo = profile_clamp(piece.value + piece.slope * (lo - start), piece.low, piece.high);
        const T part = linear_times_lobe(p, value_lo, piece.slope, profile_select(some, lo, lobe) - lobe,
                                         profile_select(some, hi, lobe) - lobe);
        sum = sum + profile_select(some, part, T(0.0));
      }
    }
  }
  return sum;
}

}  // namespace profile_detail

// An antiderivative of c(u) * s(u) (each 1 when absent) on u in [0, 2 pi].
template <class T>
T profile_cumulative(const AngularProfile<T>& p, const T& u) noexcept {
  using namespace profile_detail;
  if (p.cookie) return p.shading ? cookie_lobe_cumulative(p, u) : cookie_cumulative(p, u);
  if (!p.cone && !p.shading) return u;
  // Copies of the profile at -2pi, 0, +2pi: the ones that can meet [0, 2 pi] (each piece's
  // support is at most 2 pi wide and centered in [0, 2 pi)).
  if (!p.shading) {
    T sum(0.0);
    for (int k = -1; k <= 1; ++k) sum = sum + trapezoid_cumulative(p, u - p.cone_center - profile_constant<T>(k * kProfileTwoPi));
    return sum;
  }
  if (!p.cone) {
    T sum(0.0);
    for (int k = -1; k <= 1; ++k) sum = sum + lobe_cumulative(p, u - p.lobe_center - profile_constant<T>(k * kProfileTwoPi));
    return sum;
  }
  // Both: the cone's three linear pieces times the lobe, for every pair of copies that can
  // overlap, integrated from -infinity (a constant that differences cancel) to u.
  T sum(0.0);
  for (int j = -1; j <= 1; ++j) {
    const T lobe = p.lobe_center + profile_constant<T>(j * kProfileTwoPi);
    const T lobe_lo = lobe - p.lobe_half, lobe_hi = profile_min(lobe + p.lobe_half, u);
    for (int k = -1; k <= 1; ++k) {
      const T axis = p.cone_center + profile_constant<T>(k * kProfileTwoPi);
      // (start, end, slope) of the rise, the plateau and the fall.
      const T starts[3] = {axis - p.half, axis - p.plateau, axis + p.plateau};
      const T ends[3] = {axis - p.plateau, axis + p.plateau, axis + p.half};
      const T slopes[3] = {p.inv_fade, T(0.0), -p.inv_fade};
      for (int piece = 0; piece < 3; ++piece) {
        const T lo = profile_max(starts[piece], lobe_lo);
        const T hi = profile_min(ends[piece], lobe_hi);
        const auto some = hi > lo;
        // The cone's weight where the piece starts (in [0, 1] up to rounding of lo).
        const T value_lo = piece == 1   ? T(1.0)
                           : piece == 0 ? profile_clamp((lo - starts[0]) * p.inv_fade, T(0.0), T(1.0))
                                        : profile_clamp((ends[2] - lo) * p.inv_fade, T(0.0), T(1.0));
        const T part = linear_times_lobe(p, value_lo, slopes[piece], profile_select(some, lo, lobe) - lobe,
                                         profile_select(some, hi, lobe) - lobe);
        sum = sum + profile_select(some, part, T(0.0));
      }
    }
  }
  return sum;
}

// The range window w(d) = clamp(1 - (d / range)^2, 0, 1)^falloff for d < range, 0 beyond,
// range > 0, falloff in [0, 16]. Divided, not multiplied by 1 / range: a range near the number
// type's smallest values has no finite inverse (0 * inf would be NaN inside the light). d >=
// range gives 0 directly, so the quotient is in [0, 1); d = 0 (inside the light) gives 1 even
// where the range itself rounded to 0. The default falloff 2 is a product, any other a power
// (`power(base)`: base^falloff in the number type, base in (0, 1]).
template <class T, class Power>
T range_window(const T& distance, const T& range, double falloff, const Power& power) noexcept {
  const auto within = distance < range;
  const T q = profile_select(within, distance / profile_select(within, range, T(1.0)), T(1.0));
  const T w = T(1.0) - q * q;
  T window = w * w;
  if (falloff != 2.0) {
    // w is 0 only at or beyond the range (0^0 would be 1 there); the power of a positive base.
    const auto positive = w > T(0.0);
    window = profile_select(positive, power(profile_select(positive, w, T(1.0))), T(0.0));
  }
  return profile_select(distance > T(0.0), window, T(1.0));
}

// The default falloff's window, clamp(1 - (d / range)^2, 0, 1)^2.
template <class T>
T range_window(const T& distance, const T& range) noexcept {
  return range_window(distance, range, 2.0, [](const T& base) { return base; });
}

}  // namespace par2d::detail
