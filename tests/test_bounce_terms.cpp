// One bounce beyond the reference (docs/contract.md section 7): the direct and bounce terms
// rendered apart (RenderOptions::bounce) on every backend, and the per-tile culling of
// reflectors (render/bounce_tiles.cpp) in a level of rooms where it hides most of them.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

Occluder wall(Vec2 a, Vec2 b, Rgb albedo) {
  Occluder o;
  o.shape = Polygon{{a, {b.x, a.y}, b, {a.x, b.y}}};
  o.albedo = albedo;
  return o;
}

// Three rooms in a row, 40 x 40 each, walls 4 thick, a doorway between the first two and
// none into the third; a lamp in the first, reflecting pillars in every room. From most of
// the first two rooms the third room's pillars are hidden by the solid wall.
Scene rooms() {
  Scene s;
  s.width = 144;
  s.height = 48;
  s.view = {0, 0, 132, 44};
  const Rgb grey{0.5, 0.5, 0.5}, red{0.9, 0.2, 0.1};
  s.occluders.push_back(wall({0, 0}, {132, 2}, grey));    // top
  s.occluders.push_back(wall({0, 42}, {132, 44}, grey));  // bottom
  s.occluders.push_back(wall({0, 2}, {2, 42}, red));      // left
  s.occluders.push_back(wall({130, 2}, {132, 42}, grey)); // right
  s.occluders.push_back(wall({42, 2}, {46, 16}, grey));   // first inner wall, door at 16..28
  s.occluders.push_back(wall({42, 28}, {46, 42}, grey));
  s.occluders.push_back(wall({86, 2}, {90, 42}, grey));   // second inner wall, solid
  for (const double x : {20.0, 66.0, 110.0}) {
    Occluder pillar;
    pillar.shape = Circle{{x, 30}, 3};
    pillar.albedo = {0.3, 0.8, 0.3};
    s.occluders.push_back(pillar);
  }
  Light lamp;
  lamp.shape = Circle{{15, 14}, 2.5};
  lamp.intensity = 3;
  s.lights.push_back(lamp);
  Light far;  // lights the third room, so its pieces are lit
  far.shape = Segment{{100, 8}, {120, 8}};
  s.lights.push_back(far);
  s.bounce.piece = 3;
  return s;
}

RenderOptions with_term(Backend backend, BounceTerm term) {
  RenderOptions options = options_for(backend);
  options.bounce = term;
  return options;
}

}  // namespace

TEST_CASE("bounce terms: excluded plus only is included, on every backend; excluded is the scene without albedo" *
          per_isa()) {
  Scene scene = rooms();
  scene.width = 33;
  scene.height = 11;
  Scene direct = scene;
  for (Occluder& o : direct.occluders) o.albedo = {0, 0, 0};
  const double e_max = emission_max_sum(scene);
  // The scalar reference, the automatic backend and the ray-casting baseline.
  for (const std::string method : {"scalar", "auto", "raycast"}) {
    CAPTURE(method);
    const Backend backend = method == "scalar" ? Backend::scalar : Backend::automatic;
    const bool raycast = method == "raycast";
    const RenderedImage all = render_or_fail(scene, with_term(backend, BounceTerm::included), raycast);
    const RenderedImage excluded = render_or_fail(scene, with_term(backend, BounceTerm::excluded), raycast);
    const RenderedImage only = render_or_fail(scene, with_term(backend, BounceTerm::only), raycast);
    const RenderedImage plain = render_or_fail(direct, with_term(backend, BounceTerm::included), raycast);
    CHECK(excluded.pixels == plain.pixels);
    double bounce = 0.0, worst = 0.0;
    for (std::size_t p = 0; p < all.pixels.size(); ++p) {
      bounce = std::max(bounce, double(only.pixels[p]));
      worst = std::max(worst, std::fabs(double(excluded.pixels[p]) + only.pixels[p] - all.pixels[p]));
      REQUIRE(only.pixels[p] >= 0.0f);
    }
    CHECK(bounce > 1e-3 * e_max);  // the bounce is there
    // The sum of the two float images against the one: float rounding of the addition.
    CHECK(worst <= 1e-6 * e_max);
  }
  // Without reflectors the bounce term is black and the others are the direct light.
  for (const Backend backend : {Backend::scalar, Backend::automatic}) {
    const RenderedImage only = render_or_fail(direct, with_term(backend, BounceTerm::only));
    for (const float v : only.pixels) REQUIRE(v == 0.0f);
    CHECK(render_or_fail(direct, with_term(backend, BounceTerm::excluded)).pixels ==
          render_or_fail(direct, with_term(backend, BounceTerm::included)).pixels);
  }
  RenderOptions bad;
  bad.bounce = static_cast<BounceTerm>(7);
  std::vector<float> pixels(3u * scene.width * scene.height);
  const Status s = render(scene, bad, ImageView{pixels.data(), scene.width, scene.height, 3 * scene.width});
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(std::string(s.message()).find("unknown bounce term 7") != std::string::npos);
  CHECK(parse_bounce_term("only") == BounceTerm::only);
  CHECK(!parse_bounce_term("none"));
  CHECK(std::string(bounce_term_name(BounceTerm::excluded)) == "excluded");
}

TEST_CASE("bounce culling: reflectors hidden from whole tiles by proofs are skipped, and the image stays exact" *
          per_isa()) {
  const Scene scene = rooms();
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  const FrameCounts stats = frame_counts(scene, options_for(Backend::automatic));
  CHECK(stats.bounce_pieces > 0);
  CHECK(stats.bounce_lit_sources == scene.occluders.size());
  CHECK(stats.bounce_tile_sources == stats.tiles * stats.bounce_lit_sources);
  MESSAGE("hidden " << stats.bounce_tile_sources_hidden << " of " << stats.bounce_tile_sources);
  if (resolved_isa(options_for(Backend::automatic)) == Isa::scalar) {
    // PAR2D_ISA=scalar: the reference path, which culls nothing.
    CHECK(stats.bounce_tile_sources_hidden == 0);
  } else {
    // The solid wall hides the third room's pillar and walls from the first room's tiles,
    // and the first room's from the third.
    CHECK(stats.bounce_tile_sources_hidden * 5 > stats.bounce_tile_sources);
  }
  CHECK(stats.bounce_source_walks <= (stats.bounce_tile_sources - stats.bounce_tile_sources_hidden) * 16 * 16);
  // Hidden reflectors add exactly nothing: the culled SIMD renders are within section 5 of the
  // unculled reference, and culling off walks every lit reflector at every pixel.
  const double pixel = 132.0 / scene.width;
  check_simd_against_scalar(
      scene, ref, "bounce rooms", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * pixel); }, 1000);
  RenderOptions unculled = options_for(Backend::automatic, std::nullopt, false);
  const FrameCounts all = frame_counts(scene, unculled);
  CHECK(all.bounce_tile_sources_hidden == 0);
  CHECK(all.bounce_source_walks == all.pixels * all.bounce_lit_sources);
}

}  // namespace par2d::test
