// Geometric edge cases through the public API, each against docs/contract.md section 1's definition, and the fuzz corpus replay.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_checks.hpp"
#include "fuzz/fuzz_contact_checks.hpp"
#include "fuzz/fuzz_huge_checks.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"
#include "support/test_tiers.hpp"

namespace {

using namespace par2d;
using test::RenderedImage;

constexpr double kPi = 3.14159265358979323846;
// docs/contract.md section 5: the scalar path is exact to 1e-6 e_max away from boundaries.
constexpr double kScalarBound = 1e-6;
constexpr double kSimdBound = 1e-4;

std::vector<Isa> simd_isas() {
  std::vector<Isa> isas;
  for (Isa isa : kSimdIsas)
    if (isa_supported(isa)) isas.push_back(isa);
  return isas;
}

RenderOptions scalar_options() {
  RenderOptions o;
  o.backend = Backend::scalar;
  o.threads = 1;
  return o;
}

RenderOptions simd_options(Isa isa) {
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = isa;
  o.threads = 1;
  return o;
}

// A 1x1 image whose only pixel center is exactly x (half-width `half`, a power of two, so
// x0 + 0.5 * (x1 - x0) rounds back to x for the coordinates used here).
Scene at_point(Scene scene, Vec2 x, double half = 0.5) {
  scene.width = scene.height = 1;
  scene.view = {x.x - half, x.y - half, x.x + half, x.y + half};
  return scene;
}

// Red channel of the single pixel (every light here is white unless said otherwise).
// The one pixel of `scene` (with `raycast`, by the ray caster).
double render_one(const Scene& scene, const RenderOptions& options, bool raycast = false) {
  Status status;
  const RenderedImage image = test::render_image(scene, options, status, raycast);
  REQUIRE_MESSAGE(status.ok(), status.message());
  return image.at(0, 0, 0);
}

Light white_light(Shape shape, double intensity = 1.0) {
  Light l;
  l.shape = std::move(shape);
  l.intensity = intensity;
  return l;
}

Polygon square(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

Polygon regular_polygon(Vec2 c, double r, int n) {
  Polygon p;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    p.vertices.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  return p;
}

void check_finite_and_bounded(const Scene& scene, const RenderOptions& options, bool raycast = false) {
  Status status;
  const RenderedImage image = test::render_image(scene, options, status, raycast);
  REQUIRE_MESSAGE(status.ok(), status.message());
  const std::string problem = fuzz::check_bounds(scene, image, raycast ? "raycast" : backend_name(options.backend));
  CHECK_MESSAGE(problem.empty(), problem);
}

}  // namespace

TEST_CASE("a pixel on a light's vertex or edge lies in the closed light: full e") {
  for (const Shape& light : {Shape{square(0, 0, 4, 4)}, Shape{Circle{{0, 0}, 4}}, Shape{Segment{{0, 0}, {4, 4}}}}) {
    Scene scene;
    scene.lights.push_back(white_light(light, 2.5));
    scene.occluders.push_back({Circle{{20, 20}, 1}});  // elsewhere, so the occluder code runs
    std::vector<Vec2> points;
    if (std::holds_alternative<Polygon>(light)) points = {{4, 4}, {0, 0}, {4, 2}, {1, 0}};
    if (std::holds_alternative<Circle>(light)) points = {{4, 0}, {0, -4}, {-4, 0}};
    if (std::holds_alternative<Segment>(light)) points = {{0, 0}, {4, 4}, {2, 2}};
    for (Vec2 p : points) {
      INFO("light index ", light.index(), " point (", p.x, ", ", p.y, ")");
      CHECK(render_one(at_point(scene, p), scalar_options()) == doctest::Approx(2.5).epsilon(1e-12));
      // A boundary pixel is exempt from docs/contract.md section 5, but still finite and in [0, sum e].
      for (Isa isa : simd_isas()) check_finite_and_bounded(at_point(scene, p), simd_options(isa));
      RenderOptions rays = scalar_options();
      rays.rays = 64;
      check_finite_and_bounded(at_point(scene, p), rays, /*raycast=*/true);
    }
  }
}

TEST_CASE("a pixel on an occluder's vertex or edge lies in the closed occluder: black") {
  for (const Shape& occluder : {Shape{square(0, 0, 4, 4)}, Shape{Circle{{0, 0}, 4}}, Shape{Segment{{0, 0}, {4, 4}}}}) {
    Scene scene;
    scene.lights.push_back(white_light(Circle{{-10, -10}, 3}));
    scene.occluders.push_back({occluder});
    std::vector<Vec2> points;
    if (std::holds_alternative<Polygon>(occluder)) points = {{4, 4}, {0, 0}, {4, 2}, {1, 0}};
    if (std::holds_alternative<Circle>(occluder)) points = {{4, 0}, {0, 4}, {0, -4}};
    if (std::holds_alternative<Segment>(occluder)) points = {{0, 0}, {4, 4}, {1, 1}};
    for (Vec2 p : points) {
      INFO("occluder index ", occluder.index(), " point (", p.x, ", ", p.y, ")");
      CHECK(render_one(at_point(scene, p), scalar_options()) == 0.0);
      for (Isa isa : simd_isas()) check_finite_and_bounded(at_point(scene, p), simd_options(isa));
    }
  }
}

TEST_CASE("a pixel collinear with an occluder edge: the edge blocks a zero-measure set, the face blocks its arc") {
  // Segment light at x = 6 from y = -1 to 1, seen from the origin: 2·atan(1/6).
  const double light_arc = 2.0 * std::atan(1.0 / 6.0);
  Scene scene;
  scene.lights.push_back(white_light(Segment{{6, -1}, {6, 1}}));
  SUBCASE("a segment occluder on the pixel's line of sight blocks nothing") {
    scene.occluders.push_back({Segment{{2, 0}, {4, 0}}});
    const Scene s = at_point(scene, {0, 0});
    CHECK(std::fabs(render_one(s, scalar_options()) - light_arc / (2 * kPi)) <= kScalarBound);
    for (Isa isa : simd_isas()) CHECK(std::fabs(render_one(s, simd_options(isa)) - light_arc / (2 * kPi)) <= kSimdBound);
  }
  SUBCASE("a triangle with an edge on the line of sight blocks exactly the half on its side") {
    scene.occluders.push_back({Polygon{{{2, 0}, {4, 0}, {3, -1}}}});
    const Scene s = at_point(scene, {0, 0});
    CHECK(std::fabs(render_one(s, scalar_options()) - 0.5 * light_arc / (2 * kPi)) <= kScalarBound);
    for (Isa isa : simd_isas())
      CHECK(std::fabs(render_one(s, simd_options(isa)) - 0.5 * light_arc / (2 * kPi)) <= kSimdBound);
  }
}

TEST_CASE("an occluder sharing an edge with a light: hidden behind it from one side, hiding it from the other") {
  Scene scene;
  scene.lights.push_back(white_light(square(0, 0, 2, 2)));
  scene.occluders.push_back({square(2, 0, 4, 2)});
  // From (-3, 1) the light's near face is hit first along every ray that meets the occluder.
  CHECK(std::fabs(render_one(at_point(scene, {-3, 1}), scalar_options()) - 2 * std::atan(1.0 / 3.0) / (2 * kPi)) <=
        kScalarBound);
  // From (7, 1) the occluder covers the light's whole arc and comes first.
  CHECK(render_one(at_point(scene, {7, 1}), scalar_options()) == 0.0);
  // On the shared edge: inside the occluder.
  CHECK(render_one(at_point(scene, {2, 1}), scalar_options()) == 0.0);
  // Touching at one corner only: from (-3, 1) the corner occluder is behind the light too.
  scene.occluders = {{square(2, 2, 4, 4)}};
  CHECK(std::fabs(render_one(at_point(scene, {-3, 1}), scalar_options()) - 2 * std::atan(1.0 / 3.0) / (2 * kPi)) <=
        kScalarBound);
}

TEST_CASE("a light wholly inside an occluder is hidden from every point outside it") {
  // Any ray from outside must cross the occluder's boundary before it reaches the light.
  for (const Shape& light : {Shape{Circle{{0, 0}, 1}}, Shape{square(-1, -1, 1, 1)}, Shape{Segment{{-1, 0}, {1, 0}}}}) {
    Scene scene;
    scene.lights.push_back(white_light(light, 3.0));
    scene.occluders.push_back({Circle{{0, 0}, 3}});
    for (Vec2 p : {Vec2{5, 0}, Vec2{0, -7}, Vec2{3, 0}, Vec2{2, 0}, Vec2{0, 0}, Vec2{-40, 25}}) {
      INFO("light index ", light.index(), " point (", p.x, ", ", p.y, ")");
      CHECK(render_one(at_point(scene, p), scalar_options()) == 0.0);
      RenderOptions rays = scalar_options();
      rays.rays = 256;
      CHECK(render_one(at_point(scene, p), rays, /*raycast=*/true) == 0.0);
    }
  }
}

TEST_CASE("an occluder wholly inside a light: full e around it, and invisible from outside the light") {
  Scene scene;
  scene.lights.push_back(white_light(Circle{{0, 0}, 4}, 2.0));
  scene.occluders.push_back({Circle{{0, 0}, 1}});
  // Inside the light, outside the occluder: t_L = 0 < t_occ.
  CHECK(render_one(at_point(scene, {2, 0}), scalar_options()) == doctest::Approx(2.0).epsilon(1e-12));
  CHECK(render_one(at_point(scene, {0, -3.5}), scalar_options()) == doctest::Approx(2.0).epsilon(1e-12));
  // Inside the occluder.
  CHECK(render_one(at_point(scene, {0.5, 0}), scalar_options()) == 0.0);
  // Outside the light the occluder is behind the light's boundary along every ray: the full
  // arc 2·asin(4/8) = pi/3 counts, E = e / 6.
  CHECK(std::fabs(render_one(at_point(scene, {8, 0}), scalar_options()) - 2.0 / 6.0) <= kScalarBound * 2.0);
  CHECK(std::fabs(render_one(at_point(scene, {0, 8}), scalar_options()) - 2.0 / 6.0) <= kScalarBound * 2.0);
  // The same with polygons: a square occluder inside a square light, seen from (-4, 2): 2·atan(2/4).
  Scene squares;
  squares.lights.push_back(white_light(square(0, 0, 4, 4)));
  squares.occluders.push_back({square(1, 1, 3, 3)});
  CHECK(std::fabs(render_one(at_point(squares, {-4, 2}), scalar_options()) - std::atan(0.5) / kPi) <= kScalarBound);
}

TEST_CASE("coordinates of 1e7 with a view 1e-3 wide: circle light gives 2·asin(r/d) at every pixel") {
  const Vec2 base{1e7, -1e7};
  Scene scene;
  scene.width = 8;
  scene.height = 8;
  scene.view = {base.x - 5e-4, base.y - 5e-4, base.x + 5e-4, base.y + 5e-4};
  const Circle light{{base.x + 3.0, base.y + 0.25}, 1.0};
  scene.lights.push_back(white_light(light));
  const double e_max = 1.0;
  Status status;
  const RenderedImage scalar = test::render_image(scene, scalar_options(), status);
  REQUIRE(status.ok());
  std::vector<RenderedImage> simd;
  for (Isa isa : simd_isas()) {
    simd.push_back(test::render_image(scene, simd_options(isa), status));
    REQUIRE(status.ok());
  }
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = test::pixel_center(scene, i, j);
      // Differences of nearby large numbers are exact here, so d is as exact as a double gets.
      const double d = std::hypot(light.center.x - p.x, light.center.y - p.y);
      const double expected = 2.0 * std::asin(light.radius / d) / (2.0 * kPi);
      INFO("pixel ", i, ", ", j);
      CHECK(std::fabs(scalar.at(i, j, 0) - expected) <= kScalarBound * e_max);
      for (const RenderedImage& s : simd) CHECK(std::fabs(s.at(i, j, 0) - expected) <= kSimdBound * e_max);
    }
}

TEST_CASE("a segment light five ulps long at 1e15: angle(a - x, b - x) at every point of the coordinate grid near it") {
  // Regression (FINDINGS.md #6): the scalar path measured a shape's span from the direction to
  // its centroid, which for a segment is its midpoint, rounded off the segment far from the
  // origin (0.06 units here); seen from under a unit away that direction fell outside the
  // segment's span, which grew to include it: 0.0563 instead of 0.0514 at (0.25, 0.75).
  const double base = 1e15;  // coordinates 0.125 apart
  const Vec2 a{base, base + 0.125}, b{base - 0.375, base - 0.375};
  for (int i = -4; i <= 4; ++i) {
    for (int j = -4; j <= 8; ++j) {
      const Vec2 x{base + 0.125 * i, base + 0.125 * j};
      // One pixel centered on x (the view's corners are on the grid too).
      Scene scene;
      scene.width = scene.height = 1;
      scene.view = {x.x - 0.125, x.y - 0.125, x.x + 0.125, x.y + 0.125};
      scene.lights.push_back(white_light(Segment{a, b}));
      const Vec2 da{a.x - x.x, a.y - x.y}, db{b.x - x.x, b.y - x.y};  // exact: nearby doubles
      const double cross = da.x * db.y - da.y * db.x, dot = da.x * db.x + da.y * db.y;
      if (cross == 0.0) continue;  // on the segment's line: a boundary, or seen edge-on
      const double expected = std::abs(std::atan2(cross, dot)) / (2.0 * kPi);
      Status status;
      const RenderedImage scalar = test::render_image(scene, scalar_options(), status);
      REQUIRE(status.ok());
      INFO("x = base + (", 0.125 * i, ", ", 0.125 * j, ")");
      CHECK(std::fabs(scalar.at(0, 0, 0) - expected) <= kScalarBound);
      for (Isa isa : simd_isas()) {
        const RenderedImage simd = test::render_image(scene, simd_options(isa), status);
        REQUIRE(status.ok());
        CHECK(std::fabs(simd.at(0, 0, 0) - expected) <= kSimdBound);
      }
    }
  }
}

TEST_CASE("translating an occluded scene by 1e7 keeps the scalar image within twice the scalar bound") {
  Scene near;
  near.width = 12;
  near.height = 10;
  near.view = {0, 0, 12, 10};
  near.lights.push_back(white_light(Circle{{2, 3}, 1.5}));
  near.lights.push_back(white_light(Segment{{11, 1}, {11, 9}}, 0.5));
  near.occluders.push_back({Polygon{{{5, 2}, {7, 3}, {6, 6}}}});
  near.occluders.push_back({Circle{{8.5, 7.5}, 0.7}});
  Scene far = near;
  const double shift = 1e7;
  auto move = [&](Vec2& v) { v = {v.x + shift, v.y + shift}; };
  far.view = {near.view.x0 + shift, near.view.y0 + shift, near.view.x1 + shift, near.view.y1 + shift};
  for (Light& l : far.lights) {
    if (auto* c = std::get_if<Circle>(&l.shape)) move(c->center);
    if (auto* s = std::get_if<Segment>(&l.shape)) move(s->a), move(s->b);
  }
  for (Occluder& o : far.occluders) {
    if (auto* c = std::get_if<Circle>(&o.shape)) move(c->center);
    if (auto* p = std::get_if<Polygon>(&o.shape))
      for (Vec2& v : p->vertices) move(v);
  }
  Status status;
  const RenderedImage a = test::render_image(near, scalar_options(), status);
  REQUIRE(status.ok());
  const RenderedImage b = test::render_image(far, scalar_options(), status);
  REQUIRE(status.ok());
  const double e_max = test::emission_max_sum(near);
  int checked = 0;
  for (int j = 0; j < near.height; ++j)
    for (int i = 0; i < near.width; ++i) {
      if (test::near_boundary(near, test::pixel_center(near, i, j), 1e-6)) continue;
      ++checked;
      for (int c = 0; c < 3; ++c) CHECK(std::fabs(a.at(i, j, c) - b.at(i, j, c)) <= 2 * kScalarBound * e_max);
    }
  CHECK(checked > 100);
}

TEST_CASE("repeated and collinear polygon vertices change nothing") {
  // Square light [0, 4]^2 seen from (-4, 2): arc 2·atan(2/4), E = atan(0.5)/pi.
  const Polygon plain = square(0, 0, 4, 4);
  const Polygon messy{{{0, 0}, {0, 0}, {2, 0}, {4, 0}, {4, 0}, {4, 1}, {4, 3}, {4, 4}, {2, 4}, {0, 4}, {0, 2}, {0, 0}}};
  for (const Polygon& light : {plain, messy}) {
    Scene scene;
    scene.lights.push_back(white_light(light));
    CHECK(std::fabs(render_one(at_point(scene, {-4, 2}), scalar_options()) - std::atan(0.5) / kPi) <= kScalarBound);
    // As occluder in front of a segment light at x = 10 (y from -8 to 12): from (-4, 2) the
    // square's arc [-atan(2/4), atan(2/4)] lies inside the light's and is removed.
    Scene blocked;
    blocked.lights.push_back(white_light(Segment{{10, -8}, {10, 12}}));
    blocked.occluders.push_back({light});
    const double expected = (2 * std::atan(10.0 / 14.0) - 2 * std::atan(0.5)) / (2 * kPi);
    const Scene s = at_point(blocked, {-4, 2});
    CHECK(std::fabs(render_one(s, scalar_options()) - expected) <= kScalarBound);
    for (Isa isa : simd_isas()) CHECK(std::fabs(render_one(s, simd_options(isa)) - expected) <= kSimdBound);
  }
}

TEST_CASE("a 4000-gon matches its circle's closed form within the inscribed/circumscribed gap") {
  // An n-gon inscribed in a circle of radius R contains the circle of radius R·cos(pi/n), so
  // from distance d its arc lies in [2·asin(R·cos(pi/n)/d), 2·asin(R/d)]; for n = 4000,
  // R = 10, d = 30 that gap is about 2.2e-7 rad. The scalar path may add 1e-6 e_max.
  const int n = 4000;
  const double R = 10.0, d = 30.0;
  const double lo = 2 * std::asin(R * std::cos(kPi / n) / d), hi = 2 * std::asin(R / d);
  Scene scene;
  scene.lights.push_back(white_light(regular_polygon({0, 0}, R, n)));
  const double got = render_one(at_point(scene, {-d, 0}), scalar_options());
  CHECK(got >= lo / (2 * kPi) - kScalarBound);
  CHECK(got <= hi / (2 * kPi) + kScalarBound);
  for (Isa isa : simd_isas()) {
    const double simd = render_one(at_point(scene, {-d, 0}), simd_options(isa));
    CHECK(simd >= lo / (2 * kPi) - kSimdBound);
    CHECK(simd <= hi / (2 * kPi) + kSimdBound);
  }
  // As an occluder: a 4000-gon of radius 2 at distance 10 in front of a segment light.
  Scene blocked;
  blocked.lights.push_back(white_light(Segment{{20, -10}, {20, 10}}));
  blocked.occluders.push_back({regular_polygon({10, 0}, 2, n)});
  const double light_arc = 2 * std::atan(0.5);
  const double block_lo = 2 * std::asin(2 * std::cos(kPi / n) / 10), block_hi = 2 * std::asin(2.0 / 10);
  const Scene s = at_point(blocked, {0, 0});
  const double e = render_one(s, scalar_options());
  CHECK(e >= (light_arc - block_hi) / (2 * kPi) - kScalarBound);
  CHECK(e <= (light_arc - block_lo) / (2 * kPi) + kScalarBound);
  for (Isa isa : simd_isas()) {
    const double simd = render_one(s, simd_options(isa));
    CHECK(simd >= (light_arc - block_hi) / (2 * kPi) - kSimdBound);
    CHECK(simd <= (light_arc - block_lo) / (2 * kPi) + kSimdBound);
  }
}

TEST_CASE("zero-area views are refused; a 1e-300-wide view renders its one world point" * par2d::test::per_isa()) {
  Scene scene;
  scene.width = 4;
  scene.height = 3;
  scene.lights.push_back(white_light(Circle{{1, 0}, 0.5}));
  std::vector<float> pixels(4 * 3 * 3, -1.0f);
  const ImageView image{pixels.data(), 4, 3, 12};
  for (View v : {View{0, 0, 0, 3}, View{0, 0, 4, 0}, View{2, 2, 2, 2}}) {
    scene.view = v;
    const Status s = render(scene, scalar_options(), image);
    CHECK(s.code() == StatusCode::invalid_scene);
    CHECK(s.message().find("view") != std::string::npos);
  }
  Scene parsed;
  CHECK(parse_scene(R"({"width": 4, "height": 3, "view": [1, 0, 1, 3]})", "v.json", parsed).code() ==
        StatusCode::invalid_scene);
  // Every pixel sits at the origin to within 1e-300: E = 2·asin(0.5/1)/2pi = 1/6.
  scene.view = {0, 0, 1e-300, 1e-300};
  for (const RenderOptions& o : {scalar_options(), simd_options(default_isa())}) {
    if (o.isa && *o.isa == Isa::scalar) continue;
    Status status;
    const RenderedImage got = test::render_image(scene, o, status);
    REQUIRE(status.ok());
    for (float v : got.pixels) CHECK(std::fabs(v - 1.0 / 6.0) <= kSimdBound);
  }
}

TEST_CASE("fuzz corpora replay: every checked-in input keeps every fuzz property") {
  namespace fs = std::filesystem;
  int replayed = 0;
  for (const char* which : {"loader", "render", "contact", "huge"}) {
    const fs::path dir = fs::path(PAR2D_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / which;
    REQUIRE(fs::is_directory(dir));
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
      const std::string kind = which;
      const std::string problem = kind == "loader"   ? fuzz::check_scene_text(data, bytes.size())
                                  : kind == "render" ? fuzz::check_render_bytes(data, bytes.size())
                                  : kind == "huge"   ? fuzz::check_huge_bytes(data, bytes.size())
                                                     : fuzz::check_contact_bytes(data, bytes.size());
      INFO(entry.path().string());
      CHECK_MESSAGE(problem.empty(), problem);
      ++replayed;
    }
  }
  CHECK(replayed >= 8);
}

TEST_CASE("polygons with coordinates up to 1e307 keep their shape: a pixel inside the occluder is black") {
  // Regression: make_convex_shape summed raw cross products, which overflow beyond ~1e154;
  // every vertex then tested "straight" (inf <= 1e-9 * inf) and a clockwise polygon was not
  // reversed, so the pixel at (1, 0) fell outside the occluder x in [0, S], |y| <= S and the
  // light at (-3, 0) shone through it.
  for (double S : {1e10, 1e160, 1e200, 1e307}) {
    for (bool clockwise : {false, true}) {
      Scene scene;
      scene.lights.push_back(white_light(Circle{{-3, 0}, 1}));
      Polygon occluder{{{0, -S}, {S, -S}, {S, S}, {0, S}}};
      if (clockwise) std::swap(occluder.vertices[1], occluder.vertices[3]);
      scene.occluders.push_back({occluder});
      INFO("S = ", S, " clockwise = ", clockwise);
      CHECK(render_one(at_point(scene, {1, 0}), scalar_options()) == 0.0);
      // Outside it, at (-1, 0), the light is unobstructed: 2·asin(1/2)/2pi = 1/6.
      CHECK(std::fabs(render_one(at_point(scene, {-1, 0}), scalar_options()) - 1.0 / 6.0) <= kScalarBound);
    }
  }
}
