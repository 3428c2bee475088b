// Error-free sums and products, and the pseudo-cross product exact in sign, for the geometry
// room's .cpp files (convex_shape.cpp, convex_shape_queries.cpp); not an interface for other rooms.
#pragma once

#include <cmath>
#include <limits>

#include "geometry/vec2.hpp"

namespace par2d::detail {

// Error-free transformations: a + b = s + e and a * b = p + e exactly (no overflow assumed;
// coordinates are scaled to at most 2^500 before they get here, so products fit).
inline void two_sum(double a, double b, double& s, double& e) noexcept {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

inline void two_product(double a, double b, double& p, double& e) noexcept {
  p = a * b;
  e = std::fma(a, b, -p);
}

// An exact sum of doubles as a nonoverlapping expansion (Shewchuk's grow-expansion with zero
// elimination): components in increasing magnitude whose sum is exactly what was added.
class ExactSum {
 public:
  void add(double x) noexcept {
    int kept = 0;
    for (int i = 0; i < count_; ++i) {
      double s, e;
      two_sum(x, parts_[i], s, e);
      if (e != 0.0) parts_[kept++] = e;
      x = s;
    }
    if (x != 0.0) parts_[kept++] = x;
    count_ = kept;
  }
  void add_product(double a, double b) noexcept {
    double p, e;
    two_product(a, b, p, e);
    add(e);
    add(p);
  }
  // The sum to about an ulp: the components, smallest first, add up with little rounding.
  double value() const noexcept {
    double v = 0.0;
    for (int i = 0; i < count_; ++i) v += parts_[i];
    return v;
  }

 private:
  static constexpr int kMaxParts = 40;  // at most one part per input: 20 products here
  double parts_[kMaxParts];
  int count_ = 0;
};

// Beyond this fraction of the sum of the magnitudes of its terms, a plain cross product or
// power is accurate to ~2^-30 of itself (its rounding is a few ulps of the magnitudes).
inline constexpr double kPlainEnough = 0x1p-20;

// cross(a - x, b - x) summed without error (convex_shape.cpp). Out of line: rarely needed.
[[gnu::noinline]] double exact_cross_from(Vec2 a, Vec2 b, Vec2 x) noexcept;

// cross_from's plain path, inlined where the geometry room uses it (the exact one is out of line).
inline double side_of(Vec2 a, Vec2 b, Vec2 x) noexcept {
  const Vec2 w = a - x, e = b - a;
  const double l = w.x * e.y, r = w.y * e.x;
  const double plain = l - r;
  const double magnitude = std::abs(l) + std::abs(r);
  if (std::abs(plain) > kPlainEnough * magnitude || !(magnitude < std::numeric_limits<double>::infinity()))
    return plain;
  return exact_cross_from(a, b, x);
}

}  // namespace par2d::detail
