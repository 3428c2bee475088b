// Scene to JSON: writing then loading gives back the same scene, bit for bit; refused scenes write nothing.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <variant>

#include <doctest/doctest.h>

#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "support/random_scenes.hpp"

namespace {

using par2d::Scene;

// Bitwise equality of doubles (so -0.0 and 0.0 differ, and any lost digit shows).
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const par2d::Vec2& a, const par2d::Vec2& b) { return same(a.x, b.x) && same(a.y, b.y); }

bool same(const par2d::Shape& a, const par2d::Shape& b) {
  if (a.index() != b.index()) return false;
  if (const auto* p = std::get_if<par2d::Polygon>(&a)) {
    const auto& q = std::get<par2d::Polygon>(b);
    if (p->vertices.size() != q.vertices.size()) return false;
    for (std::size_t i = 0; i < p->vertices.size(); ++i)
      if (!same(p->vertices[i], q.vertices[i])) return false;
    return true;
  }
  if (const auto* c = std::get_if<par2d::Circle>(&a)) {
    const auto& d = std::get<par2d::Circle>(b);
    return same(c->center, d.center) && same(c->radius, d.radius);
  }
  const auto& s = std::get<par2d::Segment>(a);
  const auto& t = std::get<par2d::Segment>(b);
  return same(s.a, t.a) && same(s.b, t.b);
}

void check_same(const Scene& a, const Scene& b) {
  CHECK(a.width == b.width);
  CHECK(a.height == b.height);
  CHECK(same(a.view.x0, b.view.x0));
  CHECK(same(a.view.y0, b.view.y0));
  CHECK(same(a.view.x1, b.view.x1));
  CHECK(same(a.view.y1, b.view.y1));
  REQUIRE(a.lights.size() == b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    CHECK(same(a.lights[i].shape, b.lights[i].shape));
    for (std::size_t c = 0; c < 3; ++c) CHECK(same(a.lights[i].color[c], b.lights[i].color[c]));
    CHECK(same(a.lights[i].intensity, b.lights[i].intensity));
  }
  REQUIRE(a.occluders.size() == b.occluders.size());
  for (std::size_t i = 0; i < a.occluders.size(); ++i) CHECK(same(a.occluders[i].shape, b.occluders[i].shape));
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("scene_to_json then parse_scene gives back random scenes bit for bit") {
  for (std::uint32_t seed = 1; seed <= 200; ++seed) {
    par2d::test::RandomSceneOptions options;
    // Far-from-origin and mirrored views too: their coordinates need all 17 digits.
    if (seed % 3 == 1) options.view = par2d::View{1e5 + 0.1, 1e5, 1e5 + 24.3, 1e5 + 18.7};
    if (seed % 3 == 2) options.view = par2d::View{24, 0, 0, 18};
    const Scene scene = par2d::test::random_scene(seed, options);
    Scene back;
    const par2d::Status status = par2d::parse_scene(par2d::scene_to_json(scene), "w.json", back);
    INFO("seed " << seed << ": " << status.message());
    REQUIRE(status.ok());
    check_same(scene, back);
  }
}

TEST_CASE("scene_to_json of the contract's example reads back and is one shape per line") {
  Scene scene;
  REQUIRE(par2d::load_scene_file(PAR2D_SOURCE_DIR "/examples/colored_lights.json", scene).ok());
  const std::string json = par2d::scene_to_json(scene);
  Scene back;
  REQUIRE(par2d::parse_scene(json, "w.json", back).ok());
  check_same(scene, back);
  // Lines: {, size, view, "lights": [, one per light, ], "occluders": [, one per occluder, ], }.
  const auto lines = static_cast<std::size_t>(std::count(json.begin(), json.end(), '\n'));
  CHECK(lines == 8 + scene.lights.size() + scene.occluders.size());
}

TEST_CASE("scene_to_json of a scene without lights or occluders reads back") {
  Scene scene;
  scene.width = 3;
  scene.height = 2;
  scene.view = {0.5, -0.25, 3e-300, 2e300};
  Scene back;
  REQUIRE(par2d::parse_scene(par2d::scene_to_json(scene), "w.json", back).ok());
  check_same(scene, back);
}

TEST_CASE("save_scene_file writes a loadable file and refuses an invalid scene without touching the file") {
  const std::string path = "par2d_test_scene_write.tmp.json";
  std::remove(path.c_str());
  Scene scene = par2d::test::random_scene(7);
  REQUIRE(par2d::save_scene_file(path, scene).ok());
  Scene back;
  REQUIRE(par2d::load_scene_file(path, back).ok());
  check_same(scene, back);
  const std::string before = read_file(path);

  Scene bad = scene;
  bad.lights[0].intensity = std::numeric_limits<double>::quiet_NaN();
  const par2d::Status refused = par2d::save_scene_file(path, bad);
  CHECK(refused.code() == par2d::StatusCode::invalid_scene);
  CHECK(refused.message().rfind(path + ": lights[0]", 0) == 0);
  CHECK(read_file(path) == before);
  std::remove(path.c_str());
}

TEST_CASE("save_scene_file into a missing directory fails with the path and leaves nothing") {
  const std::string path = "par2d_no_such_dir.tmp/scene.json";
  const par2d::Status status = par2d::save_scene_file(path, par2d::test::random_scene(3));
  CHECK(status.code() == par2d::StatusCode::io_error);
  CHECK(status.message().rfind(path + ": cannot create", 0) == 0);
  CHECK(status.message().find('\n') == std::string::npos);
  std::ifstream in(path);
  CHECK(!in.good());
}
