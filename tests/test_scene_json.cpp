// Scene JSON loading and validation: every bad-input class of docs/contract.md section 3 is refused with its place.
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "par2d/scene.hpp"

namespace {

using par2d::Scene;
using par2d::Status;
using par2d::StatusCode;

constexpr const char* kSpecExample = R"({
  "width": 512, "height": 384,
  "view": [0, 0, 512, 384],
  "lights": [
    { "circle":  { "center": [100, 80], "radius": 12 }, "color": [1.0, 0.85, 0.6], "intensity": 4 },
    { "polygon": [[300, 40], [340, 40], [340, 60], [300, 60]], "color": [0.3, 0.5, 1.0] },
    { "segment": [[20, 370], [200, 370]], "intensity": 2 }
  ],
  "occluders": [
    { "polygon": [[200, 150], [260, 150], [230, 210]] },
    { "circle":  { "center": [400, 250], "radius": 30 } },
    { "segment": [[50, 200], [150, 260]] }
  ]
})";

Status parse(const std::string& json, Scene& scene) { return par2d::parse_scene(json, "s.json", scene); }

Status parse(const std::string& json) {
  Scene scene;
  return parse(json, scene);
}

// A scene of the given size holding one light with the given body (JSON object members).
std::string with_light(const std::string& body) {
  return R"({"width": 8, "height": 8, "lights": [{)" + body + "}]}";
}

std::string with_occluder(const std::string& body) {
  return R"({"width": 8, "height": 8, "occluders": [{)" + body + "}]}";
}

std::string with_polygon(const std::string& vertices) { return with_light(R"("polygon": )" + vertices); }

// The refusal is an invalid_scene whose message starts with the file name and the place.
void check_refused(const std::string& json, const std::string& place_and_what) {
  const Status status = parse(json);
  CAPTURE(json);
  CAPTURE(status.message());
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message().rfind("s.json: " + place_and_what, 0) == 0);
  CHECK(status.message().find('\n') == std::string::npos);
}

}  // namespace

TEST_CASE("the contract's example scene parses with every value in place") {
  Scene scene;
  const Status status = parse(kSpecExample, scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  CHECK(scene.width == 512);
  CHECK(scene.height == 384);
  CHECK(scene.view.x1 == 512.0);
  REQUIRE(scene.lights.size() == 3);
  REQUIRE(scene.occluders.size() == 3);
  const auto* circle = std::get_if<par2d::Circle>(&scene.lights[0].shape);
  REQUIRE(circle != nullptr);
  CHECK(circle->center.x == 100.0);
  CHECK(circle->radius == 12.0);
  CHECK(scene.lights[0].intensity == 4.0);
  CHECK(scene.lights[0].color[1] == 0.85);
  CHECK(std::get<par2d::Polygon>(scene.lights[1].shape).vertices.size() == 4);
  CHECK(scene.lights[1].intensity == 1.0);
  CHECK(std::get<par2d::Segment>(scene.lights[2].shape).b.x == 200.0);
  CHECK(std::get<par2d::Segment>(scene.occluders[2].shape).b.y == 260.0);
  CHECK(par2d::validate_scene(scene, "x").ok());
  CHECK(par2d::max_emission_sum(scene) == doctest::Approx(4.0 + 1.0 + 2.0));
}

TEST_CASE("defaults: view is [0, 0, width, height], color white, intensity 1, no lights or occluders") {
  Scene scene;
  REQUIRE(parse(R"({"width": 64, "height": 32.0, "lights": [{"segment": [[0, 0], [1, 1]]}]})", scene).ok());
  CHECK(scene.width == 64);
  CHECK(scene.height == 32);
  CHECK(scene.view.x0 == 0.0);
  CHECK(scene.view.y0 == 0.0);
  CHECK(scene.view.x1 == 64.0);
  CHECK(scene.view.y1 == 32.0);
  REQUIRE(scene.lights.size() == 1);
  CHECK(scene.lights[0].color == par2d::Rgb{1.0, 1.0, 1.0});
  CHECK(scene.lights[0].intensity == 1.0);
  CHECK(scene.occluders.empty());

  Scene empty;
  REQUIRE(parse(R"({"width": 1, "height": 16384})", empty).ok());
  CHECK(empty.lights.empty());
  CHECK(par2d::max_emission_sum(empty) == 0.0);
}

TEST_CASE("a mirrored view is accepted") {
  Scene scene;
  REQUIRE(parse(R"({"width": 4, "height": 4, "view": [0, 4, 4, 0]})", scene).ok());
  CHECK(scene.view.y0 == 4.0);
}

TEST_CASE("width and height: required integers from 1 to 16384") {
  check_refused(R"({"height": 8})", "width: missing");
  check_refused(R"({"width": 8})", "height: missing");
  check_refused(R"({"width": 64.5, "height": 8})", "width: expected an integer");
  check_refused(R"({"width": "64", "height": 8})", "width: expected an integer");
  check_refused(R"({"width": true, "height": 8})", "width: expected an integer");
  check_refused(R"({"width": 0, "height": 8})", "width: must be an integer from 1 to 16384");
  check_refused(R"({"width": 16385, "height": 8})", "width: must be an integer from 1 to 16384");
  check_refused(R"({"width": 8, "height": -3})", "height: must be an integer from 1 to 16384");
  // Far beyond int (and int64) must be refused, not wrapped.
  check_refused(R"({"width": 4294967360, "height": 8})", "width: must be an integer");
  check_refused(R"({"width": 18446744073709551616, "height": 8})", "width: must be an integer");
  check_refused(R"({"width": 1e30, "height": 8})", "width: must be an integer");
}

TEST_CASE("view: four finite numbers with x0 != x1 and y0 != y1") {
  check_refused(R"({"width": 8, "height": 8, "view": [1, 0, 1, 8]})", "view: x0 and x1 are equal");
  check_refused(R"({"width": 8, "height": 8, "view": [0, 2, 8, 2]})", "view: y0 and y1 are equal");
  check_refused(R"({"width": 8, "height": 8, "view": [0, 0, 8]})", "view: expected [x0, y0, x1, y1]");
  check_refused(R"({"width": 8, "height": 8, "view": [0, 0, 8, "8"]})", "view: expected [x0, y0, x1, y1]");
  check_refused(R"({"width": 8, "height": 8, "view": [-1e308, 0, 1e308, 8]})", "view: extent is too large");
}

TEST_CASE("numbers too large for a double are refused as out of range, with their place") {
  check_refused(R"({"width": 8, "height": 8, "view": [0, 0, 1e400, 8]})", "view[2]: number out of range");
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": 1}, "intensity": -1e999)"),
                "lights[0].intensity: number out of range");
}

TEST_CASE("a megabyte-long out-of-range number is echoed cut short, on one short line") {
  const std::string digits = "1" + std::string(1000000, '0');
  check_refused(R"({"width": 8, "height": 8, "view": [0, 0, )" + digits + ", 8]}", "view[2]: number out of range");
  const Status s = parse(R"({"width": )" + digits + R"(, "height": 8})");
  CHECK(s.message() == "s.json: width: number out of range (" + digits.substr(0, 32) + "... (1000001 characters))");
  // Short numbers are echoed whole.
  CHECK(parse(R"({"width": 1e400, "height": 8})").message() == "s.json: width: number out of range (1e400)");
}

TEST_CASE("unknown keys are refused at every level") {
  check_refused(R"({"width": 8, "height": 8, "lihgts": []})", "lihgts: unknown key");
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": 1}, "colour": [1, 1, 1])"),
                "lights[0].colour: unknown key");
  check_refused(with_light(R"("circle": {"center": [0, 0], "raduis": 1})"), "lights[0].circle.raduis: unknown key");
  // A key that is not an identifier is quoted, so the message stays on one line.
  check_refused(R"({"width": 8, "height": 8, "a\nb": 1})", "[\"a\\nb\"]: unknown key");
}

TEST_CASE("duplicate keys are refused with their place") {
  check_refused(R"({"width": 8, "height": 8, "width": 16})", "width: duplicate key");
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": 1, "radius": 2})"),
                "lights[0].circle.radius: duplicate key");
  check_refused(R"({"width": 8, "height": 8, "occluders": [{"segment": [[0, 0], [1, 1]]}, )"
                R"({"segment": [[0, 0], [1, 1]], "segment": [[0, 0], [2, 2]]}]})",
                "occluders[1].segment: duplicate key");
}

TEST_CASE("a light or occluder has exactly one shape") {
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": 1}, "segment": [[0, 0], [1, 1]])"),
                "lights[0]: has both circle and segment");
  check_refused(with_light(R"("color": [1, 1, 1])"), "lights[0]: needs one of polygon, circle, segment");
  check_refused(with_occluder(""), "occluders[0]: needs one of polygon, circle, segment");
  check_refused(R"({"width": 8, "height": 8, "lights": [[0, 0]]})", "lights[0]: expected an object");
  check_refused(R"({"width": 8, "height": 8, "lights": {}})", "lights: expected an array");
}

TEST_CASE("occluders take no color or intensity") {
  check_refused(with_occluder(R"("segment": [[0, 0], [1, 1]], "color": [1, 0, 0])"),
                "occluders[0].color: occluders take no color or intensity");
  check_refused(with_occluder(R"("segment": [[0, 0], [1, 1]], "intensity": 2)"),
                "occluders[0].intensity: occluders take no color or intensity");
}

TEST_CASE("wrong types are named with their place") {
  check_refused(with_light(R"("circle": {"center": [0], "radius": 1})"), "lights[0].circle.center: expected [x, y]");
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": "1"})"),
                "lights[0].circle.radius: expected a number");
  check_refused(with_light(R"("circle": {"center": [0, 0]})"), "lights[0].circle.radius: missing");
  check_refused(with_light(R"("circle": [0, 0, 1])"), "lights[0].circle: expected {");
  check_refused(with_light(R"("segment": [[0, 0]])"), "lights[0].segment: expected [[x, y], [x, y]]");
  check_refused(with_polygon(R"([[0, 0], [1, 0], [1, null]])"), "lights[0].polygon[2]: expected [x, y]");
  check_refused(with_polygon(R"({"a": 1})"), "lights[0].polygon: expected an array");
  check_refused(with_light(R"("segment": [[0, 0], [1, 1]], "color": [1, 1])"), "lights[0].color: expected [r, g, b]");
  check_refused(with_light(R"("segment": [[0, 0], [1, 1]], "intensity": [1])"),
                "lights[0].intensity: expected a number");
  check_refused("[1, 2]", "expected a JSON object at the top level");
}

TEST_CASE("polygon: at least 3 vertices") {
  check_refused(with_polygon("[[0, 0], [1, 1]]"), "lights[0].polygon: needs at least 3 vertices, got 2");
  check_refused(with_polygon("[]"), "lights[0].polygon: needs at least 3 vertices, got 0");
}

TEST_CASE("polygon: a simple concave outline is a shape; crossings and folds are named by edge and vertex") {
  // An arrowhead (vertex 3 reflex), either winding: a concave light (test_concave_lights.cpp).
  CHECK(parse(with_polygon("[[0, 0], [10, 5], [0, 10], [3, 5]]")).ok());
  CHECK(parse(with_polygon("[[10, 5], [0, 0], [3, 5], [0, 10]]")).ok());
  // A bow-tie crosses itself.
  check_refused(with_polygon("[[0, 0], [2, 2], [2, 0], [0, 2]]"), "lights[0].polygon: edges 0 and 2 cross");
  // A spike that runs out along an edge and back folds at its tip.
  check_refused(with_polygon("[[0, 0], [15, 0], [10, 0], [0, 10]]"),
                "lights[0].polygon: the edges at vertex 1 fold back onto each other");
}

TEST_CASE("polygon: folds (an edge running straight back) are refused at the fold's vertex, one or several") {
  // Every other turn here is convex: only the fold check can refuse these.
  check_refused(with_polygon("[[0, 0], [6, 0], [3, 0], [6, 0], [3, 3]]"), "lights[0].polygon: the edges at vertex 1 fold back onto each other");
  check_refused(with_polygon("[[0, 0], [10, 0], [10, 10], [10, 5], [10, 10], [0, 10]]"),
                "lights[0].polygon: the edges at vertex 2 fold back onto each other");
  check_refused(with_polygon("[[0, 0], [10, 0], [5, 0], [10, 0], [5, 0], [10, 0], [10, 10], [0, 10]]"),
                "lights[0].polygon: the edges at vertex 1 fold back onto each other");
  check_refused(with_polygon("[[0, 0], [10, 0], [10, 10], [10, 5], [10, 10], [0, 10], [5, 10], [0, 10]]"),
                "lights[0].polygon: the edges at vertex 2 fold back onto each other");
  check_refused(with_polygon("[[0, 10], [10, 10], [10, 0], [10, 5], [10, 0], [0, 0]]"),
                "lights[0].polygon: the edges at vertex 2 fold back onto each other");
  // Property: a fold spliced into any edge of convex integer polygons (exact midpoints), either
  // winding, is named at the edge's end vertex.
  const int octagon[8][2] = {{4, 0}, {12, 0}, {16, 4}, {16, 12}, {12, 16}, {4, 16}, {0, 12}, {0, 4}};
  for (int reversed = 0; reversed < 2; ++reversed) {
    for (int k = 0; k < 8; ++k) {
      std::string list;
      int fold_vertex = -1, index = 0;
      auto add = [&](int x, int y) {
        list += (list.empty() ? "[" : ", ") + std::string("[") + std::to_string(x) + ", " + std::to_string(y) + "]";
        ++index;
      };
      for (int i = 0; i < 8; ++i) {
        const int* v = octagon[reversed ? 7 - i : i];
        const int* w = octagon[reversed ? (14 - i) % 8 : (i + 1) % 8];
        add(v[0], v[1]);
        if (i == k && k < 7) {  // ..., v, w, mid(v, w), w, ...
          fold_vertex = index;
          add(w[0], w[1]);
          add((v[0] + w[0]) / 2, (v[1] + w[1]) / 2);
        }
      }
      if (fold_vertex < 0) continue;
      list += "]";
      check_refused(with_polygon(list),
                    "lights[0].polygon: the edges at vertex " + std::to_string(fold_vertex) + " fold back");
    }
  }
}

TEST_CASE("polygon: a vertex list that winds around twice is refused") {
  // A pentagram: every turn is to the same side, but the boundary goes round twice.
  check_refused(with_polygon("[[0, -10], [5.878, 8.09], [-9.511, -3.09], [9.511, -3.09], [-5.878, 8.09]]"),
                "lights[0].polygon: edges 1 and 3 cross");
  // A square listed twice over.
  check_refused(with_polygon("[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [1, 0], [1, 1], [0, 1]]"),
                "lights[0].polygon: edges 0 and 3 touch");
}

TEST_CASE("polygon: zero area is refused") {
  check_refused(with_polygon("[[0, 0], [1, 1], [2, 2]]"), "lights[0].polygon: zero area");
  check_refused(with_polygon("[[0, 0], [2, 2], [1, 1], [3, 3]]"), "lights[0].polygon: zero area");
  check_refused(with_polygon("[[5, 5], [5, 5], [5, 5]]"), "lights[0].polygon: zero area");
  check_refused(with_polygon("[[0, 0], [0, 0], [0, 0], [0, 0]]"), "lights[0].polygon: zero area");
  // Within the straight tolerance of a line counts as collinear.
  check_refused(with_polygon("[[0, 0], [1, 0], [2, 1e-12]]"), "lights[0].polygon: zero area");
}

TEST_CASE("polygon: collinear and repeated vertices are tolerated, either winding accepted") {
  Scene scene;
  CHECK(parse(with_polygon("[[0, 0], [1, 0], [2, 0], [2, 2], [0, 2]]")).ok());           // collinear
  CHECK(parse(with_polygon("[[0, 0], [2, 0], [2, 2], [2, 2], [0, 2], [0, 0]]")).ok());   // repeats
  CHECK(parse(with_polygon("[[0, 0], [0, 0], [2, 0], [2, 2], [0, 2]]")).ok());
  CHECK(parse(with_polygon("[[0, 0], [2, 0], [2, 2]]")).ok());                          // y-down clockwise
  CHECK(parse(with_polygon("[[0, 0], [2, 2], [2, 0]]")).ok());                          // the other winding
  // Nearly straight within 1e-9 of a turn, either way, is still straight.
  CHECK(parse(with_polygon("[[0, 0], [1, 1e-12], [2, 0], [2, 2], [0, 2]]")).ok());
  CHECK(parse(with_polygon("[[0, 0], [1, -1e-12], [2, 0], [2, 2], [0, 2]]")).ok());
  // Huge and tiny coordinates: the check must not overflow or underflow.
  CHECK(parse(with_polygon("[[-1e307, -1e307], [1e307, -1e307], [0, 1e307]]")).ok());
  CHECK(parse(with_polygon("[[1e-300, 1e-300], [2e-300, 1e-300], [1e-300, 2e-300]]")).ok());
}

TEST_CASE("circle: radius > 0") {
  check_refused(with_light(R"("circle": {"center": [0, 0], "radius": 0})"), "lights[0].circle.radius: must be > 0");
  check_refused(with_occluder(R"("circle": {"center": [0, 0], "radius": -2})"),
                "occluders[0].circle.radius: must be > 0");
}

TEST_CASE("segment: two distinct points") {
  check_refused(with_light(R"("segment": [[3, 4], [3, 4]])"), "lights[0].segment: the two points coincide");
  check_refused(with_occluder(R"("segment": [[0, 0], [-0.0, 0]])"), "occluders[0].segment: the two points coincide");
}

TEST_CASE("color and intensity must be >= 0") {
  check_refused(with_light(R"("segment": [[0, 0], [1, 1]], "color": [1, -0.5, 1])"),
                "lights[0].color[1]: must be >= 0");
  check_refused(with_light(R"("segment": [[0, 0], [1, 1]], "intensity": -1)"), "lights[0].intensity: must be >= 0");
  CHECK(parse(with_light(R"("segment": [[0, 0], [1, 1]], "color": [0, 0, 0], "intensity": 0)")).ok());
}

TEST_CASE("syntax errors report line and column") {
  check_refused("{\"width\": 8,\n \"height\": 8,,}", "parse error at line 2, column 14");
  check_refused("", "parse error at line 1, column 1");
  check_refused(R"({"width": 8, "height": 8} trailing)", "parse error at line 1");
  check_refused(R"({"width": 8, "height": NaN})", "parse error");
  // Broken UTF-8 is refused, and the message quoting it stays printable ASCII.
  const Status status = parse("{\"width\": 8, \"height\": 8, \"x\xff\": 1}");
  CHECK(status.code() == StatusCode::invalid_scene);
  for (char ch : status.message()) CHECK((ch >= 0x20 && ch < 0x7F));
}

TEST_CASE("absurd nesting is refused without building it") {
  check_refused(R"({"width": 8, "height": 8, "lights": )" + std::string(100000, '['),
                "lights[0][0][0][0][0]: nested too deeply");
}

TEST_CASE("a refused scene leaves the output untouched") {
  Scene scene;
  REQUIRE(parse(R"({"width": 3, "height": 5})", scene).ok());
  CHECK_FALSE(parse(R"({"width": 7, "height": 0})", scene).ok());
  CHECK(scene.width == 3);
  CHECK(scene.height == 5);
}

TEST_CASE("validate_scene checks scenes built in code, with the same places") {
  Scene scene;
  scene.width = 16;
  scene.height = 16;
  scene.view = {0, 0, 16, 16};
  CHECK(par2d::validate_scene(scene).ok());

  Scene bad = scene;
  bad.width = 0;
  CHECK(par2d::validate_scene(bad, "code").message().rfind("code: width:", 0) == 0);

  bad = scene;
  bad.view.x1 = std::numeric_limits<double>::quiet_NaN();
  CHECK(par2d::validate_scene(bad, "code").message().rfind("code: view[2]: not a finite number", 0) == 0);

  bad = scene;
  bad.lights.push_back({par2d::Circle{{1, 1}, 1}, {1, 1, 1}, 1});
  bad.lights.push_back({par2d::Circle{{1, std::numeric_limits<double>::infinity()}, 1}, {1, 1, 1}, 1});
  CHECK(par2d::validate_scene(bad, "code").message().rfind("code: lights[1].circle.center: not a finite", 0) == 0);

  bad = scene;
  // A polygon must be a simple outline (it may be concave: tests/test_concave_lights.cpp).
  bad.lights.push_back({par2d::Polygon{{{0, 0}, {4, 0}, {0, 4}, {4, 4}}}});
  const Status status = par2d::validate_scene(bad, "code");
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == "code: lights[0].polygon: edges 1 and 3 cross");

  bad = scene;
  bad.lights.push_back({par2d::Segment{{0, 0}, {1, 0}}, {1, 1, 1}, std::numeric_limits<double>::quiet_NaN()});
  CHECK(par2d::validate_scene(bad, "code").message().rfind("code: lights[0].intensity: not a finite number", 0) == 0);
}

TEST_CASE("load_scene_file reads a file and names it in messages") {
  const std::string path = "par2d_test_scene_json.tmp.json";
  {
    std::ofstream file(path, std::ios::binary);
    file << R"({"width": 8, "height": 8, "lights": [{"circle": {"center": [0, 0], "radius": 0}}]})";
  }
  Scene scene;
  const Status status = par2d::load_scene_file(path, scene);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message().rfind(path + ": lights[0].circle.radius: must be > 0", 0) == 0);
  {
    std::ofstream file(path, std::ios::binary);
    file << kSpecExample;
  }
  CHECK(par2d::load_scene_file(path, scene).ok());
  CHECK(scene.width == 512);
  std::remove(path.c_str());
}

TEST_CASE("an unreadable file is an io_error naming the path and the reason") {
  Scene scene;
  const Status missing = par2d::load_scene_file("no/such/dir/scene.json", scene);
  CHECK(missing.code() == StatusCode::io_error);
  CHECK(missing.message().rfind("no/such/dir/scene.json: ", 0) == 0);
  CHECK(missing.message().find("No such file or directory") != std::string::npos);

  const Status directory = par2d::load_scene_file(".", scene);
  CHECK(directory.code() == StatusCode::io_error);
  CHECK(directory.message().find("Is a directory") != std::string::npos);
}
