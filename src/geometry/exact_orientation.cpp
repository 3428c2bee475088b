// Exact orientation of three points (polygon_partition.hpp's `orientation`): a floating-point
// filter, then a fixed-point sum wide enough for any product of two doubles where the filter
// cannot decide. The partition's decisions all rest on it.
#include <cmath>
#include <cstdint>
#include <limits>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

int sign_of(double v) noexcept { return (v > 0.0) - (v < 0.0); }

// The library's exact_cross_from assumes coordinates scaled below 2^500 and no underflow; a partition takes raw user coordinates, so its fallback is a fixed-point sum
// wide enough for any product of two doubles (2^-2252 .. 2^2048): never wrong, and only
// reached when the filter cannot decide (exactly or nearly collinear points).

constexpr int kLimbs = 68;  // 4352 bits: products span bits 0..4300, three of them add up to 4302

struct WideSum {
  std::uint64_t limb[kLimbs] = {};

  void add_shifted(std::uint64_t low, std::uint64_t high, int offset) noexcept {
    const int k = offset / 64, s = offset % 64;
    std::uint64_t words[3];
    if (s == 0) {
      words[0] = low;
      words[1] = high;
      words[2] = 0;
    } else {
      words[0] = low << s;
      words[1] = (low >> (64 - s)) | (high << s);
      words[2] = high >> (64 - s);
    }
    std::uint64_t carry = 0;
    for (int i = k; i < kLimbs; ++i) {
      const std::uint64_t add = (i - k < 3 ? words[i - k] : 0);
      if (i - k >= 3 && carry == 0) break;
      const std::uint64_t sum = limb[i] + add;
      const std::uint64_t c1 = sum < add ? 1u : 0u;
      const std::uint64_t total = sum + carry;
      const std::uint64_t c2 = total < sum ? 1u : 0u;
      limb[i] = total;
      carry = c1 + c2;
    }
  }
};

// |x| = mantissa * 2^exponent with an integer mantissa below 2^53 (x != 0, finite).
void split_double(double x, std::uint64_t& mantissa, int& exponent) noexcept {
  int e = 0;
  const double f = std::frexp(std::abs(x), &e);  // f in [0.5, 1)
  mantissa = static_cast<std::uint64_t>(std::ldexp(f, 53));
  exponent = e - 53;  // >= -1126 (2^-1074 = 2^52 * 2^-1126), <= 971
}

// Adds sign * x * y exactly to `positive` or `negative`.
void add_product(WideSum& positive, WideSum& negative, int sign, double x, double y) noexcept {
  if (x == 0.0 || y == 0.0) return;
  if (x < 0.0) sign = -sign;
  if (y < 0.0) sign = -sign;
  std::uint64_t mx = 0, my = 0;
  int ex = 0, ey = 0;
  split_double(x, mx, ex);
  split_double(y, my, ey);
  // 53 x 53 -> 106 bits in two words, from 32-bit halves.
  const std::uint64_t xl = mx & 0xffffffffu, xh = mx >> 32, yl = my & 0xffffffffu, yh = my >> 32;
  const std::uint64_t ll = xl * yl, mid = xh * yl + xl * yh, hh = xh * yh;  // mid < 2^54
  const std::uint64_t low = ll + (mid << 32);
  const std::uint64_t high = hh + (mid >> 32) + (low < ll ? 1u : 0u);
  (sign > 0 ? positive : negative).add_shifted(low, high, ex + ey + 2252);
}

[[gnu::noinline]] int exact_orientation(Vec2 a, Vec2 b, Vec2 c) noexcept {
  // (b - a) x (c - a) = bx cy - bx ay - ax cy - by cx + by ax + ay cx.
  WideSum positive, negative;
  add_product(positive, negative, 1, b.x, c.y);
  add_product(positive, negative, -1, b.x, a.y);
  add_product(positive, negative, -1, a.x, c.y);
  add_product(positive, negative, -1, b.y, c.x);
  add_product(positive, negative, 1, b.y, a.x);
  add_product(positive, negative, 1, a.y, c.x);
  for (int i = kLimbs - 1; i >= 0; --i) {
    if (positive.limb[i] != negative.limb[i]) return positive.limb[i] > negative.limb[i] ? 1 : -1;
  }
  return 0;
}

}  // namespace

int orientation(Vec2 a, Vec2 b, Vec2 c) noexcept {
  const double dx1 = b.x - a.x, dy1 = b.y - a.y, dx2 = c.x - a.x, dy2 = c.y - a.y;
  // A difference of doubles is zero only when they are equal, and its sign is always exact,
  // so where one product has a zero factor the result's sign is the other product's sign
  // (axis-aligned outlines, tile maps, live here).
  if (dx1 == 0.0 || dy2 == 0.0) return -(sign_of(dy1) * sign_of(dx2));
  if (dy1 == 0.0 || dx2 == 0.0) return sign_of(dx1) * sign_of(dy2);
  const double l = dx1 * dy2, r = dy1 * dx2;
  const double magnitude = std::abs(l) + std::abs(r);
  // Shewchuk's orient2d bound is (3 + 16 eps) eps * magnitude (eps = 2^-53); 2^-50 leaves room
  // for the absolute error of products that underflowed, which the 2^-900 floor keeps far
  // below it. Infinite or NaN magnitudes (overflowed differences) fail the test.
  if (magnitude < kInfinity && magnitude > 0x1p-900) {
    const double det = l - r, bound = 0x1p-50 * magnitude;
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return exact_orientation(a, b, c);
}

}  // namespace par2d::detail
