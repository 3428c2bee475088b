// Vectorized atan2 in float for the tile kernels (reference: std::atan2).
//
// Range reduction to |t| <= tan(pi/8) and the Cephes atanf polynomial: the absolute
// error is below 3e-7 rad over all inputs (measured worst 2.7e-7, near +-pi where one
// float ulp is 2.4e-7; pinned by tests/test_simd.cpp). An angle error e moves E by at
// most e/(2*pi) * e_L per arc end, far inside the contract's 1e-4 * e_max. No NaN for any
// finite input: atan2(0, 0) is 0.
#pragma once

#include <xsimd/xsimd.hpp>

namespace par2d::simd {

template <class A>
inline xsimd::batch<float, A> fast_atan2(const xsimd::batch<float, A>& y, const xsimd::batch<float, A>& x) noexcept {
  using B = xsimd::batch<float, A>;
  const B ax = xsimd::abs(x), ay = xsimd::abs(y);
  const B hi = xsimd::max(ax, ay), lo = xsimd::min(ax, ay);
  // One division: t = lo/hi, or (lo - hi)/(lo + hi) = tan(atan(lo/hi) - pi/4) when
  // lo/hi > tan(pi/8). atan2(0, 0) = 0: the denominator is kept off 0 (it is below float's
  // smallest normal only within ~1e-38 of the origin, where the direction is noise anyway).
  const auto reduce = lo > B(0.41421356237f) * hi;
  const B num = xsimd::select(reduce, lo - hi, lo);
  const B den = xsimd::max(xsimd::select(reduce, lo + hi, hi), B(1.17549435e-38f));
  const B t = num / den;
  const B z = t * t;
  B p = xsimd::fma(B(8.05374449538e-2f), z, B(-1.38776856032e-1f));
  p = xsimd::fma(p, z, B(1.99777106478e-1f));
  p = xsimd::fma(p, z, B(-3.33329491539e-1f));
  p = xsimd::fma(p * z, t, t);
  p += xsimd::select(reduce, B(0.785398163397f), B(0.0f));
  B r = xsimd::select(ay > ax, B(1.57079632679f) - p, p);
  r = xsimd::select(x < B(0.0f), B(3.14159265359f) - r, r);
  // The sign of y (a sign flip, no compare).
  return xsimd::bitwise_xor(r, xsimd::bitwise_and(y, B(-0.0f)));
}

}  // namespace par2d::simd
