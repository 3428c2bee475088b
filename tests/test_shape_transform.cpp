// Sprite transforms (par2d/scene.hpp Transform): shapes placed exactly, refusals that name the
// field, and a Renderer moved by transforms equal to one moved by placed shapes.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

bool same_points(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].x != b[k].x || a[k].y != b[k].y) return false;
  return true;
}

}  // namespace

TEST_CASE("transform_shape: quarter turns are exact, then scale, rotation and position in that order") {
  const Shape tile = box(0, 0, 2, 1);
  Shape out;
  // A quarter turn clockwise on screen (toward +y), then moved: every corner stays on the grid.
  REQUIRE(transform_shape(tile, Transform{{10, 20}, 90, {1, 1}}, out).ok());
  CHECK(same_points(std::get<Polygon>(out).vertices, {{10, 20}, {10, 22}, {9, 22}, {9, 20}}));
  for (const double turns : {-450.0, 270.0, 630.0, 1e6 * 360.0 + 180.0}) {
    CAPTURE(turns);
    REQUIRE(transform_shape(tile, Transform{{0, 0}, turns, {1, 1}}, out).ok());
    for (const Vec2 v : std::get<Polygon>(out).vertices) {
      CHECK(v.x == std::round(v.x));
      CHECK(v.y == std::round(v.y));
    }
  }
  // Scale before rotation: a 2 x 1 box scaled by (3, 0.5) then turned 90 degrees is 1 wide, 6 tall.
  REQUIRE(transform_shape(tile, Transform{{0, 0}, 90, {3, 0.5}}, out).ok());
  CHECK(same_points(std::get<Polygon>(out).vertices, {{0, 0}, {0, 6}, {-0.5, 6}, {-0.5, 0}}));
  // A general angle: rotation by 30 degrees of (1, 0) is (cos 30, sin 30).
  REQUIRE(transform_shape(Segment{{0, 0}, {1, 0}}, Transform{{5, 5}, 30, {1, 1}}, out).ok());
  const Segment& s = std::get<Segment>(out);
  CHECK(s.a.x == 5.0);
  CHECK(s.a.y == 5.0);
  CHECK(std::fabs(s.b.x - (5.0 + std::sqrt(3.0) / 2.0)) <= 1e-15);
  CHECK(std::fabs(s.b.y - 5.5) <= 1e-15);
  // A mirror keeps a circle a circle, radius by the absolute scale.
  REQUIRE(transform_shape(Circle{{1, 2}, 3}, Transform{{0, 0}, 0, {-2, 2}}, out).ok());
  CHECK(std::get<Circle>(out).center.x == -2.0);
  CHECK(std::get<Circle>(out).center.y == 4.0);
  CHECK(std::get<Circle>(out).radius == 6.0);
  // In place (out is local): the polygon's own storage.
  Shape moving = box(0, 0, 1, 1);
  const Vec2* storage = std::get<Polygon>(moving).vertices.data();
  REQUIRE(transform_shape(moving, Transform{{4, 0}, 0, {1, 1}}, moving).ok());
  CHECK(std::get<Polygon>(moving).vertices.data() == storage);
  CHECK(same_points(std::get<Polygon>(moving).vertices, {{4, 0}, {5, 0}, {5, 1}, {4, 1}}));
}

TEST_CASE("transform_shape: refused values name the field and leave the output as it was") {
  Shape out = Segment{{7, 7}, {8, 8}};
  auto refused = [&](const Shape& local, const Transform& t, const std::string& message) {
    const Status status = transform_shape(local, t, out);
    CHECK(status.code() == StatusCode::invalid_scene);
    CHECK(status.message() == message);
    REQUIRE(std::holds_alternative<Segment>(out));
    CHECK(std::get<Segment>(out).a.x == 7.0);
  };
  refused(box(0, 0, 1, 1), Transform{{0, 0}, 0, {0, 1}}, "transform.scale[0]: must be non-zero, got 0");
  refused(box(0, 0, 1, 1), Transform{{0, 0}, 0, {1, -0.0}}, "transform.scale[1]: must be non-zero, got 0");
  refused(box(0, 0, 1, 1), Transform{{0, std::nan("")}, 0, {1, 1}}, "transform.position[1]: not a finite number (nan)");
  refused(box(0, 0, 1, 1), Transform{{0, 0}, HUGE_VAL, {1, 1}}, "transform.rotation: not a finite number (inf)");
  refused(Circle{{0, 0}, 1}, Transform{{0, 0}, 0, {2, 3}},
          "transform.scale: a circle takes the same scale on both axes, got [2, 3]");
}

TEST_CASE("a Renderer moved by transforms renders what it renders moved by placed shapes, bit for bit" *
          par2d::test::per_isa()) {
  Scene scene;
  scene.width = 48;
  scene.height = 32;
  scene.view = {0, 0, 48, 32};
  scene.lights.push_back(Light{Circle{{6, 6}, 2}, {1.0, 0.8, 0.6}, 2.0});
  const Occluder crate{box(-2, -1, 2, 1)};  // local frame: centered on the sprite's origin
  const Light lantern{Segment{{-1, 0}, {1, 0}}, {0.4, 0.6, 1.0}, 1.5};
  Renderer by_transform, by_shape;
  std::vector<LightHandle> lights;
  REQUIRE(by_transform.set_scene(scene, &lights).ok());
  REQUIRE(by_shape.set_scene(scene).ok());
  OccluderHandle crate_t, crate_s;
  LightHandle lantern_t, lantern_s;
  REQUIRE(by_transform.add_occluder(crate, Transform{{20, 14}, 0, {1, 1}}, &crate_t).ok());
  REQUIRE(by_transform.add_light(lantern, Transform{{30, 25}, 0, {1, 1}}, &lantern_t).ok());
  Occluder placed_crate = crate;
  Light placed_lantern = lantern;
  REQUIRE(transform_shape(crate.shape, Transform{{20, 14}, 0, {1, 1}}, placed_crate.shape).ok());
  REQUIRE(transform_shape(lantern.shape, Transform{{30, 25}, 0, {1, 1}}, placed_lantern.shape).ok());
  REQUIRE(by_shape.add_occluder(placed_crate, &crate_s).ok());
  REQUIRE(by_shape.add_light(placed_lantern, &lantern_s).ok());
  std::vector<float> a(48 * 32 * 3), b(48 * 32 * 3);
  const FrameBuffer fa{reinterpret_cast<unsigned char*>(a.data()), PixelFormat::rgb_f32, 48 * 12, 1.0};
  const FrameBuffer fb{reinterpret_cast<unsigned char*>(b.data()), PixelFormat::rgb_f32, 48 * 12, 1.0};
  for (int frame = 0; frame < 6; ++frame) {
    CAPTURE(frame);
    const Transform crate_at{{20.0 + 2.5 * frame, 14.0 + frame}, 17.0 * frame, {1.0 + 0.1 * frame, frame % 2 ? -1.0 : 1.0}};
    const Transform lantern_at{{30.0 - frame, 25.0}, -40.0 * frame, {0.5 + 0.5 * frame, 1.0}};
    REQUIRE(by_transform.update_occluder(crate_t, crate, crate_at).ok());
    REQUIRE(by_transform.update_light(lantern_t, lantern, lantern_at).ok());
    REQUIRE(transform_shape(crate.shape, crate_at, placed_crate.shape).ok());
    REQUIRE(transform_shape(lantern.shape, lantern_at, placed_lantern.shape).ok());
    REQUIRE(by_shape.update_occluder(crate_s, placed_crate).ok());
    REQUIRE(by_shape.update_light(lantern_s, placed_lantern).ok());
    REQUIRE(by_transform.render(fa).ok());
    REQUIRE(by_shape.render(fb).ok());
    CHECK(a == b);
    // What the world holds is the placed shape.
    Occluder held;
    REQUIRE(by_transform.occluder(crate_t, &held).ok());
    CHECK(same_points(std::get<Polygon>(held.shape).vertices, std::get<Polygon>(placed_crate.shape).vertices));
  }
  // A refused transform names the handle and the field, and keeps the world as it was.
  const Status status = by_transform.update_occluder(crate_t, crate, Transform{{0, 0}, 0, {1, 0}});
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == "occluder " + std::to_string(crate_t.id) + ": transform.scale[1]: must be non-zero, got 0");
  const Status circle = by_transform.add_light(Light{Circle{{0, 0}, 1}}, Transform{{0, 0}, 0, {1, 2}}, &lantern_s);
  CHECK(circle.message() == "add_light: transform.scale: a circle takes the same scale on both axes, got [1, 2]");
  REQUIRE(by_transform.render(fa).ok());
  CHECK(a == b);
}

}  // namespace par2d::test
