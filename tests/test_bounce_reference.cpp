// One bounce of indirect light (docs/contract.md section 7): the scalar reference against closed
// forms, the ray caster converging to it, and every SIMD level within section 5 of it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "raycast/raycast_renderer.hpp"
#include "render/bounce_tiles.hpp"
#include "scalar/bounce_reference.hpp"
#include "support/bounce_scenes.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"
#include "world/world.hpp"

namespace par2d::test {
namespace {

constexpr double kPiValue = 3.14159265358979323846;
constexpr double kDegree = kPiValue / 180.0;

Scene base_scene() {
  Scene s;
  s.width = 32;
  s.height = 24;
  s.view = {-80, -60, 80, 60};
  return s;
}

// The prepared scene, its bounce frame, and the bounce term at points (world coordinates).
struct Bounced {
  detail::PreparedScene prepared;
  detail::BounceFrame frame;
  detail::BounceScratch scratch;
  explicit Bounced(const Scene& scene) : prepared(detail::prepare_scene(scene)) {
    detail::prepare_bounce_frame(prepared, frame, scratch.scalar);
  }
  Rgb at(Vec2 world, const Vec3* normal = nullptr) {
    const Vec2 x{world.x * prepared.scale, world.y * prepared.scale};
    return detail::bounce_irradiance(prepared, frame, x, normal, scratch);
  }
};

double angle_between(Vec2 a, Vec2 b, Vec2 x) {
  const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
  return std::fabs(std::atan2(ax * by - ay * bx, ax * bx + ay * by));
}

// A sky of radiance `e` along every ray direction but (80, 100) degrees (straight down, give
// or take 10), and a horizontal wall (-50, 0)-(50, 0) reflecting `albedo`.
Scene sky_and_wall(Rgb albedo, double e) {
  Scene s = base_scene();
  DirectionalLight sky;
  sky.angle0 = 100;
  sky.angle1 = 440;
  sky.intensity = e;
  s.directional_lights.push_back(sky);
  s.occluders.push_back(reflector(Segment{{-50, 0}, {50, 0}}, albedo));
  s.bounce.piece = 10;
  return s;
}

}  // namespace

TEST_CASE("bounce: a white wall under a sky from all around reflects the sky's radiance") {
  const Rgb albedo{1.0, 0.5, 0.25};
  const double e = 2.0;
  Bounced b(sky_and_wall(albedo, e));
  REQUIRE(b.frame.pieces.size() == 20);  // two faces of 10
  // The top face (normal up, -y) sees the whole sky: S = e / pi, L = albedo * e. The bottom
  // face misses the 20 degrees around straight down: S = e (2 - 2 sin 10 deg) / (2 pi).
  const double bottom = 1.0 - std::sin(10 * kDegree);
  for (std::size_t k = 0; k < 20; ++k) {
    CAPTURE(k);
    const double expected = k < 10 ? e : e * bottom;
    CHECK(b.frame.pieces[k].normal.y == (k < 10 ? -1.0 : 1.0));
    for (int c = 0; c < 3; ++c) CHECK(b.frame.radiance[k][c] == doctest::Approx(albedo[c] * expected).epsilon(1e-12));
  }
  // Above the wall: the top face, a segment light of radiance albedo * e.
  for (const Vec2 x : {Vec2{0, -10}, Vec2{-70, -3}, Vec2{31.5, -47.25}}) {
    CAPTURE(x.x);
    const Rgb got = b.at(x);
    const double angle = angle_between({-50, 0}, {50, 0}, x) / (2 * kPiValue);
    for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(albedo[c] * e * angle).epsilon(1e-12));
    // Shaded: a normal facing the viewer catches no bounce light; one tilted toward the wall
    // (down, +y) by phi catches sin(phi) * (cos t1 - cos t2) over the wall's directions.
    const Vec3 facing{0, 0, 1};
    const Rgb none = b.at(x, &facing);
    for (int c = 0; c < 3; ++c) CHECK(none[c] == 0.0);
    const double phi = 0.6;
    const Vec3 tilted{0, std::sin(phi), std::cos(phi)};
    const double t1 = std::atan2(0 - x.y, 50 - x.x), t2 = std::atan2(0 - x.y, -50 - x.x);
    const double weight = std::sin(phi) * (std::cos(t1) - std::cos(t2)) / (2 * kPiValue);
    const Rgb shaded = b.at(x, &tilted);
    for (int c = 0; c < 3; ++c) CHECK(shaded[c] == doctest::Approx(albedo[c] * e * weight).epsilon(1e-12));
  }
  // Below: the bottom face.
  const Rgb below = b.at({10, 20});
  const double angle = angle_between({-50, 0}, {50, 0}, {10, 20}) / (2 * kPiValue);
  for (int c = 0; c < 3; ++c) CHECK(below[c] == doctest::Approx(albedo[c] * e * bottom * angle).epsilon(1e-12));
}

TEST_CASE("bounce: a single lit segment's pieces in closed form, elevation included, the dark face 0") {
  Scene s = base_scene();
  Light light;
  light.shape = Circle{{3, -20}, 2};
  light.intensity = 3;
  light.color = {1, 0.5, 1};
  light.elevation = 60;  // cos = 1/2
  s.lights.push_back(light);
  s.occluders.push_back(reflector(Segment{{-10, 0}, {10, 0}}, {0.5, 1, 1}));
  s.bounce.piece = 5.5;  // 20 / 5.5 = 3.6: 4 pieces per face
  Bounced b(s);
  REQUIRE(b.frame.pieces.size() == 8);
  for (std::size_t k = 0; k < 8; ++k) {
    CAPTURE(k);
    const detail::BouncePiece& p = b.frame.pieces[k];
    const double mx = p.mid.x / b.prepared.scale, my = p.mid.y / b.prepared.scale;
    CHECK(mx == doctest::Approx(-10 + 5 * (static_cast<double>(k % 4) + 0.5)).epsilon(1e-15));
    if (k >= 4) {  // facing down, away from the light
      for (int c = 0; c < 3; ++c) CHECK(b.frame.radiance[k][c] == 0.0);
      continue;
    }
    // S = e cos(el) / 2pi * integral over the light's arc of cos(theta - psi_n), psi_n = -90 deg.
    const double dx = 3 - mx, dy = -20 - my;
    const double phi = std::atan2(dy, dx), half = std::asin(2 / std::hypot(dx, dy));
    const double psi = -kPiValue / 2;
    const double integral = std::sin(phi + half - psi) - std::sin(phi - half - psi);
    for (int c = 0; c < 3; ++c) {
      const double expected = kPiValue * s.occluders[0].albedo[c] * 3 * light.color[c] * 0.5 * integral / (2 * kPiValue);
      CHECK(b.frame.radiance[k][c] == doctest::Approx(expected).epsilon(1e-12));
    }
  }
}

TEST_CASE("bounce: one-sided behind a translucent occluder, and a translucent occluder in front scales it") {
  // A translucent reflecting wall lit from above: below it the direct light comes through, the
  // bounce does not (the lit face faces away and the face below is dark).
  Scene s = base_scene();
  Light light;
  light.shape = Circle{{0, -30}, 4};
  s.lights.push_back(light);
  Occluder wall = reflector(Segment{{-40, 0}, {40, 0}}, {1, 1, 1});
  wall.transmittance = {0.5, 0.5, 0.5};
  s.occluders.push_back(wall);
  Bounced b(s);
  for (const Vec2 x : {Vec2{0, 10}, Vec2{-30, 2}, Vec2{25, 40}}) {
    const Rgb got = b.at(x);
    for (int c = 0; c < 3; ++c) CHECK(got[c] == 0.0);
  }
  CHECK(b.at({0, -10})[0] > 0.0);

  // The sky and wall above, with a translucent bar between x and the wall that acts on the
  // pieces (masks share bit 2) but not on the sky (mask 1): the bounce is scaled by its
  // transmittance per channel, the pieces' radiances unchanged.
  Scene t = sky_and_wall({1, 1, 1}, 1.0);
  t.directional_lights[0].mask = 1;
  t.occluders[0].mask = 3;
  Occluder bar;
  bar.shape = Polygon{{{-200, -12}, {200, -12}, {200, -11}, {-200, -11}}};
  bar.transmittance = {0.5, 0.25, 1};
  bar.mask = 2;
  t.occluders.push_back(bar);
  Bounced tb(t);
  for (std::size_t k = 0; k < 10; ++k) CHECK(tb.frame.radiance[k][0] == doctest::Approx(1.0).epsilon(1e-12));
  const Vec2 x{5, -20};
  const double angle = angle_between({-50, 0}, {50, 0}, x) / (2 * kPiValue);
  const Rgb got = tb.at(x);
  for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(bar.transmittance[c] * angle).epsilon(1e-12));
  // Inside the bar (x contained: every direction crosses it).
  const Rgb in_bar = tb.at({5, -11.5});
  const double angle_in = angle_between({-50, 0}, {50, 0}, {5, -11.5}) / (2 * kPiValue);
  for (int c = 0; c < 3; ++c) CHECK(in_bar[c] == doctest::Approx(bar.transmittance[c] * angle_in).epsilon(1e-12));
}

TEST_CASE("bounce: pieces buried in another occluder get nothing and light nothing") {
  Scene s = sky_and_wall({1, 1, 1}, 1.0);
  // An opaque box swallowing the wall's left end: x in [-60, -27] around y = 0.
  Occluder box;
  box.shape = Polygon{{{-60, -5}, {-27, -5}, {-27, 5}, {-60, 5}}};
  s.occluders.push_back(box);
  Bounced b(s);
  REQUIRE(b.frame.pieces.size() == 20);
  for (std::size_t k = 0; k < 20; ++k) {
    CAPTURE(k);
    const double mid = b.frame.pieces[k].mid.x / b.prepared.scale;
    if (mid < -27) {
      CHECK(b.frame.radiance[k][0] == 0.0);
    } else {
      CHECK(b.frame.radiance[k][0] > 0.1);
    }
  }
  // Straight above the buried part nothing of it shows; the pieces to the right light x.
  const Vec2 x{-40, -30};
  const Rgb got = b.at(x);
  CHECK(got[0] > 0.0);
  // The box hides the wall up to its corner (-27, -5) as seen from x; the rest is seen, top
  // pieces only (all with radiance 1 but those the box shadows: their sky is cut).
  CHECK(got[0] < angle_between({-27, 0}, {50, 0}, x) / (2 * kPiValue));
}

namespace {

// A scene with every kind of reflector and a translucent and an opaque occluder.
Scene mixed_scene() { return bounce_mixed_scene(); }

// Worst difference of the ray caster's piece radiances (rays each) and bounce term at `points`
// (its total minus its direct value, the same rays) from the reference, over e_max.
struct Errors {
  double radiance = 0.0, bounce = 0.0;
};
Errors raycast_errors(const Scene& scene, const std::vector<Vec2>& points, int rays) {
  Bounced ref(scene);
  const double e_max = emission_max_sum(scene);
  const detail::RaycastRenderer caster(scene);
  Scene direct = scene;
  for (Occluder& o : direct.occluders) o.albedo = {0, 0, 0};
  const detail::RaycastRenderer direct_caster(direct);
  Errors err;
  const std::vector<Rgb> radiance = caster.bounce_radiances(rays);
  REQUIRE(radiance.size() == ref.frame.radiance.size());
  for (std::size_t k = 0; k < radiance.size(); ++k)
    for (int c = 0; c < 3; ++c)
      err.radiance = std::max(err.radiance, std::fabs(radiance[k][c] - ref.frame.radiance[k][c]) / e_max);
  for (const Vec2 x : points) {
    const Rgb total = caster.irradiance(x, rays, 0.37), plain = direct_caster.irradiance(x, rays, 0.37);
    const Rgb want = ref.at(x);
    for (int c = 0; c < 3; ++c) err.bounce = std::max(err.bounce, std::fabs(total[c] - plain[c] - want[c]) / e_max);
  }
  return err;
}

const std::vector<Vec2> kPoints{{0, -30}, {-20, 0}, {25, -20}, {45, 15}, {-70, -40}, {5, 40}};

}  // namespace

TEST_CASE("bounce: the ray caster converges to the reference as its ray count grows") {
  const Scene scene = mixed_scene();
  Errors previous{1e300, 1e300};
  for (const int rays : {250, 2500, 25000}) {
    const Errors err = raycast_errors(scene, kPoints, rays);
    MESSAGE("rays " << rays << ": radiance error " << err.radiance << " e_max, bounce error " << err.bounce << " e_max");
    CHECK(err.radiance < previous.radiance);
    CHECK(err.bounce < previous.bounce);
    previous = err;
  }
  // Stratified rays misplace each jump of the integrand by at most one stratum (2 pi / rays).
  CHECK(previous.radiance < 2e-4);
  CHECK(previous.bounce < 2e-4);
}

TEST_CASE("bounce: the ray caster within 1e-6 e_max of the reference at 2^21 rays" * long_tier()) {
  const Scene scene = mixed_scene();
  const Errors err = raycast_errors(scene, kPoints, 1 << 21);
  MESSAGE("rays 2^21: radiance error " << err.radiance << " e_max, bounce error " << err.bounce << " e_max");
  CHECK(err.radiance < 1e-6);
  CHECK(err.bounce < 1e-6);
}

TEST_CASE("bounce: every SIMD level within 1e-4 e_max of the scalar reference") {
  Scene scene = mixed_scene();
  scene.width = 40;
  scene.height = 30;
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  // The bounce is visible: the same scene without albedo differs.
  Scene direct = scene;
  for (Occluder& o : direct.occluders) o.albedo = {0, 0, 0};
  const RenderedImage plain = render_or_fail(direct, options_for(Backend::scalar));
  double gain = 0.0;
  for (std::size_t p = 0; p < ref.pixels.size(); ++p) gain = std::max(gain, double(ref.pixels[p]) - plain.pixels[p]);
  CHECK(gain > 0.01);
  const double pixel = 160.0 / 40;
  check_simd_against_scalar(
      scene, ref, "bounce mixed scene", [&](Vec2 p) { return near_boundary(scene, p, 0.05 * pixel); }, 1000);
}

TEST_CASE("bounce: a scene whose albedos are all 0 renders the same bytes as one without the keys" * per_isa()) {
  Scene scene = mixed_scene();
  for (Occluder& o : scene.occluders) o.albedo = {0, 0, 0};
  Scene bare = scene;
  bare.bounce = Bounce{};
  scene.bounce.piece = 0.5;
  for (const Backend backend : {Backend::scalar, Backend::automatic}) {
    const RenderedImage a = render_or_fail(scene, options_for(backend)), b = render_or_fail(bare, options_for(backend));
    CHECK(a.pixels == b.pixels);
  }
}

}  // namespace par2d::test

namespace par2d::test {
namespace {

std::vector<float> renderer_frame(Renderer& r, int width, int height) {
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3, -1.0f);
  REQUIRE(r.render(ImageView{pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3}).ok());
  return pixels;
}

}  // namespace

TEST_CASE("bounce: a Renderer after moving a light, a reflecting wall and the ambient equals a one-shot render" *
          per_isa()) {
  Scene scene = mixed_scene();
  scene.width = 24;
  scene.height = 18;
  Renderer r;
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(r.set_scene(scene, &lights, &occluders).ok());
  const std::vector<float> first = renderer_frame(r, 24, 18);
  CHECK(first == render_or_fail(scene, RenderOptions{}).pixels);

  // A moved light changes every piece's radiance, so pixels it cannot reach directly change too.
  Light moved = scene.lights[0];
  moved.shape = Circle{{-20, 40}, 5};
  REQUIRE(r.update_light(lights[0], moved).ok());
  const std::vector<float> second = renderer_frame(r, 24, 18);
  CHECK(second == render_or_fail(r.snapshot(), RenderOptions{}).pixels);
  CHECK(second != first);

  // A moved reflecting wall moves its pieces.
  Occluder wall = scene.occluders[0];
  wall.shape = Polygon{{{-50, 20}, {10, 20}, {10, 30}, {-50, 30}}};
  REQUIRE(r.update_occluder(occluders[0], wall).ok());
  CHECK(renderer_frame(r, 24, 18) == render_or_fail(r.snapshot(), RenderOptions{}).pixels);

  // Scene-wide terms set on their own keep the piece length.
  REQUIRE(r.set_ambient({0.01, 0.02, 0.03}).ok());
  CHECK(r.snapshot().bounce.piece == 7.0);
  CHECK(renderer_frame(r, 24, 18) == render_or_fail(r.snapshot(), RenderOptions{}).pixels);
}

}  // namespace par2d::test

namespace par2d::test {

TEST_CASE("bounce: a Renderer refuses an update past 1048576 pieces in one line and renders on as before" *
          per_isa()) {
  Scene scene = mixed_scene();
  scene.width = 8;
  scene.height = 6;
  Renderer r;
  REQUIRE(r.set_scene(scene).ok());
  std::vector<float> pixels(8 * 6 * 3), before(8 * 6 * 3);
  const ImageView image{pixels.data(), 8, 6, 8 * 3};
  REQUIRE(r.render(image).ok());
  before = pixels;
  // 2 pi 1e6 / 7 = 897 598 pieces more than the scene's: past the limit.
  OccluderHandle huge;
  const Status status = r.add_occluder(reflector(Circle{{0, 0}, 1.2e6}, {1, 1, 1}), &huge);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message().rfind("add_occluder: albedo: cuts the reflecting occluders into more than 1048576 pieces",
                               0) == 0);
  CHECK(status.message().find('\n') == std::string::npos);
  REQUIRE(r.render(image).ok());
  CHECK(pixels == before);
  // The same circle, dark, is taken; making it reflect is refused the same way.
  REQUIRE(r.add_occluder(reflector(Circle{{0, 0}, 1.2e6}, {0, 0, 0}), &huge).ok());
  CHECK(r.update_occluder(huge, reflector(Circle{{0, 0}, 1.2e6}, {1, 1, 1}))
            .message()
            .rfind("occluder " + std::to_string(huge.id) + ": albedo: cuts the reflecting occluders", 0) == 0);
  REQUIRE(r.remove_occluder(huge).ok());
  REQUIRE(r.render(image).ok());
  CHECK(pixels == before);
}

}  // namespace par2d::test

namespace par2d::test {

namespace {

// Piece radiances culled (with the lights' reach when `with_reach`) against the reference's:
// how many pieces, how many equal to the bit, the worst difference over e_max.
struct RadianceComparison {
  int pieces = 0, identical = 0;
  double worst = 0.0;
};
void compare_radiances(const Scene& scene, bool with_reach, RadianceComparison& out) {
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  detail::BounceFrame frame;
  detail::build_bounce_sources(prepared, frame);
  detail::ScalarScratch scratch;
  detail::bounce_radiances(prepared, frame, 0, frame.pieces.size(), scratch, false);
  const std::vector<Rgb> reference = frame.radiance;
  std::vector<detail::LightReach> reaches;
  detail::LightReachScratch reach_scratch;
  for (std::size_t l = 0; with_reach && l < prepared.lights.size(); ++l)
    reaches.push_back(detail::compute_light_reach(prepared, l, reach_scratch));
  const detail::ReachHidesLights hidden(reaches.data());
  detail::bounce_radiances(prepared, frame, 0, frame.pieces.size(), scratch, true,
                           with_reach ? &hidden : nullptr);
  const double e_max = emission_max_sum(scene);
  for (std::size_t k = 0; k < reference.size(); ++k) {
    ++out.pieces;
    if (frame.radiance[k] == reference[k]) ++out.identical;
    for (int c = 0; c < 3; ++c)
      out.worst = std::max(out.worst, std::fabs(frame.radiance[k][c] - reference[k][c]) / e_max);
  }
}

}  // namespace

TEST_CASE("bounce: piece radiances over the occluders near each light equal the reference's") {
  // Random scenes with every lighting-model term (ranges, cones, cookies, masks, translucent
  // and lit-interior occluders, elevations, directional lights) and every occluder reflecting,
  // and the dungeon example (walls: the reach hides most lights from most pieces). The culled
  // evaluation leaves out lights behind a piece or beyond their proven reach, and occluders off
  // the segments to a light, so it sums the same blocked pieces in the same order; a light left
  // out adds exactly 0 in exact arithmetic (the reference may round it to a tiny value).
  for (const bool with_reach : {false, true}) {
    CAPTURE(with_reach);
    RadianceComparison random, dungeon;
    for (std::uint32_t seed = 1; seed <= 24; ++seed) {
      RandomSceneOptions options = with_every_model_term({});
      options.normals = RandomSceneOptions::Normals::none;
      options.max_occluders = 16;
      Scene scene = random_scene(seed, options);
      for (Occluder& o : scene.occluders) o.albedo = {0.7, 0.5, 0.3};
      scene.bounce.piece = 1.5;
      compare_radiances(scene, with_reach, random);
    }
    Scene level;
    REQUIRE(load_scene_file(std::string(PAR2D_SOURCE_DIR) + "/examples/dungeon.json", level).ok());
    for (Occluder& o : level.occluders) o.albedo = {0.5, 0.5, 0.5};
    level.bounce.piece = 16;
    compare_radiances(level, with_reach, dungeon);
    for (const auto* c : {&random, &dungeon}) {
      MESSAGE(std::string(c == &random ? "random scenes: " : "dungeon: ") << c->pieces << " pieces, " << c->identical
                                                                << " identical, worst " << c->worst << " e_max");
      CHECK(c->pieces > 1000);
      CHECK(c->identical > c->pieces * 9 / 10);
      CHECK(c->worst <= 1e-12);
    }
  }
}

}  // namespace par2d::test
