// One bounce of indirect light as users state it (docs/contract.md section 7): the albedo and
// bounce keys, their checks and messages, writing back, and the boundary pieces.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "geometry/bounce_pieces.hpp"
#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "scene/scene_validate.hpp"
#include "support/test_tiers.hpp"

namespace {

using par2d::Scene;
using par2d::Status;
using par2d::StatusCode;
using par2d::detail::BouncePiece;

Status parse(const std::string& json, Scene& scene) { return par2d::parse_scene(json, "s.json", scene); }

void check_message(const std::string& json, const std::string& message) {
  Scene scene;
  const Status status = parse(json, scene);
  CAPTURE(json);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == message);
}

std::string scene_with(const std::string& members) { return R"({"width": 4, "height": 3, )" + members + "}"; }
std::string occluder_with(const std::string& terms) {
  return scene_with(R"("occluders": [{"segment": [[0, 0], [1, 1]], )" + terms + "}]");
}

constexpr double kTwoPi = 6.283185307179586476925286766559;

}  // namespace

TEST_CASE("albedo and bounce.piece load, default, and write back bit for bit") {
  Scene scene;
  REQUIRE(parse(scene_with(R"("occluders": [{"circle": {"center": [2, 2], "radius": 1}, "albedo": [0.5, 0.25, 1]},
                                            {"polygon": [[0, 0], [1, 0], [1, 1]]}],
                             "bounce": {"piece": 0.75})"),
                scene)
              .ok());
  REQUIRE(scene.occluders.size() == 2);
  CHECK(scene.occluders[0].albedo == par2d::Rgb{0.5, 0.25, 1.0});
  CHECK(scene.occluders[1].albedo == par2d::Rgb{0.0, 0.0, 0.0});
  CHECK(scene.bounce.piece == 0.75);
  Scene back;
  const std::string text = par2d::scene_to_json(scene);
  REQUIRE(parse(text, back).ok());
  CHECK(back.occluders[0].albedo == scene.occluders[0].albedo);
  CHECK(back.occluders[1].albedo == scene.occluders[1].albedo);
  CHECK(back.bounce.piece == 0.75);
  CHECK(par2d::scene_to_json(back) == text);

  // {} is the default piece; a scene without either key writes neither.
  Scene empty;
  REQUIRE(parse(scene_with(R"("bounce": {})"), empty).ok());
  CHECK(empty.bounce.piece == 4.0);
  const std::string plain = par2d::scene_to_json(empty);
  CHECK(plain.find("bounce") == std::string::npos);
  CHECK(plain.find("albedo") == std::string::npos);
}

TEST_CASE("bad albedo and bounce values are refused in one line naming the place") {
  check_message(occluder_with(R"("albedo": [0.5, 1.5, 0])"), "s.json: occluders[0].albedo[1]: must be between 0 and 1, got 1.5");
  check_message(occluder_with(R"("albedo": [-0.25, 0, 0])"), "s.json: occluders[0].albedo[0]: must be between 0 and 1, got -0.25");
  check_message(occluder_with(R"("albedo": [1, 1])"), "s.json: occluders[0].albedo: expected [r, g, b]");
  check_message(occluder_with(R"("albedo": 0.5)"), "s.json: occluders[0].albedo: expected [r, g, b]");
  check_message(scene_with(R"("lights": [{"circle": {"center": [1, 1], "radius": 1}, "albedo": [1, 1, 1]}])"),
                "s.json: lights[0].albedo: unknown key (expected polygon, circle, segment, color, intensity, range, "
                "falloff, normalize, cone, cookie, mask, elevation, shadow)");
  check_message(scene_with(R"("bounce": {"piece": 0})"), "s.json: bounce.piece: must be > 0, got 0");
  check_message(scene_with(R"("bounce": {"piece": -2})"), "s.json: bounce.piece: must be > 0, got -2");
  check_message(scene_with(R"("bounce": {"piece": "4"})"), "s.json: bounce.piece: expected a number");
  check_message(scene_with(R"("bounce": {"piece": [4]})"), "s.json: bounce.piece: expected a number");
  check_message(scene_with(R"("bounce": {"size": 4})"), "s.json: bounce.size: unknown key (expected piece, step)");
  check_message(scene_with(R"("bounce": 4)"), "s.json: bounce: expected {\"piece\": h, \"step\": n}");
  check_message(scene_with(R"("bounce": [4])"), "s.json: bounce: expected {\"piece\": h, \"step\": n}");

  // validate_scene words the same problems for scenes built in code.
  Scene built;
  REQUIRE(parse(occluder_with(R"("albedo": [1, 1, 1])"), built).ok());
  built.occluders[0].albedo[2] = std::nan("");
  CHECK(par2d::validate_scene(built, "code").code() == StatusCode::invalid_scene);
  CHECK(par2d::validate_scene(built, "code").message().rfind("code: occluders[0].albedo[2]: ", 0) == 0);
  built.occluders[0].albedo[2] = 1.0;
  built.bounce.piece = std::numeric_limits<double>::infinity();
  CHECK(par2d::validate_scene(built, "code").message().rfind("code: bounce.piece: ", 0) == 0);
}

TEST_CASE("more than 1048576 bounce pieces is refused naming bounce.piece; reflecting occluders only count") {
  // A circle of radius 1 cut at h: ceil(2 pi / h) pieces.
  const double h_ok = kTwoPi / 1048576.0 * (1.0 + 1e-7);   // 1048576 pieces
  const double h_bad = kTwoPi / 1048576.0 * (1.0 - 1e-7);  // 1048577 pieces
  CHECK(par2d::detail::bounce_piece_count(par2d::Circle{{0, 0}, 1.0}, h_ok) == 1048576.0);
  const auto with = [](double h, const char* albedo) {
    return scene_with(R"("occluders": [{"circle": {"center": [2, 2], "radius": 1}, "albedo": )" + std::string(albedo) +
                      R"(}], "bounce": {"piece": )" + par2d::detail::format_number(h) + "}");
  };
  Scene scene;
  CHECK(parse(with(h_ok, "[1, 1, 1]"), scene).ok());
  CHECK(parse(with(h_bad, "[0, 0, 0]"), scene).ok());
  Scene bad;
  const Status status = parse(with(h_bad, "[0, 0, 1]"), bad);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message().rfind("s.json: bounce.piece: cuts the reflecting occluders into more than 1048576 pieces", 0) == 0);
  CHECK(status.message().find('\n') == std::string::npos);
  // An absurd count is refused, not wrapped, in code too.
  Scene huge;
  CHECK(parse(scene_with(R"("occluders": [{"segment": [[0, 0], [1e300, 0]], "albedo": [1, 1, 1]}])"), huge)
            .message()
            .rfind("s.json: bounce.piece: cuts the reflecting occluders into more than 1048576 pieces", 0) == 0);
  huge = Scene{};
  huge.width = 4;
  huge.height = 3;
  huge.view = {0, 0, 4, 3};
  huge.occluders.push_back(par2d::Occluder{par2d::Segment{{0, 0}, {1e300, 0}}});
  huge.occluders.back().albedo = {1, 1, 1};
  huge.bounce.piece = 1e-300;
  CHECK(par2d::validate_scene(huge, "code").message().rfind("code: bounce.piece: cuts the reflecting", 0) == 0);
}

TEST_CASE("bounce pieces: polygon edges as given (collinear vertices too), outward normals, either winding") {
  // A 10 x 4 rectangle with a collinear vertex at (6, 0), listed clockwise on screen (y down).
  const par2d::Polygon cw{{{0, 0}, {6, 0}, {10, 0}, {10, 4}, {0, 4}}};
  std::vector<BouncePiece> pieces;
  CHECK(par2d::detail::bounce_piece_count(cw, 3.0) == 2 + 2 + 2 + 4 + 2);
  par2d::detail::bounce_pieces(cw, 3.0, pieces);
  REQUIRE(pieces.size() == 12);
  // Edge (0,0)-(6,0): two pieces of 3, normal up (-y), the outside of the top edge.
  CHECK(pieces[0].a.x == 0.0);
  CHECK(pieces[0].b.x == 3.0);
  CHECK(pieces[0].mid.x == 1.5);
  CHECK(pieces[0].mid.y == 0.0);
  CHECK(pieces[0].normal.x == 0.0);
  CHECK(pieces[0].normal.y == -1.0);
  // Edge (6,0)-(10,0): ceil(4/3) = 2 pieces of 2, so the collinear vertex stays a cut.
  CHECK(pieces[2].a.x == 6.0);
  CHECK(pieces[2].b.x == 8.0);
  CHECK(pieces[3].b.x == 10.0);
  // Edge (10,0)-(10,4): normal +x; edge (0,4)-(0,0) (last): normal -x.
  CHECK(pieces[4].normal.x == 1.0);
  CHECK(pieces[4].mid.y == 1.0);
  CHECK(pieces[10].normal.x == -1.0);
  CHECK(pieces[10].mid.y == 3.0);
  CHECK(pieces[6].normal.y == 1.0);  // bottom edge (10,4)-(0,4), 4 pieces of 2.5
  CHECK(pieces[6].mid.x == 8.75);
  // The other winding gives the same outward normals.
  const par2d::Polygon ccw{{{0, 4}, {10, 4}, {10, 0}, {6, 0}, {0, 0}}};
  pieces.clear();
  par2d::detail::bounce_pieces(ccw, 3.0, pieces);
  REQUIRE(pieces.size() == 12);
  CHECK(pieces[0].normal.y == 1.0);   // bottom edge
  CHECK(pieces[4].normal.x == 1.0);   // right edge (10,4)-(10,0)
  CHECK(pieces[6].normal.y == -1.0);  // (10,0)-(6,0)
  // Repeated vertices give zero-length edges: no pieces.
  pieces.clear();
  par2d::detail::bounce_pieces(par2d::Polygon{{{0, 0}, {0, 0}, {4, 0}, {0, 4}}}, 8.0, pieces);
  CHECK(pieces.size() == 3);
}

TEST_CASE("bounce pieces: a segment's two faces and a circle's arcs from angle 0") {
  std::vector<BouncePiece> pieces;
  par2d::detail::bounce_pieces(par2d::Segment{{0, 0}, {0, 9}}, 4.0, pieces);
  REQUIRE(pieces.size() == 6);  // ceil(9/4) = 3 per face
  CHECK(pieces[0].normal.x == 1.0);  // perp = (e.y, -e.x) / |e| = (1, 0)
  CHECK(pieces[3].normal.x == -1.0);
  CHECK(pieces[1].mid.y == 4.5);
  CHECK(pieces[4].mid.y == 4.5);
  CHECK(pieces[2].b.y == 9.0);

  pieces.clear();
  par2d::detail::bounce_pieces(par2d::Circle{{5, 5}, 2.0}, 3.0, pieces);
  const std::size_t n = static_cast<std::size_t>(std::ceil(kTwoPi * 2.0 / 3.0));
  REQUIRE(pieces.size() == n);  // 5
  for (std::size_t k = 0; k < n; ++k) {
    const BouncePiece& p = pieces[k];
    CHECK(p.arc);
    CHECK(p.angle0 == doctest::Approx(kTwoPi * static_cast<double>(k) / static_cast<double>(n)).epsilon(1e-15));
    const double middle = kTwoPi * (static_cast<double>(k) + 0.5) / static_cast<double>(n);
    CHECK(p.mid.x == doctest::Approx(5 + 2 * std::cos(middle)).epsilon(1e-15));
    CHECK(p.mid.y == doctest::Approx(5 + 2 * std::sin(middle)).epsilon(1e-15));
    CHECK(p.normal.x == doctest::Approx(std::cos(middle)).epsilon(1e-15));
  }
  CHECK(pieces[0].a.x == 7.0);
  CHECK(pieces[0].a.y == 5.0);
  CHECK(pieces.back().angle1 == kTwoPi);

  // Scaled by a power of two: every point exactly scaled, the cuts unchanged.
  std::vector<BouncePiece> scaled;
  par2d::detail::bounce_pieces(par2d::Circle{{5, 5}, 2.0}, 3.0, 0.25, scaled);
  REQUIRE(scaled.size() == n);
  CHECK(scaled[2].mid.x == 0.25 * pieces[2].mid.x);
  CHECK(scaled[2].radius == 0.5);
}

TEST_CASE("a Renderer's bounce piece follows set_bounce, and the piece limit holds for every occluder change" *
          par2d::test::per_isa()) {
  Scene scene;
  scene.width = 24;
  scene.height = 16;
  scene.view = {0, 0, 24, 16};
  scene.lights.push_back(par2d::Light{par2d::Circle{{4, 4}, 1.5}, {1, 1, 1}, 3.0});
  par2d::Occluder wall{par2d::Polygon{{{10, 2}, {12, 2}, {12, 12}, {10, 12}}}};
  wall.albedo = {0.8, 0.4, 0.2};
  scene.occluders.push_back(wall);
  par2d::Renderer renderer;
  std::vector<par2d::OccluderHandle> occluders;
  REQUIRE(renderer.set_scene(scene, nullptr, &occluders).ok());
  CHECK(renderer.bounce().piece == 4.0);
  std::vector<float> got(24 * 16 * 3), want(24 * 16 * 3);
  const par2d::FrameBuffer buffer{reinterpret_cast<unsigned char*>(got.data()), par2d::PixelFormat::rgb_f32, 24 * 12, 1.0};
  for (const double piece : {2.0, 0.5, 7.0}) {
    CAPTURE(piece);
    REQUIRE(renderer.set_bounce(par2d::Bounce{piece}).ok());
    CHECK(renderer.bounce().piece == piece);
    REQUIRE(renderer.render(buffer).ok());
    scene.bounce.piece = piece;
    const par2d::ImageView image{want.data(), 24, 16, 24 * 3};
    REQUIRE(par2d::render(scene, par2d::RenderOptions{}, image).ok());
    CHECK(got == want);
    CHECK(renderer.snapshot().bounce.piece == piece);
  }
  // Refused pieces keep the old one: not > 0, or more than 1048576 pieces of the wall (perimeter 24).
  Status status = renderer.set_bounce(par2d::Bounce{0.0});
  CHECK(status.message() == "set_bounce: bounce.piece: must be > 0, got 0");
  status = renderer.set_bounce(par2d::Bounce{24.0 / 1048576.0 * 0.5});
  CHECK(status.message().rfind("set_bounce: bounce.piece: cuts the reflecting occluders into more than 1048576 pieces", 0) == 0);
  CHECK(renderer.bounce().piece == 7.0);
  // At a piece of 1e-4 the wall is 240000 pieces; four more such walls pass the limit.
  REQUIRE(renderer.set_bounce(par2d::Bounce{1e-4}).ok());
  std::vector<par2d::OccluderHandle> more(3);
  for (auto& h : more) REQUIRE(renderer.add_occluder(wall, &h).ok());
  par2d::OccluderHandle fifth;
  status = renderer.add_occluder(wall, &fifth);
  CHECK(status.message().rfind("add_occluder: albedo: cuts the reflecting occluders into more than 1048576 pieces", 0) == 0);
  // A dark one is free, and making it reflect is refused the same way; removing one makes room.
  par2d::Occluder dark = wall;
  dark.albedo = {0, 0, 0};
  REQUIRE(renderer.add_occluder(dark, &fifth).ok());
  status = renderer.update_occluder(fifth, wall);
  CHECK(status.message().rfind("occluder " + std::to_string(fifth.id) + ": albedo: cuts the reflecting occluders", 0) == 0);
  REQUIRE(renderer.remove_occluder(more[0]).ok());
  CHECK(renderer.update_occluder(fifth, wall).ok());
  // set_scene counts the pieces of the scene it is given: four such walls at 1e-4, then a
  // fifth added is refused.
  scene.bounce.piece = 1e-4;
  scene.occluders.assign(4, wall);
  REQUIRE(renderer.set_scene(scene).ok());
  status = renderer.add_occluder(wall, &fifth);
  CHECK(status.message().rfind("add_occluder: albedo: cuts the reflecting occluders into more than 1048576 pieces", 0) == 0);
}
