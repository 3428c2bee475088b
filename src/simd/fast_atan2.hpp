// Vectorized atan2 in float for the tile kernels (reference: std::atan2).
//
// One division t = min(|x|, |y|) / max(|x|, |y|) in [0, 1] and a minimax odd polynomial
// of degree 17 for atan there, t + t^3 Q(t^2) (coefficients fitted by the Remez exchange
// for the least maximum error, 7.4e-9 rad in exact arithmetic): no second range reduction
// (the Cephes atanf reduction to |t| <= tan(pi/8) cost a compare, three selects and an add,
// more than the four extra multiply-adds). In float the absolute error is below 3e-7 rad
// over all inputs (measured worst 2.66e-7 over 3.2e7 inputs, near 3*pi/4 where one float
// ulp is 2.4e-7; pinned by tests/test_simd.cpp). An angle error e moves E by at
// most e/(2*pi) * e_L per arc end, far inside the contract's 1e-4 * e_max. No NaN for any
// finite input: atan2(0, 0) is 0.
#pragma once

#include <xsimd/xsimd.hpp>

namespace par2d::simd {

// atan(t) for |t| <= 1: the polynomial alone. It is odd, so a negative t needs no sign
// handling; fast_atan2 reduces every direction to t in [0, 1] first, and a caller that knows
// its directions lie within 45 degrees of a fixed one (the kernel's arc windows, see
// KernelShape::window) measures them from it with one division and this.
template <class A>
inline xsimd::batch<float, A> atan_unit(const xsimd::batch<float, A>& t) noexcept {
  using B = xsimd::batch<float, A>;
  const B z = t * t;
  B q = xsimd::fma(B(2.622245972e-3f), z, B(-1.513254197e-2f));
  q = xsimd::fma(q, z, B(4.112186931e-2f));
  q = xsimd::fma(q, z, B(-7.366706905e-2f));
  q = xsimd::fma(q, z, B(1.057393247e-1f));
  q = xsimd::fma(q, z, B(-1.418597540e-1f));
  q = xsimd::fma(q, z, B(1.999039664e-1f));
  q = xsimd::fma(q, z, B(-3.333298706e-1f));
  return xsimd::fma(q * z, t, t);  // t + t^3 Q: the small term's rounding stays small
}

template <class A>
inline xsimd::batch<float, A> fast_atan2(const xsimd::batch<float, A>& y, const xsimd::batch<float, A>& x) noexcept {
  using B = xsimd::batch<float, A>;
  const B ax = xsimd::abs(x), ay = xsimd::abs(y);
  const B hi = xsimd::max(ax, ay), lo = xsimd::min(ax, ay);
  // atan2(0, 0) = 0: the denominator is kept off 0 (it is below float's smallest normal only
  // within ~1e-38 of the origin, where the direction is noise anyway).
  const B t = lo / xsimd::max(hi, B(1.17549435e-38f));
  const B p = atan_unit(t);
  B r = xsimd::select(ay > ax, B(1.57079632679f) - p, p);
  r = xsimd::select(x < B(0.0f), B(3.14159265359f) - r, r);
  // The sign of y (a sign flip, no compare).
  return xsimd::bitwise_xor(r, xsimd::bitwise_and(y, B(-0.0f)));
}

// fast_atan2 for y >= 0 (an angle in [0, pi]: the angle between two directions from the
// absolute value of their cross product and their dot product): the same value, without
// y's absolute value and sign.
template <class A>
inline xsimd::batch<float, A> fast_atan2_upper(const xsimd::batch<float, A>& y, const xsimd::batch<float, A>& x) noexcept {
  using B = xsimd::batch<float, A>;
  const B ax = xsimd::abs(x);
  const B hi = xsimd::max(ax, y), lo = xsimd::min(ax, y);
  const B p = atan_unit(lo / xsimd::max(hi, B(1.17549435e-38f)));
  const B r = xsimd::select(y > ax, B(1.57079632679f) - p, p);
  return xsimd::select(x < B(0.0f), B(3.14159265359f) - r, r);
}

// fast_atan2 for x >= 0 and y >= 0 (an angle in [0, pi/2]).
template <class A>
inline xsimd::batch<float, A> fast_atan2_first_quadrant(const xsimd::batch<float, A>& y,
                                                        const xsimd::batch<float, A>& x) noexcept {
  using B = xsimd::batch<float, A>;
  const B hi = xsimd::max(x, y), lo = xsimd::min(x, y);
  const B p = atan_unit(lo / xsimd::max(hi, B(1.17549435e-38f)));
  return xsimd::select(y > x, B(1.57079632679f) - p, p);
}

}  // namespace par2d::simd
