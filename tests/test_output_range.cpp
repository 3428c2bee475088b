// Scenes at the edges of the number range: emissions float output cannot hold and subnormal pixel sizes are refused; everything accepted renders finite.
#include <doctest/doctest.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fuzz/fuzz_checks.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"

namespace {

using namespace par2d;

Scene one_light_scene(double intensity, Rgb color = {1, 1, 1}) {
  Scene s;
  s.width = s.height = 16;
  s.view = {0, 0, 16, 16};
  Light l;
  l.shape = Circle{{8, 4}, 1};
  l.intensity = intensity;
  l.color = color;
  s.lights.push_back(l);
  s.occluders.push_back({Segment{{0, 12}, {16, 12}}});
  return s;
}

// Every backend with these options, and the ray caster (`raycast`) with its own rays.
struct Method {
  RenderOptions options;
  bool raycast = false;
  const char* name() const { return raycast ? "raycast" : backend_name(options.backend); }
};

std::vector<Method> every_backend() {
  std::vector<Method> out;
  RenderOptions o;
  o.threads = 1;
  o.backend = Backend::scalar;
  out.push_back({o, false});
  o.rays = 64;
  out.push_back({o, true});
  for (Isa isa : par2d::kSimdIsas) {
    if (!isa_supported(isa)) continue;
    o.backend = Backend::simd;
    o.isa = isa;
    out.push_back({o, false});
  }
  return out;
}

void check_all_finite_and_bounded(const Scene& scene) {
  for (const Method& m : every_backend()) {
    Status status;
    const test::RenderedImage image = test::render_image(scene, m.options, status, m.raycast);
    REQUIRE_MESSAGE(status.ok(), status.message());
    const std::string problem = fuzz::check_bounds(scene, image, m.name());
    CHECK_MESSAGE(problem.empty(), problem);
  }
}

}  // namespace

TEST_CASE("emissions whose total float output cannot hold are refused at load and validate time, naming the light") {
  // 2.2e39 used to give NaN in the SIMD path (emission / 2pi overflowed float) and inf in PFMs.
  for (double intensity : {2.2e39, 1e300, 3.5e38}) {
    const Status s = validate_scene(one_light_scene(intensity), "big.json");
    CAPTURE(s.message());
    CHECK(s.code() == StatusCode::invalid_scene);
    CHECK(s.message().rfind("big.json: lights[0]: emission too large", 0) == 0);
    CHECK(s.message().find('\n') == std::string::npos);
  }
  // The total counts, not each light: two lights of 6e37 pass 1e38 at the second.
  Scene two = one_light_scene(6e37);
  two.lights.push_back(two.lights[0]);
  CHECK(validate_scene(two).message().find("lights[1]: emission too large") != std::string::npos);
  // Per channel: intensity * color overflowing a double is refused too.
  CHECK(!validate_scene(one_light_scene(1e300, {1e300, 0, 0})).ok());
  // Through the JSON loader, with the same place.
  Scene parsed;
  const Status json = parse_scene(
      R"({"width": 4, "height": 4, "lights": [{"circle": {"center": [1, 1], "radius": 1}},)"
      R"( {"circle": {"center": [1, 1], "radius": 1}, "color": [0, 1e30, 0], "intensity": 1e9}]})",
      "s.json", parsed);
  CHECK(json.code() == StatusCode::invalid_scene);
  CHECK(json.message().rfind("s.json: lights[1]: emission too large", 0) == 0);
}

TEST_CASE("the largest accepted emission renders finite and bounded on every backend") {
  check_all_finite_and_bounded(one_light_scene(1e38));
  check_all_finite_and_bounded(one_light_scene(1e38, {1, 0.5, 1e-30}));
  Scene two = one_light_scene(5e37);
  two.lights.push_back(two.lights[0]);
  std::get<Circle>(two.lights[1].shape).center = {4, 2};
  check_all_finite_and_bounded(two);
}

TEST_CASE("views whose pixel size is not a normal double are refused; the smallest normal one renders correctly") {
  Scene scene = one_light_scene(1.0);
  for (View v : {View{0, 0, 1e-310, 1e-310}, View{0, 0, 16, 16 * 1e-310}, View{0, 5, 16 * 1e-309, 6}}) {
    scene.view = v;
    const Status s = validate_scene(scene, "tiny.json");
    CAPTURE(s.message());
    CHECK(s.code() == StatusCode::invalid_scene);
    CHECK(s.message().rfind("tiny.json: view: pixel size ", 0) == 0);
  }
  Scene parsed;
  const Status json = parse_scene(R"({"width": 2, "height": 2, "view": [0, 0, 1e-310, 1e-310]})", "v.json", parsed);
  CHECK(json.message().rfind("v.json: view: pixel size", 0) == 0);

  // Pixels of exactly DBL_MIN (the scene is rescaled by a capped power of two): every pixel
  // sits at the origin to within 1e-303, E = 2·asin(0.5/1)/2pi = 1/6.
  Scene small;
  small.width = 16;
  small.height = 4;
  small.view = {0, 0, 16 * DBL_MIN, 4 * DBL_MIN};
  Light l;
  l.shape = Circle{{1, 0}, 0.5};
  small.lights.push_back(l);
  REQUIRE(validate_scene(small).ok());
  for (const Method& m : every_backend()) {
    if (m.raycast) continue;  // sampled, checked for bounds below
    Status status;
    const test::RenderedImage got = test::render_image(small, m.options, status);
    REQUIRE_MESSAGE(status.ok(), status.message());
    for (float v : got.pixels) CHECK(std::fabs(v - 1.0 / 6.0) <= 1e-4);
  }
  check_all_finite_and_bounded(small);
}

TEST_CASE("property: random scenes at the extremes that validation accepts render finite and within [0, sum e]") {
  // Emissions up to the limit, pixel sizes from DBL_MIN to 1e300, coordinates far from the
  // origin; every backend. The loader and validation decide what is accepted.
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int rendered = 0;
  for (int trial = 0; trial < 24; ++trial) {
    test::RandomSceneOptions options;
    options.max_occluders = 6;
    options.max_lights = 3;
    options.lights_disjoint_from_occluders = trial % 2 == 0;
    Scene scene = test::random_scene(1000 + trial, options);
    scene.width = 8 + trial % 9;
    scene.height = 8 + trial % 5;
    // Rescale the whole scene to a pixel size 10^k (k in -307 .. 300) around an origin.
    const double exponents[] = {-307.6, -300, -150, -3, 0, 7, 150, 290};
    const double pixel = std::pow(10.0, exponents[trial % 8]);
    const double old_pixel = test::pixel_width(scene);
    const double origin = (trial % 3 == 0) ? 0.0 : pixel * 1e6;
    auto map = [&](Vec2 p) { return Vec2{origin + (p.x - scene.view.x0) / old_pixel * pixel, origin + (p.y - scene.view.y0) / old_pixel * pixel}; };
    auto map_shape = [&](Shape& sh) {
      if (auto* p = std::get_if<Polygon>(&sh))
        for (Vec2& v : p->vertices) v = map(v);
      if (auto* c = std::get_if<Circle>(&sh)) c->center = map(c->center), c->radius = c->radius / old_pixel * pixel;
      if (auto* g = std::get_if<Segment>(&sh)) g->a = map(g->a), g->b = map(g->b);
    };
    for (Light& light : scene.lights) {
      map_shape(light.shape);
      light.intensity = std::ldexp(unit(rng), 120);  // ~1e36 each: near the total's limit
    }
    for (Occluder& o : scene.occluders) map_shape(o.shape);
    const Vec2 v0 = map({scene.view.x0, scene.view.y0});
    scene.view = {v0.x, v0.y, v0.x + scene.width * pixel, v0.y + scene.height * pixel};
    if (!validate_scene(scene).ok()) continue;  // e.g. a shape collapsed by the rescale
    INFO("trial ", trial, " pixel ", pixel);
    check_all_finite_and_bounded(scene);
    ++rendered;
  }
  CHECK(rendered >= 16);
}

// Callers may hand render() uninitialized memory (the CLI does): every pixel of the view must
// be written. Images pre-filled with NaN, at sizes that are not multiples of the tile or the
// vector width, through every path (scalar, each ISA, culling off, several samples, the game
// model with a normal map), must hold no NaN afterwards.
TEST_CASE("render writes every pixel of its view: NaN-filled images come back all finite") {
  int checked = 0;
  for (std::uint32_t trial = 0; trial < 6; ++trial) {
    test::RandomSceneOptions scene_options;
    if (trial % 3 == 2) scene_options = test::with_every_model_term(scene_options);  // a normal map too
    scene_options.width = 17 + 13 * static_cast<int>(trial);
    scene_options.height = 9 + 7 * static_cast<int>(trial);
    const Scene scene = test::random_scene(4200 + trial, scene_options);
    std::vector<RenderOptions> paths{test::options_for(Backend::scalar)};
    for (Isa isa : test::simd_isas_here()) {
      paths.push_back(test::options_for(Backend::simd, isa));
      paths.push_back(test::options_for(Backend::simd, isa, false));
      RenderOptions samples = test::options_for(Backend::simd, isa);
      samples.spp = 3;
      paths.push_back(samples);
    }
    for (const RenderOptions& options : paths) {
      const int stride = scene.width * 3 + 2;  // padded rows: the padding must stay as it was
      std::vector<float> pixels(static_cast<std::size_t>(stride) * scene.height,
                                std::numeric_limits<float>::quiet_NaN());
      const ImageView view{pixels.data(), scene.width, scene.height, stride};
      INFO("trial ", trial, " isa ", std::string(options.isa ? isa_name(*options.isa) : "scalar"), " culling ", options.culling, " spp ",
           options.spp);
      REQUIRE(render(scene, options, view).ok());
      int nan_pixels = 0, padding_written = 0;
      for (int j = 0; j < scene.height; ++j)
        for (int i = 0; i < stride; ++i) {
          const bool nan = std::isnan(pixels[static_cast<std::size_t>(j) * stride + i]);
          if (i < scene.width * 3) nan_pixels += nan;
          else padding_written += !nan;
        }
      CHECK(nan_pixels == 0);
      CHECK(padding_written == 0);
      ++checked;
    }
  }
  CHECK(checked >= 6);
}
