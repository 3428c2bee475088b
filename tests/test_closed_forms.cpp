// Scalar renderer against closed-form irradiance values (docs/contract.md section 1 consequences, section 5 bound).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"

namespace par2d::test {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

RenderOptions scalar_options() {
  RenderOptions options;
  options.backend = Backend::scalar;
  options.threads = 2;
  return options;
}

RenderedImage render_scalar(const Scene& scene) {
  Status status;
  RenderedImage image = render_image(scene, scalar_options(), status);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
}


// Angle between a - x and b - x in [0, pi], computed stably.
double angle_between(Vec2 a, Vec2 b, Vec2 x) {
  const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
  return std::atan2(std::fabs(ax * by - ay * bx), ax * bx + ay * by);
}

// Compares every pixel farther than `skip` pixel widths from every shape boundary
// with expected(pixel center), requiring |got - expected| <= 1e-6 * e_max per
// channel (docs/contract.md section 5). Reports the worst pixel; returns how many were compared.
int check_against(const Scene& scene, const RenderedImage& image, const std::function<Rgb(Vec2)>& expected,
                  double skip = 1e-3) {
  return check_against_closed_form(scene, image, [&](int, int, Vec2 p) { return expected(p); }, skip);
}

Polygon rectangle(double x0, double y0, double x1, double y1) {
  return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
}

}  // namespace

TEST_CASE("circle light at distance d gives 2·asin(r/d)") {
  struct Case {
    Vec2 center;
    double radius;
    Rgb color;
    double intensity;
    View view;
  };
  const Case cases[] = {
      {{20, 15}, 4.0, {1.0, 0.85, 0.6}, 4.0, {0, 0, 48, 36}},             // light inside the view
      {{-30, 10}, 0.5, {0.3, 0.5, 1.0}, 1.0, {0, 0, 48, 36}},             // small, far outside
      {{100, -40}, 60.0, {1.0, 1.0, 1.0}, 0.25, {0, 0, 48, 36}},          // large, near
      {{1e5 + 7, 1e5 + 9}, 3.0, {0.2, 0.0, 0.9}, 2.0, {1e5, 1e5, 1e5 + 48, 1e5 + 36}},  // far origin
      {{5, 5}, 1.5, {1.0, 0.5, 0.25}, 3.0, {48, 36, 0, 0}},               // mirrored view
  };
  for (const Case& k : cases) {
    CAPTURE(k.center.x);
    CAPTURE(k.radius);
    Scene scene;
    scene.width = 48;
    scene.height = 36;
    scene.view = k.view;
    scene.lights.push_back({Circle{k.center, k.radius}, k.color, k.intensity});
    const RenderedImage image = render_scalar(scene);
    const Rgb e = emission(scene.lights[0]);
    const int compared = check_against(scene, image, [&](Vec2 p) {
      const double d = std::hypot(p.x - k.center.x, p.y - k.center.y);
      const double f = d <= k.radius ? 1.0 : 2.0 * std::asin(k.radius / d) / (2.0 * kPi);
      return Rgb{e[0] * f, e[1] * f, e[2] * f};
    });
    CHECK(compared > 48 * 36 / 2);
  }
}

TEST_CASE("segment light gives angle(a - x, b - x) / 2pi") {
  const Segment segments[] = {
      {{10, 5}, {30, 25}},
      {{-20, 40}, {70, 40}},  // horizontal, below part of the view: collinear pixels get 0
      {{24, -100}, {24, 100}},  // through the whole view
  };
  for (const Segment& s : segments) {
    Scene scene;
    scene.width = 48;
    scene.height = 36;
    scene.view = {0, 0, 48, 36};
    scene.lights.push_back({s, {0.9, 0.4, 0.1}, 2.5});
    const RenderedImage image = render_scalar(scene);
    const Rgb e = emission(scene.lights[0]);
    check_against(scene, image, [&](Vec2 p) {
      const double f = angle_between(s.a, s.b, p) / (2.0 * kPi);
      return Rgb{e[0] * f, e[1] * f, e[2] * f};
    });
  }
}

TEST_CASE("inside a light with no occluders a pixel gets the full e, and lights add up") {
  Scene scene;
  scene.width = 32;
  scene.height = 24;
  scene.view = {0, 0, 32, 24};
  // The polygon covers the whole view; the circle light outside it adds 2·asin(r/d).
  scene.lights.push_back({Polygon{{{-5, -5}, {40, -8}, {45, 30}, {-3, 28}}}, {0.5, 1.0, 0.25}, 2.0});
  scene.lights.push_back({Circle{{60, 12}, 5}, {1.0, 0.2, 0.0}, 1.0});
  const RenderedImage image = render_scalar(scene);
  const Rgb e0 = emission(scene.lights[0]);
  const Rgb e1 = emission(scene.lights[1]);
  const int compared = check_against(scene, image, [&](Vec2 p) {
    const double f = 2.0 * std::asin(5.0 / std::hypot(p.x - 60.0, p.y - 12.0)) / (2.0 * kPi);
    return Rgb{e0[0] + e1[0] * f, e0[1] + e1[1] * f, e0[2] + e1[2] * f};
  });
  CHECK(compared == 32 * 24);
}

TEST_CASE("inside an occluder a pixel is black even inside a light") {
  Scene scene;
  scene.width = 32;
  scene.height = 24;
  scene.view = {0, 0, 32, 24};
  scene.lights.push_back({rectangle(-10, -10, 50, 40), {1.0, 0.7, 0.3}, 3.0});
  scene.occluders.push_back({Circle{{16, 12}, 6}});
  scene.occluders.push_back({rectangle(2, 2, 8, 6)});
  const RenderedImage image = render_scalar(scene);
  int inside = 0;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      const bool in_circle = std::hypot(p.x - 16, p.y - 12) < 6 - 1e-3;
      const bool in_rect = p.x > 2 && p.x < 8 && p.y > 2 && p.y < 6;
      if (!in_circle && !in_rect) continue;
      ++inside;
      for (int c = 0; c < 3; ++c) {
        INFO("pixel (" << i << ", " << j << ") channel " << c);
        CHECK(image.at(i, j, c) == 0.0f);
      }
    }
  }
  CHECK(inside > 100);
}

// docs/contract.md section 1: inside light L, t_L = 0 < t_occ in every direction, so an
// occluder that overlaps the light but not x removes nothing from L.
TEST_CASE("inside a light and outside every occluder a pixel gets the full e (t_L = 0 < t_occ)") {
  Scene scene;
  scene.width = 32;
  scene.height = 24;
  scene.view = {0, 0, 32, 24};
  scene.lights.push_back({rectangle(-10, -10, 50, 40), {1.0, 0.7, 0.3}, 3.0});
  scene.occluders.push_back({Circle{{16, 12}, 6}});
  const RenderedImage image = render_scalar(scene);
  const Rgb e = emission(scene.lights[0]);
  check_against(scene, image, [&](Vec2 p) {
    return std::hypot(p.x - 16, p.y - 12) <= 6 ? Rgb{0, 0, 0} : e;
  });
}

TEST_CASE("full umbra: a large occluder wholly between a small light and the pixel gives 0") {
  Scene scene;
  scene.width = 10;
  scene.height = 10;
  scene.view = {30, 15, 40, 25};  // every line from here to the light crosses the slab
  scene.lights.push_back({Circle{{10, 20}, 2}, {1, 1, 1}, 5.0});
  scene.occluders.push_back({rectangle(20, 0, 25, 40)});
  const RenderedImage image = render_scalar(scene);
  check_against(scene, image, [](Vec2) { return Rgb{0, 0, 0}; });
}

TEST_CASE("occluder edge on the symmetry axis of a light removes exactly half of it") {
  Scene scene;
  scene.width = 20;
  scene.height = 1;
  scene.view = {10, -0.5, 30, 0.5};  // pixel centers (10.5 .. 29.5, 0) on the axis y = 0
  SUBCASE("segment light") {
    scene.lights.push_back({Segment{{0, -10}, {0, 10}}, {0.6, 0.8, 1.0}, 2.0});
    // Its lower edge lies on y = 0; it blocks every ray from the axis to y > 0.
    scene.occluders.push_back({rectangle(2, 0, 4, 12)});
    const RenderedImage image = render_scalar(scene);
    const Rgb e = emission(scene.lights[0]);
    check_against(scene, image, [&](Vec2 p) {
      const double f = std::atan(10.0 / p.x) / (2.0 * kPi);
      return Rgb{e[0] * f, e[1] * f, e[2] * f};
    });
  }
  SUBCASE("circle light") {
    scene.lights.push_back({Circle{{0, 0}, 3}, {1.0, 0.5, 0.0}, 4.0});
    scene.occluders.push_back({rectangle(5, 0, 7, 10)});
    const RenderedImage image = render_scalar(scene);
    const Rgb e = emission(scene.lights[0]);
    check_against(scene, image, [&](Vec2 p) {
      const double f = std::asin(3.0 / p.x) / (2.0 * kPi);
      return Rgb{e[0] * f, e[1] * f, e[2] * f};
    });
  }
}

TEST_CASE("two overlapping occluders remove the union of their intervals, counted once") {
  Scene scene;
  scene.width = 10;
  scene.height = 4;
  scene.view = {15, -2, 25, 2};
  const Segment light{{0, -10}, {0, 10}};
  const Circle b0{{10, 1}, 1.0};
  const Circle b1{{10.5, -0.5}, 1.0};  // overlaps b0 (centers 1.58 apart)
  scene.lights.push_back({light, {1.0, 0.9, 0.8}, 3.0});
  scene.occluders.push_back({b0});
  scene.occluders.push_back({b1});
  const RenderedImage image = render_scalar(scene);
  const Rgb e = emission(scene.lights[0]);
  // Angles measured from the -x direction, so all the intervals here are in (-pi/2, pi/2).
  auto angle = [](Vec2 p, Vec2 q) { return std::atan2(q.y - p.y, -(q.x - p.x)); };
  check_against(scene, image, [&](Vec2 p) {
    const double l_lo = std::min(angle(p, light.a), angle(p, light.b));
    const double l_hi = std::max(angle(p, light.a), angle(p, light.b));
    const double a0 = angle(p, b0.center), h0 = std::asin(b0.radius / std::hypot(b0.center.x - p.x, b0.center.y - p.y));
    const double a1 = angle(p, b1.center), h1 = std::asin(b1.radius / std::hypot(b1.center.x - p.x, b1.center.y - p.y));
    REQUIRE(std::fabs(a0 - a1) < h0 + h1);  // the two intervals overlap: their union is one interval
    const double u_lo = std::max(l_lo, std::min(a0 - h0, a1 - h1));
    const double u_hi = std::min(l_hi, std::max(a0 + h0, a1 + h1));
    const double f = ((l_hi - l_lo) - std::max(0.0, u_hi - u_lo)) / (2.0 * kPi);
    return Rgb{e[0] * f, e[1] * f, e[2] * f};
  });
}

TEST_CASE("a scene without lights is exactly black everywhere") {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    RandomSceneOptions o;
    o.min_lights = 0;
    o.max_lights = 0;
    o.min_occluders = 1;
    Scene scene = random_scene(seed, o);
    REQUIRE(scene.lights.empty());
    const RenderedImage image = render_scalar(scene);
    const bool all_zero = std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return v == 0.0f; });
    CAPTURE(seed);
    CHECK(all_zero);
  }
}

TEST_CASE("0 <= E <= sum of e_L per channel on random scenes") {
  for (std::uint32_t seed = 100; seed < 120; ++seed) {
    RandomSceneOptions o;
    o.width = 32;
    o.height = 24;
    // Odd seeds let lights overlap occluders: the bounds hold for any scene.
    o.lights_disjoint_from_occluders = seed % 2 == 0;
    o.max_size = 0.35;
    const Scene scene = random_scene(seed, o);
    const RenderedImage image = render_scalar(scene);
    Rgb sum{0, 0, 0};
    for (const Light& l : scene.lights)
      for (int c = 0; c < 3; ++c) sum[c] += emission(l)[c];
    const double slack = 1e-6 * emission_max_sum(scene);  // float storage of the sum
    for (int j = 0; j < scene.height; ++j) {
      for (int i = 0; i < scene.width; ++i) {
        for (int c = 0; c < 3; ++c) {
          const float v = image.at(i, j, c);
          if (v >= 0.0f && v <= sum[c] + slack) continue;
          INFO("seed " << seed << " pixel (" << i << ", " << j << ") channel " << c << ": " << v
                       << " not in [0, " << sum[c] << "]");
          CHECK(false);
        }
      }
    }
  }
}

}  // namespace par2d::test
