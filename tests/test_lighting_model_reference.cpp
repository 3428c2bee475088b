// The game lighting model's reference (docs/contract.md section 6): scalar path against closed forms and against the ray caster.
//
// Ray caster tolerance, extending tests/test_raycast.cpp's argument to the new terms: the ray
// caster samples f(theta) = 1_L(theta) V_L(theta) c_L(theta) s(theta) (times e_L w_L, w_L <= 1 a
// constant per point) at N stratified directions, one per stratum of width h = 2 pi / N, and
// |h f(theta_k) - integral over the stratum of f| <= h * (oscillation of f on the stratum). The
// oscillations add up to at most the total variation of f around the circle, and for factors
// in [0, 1] TV(product) <= sum of the factors' TVs: 2 for the light's arc indicator, 1 per jump
// of V_L (each jump changes a product of transmittances by at most 1; at most 2 per occluder's
// span, plus one per boundary intersection of an overlapping pair), 2 for a cone's trapezoid
// (0 -> 1 -> 0) and 2 for the clamped cosine (one rise and one fall, values in [0, 1]). So per
// light |E_par - E_ray| <= e_L (2 + 2 #occluders + overlaps + 2 cone + 2 shading) / N. A
// directional light's N rays stratify [a0, a1] (h = (a1 - a0) / N, no end jumps): at most
// e_D (a1 - a0) / (2 pi N) (2 #occluders + 2 shading). Ambient is exact. Plus section 5's
// 1e-6 e_max for the scalar side and float storage.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "raycast/raycast_renderer.hpp"
#include "scalar/scalar_renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"
#include "world/world.hpp"

namespace par2d::test {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr int kRays = 4096;






Scene model_scene(std::uint32_t seed, bool disjoint, RandomSceneOptions::Normals normals) {
  RandomSceneOptions o = with_every_model_term({});
  o.width = 20;
  o.height = 15;
  o.max_lights = 3;
  o.max_occluders = 8;
  o.max_size = 0.3;  // larger occluders: more of them overlap (translucent pairs multiply)
  o.lights_disjoint_from_occluders = disjoint;
  o.normals = normals;
  switch (seed % 4) {
    case 1: o.view = View{1e5, 1e5, 1e5 + 20, 1e5 + 15}; break;
    case 2: o.view = View{20, 15, 0, 0}; break;  // mirrored in x and y (normals flip with it)
    case 3: o.view = View{-50, -37.5, 50, 37.5}; break;  // 5 world units per pixel
    default: break;
  }
  return random_scene(seed, o);
}

// Compares the scalar reference with the ray caster at every pixel center farther than 1e-6
// pixel widths from every boundary; `image` is the scalar render when given (the shaded result
// through render()), else the scalar path is called here, plain. Returns the worst error/bound.
double check_against_raycast(const Scene& scene, const RenderedImage* image, bool overlapping) {
  const bool shaded = image != nullptr;
  const detail::RaycastRenderer caster(scene);
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  detail::ScalarScratch scratch;
  const Rgb bound = stratification_bound(scene, kRays, overlapping, shaded);
  const double skip = 1e-6 * pixel_width(scene);
  double worst_ratio = 0.0;
  std::string where;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      if (near_boundary(scene, p, skip)) continue;
      const std::optional<Vec3> normal = shaded ? caster.normal_at(i, j) : std::nullopt;
      const Rgb ray = caster.irradiance(p, kRays, 0.5, normal ? &*normal : nullptr);
      Rgb par{};
      if (image) {
        for (int c = 0; c < 3; ++c) par[c] = image->at(i, j, c);
      } else {
        par = detail::scalar_irradiance(prepared, detail::sample_position(prepared, i, j, 0.5, 0.5), nullptr, scratch);
      }
      for (int c = 0; c < 3; ++c) {
        const double ratio = std::fabs(par[c] - ray[c]) / bound[c];
        if (ratio > worst_ratio) {
          worst_ratio = ratio;
          std::ostringstream s;
          s.precision(10);
          s << "pixel (" << i << ", " << j << ") at (" << p.x << ", " << p.y << ") channel " << c << ": PAR " << par[c]
            << ", ray cast " << ray[c] << ", bound " << bound[c];
          where = s.str();
        }
      }
    }
  }
  INFO("worst: " << where);
  CHECK(worst_ratio <= 1.0);
  return worst_ratio;
}

RenderedImage render_scalar(const Scene& scene) { return render_or_fail(scene, options_for(Backend::scalar)); }


// Compares every pixel farther than `skip` pixel widths from every shape boundary with
// expected(pixel, pixel center): |got - expected| <= 1e-6 * e_max per channel (docs/contract.md
// section 5, e_max as extended by section 6). Returns how many pixels were compared.
int check_against(const Scene& scene, const RenderedImage& image, const std::function<Rgb(int, int, Vec2)>& expected,
                  double skip = 1e-3) {
  return check_against_closed_form(scene, image, expected, skip);
}

Polygon rectangle(double x0, double y0, double x1, double y1) {
  return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
}

// Closed forms below put every shape above the view (y < 0) and every pixel below (y > 0), so
// each direction from a pixel to a shape lies in (pi, 2 pi), where intervals do not wrap.
double direction_to(Vec2 x, Vec2 p) {
  const double a = std::atan2(p.y - x.y, p.x - x.x);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

struct Interval {
  double lo = 0.0, hi = 0.0;
  double width() const { return std::max(0.0, hi - lo); }
};

Interval interval_to(Vec2 x, Vec2 a, Vec2 b) {
  const double u = direction_to(x, a), v = direction_to(x, b);
  return {std::min(u, v), std::max(u, v)};
}

Interval circle_interval(Vec2 x, Vec2 center, double radius) {
  const double mid = direction_to(x, center);
  const double half = std::asin(radius / std::hypot(center.x - x.x, center.y - x.y));
  return {mid - half, mid + half};
}

Interval meet(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

Rgb scaled(Rgb e, double f) { return {e[0] * f, e[1] * f, e[2] * f}; }

// The cone weight of docs/contract.md section 6 for ray direction theta (radians) and a cone
// in degrees: delta = |theta + pi - phi| wrapped to [0, pi].
double cone_weight(double theta, const Cone& cone) {
  const double delta = std::fabs(std::remainder(theta + kPi - cone.direction * kPi / 180.0, 2.0 * kPi));
  const double h = cone.half_angle * kPi / 180.0, f = cone.fade * kPi / 180.0;
  if (delta <= h - f) return 1.0;
  if (delta >= h) return 0.0;
  return (h - delta) / f;
}

// The cookie weight of docs/contract.md section 6 for ray direction theta (radians): light
// emitted along psi = theta + pi, offset psi - rotation - first knot into [0, 360) degrees,
// linear between the knots around it.
double cookie_weight(double theta, const Cookie& cookie) {
  const auto& k = cookie.knots;
  const double psi = (theta + kPi) * 180.0 / kPi;
  double offset = std::fmod(psi - cookie.rotation - k[0].direction, 360.0);
  if (offset < 0.0) offset += 360.0;
  std::size_t i = 0;
  while (i + 1 < k.size() && offset >= k[i + 1].direction - k[0].direction) ++i;
  const double a = k[i].direction - k[0].direction;
  const double b = i + 1 < k.size() ? k[i + 1].direction - k[0].direction : 360.0;
  const double next = k[(i + 1) % k.size()].weight;
  return k[i].weight + (offset - a) / (b - a) * (next - k[i].weight);
}

// Integral of cookie_weight over [lo, hi]: linear between the knots' ray directions, so the
// midpoint rule on each piece between them is exact.
double cookie_integral(Interval range, const Cookie& cookie) {
  if (!(range.hi > range.lo)) return 0.0;
  std::vector<double> cuts{range.lo, range.hi};
  for (const CookieKnot& knot : cookie.knots) {
    const double at = (knot.direction + cookie.rotation) * kPi / 180.0 - kPi;
    for (int k = -4; k <= 4; ++k) {
      const double t = at + 2.0 * kPi * k;
      if (t > range.lo && t < range.hi) cuts.push_back(t);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    sum += (cuts[k + 1] - cuts[k]) * cookie_weight(0.5 * (cuts[k] + cuts[k + 1]), cookie);
  return sum;
}

// Integral of cone_weight over [lo, hi] (hi - lo < pi): the weight is linear between its
// kinks (axis -+ half, axis -+ (half - fade), in ray directions), so the midpoint rule on each
// piece between kinks is exact (and ignores the jumps of a fade-0 cone).
double cone_integral(Interval range, const Cone& cone) {
  if (!(range.hi > range.lo)) return 0.0;
  const double axis = cone.direction * kPi / 180.0 + kPi;
  const double h = cone.half_angle * kPi / 180.0, f = cone.fade * kPi / 180.0;
  std::vector<double> cuts{range.lo, range.hi};
  for (int k = -2; k <= 2; ++k) {
    for (double kink : {axis - h, axis - h + f, axis + h - f, axis + h}) {
      const double t = kink + 2.0 * kPi * k;
      if (t > range.lo && t < range.hi) cuts.push_back(t);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    sum += (cuts[k + 1] - cuts[k]) * cone_weight(0.5 * (cuts[k] + cuts[k + 1]), cone);
  return sum;
}

// Integral over [lo, hi] of max(0, n . (cos a cos t, cos a sin t, sin a)) by Gauss-Legendre
// quadrature on pieces split where the clamp starts or stops acting (the integrand is smooth
// between), 64 panels of 8 points each: far below 1e-12 relative.
double clamped_cosine_quadrature(Interval range, Vec3 n, double elevation) {
  const double ca = std::cos(elevation), sa = std::sin(elevation);
  const auto g = [&](double t) { return n.x * ca * std::cos(t) + n.y * ca * std::sin(t) + n.z * sa; };
  std::vector<double> cuts{range.lo, range.hi};
  // g = A cos(t - beta) + C is 0 at t = beta -+ acos(-C / A).
  const double a = ca * std::hypot(n.x, n.y), c = n.z * sa;
  if (a > 0.0 && std::fabs(c / a) < 1.0) {
    const double beta = std::atan2(n.y, n.x), off = std::acos(-c / a);
    for (int k = -2; k <= 2; ++k) {
      for (double t : {beta - off + 2.0 * kPi * k, beta + off + 2.0 * kPi * k})
        if (t > range.lo && t < range.hi) cuts.push_back(t);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  static const double kNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
  static const double kWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const int panels = 64;
    const double step = (cuts[k + 1] - cuts[k]) / panels;
    for (int q = 0; q < panels; ++q) {
      const double mid = cuts[k] + (q + 0.5) * step, half = 0.5 * step;
      for (int r = 0; r < 4; ++r) {
        sum += half * kWeights[r] * (std::max(0.0, g(mid - half * kNodes[r])) + std::max(0.0, g(mid + half * kNodes[r])));
      }
    }
  }
  return sum;
}

}  // namespace

TEST_CASE("random scenes with the lighting model's terms keep the shapes of the same seed") {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    CAPTURE(seed);
    RandomSceneOptions plain;
    const Scene a = random_scene(seed, plain);
    const Scene b = random_scene(seed, with_every_model_term(plain));
    REQUIRE(a.lights.size() == b.lights.size());
    REQUIRE(a.occluders.size() == b.occluders.size());
    for (std::size_t k = 0; k < a.lights.size(); ++k) {
      CHECK(a.lights[k].color == b.lights[k].color);
      CHECK(a.lights[k].intensity == b.lights[k].intensity);
      CHECK(a.lights[k].shape.index() == b.lights[k].shape.index());
    }
    for (std::size_t k = 0; k < a.occluders.size(); ++k) CHECK(a.occluders[k].shape.index() == b.occluders[k].shape.index());
    CHECK(b.directional_lights.size() == 2);
    REQUIRE(b.normal_map);
    CHECK(b.normal_map->normals.size() == static_cast<std::size_t>(3 * b.width * b.height));
    const Status status = validate_scene(b);
    INFO(status.message());
    CHECK(status.ok());
  }
}

namespace {

// How many of each term the seeds [first, last] put in their scenes.
struct ModelTermCounts {
  int translucent = 0, lit = 0, cones = 0, cookies = 0, ranges = 0, masked = 0;
};

// Every term against the ray caster on seeds [first, last]: the shaded result through render()
// (each pixel's normal; seed % 3 picks none, a constant normal or a normal map) and the plain one.
ModelTermCounts check_model_terms_against_raycast(std::uint32_t first, std::uint32_t last) {
  int translucent = 0, lit = 0, cones = 0, cookies = 0, ranges = 0, masked = 0;
  double worst = 0.0;
  for (std::uint32_t seed = first; seed <= last; ++seed) {
    CAPTURE(seed);
    const auto normals = seed % 3 == 0   ? RandomSceneOptions::Normals::none
                         : seed % 3 == 1 ? RandomSceneOptions::Normals::constant
                                         : RandomSceneOptions::Normals::map;
    const Scene scene = model_scene(seed, true, normals);
    for (const Occluder& o : scene.occluders) {
      translucent += o.transmittance != Rgb{0, 0, 0};
      lit += o.interior == Interior::lit;
      masked += o.mask != kAllMaskBits;
    }
    for (const Light& l : scene.lights) {
      cones += l.cone.has_value();
      cookies += l.cookie.has_value();
      ranges += l.range.has_value();
    }
    // The shaded result through render() (each pixel's normal), and the plain one.
    const RenderedImage image = render_scalar(scene);
    worst = std::max(worst, check_against_raycast(scene, &image, false));
    worst = std::max(worst, check_against_raycast(scene, nullptr, false));
  }
  MESSAGE("worst |E_par - E_ray| / bound: " << worst);
  return {translucent, lit, cones, cookies, ranges, masked};
}

}  // namespace

TEST_CASE("scalar matches ray casting on random scenes with every lighting-model term") {
  const ModelTermCounts n = check_model_terms_against_raycast(1, 8);
  // The seeds do exercise every term.
  CHECK(n.translucent >= 3);
  CHECK(n.lit >= 2);
  CHECK(n.cones >= 2);
  CHECK(n.cookies >= 2);
  CHECK(n.ranges >= 2);
  CHECK(n.masked >= 3);
}

TEST_CASE("scalar matches ray casting on random scenes with every lighting-model term, more seeds" *
          par2d::test::long_tier()) {
  const ModelTermCounts n = check_model_terms_against_raycast(9, 24);
  CHECK(n.translucent >= 6);
  CHECK(n.lit >= 3);
  CHECK(n.cones >= 3);
  CHECK(n.cookies >= 3);
  CHECK(n.ranges >= 3);
  CHECK(n.masked >= 6);
}

TEST_CASE("scalar matches ray casting with every lighting-model term where lights overlap occluders") {
  double worst = 0.0;
  for (std::uint32_t seed = 101; seed <= 112; ++seed) {
    CAPTURE(seed);
    const Scene scene = model_scene(seed, false, RandomSceneOptions::Normals::constant);
    const RenderedImage image = render_scalar(scene);
    worst = std::max(worst, check_against_raycast(scene, &image, true));
  }
  MESSAGE("worst |E_par - E_ray| / bound: " << worst);
}

}  // namespace par2d::test

namespace par2d::test {

namespace {

// A long segment light above the view cut by one short blocker, its direction weight set by
// `weigh`, against `integral` (the weight's integral over an interval of ray directions) over
// the visible part: every pixel of the 16 x 12 view.
void check_weighted_light_cut_by_blocker(const std::function<void(Light&)>& weigh,
                                         const std::function<double(Interval)>& integral) {
  const Segment light_shape{{-200, -30}, {216, -30}};
  const Segment blocker{{4, -8}, {9, -8}};
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  Light light{light_shape, {1.0, 0.8, 0.6}, 2.0};
  weigh(light);
  scene.lights.push_back(light);
  scene.occluders.push_back({blocker});
  const Rgb e = emission(light);
  const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
    const Interval arc = interval_to(x, light_shape.a, light_shape.b);
    const Interval blocked = meet(arc, interval_to(x, blocker.a, blocker.b));
    return scaled(e, (integral(arc) - integral(blocked)) / (2.0 * kPi));
  });
  CHECK(compared == 16 * 12);
}

}  // namespace

TEST_CASE("closed form: a spot cone cut by one occluder") {
  // Cones pointing down-left (ray directions around 280 degrees): with a fade, with fade 0,
  // a half angle of 180 (no cone at all) and a full-width fade (a triangle).
  const Cone cones[] = {{100, 35, 12}, {100, 35, 0}, {-260, 180, 0}, {100, 180, 180}, {460, 20, 20}};
  for (const Cone& cone : cones) {
    CAPTURE(cone.half_angle);
    CAPTURE(cone.fade);
    check_weighted_light_cut_by_blocker([&](Light& l) { l.cone = cone; },
                                        [&](Interval range) { return cone_integral(range, cone); });
  }
}

TEST_CASE("closed form: a cookie cut by one occluder, and a cookie shaped as a cone gives the cone") {
  // Knots around the ray directions the pixels see (about 190 .. 350 degrees, emitted 10 .. 170):
  // several segments over the light, one knot alone (a constant), a narrow spike, a wrap past 360.
  const Cookie cookies[] = {
      {0, {{20, 1}, {60, 0.25}, {95, 0.8}, {130, 0}, {300, 0.5}}},
      {-40, {{10, 0.3}}},
      {30, {{60, 0}, {60.001, 1}, {60.002, 0}}},
      {200, {{-150, 1}, {-100, 0}, {0, 0.6}, {150, 0.1}}},
  };
  for (const Cookie& cookie : cookies) {
    CAPTURE(cookie.rotation);
    check_weighted_light_cut_by_blocker([&](Light& l) { l.cookie = cookie; },
                                        [&](Interval range) { return cookie_integral(range, cookie); });
  }
  // A cone is the cookie with knots at -h, -h + f, h - f, h (weights 0, 1, 1, 0) rotated to its
  // axis: the two paths give the same image, plain and shaded.
  const Cone cones[] = {{100, 35, 12}, {-170, 80, 30}, {10, 150, 149}};
  for (const Cone& cone : cones) {
    CAPTURE(cone.direction);
    for (bool shaded : {false, true}) {
      Scene with_cone;
      with_cone.width = 24;
      with_cone.height = 18;
      with_cone.view = {-40, -30, 40, 30};
      if (shaded) with_cone.normal = Vec3{0.3, -0.5, 0.8};
      Light light{Circle{{3, -2}, 2.5}, {1.0, 0.6, 0.3}, 3.0};
      light.elevation = 20.0;
      light.cone = cone;
      with_cone.lights.push_back(light);
      with_cone.occluders.push_back({Segment{{-10, 8}, {12, 5}}});
      Scene with_cookie = with_cone;
      const double h = cone.half_angle, f = cone.fade;
      with_cookie.lights[0].cone.reset();
      with_cookie.lights[0].cookie = Cookie{cone.direction, {{-h, 0}, {-h + f, 1}, {h - f, 1}, {h, 0}}};
      const RenderedImage a = render_scalar(with_cone), b = render_scalar(with_cookie);
      REQUIRE(a.pixels.size() == b.pixels.size());
      double worst = 0.0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::fabs(double{a.pixels[i]} - b.pixels[i]));
      CHECK(worst <= 1e-6 * 3.0);  // section 5's scalar bound (e_max = 3); float outputs differ by an ulp at most
    }
  }
}

TEST_CASE("closed form: range windows at known distances (circle and segment lights, vertex regions)") {
  Scene scene;
  scene.width = 24;
  scene.height = 16;
  scene.view = {0, 0, 24, 16};
  Light circle{Circle{{30, 6}, 3}, {0.5, 1.0, 0.25}, 2.0};
  circle.range = 25.0;
  Light segment{Segment{{10, -5}, {10, 5}}, {1.0, 0.3, 0.6}, 1.5};
  segment.range = 9.0;  // pixels beyond it get nothing from this light
  scene.lights = {circle, segment};
  const auto window = [](double d, double range) {
    const double w = std::clamp(1.0 - (d / range) * (d / range), 0.0, 1.0);
    return w * w;
  };
  const Rgb e0 = emission(circle), e1 = emission(segment);
  int beyond = 0, vertex_region = 0;
  const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
    const double dc = std::hypot(x.x - 30, x.y - 6);
    const double f0 = window(dc - 3.0, 25.0) * 2.0 * std::asin(3.0 / dc) / (2.0 * kPi);
    // Distance to the segment: to its end (5 along y) below it, else across.
    const double ds = x.y > 5 ? std::hypot(x.x - 10, x.y - 5) : std::fabs(x.x - 10);
    vertex_region += x.y > 5 && ds < 9.0;
    beyond += ds >= 9.0;
    const double ax = 10 - x.x, ay = -5 - x.y, bx = 10 - x.x, by = 5 - x.y;
    const double angle = std::atan2(std::fabs(ax * by - ay * bx), ax * bx + ay * by);
    const double f1 = window(ds, 9.0) * angle / (2.0 * kPi);
    return Rgb{e0[0] * f0 + e1[0] * f1, e0[1] * f0 + e1[1] * f1, e0[2] * f0 + e1[2] * f1};
  });
  CHECK(compared == 24 * 16);
  CHECK(beyond > 20);
  CHECK(vertex_region > 20);
}

TEST_CASE("closed form: range windows with falloff exponents 0, 1, 3.5 and 16") {
  for (const double falloff : {0.0, 1.0, 3.5, 16.0}) {
    Scene scene;
    scene.width = 24;
    scene.height = 16;
    scene.view = {0, 0, 24, 16};
    Light circle{Circle{{30, 6}, 3}, {0.5, 1.0, 0.25}, 2.0};
    circle.range = 25.0;
    circle.falloff = falloff;
    scene.lights = {circle};
    const Rgb e = emission(circle);
    int beyond = 0;
    INFO("falloff ", falloff);
    const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      const double dc = std::hypot(x.x - 30, x.y - 6);
      const double d = dc - 3.0;
      beyond += d >= 25.0;
      const double q = d / 25.0;
      const double w = d >= 25.0 ? 0.0 : std::pow(1.0 - q * q, falloff);
      const double f = w * 2.0 * std::asin(3.0 / dc) / (2.0 * kPi);
      return Rgb{e[0] * f, e[1] * f, e[2] * f};
    });
    CHECK(compared == 24 * 16);
    CHECK(beyond > 10);
  }
}

TEST_CASE("closed form: normalize makes intensity the irradiance at the reference distance, whatever the size") {
  // A pixel centre 12 units from each light's center; lights of radius 0.25 .. 11.5 (and one
  // beyond the distance: 1/2 of the circle's asin is pi/2 there).
  for (const double radius : {0.25, 1.0, 4.0, 11.5, 30.0}) {
    Scene scene;
    scene.width = 40;
    scene.height = 20;
    scene.view = {0, 0, 40, 20};
    Light torch{Circle{{20.5 - 12.0, 8.5}, radius}, {0.5, 1.0, 0.25}, 3.0};
    torch.normalize = 12.0;
    scene.lights = {torch};
    const RenderedImage image = render_scalar(scene);
    INFO("radius ", radius);
    // Beyond the reference distance the pixel lies inside the light and sees all of it:
    // e = intensity * pi / asin(1) = 2 * intensity.
    const double want = radius < 12.0 ? 3.0 : 6.0;
    for (int c = 0; c < 3; ++c)
      CHECK(image.at(20, 8, c) == doctest::Approx(want * torch.color[static_cast<std::size_t>(c)]).epsilon(1e-6));
  }
  // Refused where the scaled emission is too large for float output.
  Scene tiny;
  tiny.width = tiny.height = 4;
  tiny.view = {0, 0, 4, 4};
  Light speck{Circle{{1, 1}, 1e-30}, {1, 1, 1}, 1.0};
  speck.normalize = 1e10;
  tiny.lights = {speck};
  const Status s = validate_scene(tiny, "tiny.json");
  CHECK(s.code() == StatusCode::invalid_scene);
  CHECK(s.message().find("emission too large") != std::string::npos);
}

TEST_CASE("closed form: a sun through a slit lights the width of the slit's angular interval") {
  // Two walls on y = -5 leave a slit from x = 5 to x = 9; the sun's rays cover [a0, a1].
  const double arcs[][2] = {{250, 290}, {-110, -70}, {200, 340}, {266, 268}};
  for (const auto& arc : arcs) {
    CAPTURE(arc[0]);
    CAPTURE(arc[1]);
    Scene scene;
    scene.width = 16;
    scene.height = 12;
    scene.view = {0, 0, 16, 12};
    scene.occluders.push_back({Segment{{-1e4, -5}, {5, -5}}});
    scene.occluders.push_back({Segment{{9, -5}, {1e4, -5}}});
    DirectionalLight sun;
    sun.angle0 = arc[0];
    sun.angle1 = arc[1];
    sun.color = {1.0, 0.9, 0.7};
    sun.intensity = 3.0;
    scene.directional_lights.push_back(sun);
    const Rgb e{3.0, 2.7, 2.1};
    double a0 = arc[0] * kPi / 180.0, a1 = arc[1] * kPi / 180.0;
    while (a0 < 0.0) a0 += 2.0 * kPi, a1 += 2.0 * kPi;
    int lit = 0;
    const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      const double seen = meet({a0, a1}, interval_to(x, {5, -5}, {9, -5})).width();
      lit += seen > 0.0;
      return scaled(e, seen / (2.0 * kPi));
    });
    CHECK(compared == 16 * 12);
    CHECK(lit > 0);
  }
}

TEST_CASE("closed form: overlapping translucent occluders multiply where they overlap") {
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  const Segment light_shape{{-300, -40}, {316, -40}};
  scene.lights.push_back({light_shape, {1.0, 1.0, 1.0}, 2.0});
  // Two segments that cross each other (the shapes overlap, and so do their angular
  // intervals from every pixel), and a translucent block around the lower pixels.
  const Segment s1{{2, -10}, {10, -10}}, s2{{6, -14}, {12, -6}};
  const Rgb t1{0.5, 0.25, 0.8}, t2{0.3, 0.9, 0.6}, t3{0.7, 0.4, 0.2};
  Occluder o1{s1}, o2{s2}, o3{rectangle(-1, 8.2, 17, 13)};
  o1.transmittance = t1;
  o2.transmittance = t2;
  o3.transmittance = t3;
  scene.occluders = {o1, o2, o3};
  int overlapped = 0, inside = 0;
  const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
    const Interval arc = interval_to(x, light_shape.a, light_shape.b);
    const Interval i1 = interval_to(x, s1.a, s1.b), i2 = interval_to(x, s2.a, s2.b);
    const double both = meet(i1, i2).width();
    overlapped += both > 0.0;
    const bool in_block = x.y > 8.2;
    inside += in_block;
    Rgb e{};
    for (int c = 0; c < 3; ++c) {
      const double open = arc.width() - (i1.width() + i2.width() - both);
      const double seen = open + t1[c] * (i1.width() - both) + t2[c] * (i2.width() - both) + t1[c] * t2[c] * both;
      e[c] = 2.0 * seen / (2.0 * kPi) * (in_block ? t3[c] : 1.0);
    }
    return e;
  });
  CHECK(compared == 16 * 12);
  CHECK(overlapped > 100);
  CHECK(inside > 30);
}

TEST_CASE("closed form: inside a light and a translucent occluder, the light is multiplied by the transmittance") {
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  scene.lights.push_back({rectangle(-10, -10, 30, 30), {1.0, 0.7, 0.3}, 3.0});
  Occluder glass{Circle{{8, 6}, 4}};
  glass.transmittance = {0.5, 0.25, 1.0};
  scene.occluders.push_back(glass);
  const Rgb e = emission(scene.lights[0]);
  check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
    if (std::hypot(x.x - 8, x.y - 6) > 4) return e;  // t_L = 0: nothing is in front
    return Rgb{e[0] * 0.5, e[1] * 0.25, e[2] * 1.0};
  });
}

TEST_CASE("closed form: a lit-interior sprite is lit inside as if absent; other occluders still shadow it") {
  for (const bool lit : {true, false}) {
    CAPTURE(lit);
    Scene scene;
    scene.width = 16;
    scene.height = 12;
    scene.view = {0, 0, 16, 12};
    const Vec2 center{8, -30};
    scene.lights.push_back({Circle{center, 3}, {0.9, 0.6, 1.0}, 1.5});
    Occluder sprite{rectangle(-2, -2, 18, 14)};  // every pixel is inside it
    sprite.interior = lit ? Interior::lit : Interior::dark;
    sprite.transmittance = {0.0, 0.0, 0.0};
    const Segment blocker{{2, -15}, {5, -15}};
    scene.occluders = {sprite, Occluder{blocker}};
    const Rgb e = emission(scene.lights[0]);
    check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      if (!lit) return Rgb{0, 0, 0};
      const Interval arc = circle_interval(x, center, 3);
      const double seen = arc.width() - meet(arc, interval_to(x, blocker.a, blocker.b)).width();
      return scaled(e, seen / (2.0 * kPi));
    });
  }
}

TEST_CASE("closed form: masks let a light through an occluder that shadows another") {
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  const Vec2 center{8, -30};
  Light red{Circle{center, 3}, {1, 0, 0}, 2.0}, green{Circle{center, 3}, {0, 1, 0}, 2.0};
  red.mask = 1;
  green.mask = 2;
  scene.lights = {red, green};
  const Segment blocker{{2, -15}, {9, -15}};
  Occluder shadows_red{blocker}, acts_on_none{Segment{{-100, -20}, {100, -20}}};
  shadows_red.mask = 1 | 4;
  acts_on_none.mask = 4;
  scene.occluders = {shadows_red, acts_on_none};
  DirectionalLight sun;  // its mask meets neither occluder's
  sun.angle0 = 250;
  sun.angle1 = 290;
  sun.color = {0, 0, 1};
  sun.intensity = 1.0;
  sun.mask = 2;
  scene.directional_lights.push_back(sun);
  int shadowed = 0;
  check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
    const Interval arc = circle_interval(x, center, 3);
    const double blocked = meet(arc, interval_to(x, blocker.a, blocker.b)).width();
    shadowed += blocked > 0.0;
    return Rgb{2.0 * (arc.width() - blocked) / (2.0 * kPi), 2.0 * arc.width() / (2.0 * kPi), 40.0 / 360.0};
  });
  CHECK(shadowed > 50);
}

TEST_CASE("closed form: clamped-cosine shading of a segment light against quadrature") {
  const Segment light_shape{{-40, -20}, {50, -25}};
  const Vec3 normals[] = {{0.6, -0.3, 0.74}, {1, 0, 0}, {0, 0.5, -0.8}, {0, 0, 1}, {-0.2, -0.9, 0.1}};
  for (const Vec3& normal : normals) {
    for (const double elevation : {0.0, 30.0, 90.0}) {
      CAPTURE(normal.x);
      CAPTURE(normal.z);
      CAPTURE(elevation);
      Scene scene;
      scene.width = 12;
      scene.height = 9;
      scene.view = {0, 0, 12, 9};
      Light light{light_shape, {1.0, 0.5, 0.25}, 2.0};
      light.elevation = elevation;
      scene.lights.push_back(light);
      scene.normal = normal;
      const double len = std::sqrt(normal.x * normal.x + normal.y * normal.y + normal.z * normal.z);
      const Vec3 n{normal.x / len, normal.y / len, normal.z / len};
      const Rgb e = emission(light);
      check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
        return scaled(e, clamped_cosine_quadrature(interval_to(x, light_shape.a, light_shape.b), n,
                                                   elevation * kPi / 180.0) /
                             (2.0 * kPi));
      });
    }
  }
}

TEST_CASE("closed form: a normal map shades each pixel with its own normal, in world axes of the view") {
  const Segment light_shape{{-40, -20}, {50, -25}};
  for (const bool mirrored : {false, true}) {
    CAPTURE(mirrored);
    Scene scene;
    scene.width = 4;
    scene.height = 3;
    scene.view = mirrored ? View{12, 9, 0, 0} : View{0, 0, 12, 9};
    Light light{light_shape, {1.0, 1.0, 1.0}, 1.0};
    light.elevation = 20.0;
    scene.lights.push_back(light);
    NormalMap map;
    map.width = 4;
    map.height = 3;
    PortableRandom rng(7);
    for (int p = 0; p < 12; ++p) map.normals.insert(map.normals.end(), {static_cast<float>(rng.uniform(-1, 1)),
                                                                        static_cast<float>(rng.uniform(-1, 1)),
                                                                        static_cast<float>(rng.uniform(-0.3, 1))});
    scene.normal_map = map;
    check_against(scene, render_scalar(scene), [&](int i, int j, Vec2 x) {
      // Image x is world x, image up is world -y (both flip in the mirrored view).
      const float* m = map.normals.data() + 3 * (j * 4 + i);
      const double sx = mirrored ? -1.0 : 1.0, sy = mirrored ? 1.0 : -1.0;
      const double len = std::sqrt(double(m[0]) * m[0] + double(m[1]) * m[1] + double(m[2]) * m[2]);
      const Vec3 n{sx * m[0] / len, sy * m[1] / len, m[2] / len};
      const double f = clamped_cosine_quadrature(interval_to(x, light_shape.a, light_shape.b), n, 20.0 * kPi / 180.0);
      return Rgb{f / (2.0 * kPi), f / (2.0 * kPi), f / (2.0 * kPi)};
    });
  }
}

// Every length and division the model takes of a user-given number, at the ends of double:
// ranges with no finite inverse, fades and half angles far below a degree, normals whose
// squares underflow or overflow. Each against its closed form on the scalar reference.
TEST_CASE("closed form: ranges, cone angles and normals at the smallest and largest doubles") {
  Scene base;
  base.width = 16;
  base.height = 12;
  base.view = {0, 0, 16, 12};
  SUBCASE("a range with no finite inverse: e inside the light, 0 outside") {
    for (const double range : {1e-300, 4e-310, 5e-324}) {
      CAPTURE(range);
      Scene scene = base;
      Light light{Circle{{8, 6}, 2.5}, {1.0, 0.5, 0.25}, 2.0};
      light.range = range;
      scene.lights.push_back(light);
      int inside = 0;
      const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
        const bool in = std::hypot(x.x - 8, x.y - 6) < 2.5;
        inside += in;
        return in ? emission(light) : Rgb{0, 0, 0};
      });
      CHECK(compared == 16 * 12);
      CHECK(inside > 10);
    }
  }
  SUBCASE("a range of 1e300 view sizes: the window is 1") {
    Scene scene = base;
    Light light{Circle{{8, -6}, 2.5}, {1.0, 0.5, 0.25}, 2.0};
    light.range = 1e300;
    scene.lights.push_back(light);
    const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      return scaled(emission(light), circle_interval(x, {8, -6}, 2.5).width() / (2.0 * kPi));
    });
    CHECK(compared == 16 * 12);
  }
  SUBCASE("cone fades and half angles far below a degree") {
    const Segment light_shape{{-200, -30}, {216, -30}};
    const Cone cones[] = {{100, 35, 5e-324}, {100, 35, 1e-300}, {100, 35, 1e-40}, {100, 35, 1e-20},
                          {100, 35, 1e-9},   {100, 35, 1e-6},   {100, 35, 35.0 * (1.0 - 1e-15)},
                          {100, 1e-9, 1e-9}, {100, 1e-300, 0}, {100, std::nextafter(180.0, 0.0), 1e-30}};
    for (const Cone& cone : cones) {
      CAPTURE(cone.half_angle);
      CAPTURE(cone.fade);
      Scene scene = base;
      Light light{light_shape, {1.0, 0.8, 0.6}, 2.0};
      light.cone = cone;
      scene.lights.push_back(light);
      const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
        return scaled(emission(light), cone_integral(interval_to(x, light_shape.a, light_shape.b), cone) / (2.0 * kPi));
      });
      CHECK(compared == 16 * 12);
    }
  }
  SUBCASE("a normal scaled by 1e-300, a subnormal or 1e300 shades as the unit normal") {
    const Segment light_shape{{-40, -20}, {56, -20}};
    const double elevation = 30.0;
    const Vec3 unit{0.3, -0.5, std::sqrt(1.0 - 0.09 - 0.25)};
    for (const double k : {1e-300, 1e-310, 1e300, 1e307}) {
      CAPTURE(k);
      Scene scene = base;
      Light light{light_shape, {1.0, 0.8, 0.6}, 1.5};
      light.elevation = elevation;
      scene.lights.push_back(light);
      scene.normal = Vec3{unit.x * k, unit.y * k, unit.z * k};
      const int compared = check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
        const double integral =
            clamped_cosine_quadrature(interval_to(x, light_shape.a, light_shape.b), unit, elevation * kPi / 180.0);
        return scaled(emission(light), integral / (2.0 * kPi));
      });
      CHECK(compared == 16 * 12);
    }
  }
}

TEST_CASE("closed form: ambient is added everywhere, inside occluders too") {
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  scene.ambient = {0.1, 0.2, 0.3};
  scene.occluders.push_back({Circle{{8, 6}, 3}});
  SUBCASE("no lights") {
    check_against(scene, render_scalar(scene), [&](int, int, Vec2) { return scene.ambient; });
  }
  SUBCASE("with a light shadowed inside the occluder") {
    scene.lights.push_back({rectangle(-10, -10, 30, 30), {1.0, 0.7, 0.3}, 3.0});
    check_against(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      if (std::hypot(x.x - 8, x.y - 6) <= 3) return scene.ambient;
      return Rgb{0.1 + 3.0, 0.2 + 2.1, 0.3 + 0.9};
    });
  }
}

}  // namespace par2d::test

namespace par2d::test {

TEST_CASE("render_raycast matches the scalar reference on lighting-model scenes, shaded and plain") {
  for (std::uint32_t seed = 301; seed <= 304; ++seed) {
    CAPTURE(seed);
    const Scene scene = model_scene(seed, true, RandomSceneOptions::Normals::map);
    const detail::PreparedScene prepared = detail::prepare_scene(scene);
    detail::ScalarScratch scratch;
    for (const bool shaded : {true, false}) {
      CAPTURE(shaded);
      RenderOptions options;
      options.rays = kRays;
      options.threads = 2;
      options.shaded = shaded;
      Status status;
      const RenderedImage ray = render_image(scene, options, status, /*raycast=*/true);
      REQUIRE(status.ok());
      const Rgb bound = stratification_bound(scene, kRays, false, shaded);
      const double skip = 1e-6 * pixel_width(scene);
      int compared = 0;
      for (int j = 0; j < scene.height; ++j) {
        for (int i = 0; i < scene.width; ++i) {
          if (near_boundary(scene, pixel_center(scene, i, j), skip)) continue;
          ++compared;
          const Vec3 normal = prepared.normal_at(i, j);
          const Rgb par = detail::scalar_irradiance(prepared, detail::sample_position(prepared, i, j, 0.5, 0.5),
                                                    shaded ? &normal : nullptr, scratch);
          for (int c = 0; c < 3; ++c) {
            const double err = std::fabs(par[c] - ray.at(i, j, c));
            if (err <= bound[c]) continue;
            INFO("pixel (" << i << ", " << j << ") channel " << c << ": scalar " << par[c] << ", raycast "
                           << ray.at(i, j, c) << ", bound " << bound[c]);
            CHECK(false);
          }
        }
      }
      CHECK(compared > scene.width * scene.height / 2);
    }
  }
}

TEST_CASE("e_max counts directional lights and the ambient term") {
  RandomSceneOptions o = with_every_model_term({});
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    CAPTURE(seed);
    const Scene scene = random_scene(seed, o);
    const double expected = emission_max_sum(scene);
    CHECK(detail::prepare_scene(scene).e_max == doctest::Approx(expected).epsilon(1e-15));
    CHECK(max_emission_sum(scene) == doctest::Approx(expected).epsilon(1e-15));
  }
}

TEST_CASE("point_distance is the exact distance to the closed shape, 0 inside") {
  const detail::ConvexShape square = detail::make_convex_shape(rectangle(0, 0, 4, 2));
  CHECK(detail::point_distance(square, {1, 1}) == 0.0);             // inside
  CHECK(detail::point_distance(square, {4, 1}) == 0.0);             // on an edge
  CHECK(detail::point_distance(square, {2, -3}) == 3.0);            // facing an edge
  CHECK(detail::point_distance(square, {7, 6}) == doctest::Approx(5.0).epsilon(1e-15));  // vertex region (3, 4)
  const detail::ConvexShape disc = detail::make_convex_shape(Circle{{1, 1}, 2});
  CHECK(detail::point_distance(disc, {1, 2}) == 0.0);
  CHECK(detail::point_distance(disc, {4, 5}) == doctest::Approx(3.0).epsilon(1e-15));
  const detail::ConvexShape segment = detail::make_convex_shape(Segment{{0, 0}, {4, 0}});
  CHECK(detail::point_distance(segment, {2, 0}) == 0.0);
  CHECK(detail::point_distance(segment, {2, -1.5}) == 1.5);
  CHECK(detail::point_distance(segment, {-3, 4}) == doctest::Approx(5.0).epsilon(1e-15));  // end region
}

}  // namespace par2d::test
