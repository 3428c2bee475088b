// Concave occluders (docs/contract.md section 3): refused where they cannot be exact, rendered
// as an exact convex partition (against the same region given as convex pieces by hand, and
// against the ray caster, which meets the outline as it is), kept under one handle through a
// Renderer's updates, and written and read back.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "raycast/raycast_renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

Polygon rect(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// A tile-map room's walls, `t` thick, around [x0, x1] x [y0, y1], with a door gap [d0, d1] in
// the bottom wall: one concave outline (a C shape, counter-clockwise on screen).
Polygon room_walls(double x0, double y0, double x1, double y1, double t, double d0, double d1) {
  return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {d1, y1}, {d1, y1 - t}, {x1 - t, y1 - t}, {x1 - t, y0 + t},
                  {x0 + t, y0 + t}, {x0 + t, y1 - t}, {d0, y1 - t}, {d0, y1}, {x0, y1}}};
}
// The same walls as five rectangles (a convex decomposition by hand).
std::vector<Polygon> room_wall_pieces(double x0, double y0, double x1, double y1, double t, double d0, double d1) {
  return {rect(x0, y0, x1, y0 + t), rect(x1 - t, y0 + t, x1, y1), rect(d1, y1 - t, x1 - t, y1),
          rect(x0, y0 + t, x0 + t, y1), rect(x0 + t, y1 - t, d0, y1)};
}

// An H-shaped pillar, `t` thick, in [x0, x1] x [y0, y1] (a concave outline of 12 vertices), and
// its three rectangles.
Polygon h_pillar(double x0, double y0, double x1, double y1, double t) {
  const double ym0 = 0.5 * (y0 + y1) - 0.5 * t, ym1 = 0.5 * (y0 + y1) + 0.5 * t;
  return Polygon{{{x0, y0}, {x0 + t, y0}, {x0 + t, ym0}, {x1 - t, ym0}, {x1 - t, y0}, {x1, y0}, {x1, y1},
                  {x1 - t, y1}, {x1 - t, ym1}, {x0 + t, ym1}, {x0 + t, y1}, {x0, y1}}};
}
std::vector<Polygon> h_pillar_pieces(double x0, double y0, double x1, double y1, double t) {
  const double ym0 = 0.5 * (y0 + y1) - 0.5 * t, ym1 = 0.5 * (y0 + y1) + 0.5 * t;
  return {rect(x0, y0, x0 + t, y1), rect(x1 - t, y0, x1, y1), rect(x0 + t, ym0, x1 - t, ym1)};
}

// The level both ways: concave occluders, or their pieces by hand. Lights inside the room, one
// outside shining through the door, one beside the room with a cone.
Scene room_level(bool by_hand) {
  Scene scene;
  scene.width = 64;
  scene.height = 48;
  scene.view = {0, 0, 128, 96};
  scene.lights.push_back(Light{Circle{{40, 30}, 3}, {1.0, 0.8, 0.6}, 4.0});
  scene.lights.push_back(Light{Circle{{60, 90}, 2}, {0.4, 0.6, 1.0}, 6.0});
  Light lamp{rect(100, 60, 120, 64), {0.9, 0.3, 0.3}, 2.0};
  lamp.cone = Cone{200, 70, 20};
  scene.lights.push_back(lamp);
  if (by_hand) {
    for (const Polygon& p : room_wall_pieces(10, 10, 80, 75, 4, 50, 66)) scene.occluders.push_back({p});
    for (const Polygon& p : h_pillar_pieces(30, 42, 46, 58, 3)) scene.occluders.push_back({p});
  } else {
    scene.occluders.push_back({room_walls(10, 10, 80, 75, 4, 50, 66)});
    scene.occluders.push_back({h_pillar(30, 42, 46, 58, 3)});
  }
  return scene;
}

RenderedImage render_with(const Scene& scene, Backend backend) { return render_or_fail(scene, options_for(backend)); }

double worst_difference(const RenderedImage& a, const RenderedImage& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::fabs(double(a.pixels[i]) - b.pixels[i]));
  return worst;
}

}  // namespace

TEST_CASE("a concave tile-map room and an H pillar render as their convex decomposition (scalar, every SIMD ISA)") {
  const Scene concave = room_level(false), by_hand = room_level(true);
  REQUIRE(validate_scene(concave).ok());
  const double e_max = max_emission_sum(concave);
  const RenderedImage reference = render_with(by_hand, Backend::scalar);
  const RenderedImage scalar = render_with(concave, Backend::scalar);
  // Two partitions of one region: the same integral, summed in another order.
  CHECK(worst_difference(scalar, reference) <= 1e-6 * e_max);
  check_simd_against_scalar(concave, reference, "concave room against its decomposition", [](Vec2) { return false; },
                            64 * 48);
  // Something is lit and something is dark (the walls are really there).
  const auto brightest = *std::max_element(scalar.pixels.begin(), scalar.pixels.end());
  CHECK(brightest > 0.05f);
  CHECK(scalar.at(2, 10, 0) < 0.2f * brightest);
}

TEST_CASE("a level of six tile-map rooms, each one concave occluder, renders as its decomposition") {
  // Rooms on a 3 x 2 grid of 40 x 36 cells, sizes, wall thickness and doors varying; a light in
  // each room and two in the corridors between them.
  Scene concave, by_hand;
  for (Scene* s : {&concave, &by_hand}) {
    s->width = 96;
    s->height = 64;
    s->view = {0, 0, 120, 80};
  }
  for (int k = 0; k < 6; ++k) {
    const double x0 = 2 + 40 * (k % 3) + (k % 2), y0 = 3 + 40 * (k / 3);
    const double x1 = x0 + 30 + 2 * (k % 3), y1 = y0 + 28 + (k % 2);
    const double t = 2 + 0.5 * (k % 3), d0 = x0 + 6 + 3 * k % 7, d1 = d0 + 6;
    concave.occluders.push_back({room_walls(x0, y0, x1, y1, t, d0, d1)});
    for (const Polygon& p : room_wall_pieces(x0, y0, x1, y1, t, d0, d1)) by_hand.occluders.push_back({p});
    const Light light{Circle{{0.5 * (x0 + x1), 0.5 * (y0 + y1) - 3}, 1.5}, {1.0, 0.7 + 0.05 * k, 0.5}, 2.0};
    concave.lights.push_back(light);
    by_hand.lights.push_back(light);
  }
  for (const Light& corridor : {Light{Circle{{38, 37}, 1}, {0.5, 0.6, 1.0}, 3.0}, Light{Circle{{81, 39}, 1}, {0.5, 1.0, 0.6}, 3.0}}) {
    concave.lights.push_back(corridor);
    by_hand.lights.push_back(corridor);
  }
  REQUIRE(validate_scene(concave).ok());
  const RenderedImage reference = render_with(by_hand, Backend::scalar);
  CHECK(worst_difference(render_with(concave, Backend::scalar), reference) <= 1e-6 * max_emission_sum(concave));
  check_simd_against_scalar(concave, reference, "tile-map rooms against their decomposition", [](Vec2) { return false; },
                            96 * 64);
}

TEST_CASE("concave occluders: the scalar reference matches the ray caster, which meets the outline as given") {
  const Scene scene = room_level(false);
  const RenderedImage image = render_with(scene, Backend::scalar);
  const double skip = 1e-6 * (scene.view.x1 - scene.view.x0) / scene.width;
  const RaycastAgreement agreement = agreement_with_raycaster(scene, image, 2048, skip);
  INFO("worst: " << agreement.where);
  CHECK(agreement.worst <= 1.0);
  CHECK(agreement.compared > 64 * 48 / 2);
  MESSAGE("worst |E_par - E_ray| / bound: " << agreement.worst);
}

TEST_CASE("a Renderer keeps a concave occluder under one handle through every change" * per_isa()) {
  Renderer renderer;
  REQUIRE(renderer.set_frame(64, 48, View{0, 0, 128, 96}).ok());
  OccluderHandle walls, post;
  REQUIRE(renderer.add_occluder(Occluder{room_walls(10, 10, 80, 75, 4, 50, 66)}, &walls).ok());
  REQUIRE(renderer.add_occluder(Occluder{Circle{{100, 40}, 5}}, &post).ok());
  LightHandle torch, outside;
  REQUIRE(renderer.add_light(Light{Circle{{40, 30}, 3}, {1.0, 0.8, 0.6}, 4.0}, &torch).ok());
  REQUIRE(renderer.add_light(Light{Circle{{60, 90}, 2}, {0.4, 0.6, 1.0}, 6.0}, &outside).ok());
  CHECK(renderer.light_count() == 2);
  CHECK(renderer.occluder_count() == 2);

  const auto check_frame = [&](const char* what) {
    CAPTURE(what);
    CHECK(renderer_equals_snapshot(renderer));
  };
  check_frame("added");
  Occluder back;
  REQUIRE(renderer.occluder(walls, &back).ok());
  CHECK(std::get<Polygon>(back.shape).vertices.size() == 12);  // as given, not a piece

  // Moved, made convex, concave again (another outline); the circle after it untouched.
  REQUIRE(renderer.update_occluder(walls, Occluder{room_walls(14, 12, 84, 77, 5, 40, 60)}).ok());
  check_frame("walls moved");
  REQUIRE(renderer.update_occluder(walls, Occluder{rect(20, 20, 30, 60)}).ok());
  check_frame("walls convex");
  REQUIRE(renderer.update_occluder(walls, Occluder{h_pillar(20, 20, 60, 60, 6)}).ok());
  CHECK(renderer.occluder_count() == 2);
  check_frame("walls an H");
  REQUIRE(renderer.update_occluder(post, Occluder{Circle{{100, 50}, 6}}).ok());
  check_frame("post moved");
  REQUIRE(renderer.occluder(post, &back).ok());
  CHECK(std::holds_alternative<Circle>(back.shape));

  // Refused updates change nothing, and name the problem.
  Occluder glass{h_pillar(20, 20, 60, 60, 6)};
  glass.transmittance = {0.5, 0.5, 0.5};
  CHECK(renderer.update_occluder(walls, glass).message().find("transmittance: a concave occluder must be opaque") !=
        std::string::npos);
  Occluder sprite{h_pillar(20, 20, 60, 60, 6)};
  sprite.interior = Interior::lit;
  CHECK(renderer.update_occluder(walls, sprite).message().find("interior: a concave occluder") != std::string::npos);
  const Polygon bow{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}};
  CHECK(renderer.update_occluder(walls, Occluder{bow}).message().find("polygon: edges 0 and 2 cross") != std::string::npos);
  check_frame("after refusals");

  // Removed: every piece goes, and the handle with them.
  REQUIRE(renderer.remove_occluder(walls).ok());
  CHECK(renderer.occluder_count() == 1);
  CHECK_FALSE(renderer.occluder(walls, &back).ok());
  CHECK_FALSE(renderer.update_occluder(walls, Occluder{rect(0, 0, 1, 1)}).ok());
  check_frame("removed");

  // set_scene: handles in the scene's order whatever is split.
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(renderer.set_scene(room_level(false), &lights, &occluders).ok());
  REQUIRE(lights.size() == 3);
  REQUIRE(occluders.size() == 2);
  REQUIRE(renderer.occluder(occluders[1], &back).ok());
  CHECK(std::get<Polygon>(back.shape).vertices.size() == 12);
  CHECK(renderer.occluder_count() == 2);
  check_frame("set_scene");
}

TEST_CASE("concave occluders in scene files: read, written back exactly, refused with their place") {
  const std::string json = R"({"width": 8, "height": 6,
    "lights": [{"circle": {"center": [2, 2], "radius": 0.5}}],
    "occluders": [{"polygon": [[5, 0], [8, 0], [8, 6], [5, 6], [5, 5], [7, 5], [7, 1], [5, 1]]}]})";
  Scene scene;
  const Status status = parse_scene(json, "s.json", scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  Scene back;
  REQUIRE(parse_scene(scene_to_json(scene), "back.json", back).ok());
  const auto& written = std::get<Polygon>(scene.occluders[0].shape).vertices;
  const auto& read = std::get<Polygon>(back.occluders[0].shape).vertices;
  REQUIRE(read.size() == written.size());
  for (std::size_t k = 0; k < read.size(); ++k) CHECK((read[k].x == written[k].x && read[k].y == written[k].y));

  const auto message = [](const std::string& text) {
    Scene s;
    return parse_scene(text, "s.json", s).message();
  };
  const std::string head = R"({"width": 4, "height": 3, )";
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [2, 2], [2, 0], [0, 2]]}]})") ==
        "s.json: occluders[0].polygon: edges 0 and 2 cross");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [4, 0], [4, 4], [2, 0], [0, 4]]}]})") ==
        "s.json: occluders[0].polygon: edges 0 and 3 touch");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]], "interior": "lit"}]})") ==
        "s.json: occluders[0].interior: a concave occluder must be opaque, dark inside and not reflecting "
        "(split it into convex occluders)");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]], "albedo": [1, 1, 1]}]})") ==
        "s.json: occluders[0].albedo: a concave occluder must be opaque, dark inside and not reflecting "
        "(split it into convex occluders)");
}

}  // namespace par2d::test
