// Concave lights (docs/contract.md section 3): a direction adds the light's emission once for
// every time it enters the light from outside, each time with the visibility at that entry.
// Checked in closed form, against the ray caster (which follows the outline as given), on
// every SIMD level, through a Renderer's updates, and in scene files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "support/random_scenes.hpp"
#include "comb_outline.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

constexpr double kPiValue = 3.14159265358979323846;

// An L: arms [x, x + 3s] x [y, y + s] and [x, x + s] x [y, y + 3s], counter-clockwise.
Polygon ell(double x, double y, double s) {
  return Polygon{{{x, y}, {x + 3 * s, y}, {x + 3 * s, y + s}, {x + s, y + s}, {x + s, y + 3 * s}, {x, y + 3 * s}}};
}

// A U opening upward: a base [x, x + 5s] x [y, y + s] and two posts s wide, 4s tall.
Polygon cup(double x, double y, double s) {
  return Polygon{{{x, y},
                  {x + 5 * s, y},
                  {x + 5 * s, y + 4 * s},
                  {x + 4 * s, y + 4 * s},
                  {x + 4 * s, y + s},
                  {x + s, y + s},
                  {x + s, y + 4 * s},
                  {x, y + 4 * s}}};
}

bool same_outline(const Shape& shape, const Polygon& polygon) {
  const std::vector<Vec2>& v = std::get<Polygon>(shape).vertices;
  if (v.size() != polygon.vertices.size()) return false;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i].x != polygon.vertices[i].x || v[i].y != polygon.vertices[i].y) return false;
  return true;
}

Light concave_light(Polygon shape, Rgb color, double intensity) {
  Light l;
  l.shape = std::move(shape);
  l.color = color;
  l.intensity = intensity;
  return l;
}

Scene lit_by(const Light& light, std::vector<Occluder> occluders) {
  Scene s;
  s.width = 48;
  s.height = 36;
  s.view = {-40, -30, 40, 30};
  s.lights.push_back(light);
  s.occluders = std::move(occluders);
  return s;
}

Occluder box(double x0, double y0, double x1, double y1, Rgb transmittance = {0, 0, 0}) {
  Occluder o;
  o.shape = Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  o.transmittance = transmittance;
  return o;
}

}  // namespace

TEST_CASE("a concave light seen from where every direction enters it once is its angular span, in closed form") {
  // From below-left of an L every ray meets its outline entering once: E = e * span / 2 pi.
  Scene scene = lit_by(concave_light(ell(0, 0, 6), {1, 0.5, 0.25}, 2), {});
  scene.view = {-30, -30, -10, -15};  // every pixel below-left of the L
  scene.width = 32;
  scene.height = 24;
  const RenderedImage image = render_or_fail(scene, options_for(Backend::scalar));
  const int compared = check_against_closed_form(scene, image, [&](int, int, Vec2 x) {
    const double span = std::atan2(18 - x.y, 0 - x.x) - std::atan2(0 - x.y, 18 - x.x);
    const double e = 2 * span / (2 * kPiValue);
    return Rgb{e, 0.5 * e, 0.25 * e};
  });
  CHECK(compared == 32 * 24);
}

TEST_CASE("a concave light matches the ray caster: shared boundaries counted once, re-entries again, occluders between") {
  // The U's posts are both met by rays across its mouth (two entries); an opaque box and a
  // translucent one stand in front and inside it; a circle light besides.
  Light u = concave_light(cup(-12, -10, 4), {1.0, 0.8, 0.5}, 1.5);
  u.elevation = 20;
  Scene scene = lit_by(u, {box(-25, 8, -18, 12), box(-2, -3, 2, 3, {0.5, 0.3, 0.8}), box(15, -20, 19, 25)});
  Light l = concave_light(ell(20, -25, 3), {0.3, 0.6, 1.0}, 3);
  l.cone = Cone{90, 120, 20};
  scene.lights.push_back(l);
  scene.lights.push_back(Light{Circle{{-30, -20}, 2}, {1, 1, 1}, 1});
  REQUIRE(validate_scene(scene).ok());
  const RenderedImage image = render_or_fail(scene, options_for(Backend::scalar));
  const double skip = 1e-6 * 80.0 / scene.width;
  const RaycastAgreement agreement = agreement_with_raycaster(scene, image, 4096, skip, true);
  INFO("worst: " << agreement.where);
  CHECK(agreement.worst <= 1.0);
  CHECK(agreement.compared > scene.width * scene.height / 2);
  MESSAGE("worst |E_par - E_ray| / bound: " << agreement.worst);
  // Inside the U's mouth a ray toward either post enters it: more light than the U's own
  // span once, less than twice.
  check_simd_against_scalar(
      scene, image, "concave lights", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * 80.0 / scene.width); },
      scene.width * scene.height / 2);
}

TEST_CASE("comb lights along either axis match the ray caster, and every SIMD level within section 5 of scalar") {
  // A comb's teeth side by side along x or along y (its pieces and their shared boundaries,
  // found by sweeps along the axis where its edges overlap least), behind a box.
  for (const bool sideways : {false, true}) {
    CAPTURE(sideways);
    const int teeth = 40;
    std::vector<Vec2> v{{-32.0, -20.0}};
    for (int k = 0; k < teeth; ++k) {
      const double x = -32.0 + 1.5 * k;
      v.insert(v.end(), {{x, 10.0}, {x + 0.75, 10.0}, {x + 0.75, -18.0}, {x + 1.5, -18.0}});
    }
    v.push_back({-32.0 + 1.5 * teeth, -20.0});
    if (sideways)
      for (Vec2& p : v) p = {p.y, 0.75 * p.x};
    Scene scene = lit_by(concave_light(Polygon{v}, {1.0, 0.7, 0.4}, 1.0), {box(20, 12, 24, 16)});
    REQUIRE(validate_scene(scene).ok());
    const RenderedImage image = render_or_fail(scene, options_for(Backend::scalar));
    const double skip = 1e-6 * 80.0 / scene.width;
    const RaycastAgreement agreement = agreement_with_raycaster(scene, image, 2048, skip, true);
    INFO("worst: " << agreement.where);
    CHECK(agreement.worst <= 1.0);
    CHECK(agreement.compared > scene.width * scene.height / 4);
    check_simd_against_scalar(
        scene, image, "comb light", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * 80.0 / scene.width); },
        scene.width * scene.height / 4);
  }
}

TEST_CASE("a Renderer keeps a concave light under one handle: moved, recoloured, made convex and concave again" *
          per_isa()) {
  Renderer renderer;
  REQUIRE(renderer.set_frame(48, 36, View{-40, -30, 40, 30}).ok());
  OccluderHandle wall;
  REQUIRE(renderer.add_occluder(Occluder{Polygon{{{-5, -20}, {-2, -20}, {-2, 20}, {-5, 20}}}}, &wall).ok());
  LightHandle lamp, other;
  REQUIRE(renderer.add_light(concave_light(cup(-30, -10, 3), {1, 0.9, 0.7}, 2), &lamp).ok());
  REQUIRE(renderer.add_light(Light{Circle{{20, 10}, 2}, {0.4, 0.6, 1.0}, 3}, &other).ok());
  CHECK(renderer.light_count() == 2);
  const auto frame_equals_snapshot = [&](const std::string& what) {
    CAPTURE(what);
    CHECK(renderer_equals_snapshot(renderer));
  };
  frame_equals_snapshot("added");
  Light back;
  REQUIRE(renderer.light(lamp, &back).ok());
  CHECK(same_outline(back.shape, cup(-30, -10, 3)));
  REQUIRE(renderer.update_light(lamp, concave_light(cup(-28, -5, 3), {1, 0.9, 0.7}, 2)).ok());
  frame_equals_snapshot("moved");
  REQUIRE(renderer.set_light_emission(lamp, {0.2, 1, 0.2}, 4).ok());
  REQUIRE(renderer.light(lamp, &back).ok());
  CHECK(back.intensity == 4);
  CHECK(same_outline(back.shape, cup(-28, -5, 3)));
  frame_equals_snapshot("recoloured");
  Light with_shadow = back;
  with_shadow.shadow.strength = 0.5;  // each piece split in two parts
  REQUIRE(renderer.update_light(lamp, with_shadow).ok());
  frame_equals_snapshot("half shadow");
  REQUIRE(renderer.update_light(lamp, Light{Circle{{-20, 0}, 3}, {1, 1, 1}, 1}).ok());
  frame_equals_snapshot("convex");
  REQUIRE(renderer.update_light(lamp, concave_light(ell(-30, -20, 4), {1, 1, 1}, 1)).ok());
  frame_equals_snapshot("concave again");
  CHECK(renderer.light_count() == 2);
  // Refused: a range or normalize (each piece's own), an outline that crosses itself.
  Light ranged = concave_light(ell(0, 0, 4), {1, 1, 1}, 1);
  ranged.range = 30;
  Status s = renderer.update_light(lamp, ranged);
  CHECK(s.message().find(": range: a concave light takes no range or normalize (split it into convex lights)") !=
        std::string::npos);
  Light crossed = concave_light(Polygon{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}}, {1, 1, 1}, 1);
  s = renderer.update_light(lamp, crossed);
  CHECK(s.message().find(": polygon: edges") != std::string::npos);
  frame_equals_snapshot("after refusals");
  REQUIRE(renderer.remove_light(lamp).ok());
  CHECK(renderer.light_count() == 1);
  frame_equals_snapshot("removed");
}

TEST_CASE("concave lights in scene files: read, written back exactly, and refused with their place") {
  Scene scene = lit_by(concave_light(cup(-12, -10, 4), {1, 0.8, 0.5}, 1.5), {});
  const std::string text = scene_to_json(scene);
  Scene back;
  REQUIRE(parse_scene(text, "scene.json", back).ok());
  CHECK(scene_to_json(back) == text);
  CHECK(same_outline(back.lights[0].shape, cup(-12, -10, 4)));
  Scene normalized = scene;
  normalized.lights[0].normalize = 10;
  const Status s = validate_scene(normalized);
  CHECK(s.message() == "scene: lights[0].normalize: a concave light takes no range or normalize (split it into convex lights)");
}

TEST_CASE("random concave and ringed lights on a whole-unit grid: every SIMD level within section 5 of scalar") {
  // Whole-unit vertices with pixels of 1/4 or 1/5 unit put pixel centres exactly on the
  // partition's inner boundaries (diagonals included), where the float kernel must decide
  // each piece and each shared boundary alike.
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    CAPTURE(seed);
    std::mt19937 rng(seed);
    const auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    Scene scene;
    scene.width = seed % 2 ? 80 : 100;
    scene.height = seed % 2 ? 64 : 80;
    scene.view = {0, 0, 20, 16};
    const int lights = pick(1, 3);
    for (int k = 0; k < lights; ++k) {
      const double x = pick(0, 7), y = pick(0, 8), s = pick(1, 2);  // left of x 14: apart from the occluders
      Polygon shape = k % 3 == 0 ? ell(x, y, s) : k % 3 == 1 ? cup(x, y, s) : Polygon{};
      if (k % 3 == 2) shape = Polygon{{{x, y}, {x + 6, y}, {x + 6, y + 6}, {x, y + 6}}, {{{x + 2, y + 2}, {x + 4, y + 2}, {x + 4, y + 4}, {x + 2, y + 4}}}};
      Light light = concave_light(std::move(shape), {1.0, 0.5 + 0.1 * k, 0.3}, 1.0 + k);
      light.elevation = 15.0 * k;
      scene.lights.push_back(std::move(light));
    }
    scene.occluders.push_back(box(pick(14, 16), pick(0, 4), 19, pick(10, 15), {0.5, 0.7, 0.9}));
    scene.occluders.push_back(Occluder{Circle{{double(pick(14, 18)), 14.5}, 1}});
    REQUIRE(validate_scene(scene).ok());
    const RenderedImage reference = render_or_fail(scene, options_for(Backend::scalar));
    const double pixel = 20.0 / scene.width;
    check_simd_against_scalar(
        scene, reference, "concave lights on a grid", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * pixel); },
        scene.width * scene.height / 3);
  }
}

}  // namespace par2d::test


namespace par2d::test {
namespace {

Polygon comb(int teeth) { return Polygon{bench::comb_outline(teeth, false)}; }

}  // namespace

TEST_CASE("a concave light counts once per entry: E passes e, stays within e times 1 + n/2, and the limit counts entries" *
          per_isa()) {
  const Polygon teeth = comb(10);
  const double entries = 1.0 + std::floor(0.5 * static_cast<double>(teeth.vertices.size()));
  Scene scene = lit_by(concave_light(teeth, {1, 1, 1}, 1.0), {});
  scene.width = 96;
  scene.height = 16;
  scene.view = {-30, 2, 50, 8};
  // A row through the teeth from outside: rays along it enter tooth after tooth.
  double largest = 0.0;
  for (Backend backend : {Backend::scalar, Backend::simd}) {
    RenderOptions o;
    o.backend = backend;
    o.threads = 1;
    const RenderedImage image = render_or_fail(scene, o);
    for (float e : image.pixels) {
      CHECK(e >= 0.0f);
      CHECK(e <= entries);
      largest = std::max(largest, static_cast<double>(e));
    }
  }
  CHECK(largest > 1.5);  // more than the light's one emission: the bound must count entries
  // An emission whose entries pass float32's range is refused, in files and in a Renderer.
  scene.lights[0].intensity = 1e38 / entries * 1.5;
  Status status = validate_scene(scene, "comb.json");
  REQUIRE_FALSE(status.ok());
  CHECK(status.message().rfind("comb.json: lights[0]: emission too large", 0) == 0);
  scene.lights[0].intensity = 1e38 / entries * 0.5;
  CHECK(validate_scene(scene, "comb.json").ok());
  for (Backend backend : {Backend::scalar, Backend::simd}) {
    RenderOptions o;
    o.backend = backend;
    o.threads = 1;
    for (float e : render_or_fail(scene, o).pixels) CHECK(std::isfinite(e));
  }
  Renderer renderer;
  REQUIRE(renderer.set_frame(8, 8, View{-30, 2, 50, 8}).ok());
  LightHandle lamp, other;
  CHECK_FALSE(renderer.add_light(concave_light(teeth, {1, 1, 1}, 1e38 / entries * 1.5), &lamp).ok());
  REQUIRE(renderer.add_light(concave_light(teeth, {1, 1, 1}, 1e38 / entries * 0.5), &lamp).ok());
  // The concave light already holds half the limit through its entries: a convex light with
  // 0.6 of the limit, or the comb brightened past it, is refused.
  CHECK_FALSE(renderer.add_light(Light{Circle{{60, 5}, 1}, {1, 1, 1}, 0.6e38}, &other).ok());
  CHECK_FALSE(renderer.set_light_emission(lamp, {1, 1, 1}, 1e38 / entries * 1.2).ok());
  CHECK(renderer.add_light(Light{Circle{{60, 5}, 1}, {1, 1, 1}, 0.4e38}, &other).ok());
}

}  // namespace par2d::test
