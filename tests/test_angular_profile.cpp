// The closed-form cone x clamped-cosine integral (src/lighting/angular_profile.hpp) against numerical quadrature, in double and in float batches.
//
// The reference integrates c(theta) * s(theta) straight from docs/contract.md section 6's
// definitions (the cone's delta = |theta + pi - phi| wrapped to [0, pi], the clamped cosine
// max(0, n . (cos a cos theta, cos a sin theta, sin a))) with Gauss-Legendre quadrature on the
// pieces between the integrand's kinks, where it is smooth (a product of a linear function and
// a shifted cosine): 32 panels of 8 points per piece give ~1e-15, so the closed form must be
// within 1e-9 in double. Float batches (the kernels' number type, at xsimd's default
// architecture) keep ~1e-7 relative per term; 1e-5 absolute over arcs up to 2 pi.
#include <doctest/doctest.h>

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "lighting/angular_profile.hpp"
#include "support/random_scenes.hpp"

namespace par2d::test {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr double kTwoPi = 2.0 * kPi;

// One light's direction weights at one point, from the contract's definitions.
struct Case {
  double origin = 0.0;  // the arc frame's start: u = theta - origin
  bool cone = false;
  double cone_center = 0.0, half = kPi, fade = 0.0;  // ray directions (the axis), radians
  bool shading = false;
  Vec3 normal{0.0, 0.0, 1.0};  // unit
  double elevation = 0.0;      // radians
};

double weight(const Case& k, double theta) {
  double c = 1.0, s = 1.0;
  if (k.cone) {
    const double delta = std::fabs(std::remainder(theta - k.cone_center, kTwoPi));
    c = delta <= k.half - k.fade ? 1.0 : delta >= k.half ? 0.0 : (k.half - delta) / k.fade;
  }
  if (k.shading) {
    const double ce = std::cos(k.elevation);
    s = std::max(0.0, k.normal.x * ce * std::cos(theta) + k.normal.y * ce * std::sin(theta) +
                          k.normal.z * std::sin(k.elevation));
  }
  return c * s;
}

// Integral of weight over theta in [origin + a, origin + b] by Gauss-Legendre quadrature split
// at every kink: the cone's four corners and the two directions where the clamp acts.
double quadrature(const Case& k, double a, double b) {
  std::vector<double> kinks;
  if (k.cone) {
    for (double t : {k.cone_center - k.half, k.cone_center - k.half + k.fade, k.cone_center + k.half - k.fade,
                     k.cone_center + k.half})
      kinks.push_back(t);
  }
  if (k.shading) {
    const double amplitude = std::cos(k.elevation) * std::hypot(k.normal.x, k.normal.y);
    const double offset = std::sin(k.elevation) * k.normal.z;
    if (amplitude > 0.0 && std::fabs(offset / amplitude) < 1.0) {
      const double beta = std::atan2(k.normal.y, k.normal.x), off = std::acos(-offset / amplitude);
      kinks.push_back(beta - off);
      kinks.push_back(beta + off);
    }
  }
  std::vector<double> cuts{a, b};
  for (double t : kinks) {
    for (int m = -3; m <= 3; ++m) {
      const double u = t - k.origin + m * kTwoPi;
      if (u > a && u < b) cuts.push_back(u);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  static const double kNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
  static const double kWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
    const int panels = 32;
    const double step = (cuts[p + 1] - cuts[p]) / panels;
    for (int q = 0; q < panels; ++q) {
      const double mid = k.origin + cuts[p] + (q + 0.5) * step, half = 0.5 * step;
      for (int r = 0; r < 4; ++r)
        sum += half * kWeights[r] * (weight(k, mid - half * kNodes[r]) + weight(k, mid + half * kNodes[r]));
    }
  }
  return sum;
}

Vec3 unit(double x, double y, double z) {
  const double len = std::sqrt(x * x + y * y + z * z);
  return {x / len, y / len, z / len};
}

// Cases covering every cone/shading combination and the edge values: fade 0, fade = half,
// half angle 180, elevation 0 and 90, normals straight up, in the plane and facing away.
std::vector<Case> cases(std::uint32_t seed) {
  PortableRandom rng(seed);
  std::vector<Case> out;
  const Vec3 normals[] = {unit(0, 0, 1), unit(1, 0, 0), unit(0.3, -0.8, 0.5), unit(-0.5, 0.2, -0.6),
                          unit(0, 0, -1), unit(0.1, 0.05, 0.99)};
  const double elevations[] = {0.0, kPi / 2, 0.3, 1.2};
  for (int cone = 0; cone <= 1; ++cone) {
    for (int shading = 0; shading <= 1; ++shading) {
      for (int trial = 0; trial < 24; ++trial) {
        Case k;
        k.origin = rng.uniform(-10.0, 10.0);
        k.cone = cone != 0;
        if (k.cone) {
          k.cone_center = rng.uniform(-10.0, 10.0);
          const int pick = trial % 4;
          k.half = pick == 0 ? kPi : rng.uniform(0.05, kPi);
          k.fade = pick == 1 ? 0.0 : pick == 2 ? k.half : k.half * rng.uniform();
        }
        k.shading = shading != 0;
        if (k.shading) {
          k.normal = trial < 6 ? normals[trial] : unit(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
          k.elevation = elevations[trial % 4];
        }
        out.push_back(k);
      }
    }
  }
  return out;
}

// Intervals [a, b] within [0, 2 pi] to integrate over: the whole frame and random ones.
std::vector<std::array<double, 2>> intervals(PortableRandom& rng) {
  std::vector<std::array<double, 2>> out{{0.0, kTwoPi}, {0.0, 0.0}, {1.0, 1.0 + 1e-3}};
  for (int n = 0; n < 6; ++n) {
    const double a = rng.uniform(0.0, kTwoPi), b = rng.uniform(0.0, kTwoPi);
    out.push_back({std::min(a, b), std::max(a, b)});
  }
  return out;
}

template <class T>
void set_profile(par2d::detail::AngularProfile<T>& p, const Case& k, const T& origin, const T& beta, const T& nxy,
                 const T& nz) {
  if (k.cone) par2d::detail::set_profile_cone(p, origin, k.cone_center, k.half, k.fade);
  if (k.shading) par2d::detail::set_profile_shading(p, origin, beta, nxy, nz, std::sin(k.elevation), std::cos(k.elevation));
}

}  // namespace

TEST_CASE("profile_cumulative in double matches quadrature to 1e-9 for every cone and shading combination") {
  PortableRandom rng(91);
  double worst = 0.0;
  std::string where;
  int compared = 0;
  for (const Case& k : cases(17)) {
    par2d::detail::AngularProfile<double> p;
    set_profile(p, k, k.origin, std::atan2(k.normal.y, k.normal.x), std::hypot(k.normal.x, k.normal.y), k.normal.z);
    for (const auto& [a, b] : intervals(rng)) {
      const double closed = profile_cumulative(p, b) - profile_cumulative(p, a);
      const double err = std::fabs(closed - quadrature(k, a, b));
      ++compared;
      if (err > worst) {
        worst = err;
        std::ostringstream s;
        s.precision(12);
        s << "cone " << k.cone << " (center " << k.cone_center << ", half " << k.half << ", fade " << k.fade
          << ") shading " << k.shading << " (n " << k.normal.x << ", " << k.normal.y << ", " << k.normal.z
          << ", elevation " << k.elevation << ") origin " << k.origin << " over [" << a << ", " << b
          << "]: closed " << closed << ", quadrature " << quadrature(k, a, b);
        where = s.str();
      }
    }
  }
  INFO("worst: " << where);
  CHECK(worst <= 1e-9);
  CHECK(compared == 96 * 9);
  MESSAGE("worst |closed - quadrature| (double): " << worst);
}

TEST_CASE("profile_cumulative in float batches of the default architecture matches quadrature to 1e-5") {
  using Batch = xsimd::batch<float>;
  constexpr std::size_t kLanes = Batch::size;
  PortableRandom rng(92);
  double worst = 0.0;
  std::string where;
  const std::vector<Case> all = cases(18);
  // Lanes are pixels: each lane has its own origin and normal; the cone and the elevation
  // belong to the light and are the same in every lane (as in the kernels).
  for (std::size_t first = 0; first + kLanes <= all.size(); first += kLanes) {
    alignas(64) float origin[kLanes], beta[kLanes], nxy[kLanes], nz[kLanes];
    std::vector<Case> lanes;
    for (std::size_t l = 0; l < kLanes; ++l) {
      Case k = all[first + l];
      const Case& leader = all[first];
      k.cone = leader.cone;
      k.cone_center = leader.cone_center;
      k.half = leader.half;
      k.fade = leader.fade;
      k.shading = leader.shading;
      k.elevation = leader.elevation;
      // The frame's origin in float, and the reference with that same origin.
      origin[l] = static_cast<float>(std::fmod(k.origin, kTwoPi) + kTwoPi);
      k.origin = origin[l];
      beta[l] = static_cast<float>(std::atan2(k.normal.y, k.normal.x));
      nxy[l] = static_cast<float>(std::hypot(k.normal.x, k.normal.y));
      nz[l] = static_cast<float>(k.normal.z);
      lanes.push_back(k);
    }
    par2d::detail::AngularProfile<Batch> p;
    set_profile(p, lanes[0], Batch::load_aligned(origin), Batch::load_aligned(beta), Batch::load_aligned(nxy),
                Batch::load_aligned(nz));
    for (const auto& [a, b] : intervals(rng)) {
      alignas(64) float closed[kLanes];
      (profile_cumulative(p, Batch(static_cast<float>(b))) - profile_cumulative(p, Batch(static_cast<float>(a))))
          .store_aligned(closed);
      for (std::size_t l = 0; l < kLanes; ++l) {
        const double ref = quadrature(lanes[l], static_cast<float>(a), static_cast<float>(b));
        const double err = std::fabs(closed[l] - ref);
        if (err > worst) {
          worst = err;
          std::ostringstream s;
          s << "lane " << l << " of cases from " << first << " over [" << a << ", " << b << "]: closed " << closed[l]
            << ", quadrature " << ref;
          where = s.str();
        }
      }
    }
  }
  INFO("worst: " << where);
  CHECK(worst <= 1e-5);
  MESSAGE("worst |closed - quadrature| (float, " << kLanes << " lanes): " << worst);
}

TEST_CASE("range_window is clamp(1 - (d/R)^2, 0, 1)^2 in double and float") {
  const double range = 7.5;
  for (const double d : {0.0, 1.0, 3.75, 7.0, 7.5, 9.0, 1e30}) {
    CAPTURE(d);
    const double q = d / range, expected = std::max(0.0, 1.0 - q * q) * std::max(0.0, 1.0 - q * q);
    CHECK(par2d::detail::range_window(d, range) == doctest::Approx(expected).epsilon(1e-15));
    const xsimd::batch<float> w = par2d::detail::range_window(xsimd::batch<float>(static_cast<float>(d)),
                                                              xsimd::batch<float>(static_cast<float>(range)));
    CHECK(std::fabs(w.get(0) - expected) <= 1e-6);
  }
}

// Ranges with no finite inverse in the number type (subnormal doubles, floats below ~3e-39, or
// a range that rounds to 0 in float): inside the light (d = 0) the window is 1, at d = R/2 it
// is (3/4)^2, beyond the range 0; never NaN.
TEST_CASE("range_window at ranges near the smallest numbers") {
  for (const double range : {1e-300, 4e-310, 5e-324, 1e-30, 1e-38, 1e-40, 1e-45}) {
    CAPTURE(range);
    CHECK(par2d::detail::range_window(0.0, range) == 1.0);
    CHECK(par2d::detail::range_window(range, range) == 0.0);
    CHECK(par2d::detail::range_window(2.0 * range, range) == 0.0);
    if (range > 1e-320) CHECK(par2d::detail::range_window(0.5 * range, range) == doctest::Approx(0.5625));
    const auto rf = xsimd::batch<float>(static_cast<float>(range));
    CHECK(par2d::detail::range_window(xsimd::batch<float>(0.0f), rf).get(0) == 1.0f);
    const float beyond = par2d::detail::range_window(xsimd::batch<float>(1e-3f), rf).get(0);
    CHECK(beyond == 0.0f);
    if (static_cast<float>(range) >= std::numeric_limits<float>::min()) {
      const float half = par2d::detail::range_window(rf * xsimd::batch<float>(0.5f), rf).get(0);
      CHECK(std::fabs(half - 0.5625f) <= 1e-6f);
    }
  }
}

}  // namespace par2d::test
