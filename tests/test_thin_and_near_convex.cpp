// Shapes at the edge of the convexity and inside tests: slivers whose tip points at a pixel
// (the SIMD inside test must be against the polygon, not its edges' lines) and outlines whose
// every turn is within the straight tolerance but which bend into a pocket (what is called
// convex must be convex, docs/contract.md section 3). Each against closed forms or an
// independent classification written here, on the scalar reference and every SIMD level.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "scene/scene_validate.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"

namespace par2d::test {
namespace {

constexpr double kPiValue = 3.14159265358979323846;

// A 1x1 image (pixel width 1) whose only pixel center is the origin.
Scene one_pixel_at_origin() {
  Scene s;
  s.width = s.height = 1;
  s.view = {-0.5, -0.5, 0.5, 0.5};
  return s;
}

Light white(Shape shape) {
  Light l;
  l.shape = std::move(shape);
  return l;
}

// E at the pixel from a lone circle light of radius r whose center is d away.
double circle_closed_form(double r, double d) { return std::asin(r / d) / kPiValue; }

// A triangle with its tip `tip` units from the origin in direction `angle`, pointing at the
// origin, `length` long, its far end `half_width` to either side.
Polygon sliver(double tip, double angle, double length, double half_width) {
  const Vec2 u{std::cos(angle), std::sin(angle)}, n{-u.y, u.x};
  const Vec2 a{tip * u.x, tip * u.y};
  const Vec2 far{(tip + length) * u.x, (tip + length) * u.y};
  return Polygon{{a, {far.x + half_width * n.x, far.y + half_width * n.y}, {far.x - half_width * n.x, far.y - half_width * n.y}}};
}

// The angle a triangle `sliver` light subtends from the origin: the far edge seen from the
// origin (the tip lies on the line between, so the two long edges add nothing).
double sliver_angle(double tip, double length, double half_width) { return 2.0 * std::atan(half_width / (tip + length)); }

}  // namespace

TEST_CASE("a sliver light whose tip points at a pixel 0.3 px away gives its angle, not its emission, on every ISA") {
  Scene scene = one_pixel_at_origin();
  scene.lights.push_back(white(Polygon{{{0.3, 0.0}, {2.0, 0.0001}, {2.0, -0.0001}}}));
  const double exact = std::atan(5e-5) / kPiValue;  // 2 atan(1e-4 / 2) / 2 pi
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  CHECK(ref.at(0, 0, 0) == doctest::Approx(exact).epsilon(1e-6));
  for (Isa isa : simd_isas_here()) {
    INFO("ISA ", isa_name(isa));
    const RenderedImage got = render_or_fail(scene, options_for(Backend::simd, isa));
    CHECK(std::fabs(got.at(0, 0, 0) - exact) <= 1e-4);
  }
}

TEST_CASE("random slivers aimed at a pixel from 0.06 to 0.6 px, as lights and as occluders, agree with the closed form on every ISA") {
  std::mt19937_64 rng(0x51173u);
  std::uniform_real_distribution<double> tip_dist(0.06, 0.6), angle_dist(-kPiValue, kPiValue),
      length_dist(1.0, 60.0), width_exponent(-6.0, -1.5);
  const std::vector<Isa> isas = simd_isas_here();
  int worst_case = -1;
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    const double tip = tip_dist(rng), angle = angle_dist(rng), length = length_dist(rng);
    const double half_width = std::pow(10.0, width_exponent(rng));
    const Polygon shape = sliver(tip, angle, length, half_width);
    // As a light: its angle from the pixel.
    Scene as_light = one_pixel_at_origin();
    as_light.lights.push_back(white(shape));
    const double light_exact = sliver_angle(tip, length, half_width) / (2.0 * kPiValue);
    // As an occluder between the pixel and a circle light straight behind it: the light's
    // span less the sliver's (the sliver's far end is nearer than the light and narrower).
    Scene as_occluder = one_pixel_at_origin();
    const double d = tip + length + 30.0, r = 2.0;
    as_occluder.lights.push_back(white(Circle{{d * std::cos(angle), d * std::sin(angle)}, r}));
    as_occluder.occluders.push_back({shape});
    const double occluder_exact =
        circle_closed_form(r, d) - sliver_angle(tip, length, half_width) / (2.0 * kPiValue);
    for (const std::pair<Scene, double>& pair : {std::pair{as_light, light_exact}, std::pair{as_occluder, occluder_exact}}) {
      const Scene& scene = pair.first;
      const double exact = pair.second;
      const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
      REQUIRE_MESSAGE(std::fabs(ref.at(0, 0, 0) - exact) <= 1e-6, "case ", k, " scalar ", ref.at(0, 0, 0), " exact ", exact);
      for (Isa isa : isas) {
        const double error = std::fabs(render_or_fail(scene, options_for(Backend::simd, isa)).at(0, 0, 0) - exact);
        if (error > worst) worst = error, worst_case = k;
      }
    }
  }
  INFO("worst case ", worst_case);
  CHECK(worst <= 1e-4);
}

namespace {

// A counter-clockwise outline whose bottom is a chain of `chain` vertices, each turning
// clockwise by `turn` radians (straight by the tolerance of docs/contract.md section 3 where
// |turn| < 1e-9), from heading `turn` * (chain - 1) / 2 to minus that, topped far above: for
// `turn` > 0 the turns are against the winding and the chain bows `depth` units into the
// outline at its middle (x = 0), a dent; for `turn` < 0 it bows outward. Its chain too.
struct DentedOutline {
  Polygon polygon;
  std::vector<Vec2> chain;
};

DentedOutline dented_outline(int chain, double turn, double depth) {
  const double total = turn * (chain - 1);
  // Sagitta of an arc turning through `total`: depth = length * total / 8.
  const double length = 8.0 * depth / std::fabs(total);
  const double step = length / (chain - 1);
  DentedOutline out;
  Vec2 p{-0.5 * length, 0.0};
  double heading = 0.5 * total;
  for (int k = 0; k < chain; ++k) {
    out.chain.push_back(p);
    p = {p.x + step * std::cos(heading), p.y + step * std::sin(heading)};
    heading -= turn;
  }
  out.polygon.vertices = out.chain;
  out.polygon.vertices.push_back({out.chain.back().x, 0.25 * length});
  out.polygon.vertices.push_back({out.chain.front().x, 0.25 * length});
  return out;
}

// The chain's height at x (a point above it is inside the outline), by its segment under x.
double chain_height(const std::vector<Vec2>& chain, double x) {
  const auto next = std::upper_bound(chain.begin(), chain.end(), x, [](double v, const Vec2& p) { return v < p.x; });
  const Vec2 b = *next, a = *(next - 1);
  return a.y + (x - a.x) * (b.y - a.y) / (b.x - a.x);
}

}  // namespace

TEST_CASE("straight turns that add up to a 6-unit dent make a concave outline: lit and dark where the dent says, every ISA") {
  const DentedOutline dent = dented_outline(1001, 0.9e-9, 6.0);
  // The turns are against the winding: the chain heads up first, then down (clockwise).
  REQUIRE(dent.chain[1].y > dent.chain[0].y);
  const double middle = chain_height(dent.chain, 0.0);
  REQUIRE(middle == doctest::Approx(6.0).epsilon(0.02));
  for (bool as_light : {false, true}) {
    INFO((as_light ? "as a light" : "as an occluder"));
    Scene scene;
    scene.width = 16;
    scene.height = 16;
    scene.view = {-8.0, -2.0, 8.0, 14.0};
    const Circle lamp{{0.0, -60.0}, 10.0};
    if (as_light) {
      scene.lights.push_back(white(dent.polygon));
    } else {
      scene.lights.push_back(white(lamp));
      scene.occluders.push_back({dent.polygon});
    }
    REQUIRE(validate_scene(scene, "dent").ok());
    // Pixels above the chain are in the outline; below it, in the dent, out of it. The
    // occluder leaves the lamp below in full view of the dent; the light is more than half
    // the directions from inside it (all of them) and about half from the dent.
    const auto check = [&](const RenderedImage& image, double bound, const std::string& what) {
      int inside = 0, outside = 0;
      for (int j = 0; j < scene.height; ++j)
        for (int i = 0; i < scene.width; ++i) {
          const Vec2 c = pixel_center(scene, i, j);
          const double above = c.y - chain_height(dent.chain, c.x);
          if (std::fabs(above) < 0.25) continue;
          const double e = image.at(i, j, 0);
          if (above > 0.0) {
            ++inside;
            const double expected = as_light ? 1.0 : 0.0;
            CHECK_MESSAGE(std::fabs(e - expected) <= bound, what, " pixel (", i, ", ", j, ") inside: ", e);
          } else {
            ++outside;
            if (as_light) {
              CHECK_MESSAGE((e > 0.4 && e < 0.6), what, " pixel (", i, ", ", j, ") in the dent: ", e);
            } else {
              const double expected = circle_closed_form(lamp.radius, std::hypot(c.x - lamp.center.x, c.y - lamp.center.y));
              CHECK_MESSAGE(std::fabs(e - expected) <= bound, what, " pixel (", i, ", ", j, ") in the dent: ", e);
            }
          }
        }
      CHECK(inside >= 40);
      CHECK(outside >= 40);
    };
    check(render_or_fail(scene, options_for(Backend::scalar)), 1e-6, "scalar");
    // Section 5 adds 2e-6 e_L per vertex of a concave light (its pieces' float error).
    const double simd_bound = 1e-4 + (as_light ? 2e-6 * static_cast<double>(dent.polygon.vertices.size()) : 0.0);
    for (Isa isa : simd_isas_here())
      check(render_or_fail(scene, options_for(Backend::simd, isa)), simd_bound, isa_name(isa));
  }
}

TEST_CASE("straight turns that stay within one tolerance, zigzag or bulging outward, keep an outline convex") {
  // Turns of +-0.9e-9 rad alternating: the direction never falls back by more than one turn.
  Polygon zigzag;
  const int n = 2000;
  for (int k = 0; k < n; ++k) zigzag.vertices.push_back({static_cast<double>(k) * 1000.0, (k % 2) * 4.5e-7});
  zigzag.vertices.push_back({(n - 1) * 1000.0, 1e6});
  zigzag.vertices.push_back({0.0, 1e6});
  CHECK_FALSE(detail::needs_partition(Shape{zigzag}));
  // A bulge outward (turns with the winding) is convex however many there are.
  const DentedOutline bulge = dented_outline(1001, -0.9e-9, 6.0);
  REQUIRE(bulge.chain[1].y < bulge.chain[0].y);
  CHECK_FALSE(detail::needs_partition(Shape{bulge.polygon}));
  // The same turns against the winding are a dent: concave, and a range (convex lights only)
  // is refused at the vertex where the dent passes the tolerance.
  const DentedOutline dent = dented_outline(1001, 0.9e-9, 6.0);
  CHECK(detail::needs_partition(Shape{dent.polygon}));
  Scene scene;
  scene.width = scene.height = 4;
  scene.view = {-1, -1, 1, 1};
  Light ranged = white(dent.polygon);
  ranged.range = 100.0;
  scene.lights.push_back(ranged);
  const Status status = validate_scene(scene, "dent.json");
  REQUIRE_FALSE(status.ok());
  CHECK(status.message().find("dent.json: lights[0]") == 0);
}

}  // namespace par2d::test
