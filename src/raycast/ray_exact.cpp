// Exact predicates for the ray caster: error-free products and distilled sums.
#include "raycast/ray_exact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace par2d::detail::ray_exact {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Exact sum of n doubles (n <= 32) to within an ulp or so of the result, by distillation:
// passes of error-free additions (Knuth's two-sum) along the terms until none changes, which
// leaves them nonoverlapping, largest last. Written apart from src/geometry's expansions.
double distilled_sum(double* t, int n) noexcept {
  for (int pass = 0; pass < 4 * n + 8; ++pass) {
    bool changed = false;
    for (int i = 1; i < n; ++i) {
      const double s = t[i - 1] + t[i];
      const double v = s - t[i - 1];
      const double e = (t[i - 1] - (s - v)) + (t[i] - v);
      if (s != t[i] || e != t[i - 1]) changed = true;
      t[i] = s;
      t[i - 1] = e;
    }
    if (!changed) break;
  }
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += t[i];
  return sum;
}

// Writes a*b as two terms summing to it exactly (fused multiply-add gives the rounding error).
void push_product(double a, double b, double* t, int& n) noexcept {
  const double p = a * b;
  t[n++] = p;
  t[n++] = std::fma(a, b, -p);
}

// cross(a - x, b - a) (= cross(a - x, b - x)), accurate where the plain products cancel: a
// segment 1e17 long a unit from x. The plain value is kept when it is far above its rounding.
}  // namespace

double side_of(Vec2 a, Vec2 b, Vec2 x) noexcept {
  const Vec2 w = a - x, e = b - a;
  const double l = w.x * e.y, r = w.y * e.x;
  const double magnitude = std::fabs(l) + std::fabs(r);
  if (std::fabs(l - r) > 0x1p-20 * magnitude || !(magnitude < kInf)) return l - r;
  // a - x = ah + al and b - x = bh + bl exactly (two-sum), then the eight products, each split.
  auto split_difference = [](double p, double q, double& hi, double& lo) {
    hi = p - q;
    const double v = hi - p;
    lo = (p - (hi - v)) + (-q - v);
  };
  double ahx, alx, ahy, aly, bhx, blx, bhy, bly;
  split_difference(a.x, x.x, ahx, alx);
  split_difference(a.y, x.y, ahy, aly);
  split_difference(b.x, x.x, bhx, blx);
  split_difference(b.y, x.y, bhy, bly);
  double t[16];
  int n = 0;
  for (double ax : {ahx, alx})
    for (double by : {bhy, bly}) push_product(ax, by, t, n);
  for (double ay : {ahy, aly})
    for (double bx : {bhx, blx}) push_product(-ay, bx, t, n);
  return distilled_sum(t, n);
}

// |x - c|^2 - r^2, accurate where it cancels (x near a circle of radius 1e17).
double power_of(Vec2 c, double r, Vec2 x) noexcept {
  const Vec2 m = x - c;
  const double mm = dot(m, m), rr = r * r;
  if (std::fabs(mm - rr) > 0x1p-20 * (mm + rr) || !(mm + rr < kInf)) return mm - rr;
  double t[16];
  int n = 0;
  for (int axis = 0; axis < 2; ++axis) {
    const double p = axis == 0 ? x.x : x.y, q = axis == 0 ? c.x : c.y;
    const double hi = p - q, v = hi - p, lo = (p - (hi - v)) + (-q - v);
    push_product(hi, hi, t, n);
    push_product(2.0 * hi, lo, t, n);
    push_product(lo, lo, t, n);
  }
  push_product(-r, r, t, n);
  return distilled_sum(t, n);
}

// Smallest t >= 0 with x + t*d on the closed segment [a, b], or +inf.
double ray_segment(Vec2 x, Vec2 d, Vec2 a, Vec2 b) noexcept {
  const Vec2 e = b - a;
  const Vec2 w = a - x;
  const double denom = cross(d, e);
  if (denom == 0.0) {
    // Parallel: only a collinear segment can be hit, and then at its nearer end
    // (or at t = 0 when x lies on it).
    if (cross(w, d) != 0.0) return kInf;
    double ta = dot(w, d);
    double tb = dot(b - x, d);
    if (ta > tb) std::swap(ta, tb);
    if (tb < 0.0) return kInf;
    return ta <= 0.0 ? 0.0 : ta;
  }
  // The ray's line separates a from b (or touches one): decided by each end's own side, so
  // a vertex shared by two segments (a segment light ending at an occluder's corner) is on the
  // same side for both. The quotient s = cross(w, d) / denom in [0, 1] rounds differently per
  // segment there, and a ray through the corner hit the light but missed the occluder.
  const double side_a = cross(d, w), side_b = cross(d, b - x);
  if ((side_a > 0.0 && side_b > 0.0) || (side_a < 0.0 && side_b < 0.0)) return kInf;
  // The hit is a point of the segment, so its distance along the ray (|d| = 1) lies between
  // the ends' own. Clamped there: for a ray almost along the segment the quotient is two
  // rounding residues (a ray along a light's edge from an occluder's corner where the edge
  // starts put the hit before the corner, and the light in front of the occluder).
  const double ta = dot(w, d), tb = dot(b - x, d);
  const double t = std::clamp(side_of(a, b, x) / denom, std::min(ta, tb), std::max(ta, tb));
  return t < 0.0 ? kInf : t;
}

}  // namespace par2d::detail::ray_exact
