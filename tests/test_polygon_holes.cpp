// Polygons with holes (docs/contract.md section 3), as occluders and as lights: rendered as an
// exact convex partition of the region, against the same region given as convex pieces by
// hand, the ray caster (which follows the rings as given), every SIMD level on pixel-aligned
// geometry (whose pixel centres fall on the partition's inner boundaries), a Renderer's
// updates and scene files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

std::vector<Vec2> square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// A square frame: [x0, x1]^2 less the square `t` inside each side.
Polygon frame(double x0, double x1, double t) {
  return Polygon{square(x0, x0, x1, x1), {square(x0 + t, x0 + t, x1 - t, x1 - t)}};
}

// The same frame as four convex boxes.
std::vector<Polygon> frame_pieces(double x0, double x1, double t) {
  return {Polygon{square(x0, x0, x1, x0 + t)}, Polygon{square(x0, x1 - t, x1, x1)},
          Polygon{square(x0, x0 + t, x0 + t, x1 - t)}, Polygon{square(x1 - t, x0 + t, x1, x1 - t)}};
}

// A light and a framed courtyard with a pillar in it: an occluder with a hole, and a light
// that is a ring (a square with a square hole), on whole-unit coordinates so that pixel
// centres fall on the partition's diagonals.
Scene courtyard(bool by_hand) {
  Scene s;
  s.width = 160;
  s.height = 120;
  s.view = {0, 0, 64, 48};
  Light ring;
  ring.shape = Polygon{square(2, 2, 22, 22), {square(8, 8, 16, 16)}};
  ring.intensity = 2;
  ring.color = {1.0, 0.8, 0.6};
  s.lights.push_back(ring);
  if (by_hand) {
    for (const Polygon& p : frame_pieces(30, 60, 6)) s.occluders.push_back(Occluder{p});
  } else {
    s.occluders.push_back(Occluder{frame(30, 60, 6)});
  }
  s.occluders.push_back(Occluder{Circle{{45, 45}, 2}});
  Light inner{Circle{{40, 40}, 1.5}, {0.4, 0.6, 1.0}, 3.0};  // inside the courtyard
  s.lights.push_back(inner);
  return s;
}

double worst_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(double(a[i]) - b[i]));
  return worst;
}

}  // namespace

TEST_CASE("an occluder with a hole shadows as its convex pieces; a ring light, exact on every ISA") {
  const Scene scene = courtyard(false);
  REQUIRE(validate_scene(scene).ok());
  const RenderedImage reference = render_or_fail(scene, options_for(Backend::scalar));
  // The frame given as four boxes shadows the same (the ring light is the same in both).
  const RenderedImage by_hand = render_or_fail(courtyard(true), options_for(Backend::scalar));
  CHECK(worst_difference(reference.pixels, by_hand.pixels) <= 1e-6 * max_emission_sum(scene));
  // The inner lamp lights only the courtyard; outside the frame it adds nothing.
  const RenderedImage inner_only = [&] {
    Scene s = scene;
    s.lights.erase(s.lights.begin());
    return render_or_fail(s, options_for(Backend::scalar));
  }();
  CHECK(inner_only.at(155, 60, 2) == 0.0f);  // x 62: right of the frame
  CHECK(inner_only.at(100, 100, 2) > 0.0f);  // (40, 40): beside the lamp
  // Every pixel is compared (no exemption near the partition's inner boundaries, which are
  // no shape's boundary): within section 5 everywhere but near the rings.
  const double pixel = 64.0 / scene.width;
  check_simd_against_scalar(
      scene, reference, "courtyard with holes", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * pixel); },
      scene.width * scene.height / 2);
}

TEST_CASE("polygons with holes match the ray caster, which follows every ring as given") {
  Scene scene = courtyard(false);
  scene.width = 64;
  scene.height = 48;
  const RenderedImage image = render_or_fail(scene, options_for(Backend::scalar));
  const RaycastAgreement agreement = agreement_with_raycaster(scene, image, 4096, 1e-6 * 64.0 / scene.width, true);
  INFO("worst: " << agreement.where);
  CHECK(agreement.worst <= 1.0);
  CHECK(agreement.compared > scene.width * scene.height / 2);
  MESSAGE("worst |E_par - E_ray| / bound: " << agreement.worst);
}

TEST_CASE("a Renderer keeps a polygon with holes under one handle" * per_isa()) {
  Renderer renderer;
  REQUIRE(renderer.set_frame(64, 48, View{0, 0, 64, 48}).ok());
  OccluderHandle walls;
  LightHandle lamp;
  REQUIRE(renderer.add_occluder(Occluder{frame(30, 60, 6)}, &walls).ok());
  REQUIRE(renderer.add_light(Light{Circle{{40, 40}, 1.5}, {1, 1, 1}, 3.0}, &lamp).ok());
  const auto check_frame = [&](const std::string& what) {
    CAPTURE(what);
    CHECK(renderer_equals_snapshot(renderer));
  };
  check_frame("added");
  Occluder back;
  REQUIRE(renderer.occluder(walls, &back).ok());
  const auto& polygon = std::get<Polygon>(back.shape);
  CHECK(polygon.vertices.size() == 4);
  REQUIRE(polygon.holes.size() == 1);
  CHECK(polygon.holes[0].size() == 4);
  REQUIRE(renderer.update_occluder(walls, Occluder{frame(28, 62, 4)}).ok());
  check_frame("moved");
  // A light in the courtyard's walls' hole sees out only through a second hole.
  Polygon two_holes = frame(28, 62, 4);
  two_holes.holes.push_back(square(20, 20, 24, 24));  // outside the outline: refused
  const Status s = renderer.update_occluder(walls, Occluder{two_holes});
  CHECK(s.message().find(": holes[1]: not inside the outer boundary") != std::string::npos);
  CHECK(renderer.occluder_count() == 1);
  check_frame("after a refusal");
  REQUIRE(renderer.update_light(lamp, Light{Polygon{square(36, 36, 44, 44), {square(39, 39, 41, 41)}}, {1, 1, 1}, 1})
              .ok());
  check_frame("a ring light");
  REQUIRE(renderer.remove_occluder(walls).ok());
  check_frame("removed");
}

TEST_CASE("holes in scene files: read, written back exactly, and refused with their place") {
  const std::string json = R"({"width": 16, "height": 12,
    "lights": [{"polygon": [[0, 0], [6, 0], [6, 6], [0, 6]], "holes": [[[2, 2], [4, 2], [4, 4], [2, 4]]]}],
    "occluders": [{"polygon": [[8, 0], [16, 0], [16, 8], [8, 8]], "holes": [[[9, 1], [11, 1], [11, 3]], [[12, 4], [15, 4], [15, 7], [12, 7]]]}]})";
  Scene scene;
  const Status status = parse_scene(json, "s.json", scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  REQUIRE(std::get<Polygon>(scene.occluders[0].shape).holes.size() == 2);
  Scene back;
  REQUIRE(parse_scene(scene_to_json(scene), "back.json", back).ok());
  CHECK(scene_to_json(back) == scene_to_json(scene));
  CHECK(std::get<Polygon>(back.lights[0].shape).holes[0].size() == 4);

  const auto message = [](const std::string& text) {
    Scene s;
    return parse_scene(text, "s.json", s).message();
  };
  const std::string head = R"({"width": 16, "height": 12, )";
  CHECK(message(head + R"("occluders": [{"circle": {"center": [4, 4], "radius": 2}, "holes": []}]})") ==
        "s.json: occluders[0].holes: only a polygon has holes");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": [[[1, 1], [2, 1]]]}]})") ==
        "s.json: occluders[0].holes[0]: needs at least 3 vertices, got 2");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": [[[6, 6], [9, 6], [9, 9]]]}]})") ==
        "s.json: occluders[0].holes[0]: touches the outer boundary (its edge 2 and outer edge 2)");
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": [[[1, 1], [5, 1], [5, 5], [1, 5]], [[3, 3], [6, 3], [6, 6], [3, 6]]]}]})") ==
        "s.json: occluders[0].holes: holes[0] and holes[1] overlap (edges 2 and 3 cross)");
  CHECK(message(head + R"("lights": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": {"x": 1}}]})") ==
        "s.json: lights[0].holes: expected an array of holes, each an array of [x, y] vertices");
  CHECK(message(head + R"("lights": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": [[[1, 1], [2, 1], [2, "a"]]]}]})")
            .rfind("s.json: lights[0].holes[0][2]", 0) == 0);
  // A translucent occluder with a hole is not the union of its pieces.
  CHECK(message(head + R"("occluders": [{"polygon": [[0, 0], [8, 0], [8, 8], [0, 8]], "holes": [[[2, 2], [4, 2], [4, 4]]], "transmittance": [0.5, 0.5, 0.5]}]})") ==
        "s.json: occluders[0].transmittance: a concave occluder must be opaque, dark inside and not reflecting "
        "(split it into convex occluders)");
}

}  // namespace par2d::test
