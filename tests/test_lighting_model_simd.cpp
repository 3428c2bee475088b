// The SIMD kernels' game lighting model (docs/contract.md section 6), for every ISA this CPU
// runs: closed forms for each term, and the persistent Renderer against one-shot renders.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

constexpr double kPiD = 3.14159265358979323846;

RenderOptions simd_options(Isa isa) {
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = isa;
  o.threads = 2;
  return o;
}

Scene empty_scene(int width, int height) {
  Scene s;
  s.width = width;
  s.height = height;
  s.view = {0.0, 0.0, static_cast<double>(width), static_cast<double>(height)};
  return s;
}

Light circle_light(Vec2 center, double radius, Rgb color, double intensity) {
  Light l;
  l.shape = Circle{center, radius};
  l.color = color;
  l.intensity = intensity;
  return l;
}

Occluder box_occluder(double x0, double y0, double x1, double y1) {
  Occluder o;
  o.shape = Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  return o;
}

double window(double d, double range) {
  const double w = std::clamp(1.0 - (d / range) * (d / range), 0.0, 1.0);
  return w * w;
}

// Angle subtended by a circle of radius r at distance D from its center (2 pi inside).
double circle_arc(Vec2 x, Vec2 c, double r) {
  const double d = std::hypot(x.x - c.x, x.y - c.y);
  return d <= r ? 2.0 * kPiD : 2.0 * std::asin(r / d);
}

// Checks every pixel of `scene` farther than 0.05 px from the scene's boundaries against
// `expected(x, channel)` (NaN: not checked) for every SIMD ISA.
template <class F>
void check_closed_form(const Scene& scene, const std::string& what, F expected, double e_max, bool shaded = true) {
  const double bound = 1e-4 * e_max;
  const Scene& exempt_from = scene;
  for (Isa isa : simd_isas_here()) {
    RenderOptions options = simd_options(isa);
    options.shaded = shaded;
    const RenderedImage got = render_or_fail(scene, options);
    int checked = 0, over = 0;
    double worst = 0.0;
    std::string first_failure;
    for (int j = 0; j < scene.height; ++j) {
      for (int i = 0; i < scene.width; ++i) {
        const Vec2 x = pixel_center(scene, i, j);
        if (near_boundary(exempt_from, x, 0.05 * pixel_width(scene))) continue;
        if (std::isnan(expected(x, 0))) continue;
        ++checked;
        for (int c = 0; c < 3; ++c) {
          const double err = std::abs(expected(x, c) - got.at(i, j, c));
          worst = std::max(worst, err);
          if (!(err <= bound) && over++ == 0)
            first_failure = "pixel (" + std::to_string(i) + "," + std::to_string(j) + ") channel " +
                            std::to_string(c) + ": expected " + std::to_string(expected(x, c)) + ", got " +
                            std::to_string(got.at(i, j, c));
        }
      }
    }
    INFO(what, " isa=", std::string(isa_name(isa)), " checked=", checked, " worst=", worst, " bound=", bound);
    CHECK(checked > scene.width * scene.height / 3);
    CHECK_MESSAGE(over == 0, first_failure);
  }
}

}  // namespace

TEST_CASE("model SIMD: a ranged circle light and ambient match the closed form") {
  Scene s = empty_scene(64, 48);
  Light l = circle_light({20.0, 22.0}, 3.5, {1.0, 0.5, 0.25}, 2.0);
  l.range = 30.0;
  s.lights.push_back(l);
  s.ambient = {0.01, 0.02, 0.03};
  const double e_max = 2.0 + 0.03;
  check_closed_form(
      s, "range", [&](Vec2 x, int c) {
        const double d = std::max(0.0, std::hypot(x.x - 20.0, x.y - 22.0) - 3.5);
        return s.ambient[c] + l.intensity * l.color[c] * window(d, 30.0) * circle_arc(x, {20.0, 22.0}, 3.5) / (2 * kPiD);
      },
      e_max);
}

TEST_CASE("model SIMD: a polygon light's range window uses the distance to the polygon") {
  Scene s = empty_scene(48, 48);
  Light l;
  l.shape = Polygon{{{20.0, 20.0}, {26.0, 20.0}, {26.0, 24.0}, {20.0, 24.0}}};
  l.intensity = 1.5;
  l.range = 14.0;
  s.lights.push_back(l);
  // The closed form of a box light's arc: the widest angle between its corners (outside it).
  auto arc = [](Vec2 x) {
    if (x.x > 20.0 && x.x < 26.0 && x.y > 20.0 && x.y < 24.0) return 2.0 * kPiD;
    const Vec2 corners[4] = {{20.0, 20.0}, {26.0, 20.0}, {26.0, 24.0}, {20.0, 24.0}};
    double widest = 0.0;
    for (const Vec2 a : corners)
      for (const Vec2 b : corners) {
        const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
        widest = std::max(widest, std::atan2(std::abs(ax * by - ay * bx), ax * bx + ay * by));
      }
    return widest;
  };
  check_closed_form(
      s, "polygon range", [&](Vec2 x, int) {
        const double dx = std::max({20.0 - x.x, 0.0, x.x - 26.0}), dy = std::max({20.0 - x.y, 0.0, x.y - 24.0});
        return 1.5 * window(std::hypot(dx, dy), 14.0) * arc(x) / (2 * kPiD);
      },
      1.5);
}

TEST_CASE("model SIMD: a translucent occluder and a translucent box around the pixel scale the light per channel") {
  Scene s = empty_scene(64, 48);
  s.lights.push_back(circle_light({32.0, 8.0}, 3.0, {1.0, 1.0, 1.0}, 3.0));
  Occluder wall;  // crosses every line from y > 20 to the light
  wall.shape = Segment{{-100.0, 20.0}, {164.0, 20.0}};
  wall.transmittance = {0.5, 0.25, 0.0};
  s.occluders.push_back(wall);
  Occluder glass = box_occluder(40.0, 30.0, 56.0, 44.0);  // the pixels inside it see through it
  glass.transmittance = {0.8, 0.6, 0.4};
  s.occluders.push_back(glass);
  check_closed_form(
      s, "translucent", [&](Vec2 x, int c) {
        double t = x.y > 20.0 ? wall.transmittance[c] : 1.0;
        const bool in_glass = x.x > 40.0 && x.x < 56.0 && x.y > 30.0 && x.y < 44.0;
        // Outside the glass below its top, some lines to the light cross it: not checked.
        if (!in_glass && x.y > 29.0) return std::nan("");
        if (in_glass) t *= glass.transmittance[c];
        return 3.0 * t * circle_arc(x, {32.0, 8.0}, 3.0) / (2 * kPiD);
      },
      3.0);
}

TEST_CASE("model SIMD: masks and lit interiors remove occluders exactly where the contract says") {
  Scene s = empty_scene(64, 48);
  Light l = circle_light({10.0, 24.0}, 3.0, {0.2, 0.7, 1.0}, 2.0);
  l.mask = 1;
  s.lights.push_back(l);
  Occluder other = box_occluder(20.0, 4.0, 24.0, 44.0);  // acts on another light group only
  other.mask = 2;
  s.occluders.push_back(other);
  Occluder sprite = box_occluder(36.0, 10.0, 60.0, 38.0);  // lit inside, shadows beyond
  sprite.interior = Interior::lit;
  s.occluders.push_back(sprite);
  s.ambient = {0.0, 0.0, 0.05};
  check_closed_form(
      s, "mask and lit interior", [&](Vec2 x, int c) {
        const double direct = l.intensity * l.color[c] * circle_arc(x, {10.0, 24.0}, 3.0) / (2 * kPiD);
        // Right of the sprite it shadows (not checked); inside it and left of it nothing
        // acting is in front.
        const bool in_sprite = x.x > 36.0 && x.x < 60.0 && x.y > 10.0 && x.y < 38.0;
        if (x.x > 36.0 && !in_sprite) return std::nan("");
        return s.ambient[c] + direct;
      },
      2.0 + 0.05);
}

namespace {

// The arc [start, start + width] of directions from x to an axis-aligned box (x outside it).
void box_arc(Vec2 x, double x0, double y0, double x1, double y1, double& start, double& width) {
  const double toward = std::atan2(0.5 * (y0 + y1) - x.y, 0.5 * (x0 + x1) - x.x);
  double lo = 10.0, hi = -10.0;
  for (const Vec2 p : {Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x1, y1}, Vec2{x0, y1}}) {
    double a = std::atan2(p.y - x.y, p.x - x.x) - toward;
    a -= 2 * kPiD * std::floor((a + kPiD) / (2 * kPiD));
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  start = toward + lo;
  width = hi - lo;
}

}  // namespace

TEST_CASE("model SIMD: a shaded directional light cut by a box matches the closed form") {
  Scene s = empty_scene(64, 48);
  DirectionalLight sun;
  sun.angle0 = 200.0;
  sun.angle1 = 265.0;
  sun.intensity = 1.5;
  sun.color = {1.0, 0.9, 0.6};
  sun.elevation = 30.0;
  s.directional_lights.push_back(sun);
  const Vec3 n{0.3 / std::sqrt(0.94), -0.2 / std::sqrt(0.94), 0.9 / std::sqrt(0.94)};
  s.normal = n;
  s.occluders.push_back(box_occluder(30.0, 18.0, 38.0, 26.0));
  s.ambient = {0.02, 0.02, 0.02};
  const double a0 = sun.angle0 * kPiD / 180.0, a1 = sun.angle1 * kPiD / 180.0;
  const double sin_el = std::sin(30.0 * kPiD / 180.0), cos_el = std::cos(30.0 * kPiD / 180.0);
  const double amplitude = cos_el * std::hypot(n.x, n.y), offset = sin_el * n.z, beta = std::atan2(n.y, n.x);
  REQUIRE(offset > amplitude);  // the lobe is positive in every direction: one antiderivative
  auto integral = [&](double lo, double hi) {
    return amplitude * (std::sin(hi - beta) - std::sin(lo - beta)) + offset * (hi - lo);
  };
  auto expected = [&](Vec2 x, int c, bool shaded) {
    const double e = sun.intensity * sun.color[c] / (2 * kPiD);
    auto weight = [&](double lo, double hi) { return shaded ? integral(lo, hi) : hi - lo; };
    if (x.x > 30.0 && x.x < 38.0 && x.y > 18.0 && x.y < 26.0) return s.ambient[c];
    double start, width;
    box_arc(x, 30.0, 18.0, 38.0, 26.0, start, width);
    double visible = weight(a0, a1);
    for (int k = -2; k <= 2; ++k) {
      const double lo = std::max(a0, start + 2 * kPiD * k), hi = std::min(a1, start + width + 2 * kPiD * k);
      if (hi > lo) visible -= weight(lo, hi);
    }
    return s.ambient[c] + e * visible;
  };
  check_closed_form(
      s, "directional shaded", [&](Vec2 x, int c) { return expected(x, c, true); }, 1.5 + 0.02);
  check_closed_form(
      s, "directional plain", [&](Vec2 x, int c) { return expected(x, c, false); }, 1.5 + 0.02, false);
}

TEST_CASE("model SIMD: a spot cone weights the light's arc by its trapezoid profile") {
  Scene s = empty_scene(64, 48);
  Light l = circle_light({12.0, 24.0}, 4.0, {1.0, 1.0, 1.0}, 2.5);
  l.cone = Cone{10.0, 40.0, 15.0};  // emitted toward +x, a little down
  s.lights.push_back(l);
  const double center = 10.0 * kPiD / 180.0, half = 40.0 * kPiD / 180.0, fade = 15.0 * kPiD / 180.0;
  auto profile = [&](double theta) {  // theta: ray direction; emitted along theta + pi
    double delta = std::abs(theta + kPiD - center);
    delta = std::fmod(delta, 2 * kPiD);
    if (delta > kPiD) delta = 2 * kPiD - delta;
    if (delta <= half - fade) return 1.0;
    if (delta >= half) return 0.0;
    return (half - delta) / fade;
  };
  check_closed_form(
      s, "cone", [&](Vec2 x, int) {
        const double d = std::hypot(x.x - 12.0, x.y - 24.0);
        if (d <= 4.0) return std::nan("");  // inside: the whole circle of directions, checked by the scalar tests
        const double toward = std::atan2(24.0 - x.y, 12.0 - x.x), h = std::asin(4.0 / d);
        const int steps = 4000;
        double sum = 0.0;
        for (int k = 0; k < steps; ++k) sum += profile(toward - h + (k + 0.5) * (2 * h / steps));
        return 2.5 * sum * (2 * h / steps) / (2 * kPiD);
      },
      2.5);
}

namespace {

// The renderer's whole frame as float RGB.
RenderedImage render_frame(Renderer& renderer, int width, int height) {
  RenderedImage image;
  image.width = width;
  image.height = height;
  image.pixels.assign(static_cast<std::size_t>(width) * height * 3, -1.0f);
  REQUIRE(renderer.render(ImageView{image.pixels.data(), width, height, 3 * width}).ok());
  return image;
}

}  // namespace

TEST_CASE("model SIMD: a persistent Renderer with moving ranged torches equals one-shot renders") {
  Scene s = empty_scene(96, 64);
  for (int k = 0; k < 6; ++k) {
    Light l = circle_light({10.0 + 15.0 * k, 12.0 + 7.0 * (k % 3)}, 1.5, {1.0, 0.6 + 0.05 * k, 0.3}, 1.0 + 0.2 * k);
    l.range = 18.0 + 3.0 * k;
    s.lights.push_back(l);
  }
  s.occluders.push_back(box_occluder(20.0, 30.0, 40.0, 34.0));
  s.occluders.push_back(box_occluder(60.0, 20.0, 64.0, 50.0));
  Occluder glass = box_occluder(70.0, 40.0, 90.0, 44.0);
  glass.transmittance = {0.5, 0.7, 0.9};
  s.occluders.push_back(glass);
  s.ambient = {0.01, 0.01, 0.02};
  for (Isa isa : simd_isas_here()) {
    Renderer renderer;
    REQUIRE(renderer.set_options(simd_options(isa)).ok());
    std::vector<LightHandle> handles;
    REQUIRE(renderer.set_scene(s, &handles).ok());
    Scene moved = s;
    for (int frame = 0; frame < 4; ++frame) {
      for (std::size_t k = 0; k < handles.size(); ++k) {
        Light& l = moved.lights[k];
        l.shape = Circle{{10.0 + 15.0 * static_cast<double>(k) + 2.5 * frame, 12.0 + 7.0 * static_cast<double>(k % 3) + 3.0 * frame}, 1.5};
        REQUIRE(renderer.update_light(handles[k], l).ok());
      }
      const RenderedImage persistent = render_frame(renderer, s.width, s.height);
      const RenderedImage once = render_or_fail(moved, simd_options(isa));
      INFO("isa=", std::string(isa_name(isa)), " frame=", frame);
      CHECK(persistent.pixels == once.pixels);
      // The torches' ranges end inside the frame: some pixels see only the ambient term.
      CHECK(std::count(once.pixels.begin(), once.pixels.end(), 0.01f) > 0);
    }
  }
}

namespace {

// The SIMD path against the scalar reference (docs/contract.md section 5: 1e-4 e_max away from
// 0.05 px of every boundary, e_max with directional lights and ambient) for every ISA here.
void check_against_scalar(const Scene& scene, const std::string& what, bool shaded = true, int spp = 1) {
  RenderOptions scalar;
  scalar.backend = Backend::scalar;
  scalar.threads = 2;
  scalar.shaded = shaded;
  scalar.spp = spp;
  const RenderedImage reference = render_or_fail(scene, scalar);
  const double bound = 1e-4 * emission_max_sum(scene);
  for (Isa isa : simd_isas_here()) {
    RenderOptions options = simd_options(isa);
    options.shaded = shaded;
    options.spp = spp;
    const RenderedImage got = render_or_fail(scene, options);
    // With several samples a pixel is exempt when a boundary passes within 0.05 px of the
    // farthest point a sample may take (0.71 px from the center).
    const double exempt = spp == 1 ? 0.05 * pixel_width(scene) : 0.76 * pixel_width(scene);
    const Comparison c = compare_renders(scene, reference, got, bound, exempt);
    const int checked = c.checked, over = c.over;
    const double worst = c.max_error;
    const std::string& first_failure = c.first_failure;
    INFO(what, " isa=", std::string(isa_name(isa)), " checked=", checked, " worst=", worst, " bound=", bound);
    CHECK(checked > 0);
    CHECK_MESSAGE(over == 0, first_failure);
  }
}

struct Feature {
  const char* name;
  void (*apply)(RandomSceneOptions&);
};

const Feature kFeatures[] = {
    {"range", [](RandomSceneOptions& o) { o.ranges = true; }},
    {"falloff", [](RandomSceneOptions& o) { o.ranges = o.falloffs = true; }},
    {"normalize", [](RandomSceneOptions& o) { o.normalizes = true; }},
    {"cone", [](RandomSceneOptions& o) { o.cones = true; }},
    {"cookie", [](RandomSceneOptions& o) { o.cookies = true; }},
    {"mask", [](RandomSceneOptions& o) { o.masks = true; }},
    {"translucent", [](RandomSceneOptions& o) { o.translucent = true; }},
    {"lit interior", [](RandomSceneOptions& o) { o.lit_interiors = true; }},
    {"directional", [](RandomSceneOptions& o) { o.directional_lights = 2; }},
    {"ambient", [](RandomSceneOptions& o) { o.ambient = true; }},
    {"constant normal",
     [](RandomSceneOptions& o) {
       o.elevations = true;
       o.normals = RandomSceneOptions::Normals::constant;
     }},
    {"normal map",
     [](RandomSceneOptions& o) {
       o.elevations = true;
       o.normals = RandomSceneOptions::Normals::map;
     }},
    {"every term", [](RandomSceneOptions& o) { o = with_every_model_term(o); }},
};

}  // namespace

TEST_CASE("model SIMD: normalized lights in a persistent Renderer follow emission changes, resizes and falloff edits") {
  Scene s = empty_scene(80, 48);
  for (int k = 0; k < 4; ++k) {
    Light l = circle_light({10.0 + 20.0 * k, 20.0}, 1.0 + k, {1.0, 0.7, 0.4}, 1.5);
    l.normalize = 12.0;
    l.range = 30.0;
    s.lights.push_back(l);
  }
  s.occluders.push_back(box_occluder(30.0, 30.0, 50.0, 34.0));
  for (Isa isa : simd_isas_here()) {
    Renderer renderer;
    REQUIRE(renderer.set_options(simd_options(isa)).ok());
    std::vector<LightHandle> handles;
    REQUIRE(renderer.set_scene(s, &handles).ok());
    Scene now = s;
    for (int frame = 0; frame < 4; ++frame) {
      Light& l = now.lights[static_cast<std::size_t>(frame)];
      if (frame % 2 == 0) {  // a flicker: the normalized emission follows the new intensity
        l.intensity = 0.5 + frame;
        REQUIRE(renderer.set_light_emission(handles[static_cast<std::size_t>(frame)], l.color, l.intensity).ok());
      } else {  // a bigger torch, same brightness at the reference distance; another falloff
        l.shape = Circle{{10.0 + 20.0 * frame, 20.0}, 5.0};
        l.falloff = 0.5 * frame;
        REQUIRE(renderer.update_light(handles[static_cast<std::size_t>(frame)], l).ok());
      }
      const RenderedImage persistent = render_frame(renderer, s.width, s.height);
      const RenderedImage once = render_or_fail(now, simd_options(isa));
      INFO("isa=", std::string(isa_name(isa)), " frame=", frame);
      CHECK(persistent.pixels == once.pixels);
      check_against_scalar(now, "normalized frame " + std::to_string(frame));
    }
  }
}

TEST_CASE("model SIMD: random scenes with each term and all together match the scalar reference") {
  for (const Feature& feature : kFeatures) {
    for (std::uint32_t seed = 1; seed <= 12; ++seed) {
      RandomSceneOptions options;
      options.width = 40;
      options.height = 30;
      options.max_occluders = 16;
      feature.apply(options);
      const Scene scene = random_scene(7000 + seed, options);
      check_against_scalar(scene, std::string(feature.name) + " seed " + std::to_string(7000 + seed));
    }
  }
}

TEST_CASE("model SIMD: overlapping lights and occluders with every term match the scalar reference") {
  for (std::uint32_t seed = 1; seed <= 16; ++seed) {
    RandomSceneOptions options = with_every_model_term({});
    options.width = 40;
    options.height = 30;
    options.lights_disjoint_from_occluders = false;
    options.max_occluders = 10;
    const Scene scene = random_scene(7100 + seed, options);
    check_against_scalar(scene, "overlapping, every term, seed " + std::to_string(7100 + seed));
    check_against_scalar(scene, "overlapping, every term, unshaded, seed " + std::to_string(7100 + seed), false);
  }
}

TEST_CASE("model SIMD: a mirrored far view and several samples per pixel with every term match the scalar reference") {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    RandomSceneOptions options = with_every_model_term({});
    options.width = 32;
    options.height = 24;
    options.view = View{1e5 + 32.0, 1e5, 1e5, 1e5 + 24.0};
    const Scene scene = random_scene(7200 + seed, options);
    check_against_scalar(scene, "mirrored far view, seed " + std::to_string(7200 + seed));
    check_against_scalar(scene, "mirrored far view, 4 spp, seed " + std::to_string(7200 + seed), true, 4);
  }
}

TEST_CASE("model SIMD: shaded lights behind nested occluders (gap-sweep steps that add nothing) match the scalar reference") {
  // A light left of a tall wall; small boxes lie in the wall's shadow, so seen from every pixel
  // right of them their intervals of directions lie inside the wall's: after sorting, the gap
  // sweep meets intervals that neither start nor end beyond the covered part in any lane (the
  // steps profiled_gaps skips) and, from pixels between the boxes, intervals that do.
  Scene s = empty_scene(64, 40);
  s.lights.push_back(circle_light({4.0, 20.0}, 5.0, {1.0, 0.8, 0.6}, 2.0));
  s.lights.back().elevation = 20.0;
  s.lights.push_back(circle_light({5.0, 4.0}, 1.0, {0.5, 0.7, 1.0}, 1.5));
  s.lights.back().elevation = 40.0;
  s.occluders.push_back(box_occluder(12.0, 17.0, 14.0, 23.0));
  for (int k = 0; k < 6; ++k) s.occluders.push_back(box_occluder(20.0 + 6.0 * k, 19.0, 21.0 + 6.0 * k, 21.0));
  for (const bool bumpy : {false, true}) {
    NormalMap map;
    map.width = s.width;
    map.height = s.height;
    for (int j = 0; j < s.height; ++j) {
      for (int i = 0; i < s.width; ++i) {
        // Flat: the lobe covers every direction; bumpy: some lanes' lobes are partial.
        const double nx = bumpy ? 0.9 * std::sin(0.3 * i) : 0.1, ny = bumpy ? 0.9 * std::cos(0.4 * j) : -0.05;
        map.normals.push_back(static_cast<float>(nx));
        map.normals.push_back(static_cast<float>(ny));
        map.normals.push_back(1.0f);
      }
    }
    s.normal_map = map;
    check_against_scalar(s, bumpy ? "nested occluders, bumpy map" : "nested occluders, flat map");
  }
}

// The value classes where float arithmetic breaks first (a range, fade or half angle with no
// finite float inverse, a cone ramp narrower than float resolves, normals whose squares
// underflow or overflow): SIMD against the scalar reference on every ISA, shaded and plain.
TEST_CASE("model SIMD: ranges, cone angles and normals at the ends of float and double match the scalar reference") {
  SUBCASE("tiny and huge ranges") {
    for (const double range : {1e-300, 4e-310, 5e-324, 1e-40, 1e-30, 1e300}) {
      CAPTURE(range);
      Scene s = empty_scene(32, 24);
      Light l = circle_light({16.0, 12.0}, 5.0, {1.0, 0.5, 0.25}, 2.0);
      l.range = range;
      s.lights.push_back(l);
      Light far = circle_light({4.0, 4.0}, 2.0, {0.2, 0.5, 1.0}, 1.0);
      far.range = range * 1e6;
      s.lights.push_back(far);
      check_against_scalar(s, "range");
    }
  }
  SUBCASE("cone fades and half angles far below a degree") {
    const Cone cones[] = {{0, 40, 5e-324}, {0, 40, 1e-300}, {0, 40, 1e-40}, {0, 40, 1e-20}, {0, 40, 1e-9},
                          {0, 40, 1e-6},   {0, 40, 1e-4},   {0, 40, 40.0 * (1.0 - 1e-15)}, {0, 1e-9, 1e-9},
                          {0, 1e-30, 0},   {0, std::nextafter(180.0, 0.0), 1e-30}};
    for (const Cone& cone : cones) {
      CAPTURE(cone.half_angle);
      CAPTURE(cone.fade);
      Scene s = empty_scene(48, 32);
      Light l = circle_light({4.0, 16.0}, 3.0, {1.0, 1.0, 1.0}, 2.5);
      l.cone = cone;
      l.elevation = 25.0;
      s.lights.push_back(l);
      s.occluders.push_back(box_occluder(20.0, 12.0, 22.0, 15.0));
      check_against_scalar(s, "cone, plain", false);
      s.normal = Vec3{0.2, -0.3, 0.9};  // the cone's pieces times the shading lobe
      check_against_scalar(s, "cone, shaded");
    }
  }
  SUBCASE("normals scaled to the ends of double") {
    for (const double k : {1e-300, 1e-310, 5e-324, 1e300, 1e307}) {
      CAPTURE(k);
      Scene s = empty_scene(32, 24);
      Light l = circle_light({8.0, 12.0}, 3.0, {1.0, 0.8, 0.6}, 2.0);
      l.elevation = 30.0;
      s.lights.push_back(l);
      s.occluders.push_back(box_occluder(16.0, 8.0, 18.0, 12.0));
      const Vec3 n{0.3 * k, -0.5 * k, 0.8 * k};
      s.normal = std::max({std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)}) > 0.0 ? n : Vec3{0.0, 0.0, k};
      check_against_scalar(s, "scaled normal");
    }
  }
}

TEST_CASE("model SIMD: random scenes with every term drawn at extreme values match the scalar reference") {
  int extreme_ranges = 0, extreme_fades = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    RandomSceneOptions options = with_every_model_term({});
    options.width = 32;
    options.height = 24;
    options.max_occluders = 10;
    options.normals = seed % 2 ? RandomSceneOptions::Normals::constant : RandomSceneOptions::Normals::map;
    options.extreme_values = true;
    const Scene scene = random_scene(7300 + seed, options);
    for (const Light& l : scene.lights) {
      extreme_ranges += l.range && (*l.range < 1e-12 || *l.range > 1e12);
      extreme_fades += l.cone && l.cone->fade > 0.0 && l.cone->fade < 1e-3;
    }
    check_against_scalar(scene, "extreme values, seed " + std::to_string(7300 + seed));
    check_against_scalar(scene, "extreme values, unshaded, seed " + std::to_string(7300 + seed), false);
  }
  // The seeds do draw from the extreme classes.
  CHECK(extreme_ranges >= 3);
  CHECK(extreme_fades >= 2);
}

// A light that overlaps a lit-interior occluder: at pixels inside the occluder it is absent, so
// the light there is exactly its unblocked arc (the whole circle inside the light too); outside,
// the occluder's edges cut the light where its part lies behind them. Every ISA against the
// closed form inside and the scalar reference everywhere.
TEST_CASE("model SIMD: pixels inside a lit-interior occluder that a light overlaps see the whole light") {
  Scene s = empty_scene(48, 32);
  // A sprite box with a torch half inside it, and a dark wall up and to the right of it (it
  // shadows the world outside the sprite, never a sight line from inside it to a light).
  Occluder sprite = box_occluder(8.0, 4.0, 32.0, 28.0);
  sprite.interior = Interior::lit;
  s.occluders.push_back(sprite);
  s.occluders.push_back(box_occluder(36.0, 0.0, 38.0, 4.0));
  Light torch = circle_light({8.0, 16.0}, 3.0, {1.0, 0.7, 0.4}, 2.0);
  s.lights.push_back(torch);
  Light lamp = circle_light({44.0, 20.0}, 2.0, {0.3, 0.6, 1.0}, 1.0);  // apart from both
  s.lights.push_back(lamp);
  // Inside the sprite the torch and the lamp count whole.
  const auto inside_sprite = [](Vec2 x) { return x.x > 8.0 && x.x < 32.0 && x.y > 4.0 && x.y < 28.0; };
  check_closed_form(
      s, "inside a lit sprite", [&](Vec2 x, int c) {
        if (!inside_sprite(x)) return std::nan("");
        const double torch_part = circle_arc(x, {8.0, 16.0}, 3.0) / (2 * kPiD);
        const double lamp_part = circle_arc(x, {44.0, 20.0}, 2.0) / (2 * kPiD);
        return torch.intensity * torch.color[c] * torch_part + lamp.intensity * lamp.color[c] * lamp_part;
      },
      2.0 + 1.0, false);
  check_against_scalar(s, "lit sprite overlapped by a torch, plain", false);
  s.occluders[0].transmittance = {0.5, 0.25, 0.75};  // the translucent pieces' path
  check_against_scalar(s, "translucent lit sprite overlapped by a torch, plain", false);
  s.normal = Vec3{0.1, -0.2, 1.0};
  check_against_scalar(s, "translucent lit sprite overlapped by a torch, shaded");
}
