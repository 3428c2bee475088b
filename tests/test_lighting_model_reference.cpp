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
#include "world/prepared_scene.hpp"

namespace par2d::test {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr int kRays = 4096;

Rgb emission(const Light& light) {
  return {light.intensity * light.color[0], light.intensity * light.color[1], light.intensity * light.color[2]};
}

int boundary_complexity(const Shape& shape) {
  if (const auto* p = std::get_if<Polygon>(&shape)) return static_cast<int>(p->vertices.size());
  if (std::holds_alternative<Segment>(shape)) return 1;
  return std::numeric_limits<int>::max();
}

// Per-channel bound on |E_par - E_ray| at any pixel (see the file comment).
Rgb stratification_bound(const Scene& scene, int rays, bool overlapping, bool shaded) {
  const double shading = shaded && (scene.normal || scene.normal_map) ? 2.0 : 0.0;
  Rgb bound{0, 0, 0};
  for (const Light& l : scene.lights) {
    double variation = 2.0 + 2.0 * static_cast<double>(scene.occluders.size()) + shading + (l.cone ? 2.0 : 0.0);
    if (overlapping) {
      for (const Occluder& o : scene.occluders) {
        const bool circles = std::holds_alternative<Circle>(l.shape) && std::holds_alternative<Circle>(o.shape);
        variation += circles ? 2.0 : 2.0 * std::min(boundary_complexity(l.shape), boundary_complexity(o.shape));
      }
    }
    const Rgb e = emission(l);
    for (int c = 0; c < 3; ++c) bound[c] += e[c] * variation / rays;
  }
  for (const DirectionalLight& d : scene.directional_lights) {
    const double variation = 2.0 * static_cast<double>(scene.occluders.size()) + shading;
    const double share = (d.angle1 - d.angle0) / 360.0;
    for (int c = 0; c < 3; ++c) bound[c] += d.intensity * d.color[c] * share * variation / rays;
  }
  const double par_slack = 1e-6 * emission_max_sum(scene);
  for (double& b : bound) b += par_slack;
  return bound;
}

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

RenderedImage render_scalar(const Scene& scene) {
  RenderOptions options;
  options.backend = Backend::scalar;
  options.threads = 2;
  Status status;
  RenderedImage image = render_image(scene, options, status);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
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

TEST_CASE("scalar matches ray casting on random scenes with every lighting-model term") {
  int translucent = 0, lit = 0, cones = 0, ranges = 0, masked = 0;
  double worst = 0.0;
  for (std::uint32_t seed = 1; seed <= 24; ++seed) {
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
      ranges += l.range.has_value();
    }
    // The shaded result through render() (each pixel's normal), and the plain one.
    const RenderedImage image = render_scalar(scene);
    worst = std::max(worst, check_against_raycast(scene, &image, false));
    worst = std::max(worst, check_against_raycast(scene, nullptr, false));
  }
  MESSAGE("worst |E_par - E_ray| / bound: " << worst);
  // The seeds do exercise every term.
  CHECK(translucent >= 10);
  CHECK(lit >= 5);
  CHECK(cones >= 5);
  CHECK(ranges >= 5);
  CHECK(masked >= 10);
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
