// The viewer's parts without a window: picking and editing lights, and the display path (Renderer sRGB frames) against the PNG writer.
#include <stb_image.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <doctest/doctest.h>

#include "par2d/par2d.hpp"
#include "support/test_tiers.hpp"
#include "viewer/scene_edit.hpp"

namespace {

using par2d::Circle;
using par2d::Light;
using par2d::Polygon;
using par2d::Scene;
using par2d::Segment;
using par2d::Vec2;

Scene three_lights() {
  Scene s;
  s.width = 100;
  s.height = 80;
  s.view = {0, 0, 100, 80};
  s.lights.push_back(Light{Circle{{20, 20}, 5}, {1, 0.5, 0.25}, 2});
  s.lights.push_back(Light{Polygon{{{50, 10}, {70, 10}, {70, 30}, {50, 30}}}, {1, 1, 1}, 1});
  s.lights.push_back(Light{Segment{{10, 60}, {90, 60}}, {1, 1, 1}, 1});
  return s;
}

}  // namespace

TEST_CASE("pick_light takes the light within the radius, the nearest, and the last of overlapping ones") {
  const Scene s = three_lights();
  using par2d::viewer::pick_light;
  CHECK(pick_light(s, {20, 20}, 1.0) == 0u);       // circle center
  CHECK(pick_light(s, {20, 27.9}, 3.0) == 0u);     // 2.9 outside the circle's edge
  CHECK(!pick_light(s, {20, 28.1}, 3.0));          // 3.1 outside
  CHECK(pick_light(s, {60, 20}, 0.0) == 1u);       // inside the square
  CHECK(pick_light(s, {72, 20}, 2.5) == 1u);       // 2 right of its edge
  CHECK(!pick_light(s, {73, 20}, 2.5));
  CHECK(pick_light(s, {50, 61}, 1.5) == 2u);       // 1 below the segment
  Scene overlap = s;
  overlap.lights.push_back(Light{Circle{{60, 20}, 3}, {1, 1, 1}, 1});
  CHECK(pick_light(overlap, {60, 20}, 0.0) == 3u);  // drawn last, picked first
  CHECK(pick_light(overlap, {52, 12}, 0.0) == 1u);  // only the square there
  // A concave light (an L): picked inside either arm, not in the notch between them.
  Scene ell = s;
  ell.lights.push_back(Light{Polygon{{{100, 0}, {130, 0}, {130, 10}, {110, 10}, {110, 30}, {100, 30}}}, {1, 1, 1}, 1});
  CHECK(pick_light(ell, {125, 5}, 0.0) == 3u);
  CHECK(pick_light(ell, {105, 25}, 0.0) == 3u);
  CHECK(!pick_light(ell, {112, 25}, 0.0));  // in the notch, 2 right of the upright arm
  CHECK(pick_light(ell, {112, 25}, 2.5) == 3u);
  // A ring light: not picked in its hole, away from the hole's edges.
  Scene ring = s;
  ring.lights.push_back(Light{Polygon{{{100, 0}, {130, 0}, {130, 30}, {100, 30}}, {{{105, 5}, {125, 5}, {125, 25}, {105, 25}}}},
                              {1, 1, 1}, 1});
  CHECK(pick_light(ring, {102, 15}, 0.0) == 3u);
  CHECK(!pick_light(ring, {115, 15}, 5.0));  // 10 from the hole's edges
  CHECK(pick_light(ring, {115, 15}, 10.5) == 3u);
}

TEST_CASE("move and scale keep shapes' form: circle radius, polygon about its vertex mean, segment about its middle") {
  Scene s = three_lights();
  using namespace par2d::viewer;
  REQUIRE(move_light(s, 0, {10, -5}));
  CHECK(std::get<Circle>(s.lights[0].shape).center.x == 30);
  CHECK(std::get<Circle>(s.lights[0].shape).center.y == 15);
  REQUIRE(scale_light(s, 0, 2.0));
  CHECK(std::get<Circle>(s.lights[0].shape).radius == 10);
  REQUIRE(scale_light(s, 1, 0.5));
  const auto& v = std::get<Polygon>(s.lights[1].shape).vertices;
  CHECK(v[0].x == 55);
  CHECK(v[0].y == 15);
  CHECK(v[2].x == 65);
  CHECK(v[2].y == 25);
  REQUIRE(scale_light(s, 2, 0.25));
  CHECK(std::get<Segment>(s.lights[2].shape).a.x == 40);
  CHECK(std::get<Segment>(s.lights[2].shape).b.x == 60);
  CHECK(s.lights[0].color[1] == 0.5);  // color and intensity untouched
  CHECK(s.lights[0].intensity == 2);
}

TEST_CASE("edits that would make the scene invalid are refused and change nothing") {
  Scene s = three_lights();
  const std::string before = par2d::scene_to_json(s);
  using namespace par2d::viewer;
  CHECK(!move_light(s, 0, {std::numeric_limits<double>::infinity(), 0}));
  CHECK(!scale_light(s, 1, 0.0));
  CHECK(!scale_light(s, 0, -1.0));
  CHECK(!scale_light(s, 2, 1e-320));  // the segment's ends would coincide
  CHECK(!move_light(s, 3, {1, 1}));   // no such light
  CHECK(!delete_light(s, 3));
  CHECK(par2d::scene_to_json(s) == before);
  REQUIRE(add_light(s, {5, 6}, 2.0, &s.lights[0]));
  CHECK(s.lights.size() == 4);
  CHECK(std::get<Circle>(s.lights[3].shape).radius == 2.0);
  CHECK(s.lights[3].intensity == 2);
  CHECK(!add_light(s, {5, 6}, 0.0, nullptr));
  REQUIRE(delete_light(s, 0));
  CHECK(s.lights.size() == 3);
  CHECK(std::holds_alternative<Polygon>(s.lights[0].shape));
}

TEST_CASE("window mapping follows the contract's pixel centers, mirrored views included") {
  par2d::viewer::WindowMapping m{{100, 50, 0, 250}, 50, 100};  // x mirrored, 2 units per pixel
  const Vec2 p = m.to_world(0.5, 0.5);
  CHECK(p.x == 99);
  CHECK(p.y == 51);
  const Vec2 d = m.delta_to_world(10, 10);
  CHECK(d.x == -20);
  CHECK(d.y == 20);
  CHECK(m.pixel_size() == 2);
  const Vec2 back = m.to_window({99, 51});
  CHECK(back.x == 0.5);
  CHECK(back.y == 0.5);
}

TEST_CASE("outlines: closed loops for circles and polygons, the two ends of a segment") {
  const auto circle = par2d::viewer::outline(Circle{{10, 20}, 5}, 8);
  REQUIRE(circle.size() == 9);
  for (const Vec2& p : circle) CHECK(std::hypot(p.x - 10, p.y - 20) == doctest::Approx(5).epsilon(1e-12));
  CHECK(circle.front().x == circle.back().x);
  const auto square = par2d::viewer::outline(Polygon{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  REQUIRE(square.size() == 5);
  CHECK(square.back().x == 0);
  CHECK(square.back().y == 0);
  CHECK(par2d::viewer::outline(Segment{{1, 2}, {3, 4}}).size() == 2);
}

TEST_CASE("the viewer's display path: edits mirrored by handle, sRGB bytes as the PNG writer's" * par2d::test::per_isa()) {
  // What the viewer does: one Renderer at the window's size, each scene_edit change passed on
  // through the light's handle, frames as rgba8_srgb into a padded texture. Its bytes must be
  // those par2d::write_png stores for a fresh render of the edited scene.
  Scene scene = three_lights();
  scene.occluders.push_back(par2d::Occluder{Circle{{35, 45}, 4}});
  REQUIRE(par2d::validate_scene(scene).ok());
  par2d::Renderer renderer;
  std::vector<par2d::LightHandle> handles;
  REQUIRE(renderer.set_scene(scene, &handles).ok());
  const par2d::RendererStats before = renderer.stats();

  REQUIRE(par2d::viewer::move_light(scene, 0, {7.5, -3.25}));
  REQUIRE(renderer.update_light(handles[0], scene.lights[0]).ok());
  REQUIRE(par2d::viewer::scale_light(scene, 1, 1.1));
  REQUIRE(renderer.update_light(handles[1], scene.lights[1]).ok());
  REQUIRE(par2d::viewer::add_light(scene, {20, 70}, 3.0, &scene.lights[1]));
  par2d::LightHandle added;
  REQUIRE(renderer.add_light(scene.lights.back(), &added).ok());
  handles.push_back(added);
  REQUIRE(par2d::viewer::delete_light(scene, 2));
  REQUIRE(renderer.remove_light(handles[2]).ok());
  handles.erase(handles.begin() + 2);

  for (double exposure : {1.0, 1.25, 0.3}) {
    const int pitch = 4 * scene.width + 12;  // textures may pad their rows
    std::vector<std::uint8_t> texture(static_cast<std::size_t>(pitch) * scene.height, 7);
    par2d::FrameBuffer buffer;
    buffer.data = texture.data();
    buffer.format = par2d::PixelFormat::rgba8_srgb;
    buffer.row_stride = pitch;
    buffer.exposure = exposure;
    REQUIRE(renderer.render(buffer).ok());

    std::vector<float> pixels(static_cast<std::size_t>(scene.width) * scene.height * 3);
    const par2d::ImageView image{pixels.data(), scene.width, scene.height, 3 * scene.width};
    REQUIRE(par2d::render(scene, par2d::RenderOptions{}, image).ok());
    const std::string path = "par2d_test_viewer_srgb." + std::to_string(::getpid()) + ".png";
    REQUIRE(par2d::write_png(path, image, exposure).ok());
    int w = 0, h = 0, n = 0;
    unsigned char* png = stbi_load(path.c_str(), &w, &h, &n, 3);
    std::remove(path.c_str());
    REQUIRE(png != nullptr);
    REQUIRE(w == scene.width);
    REQUIRE(h == scene.height);
    int mismatches = 0, distinct_reds = 0;
    std::vector<bool> seen(256, false);
    for (int y = 0; y < scene.height; ++y)
      for (int x = 0; x < scene.width; ++x) {
        const std::uint8_t* t = &texture[static_cast<std::size_t>(y) * pitch + 4 * x];
        const unsigned char* p = &png[3 * (static_cast<std::size_t>(y) * scene.width + x)];
        mismatches += t[0] != p[0] || t[1] != p[1] || t[2] != p[2] || t[3] != 255;
        if (!seen[t[0]]) distinct_reds += 1, seen[t[0]] = true;
      }
    int padding_written = 0;
    for (int y = 0; y < scene.height; ++y)
      for (int k = 4 * scene.width; k < pitch; ++k) padding_written += texture[static_cast<std::size_t>(y) * pitch + k] != 7;
    stbi_image_free(png);
    CHECK(mismatches == 0);
    CHECK(padding_written == 0);
    CHECK(distinct_reds > 10);  // a lit image, not a flat one
  }
  // Moving and resizing lights never rebuilt the occluder index.
  CHECK(renderer.stats().index_builds == before.index_builds);
}
