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
};

// A cone whose axis is the ray direction `center` (radians, any value), half angle `half`
// and fade `fade` (radians, 0 <= fade <= half <= pi), in the frame starting at `origin`.
template <class T>
void set_profile_cone(AngularProfile<T>& p, const T& origin, double center, double half, double fade) noexcept {
  p.cone = true;
  p.cone_center = profile_wrap(T(center) - origin);
  p.half = T(half);
  p.plateau = T(half - fade);
  p.inv_fade = T(fade > 0.0 ? 1.0 / fade : 0.0);
}

// Shading by the unit surface normal (nx, ny, nz) for light from elevation angle alpha
// (sin_el = sin alpha, cos_el = cos alpha): s(theta) = max(0, n . (cos_el cos theta,
// cos_el sin theta, sin_el)) = max(0, A cos(theta - beta) + C) with A = cos_el |n_xy|,
// beta = atan2(ny, nx), C = sin_el nz. `beta` is passed in (it is the same for every light).
template <class T>
void set_profile_shading(AngularProfile<T>& p, const T& origin, const T& beta, const T& normal_xy,
                         const T& nz, double sin_el, double cos_el) noexcept {
  p.shading = true;
  p.amplitude = T(cos_el) * normal_xy;
  p.offset = T(sin_el) * nz;
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

// Integral over v in [lo, hi] (relative to the lobe's center) of (c0 + slope v)(A cos v + C).
template <class T>
T linear_times_lobe(const AngularProfile<T>& p, const T& c0, const T& slope, const T& lo, const T& hi) noexcept {
  T slo, clo, shi, chi;
  profile_sincos(lo, slo, clo);
  profile_sincos(hi, shi, chi);
  const T& a = p.amplitude;
  const T& c = p.offset;
  const T base = a * (shi - slo) + c * (hi - lo);
  const T ramp = a * ((hi * shi + chi) - (lo * slo + clo)) + c * T(0.5) * (hi * hi - lo * lo);
  return c0 * base + slope * ramp;
}

}  // namespace profile_detail

// An antiderivative of c(u) * s(u) (each 1 when absent) on u in [0, 2 pi].
template <class T>
T profile_cumulative(const AngularProfile<T>& p, const T& u) noexcept {
  using namespace profile_detail;
  if (!p.cone && !p.shading) return u;
  // Copies of the profile at -2pi, 0, +2pi: the ones that can meet [0, 2 pi] (each piece's
  // support is at most 2 pi wide and centered in [0, 2 pi)).
  if (!p.shading) {
    T sum(0.0);
    for (int k = -1; k <= 1; ++k) sum = sum + trapezoid_cumulative(p, u - p.cone_center - T(k * kProfileTwoPi));
    return sum;
  }
  if (!p.cone) {
    T sum(0.0);
    for (int k = -1; k <= 1; ++k) sum = sum + lobe_cumulative(p, u - p.lobe_center - T(k * kProfileTwoPi));
    return sum;
  }
  // Both: the cone's three linear pieces times the lobe, for every pair of copies that can
  // overlap, integrated from -infinity (a constant that differences cancel) to u.
  T sum(0.0);
  for (int j = -1; j <= 1; ++j) {
    const T lobe = p.lobe_center + T(j * kProfileTwoPi);
    const T lobe_lo = lobe - p.lobe_half, lobe_hi = profile_min(lobe + p.lobe_half, u);
    for (int k = -1; k <= 1; ++k) {
      const T axis = p.cone_center + T(k * kProfileTwoPi);
      // (start, end, value at the lobe's center, slope) of the rise, the plateau and the fall.
      const T starts[3] = {axis - p.half, axis - p.plateau, axis + p.plateau};
      const T ends[3] = {axis - p.plateau, axis + p.plateau, axis + p.half};
      const T values[3] = {(lobe - starts[0]) * p.inv_fade, T(1.0), (ends[2] - lobe) * p.inv_fade};
      const T slopes[3] = {p.inv_fade, T(0.0), -p.inv_fade};
      for (int piece = 0; piece < 3; ++piece) {
        const T lo = profile_max(starts[piece], lobe_lo);
        const T hi = profile_min(ends[piece], lobe_hi);
        const auto some = hi > lo;
        const T part = linear_times_lobe(p, values[piece], slopes[piece], profile_select(some, lo, lobe) - lobe,
                                         profile_select(some, hi, lobe) - lobe);
        sum = sum + profile_select(some, part, T(0.0));
      }
    }
  }
  return sum;
}

// The range window w(d) = clamp(1 - (d / range)^2, 0, 1)^2 (inv_range = 1 / range; 0: none).
template <class T>
T range_window(const T& distance, const T& inv_range) noexcept {
  const T q = distance * inv_range;
  const T w = profile_clamp(T(1.0) - q * q, T(0.0), T(1.0));
  return w * w;
}

}  // namespace par2d::detail
