// Angles in the SIMD path at render level: lights seen from every direction, axis-aligned and diagonal tangents, against closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"

namespace {

using namespace par2d;

constexpr double kPi = 3.14159265358979323846;

// Angle the convex vertex set subtends from x (x outside it): the widest pair.
double subtended(const std::vector<Vec2>& vertices, Vec2 x) {
  double widest = 0.0;
  for (const Vec2& a : vertices)
    for (const Vec2& b : vertices) {
      const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
      widest = std::max(widest, std::fabs(std::atan2(ax * by - ay * bx, ax * bx + ay * by)));
    }
  return widest;
}

bool inside_polygon(const std::vector<Vec2>& v, Vec2 x) {
  int sign = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % v.size()];
    const double c = (b.x - a.x) * (x.y - a.y) - (b.y - a.y) * (x.x - a.x);
    if (c == 0.0) continue;
    if (sign == 0) sign = c > 0 ? 1 : -1;
    if ((c > 0 ? 1 : -1) != sign) return false;
  }
  return true;
}

struct Probe {
  std::string name;
  Shape shape;
  // Closed form E / e at x (no occluders), or a negative value at pixels to skip (on the light).
  std::function<double(Vec2)> expected;
};

// Worst |E_simd - closed form| / e over every pixel more than 0.05 px from the light's boundary.
double worst_error(const Probe& probe, Isa isa, Vec2 view_origin, int& where_i, int& where_j) {
  Scene scene;
  scene.width = scene.height = 64;
  scene.view = {view_origin.x, view_origin.y, view_origin.x + 64, view_origin.y + 64};
  Light light;
  light.shape = probe.shape;
  light.intensity = 1.0;
  scene.lights.push_back(light);
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = isa;
  o.threads = 1;
  Status status;
  const test::RenderedImage image = test::render_image(scene, o, status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  double worst = 0.0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const Vec2 x = test::pixel_center(scene, i, j);
      if (test::distance_to_boundary(probe.shape, x) <= 0.05) continue;
      const double e = probe.expected(x);
      if (e < 0.0) continue;
      const double d = std::fabs(double(image.at(i, j, 0)) - e);
      if (d > worst) worst = d, where_i = i, where_j = j;
    }
  return worst;
}

}  // namespace

TEST_CASE("SIMD angles at render level: lights seen from all four quadrants and along the axes match closed forms to 1e-6") {
  // The vector atan2's own error is < 3e-7 rad, i.e. < 5e-8 e per arc end, and float
  // positions add ~1e-7: these scenes measure at most 9.8e-8 e (circle) and 3.7e-8 e (the
  // rest). 1e-6 e is 100x below the contract's 1e-4 bound; an atan2 off by 3e-5 rad in some
  // octants moves E by up to 4.8e-6 e and fails it.
  // Vertices sit on pixel-center rows and columns, so tangents run exactly along the axes
  // (atan2 with a zero argument, either sign) from whole rows and columns of pixels.
  const std::vector<Vec2> square{{24.5, 24.5}, {40.5, 24.5}, {40.5, 40.5}, {24.5, 40.5}};
  const std::vector<Vec2> diamond{{32.5, 22.5}, {42.5, 32.5}, {32.5, 42.5}, {22.5, 32.5}};
  std::vector<Probe> probes;
  probes.push_back({"circle", Circle{{32.5, 32.5}, 6.0}, [](Vec2 x) {
                      const double d = std::hypot(x.x - 32.5, x.y - 32.5);
                      return d <= 6.0 ? -1.0 : 2.0 * std::asin(6.0 / d) / (2 * kPi);
                    }});
  probes.push_back({"square", Polygon{square}, [&](Vec2 x) {
                      return inside_polygon(square, x) ? -1.0 : subtended(square, x) / (2 * kPi);
                    }});
  probes.push_back({"diamond", Polygon{diamond}, [&](Vec2 x) {
                      return inside_polygon(diamond, x) ? -1.0 : subtended(diamond, x) / (2 * kPi);
                    }});
  probes.push_back({"horizontal segment", Segment{{20.5, 32.5}, {44.5, 32.5}}, [](Vec2 x) {
                      return subtended({{20.5, 32.5}, {44.5, 32.5}}, x) / (2 * kPi);
                    }});
  probes.push_back({"vertical segment", Segment{{32.5, 44.5}, {32.5, 20.5}}, [](Vec2 x) {
                      return subtended({{32.5, 44.5}, {32.5, 20.5}}, x) / (2 * kPi);
                    }});
  int isas = 0;
  for (Isa isa : par2d::kSimdIsas) {
    if (!isa_supported(isa)) continue;
    ++isas;
    for (const Probe& p : probes) {
      int i = -1, j = -1;
      const double worst = worst_error(p, isa, {0, 0}, i, j);
      INFO(std::string(isa_name(isa)), " ", p.name, ": worst ", worst, " at pixel (", i, ", ", j, ")");
      CHECK(worst <= 1e-6);
    }
  }
  CHECK(isas >= 1);
}
