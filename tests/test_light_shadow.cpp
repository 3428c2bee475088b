// A light's shadow strength and colour (docs/contract.md section 6): E = (1 - k) U + k S per
// channel, k = strength * (1 - color), against closed forms (scalar), the SIMD path against the
// scalar one, and a Renderer that splits, merges and drops such lights as they change.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

// Every shape lies above the view (y < 0), so directions from a pixel to them lie in (pi, 2 pi).
double direction_to(Vec2 x, Vec2 p) {
  const double a = std::atan2(p.y - x.y, p.x - x.x);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

// The width of the directions from x to segment ab, and of their part within [lo, hi].
struct Arc {
  double lo, hi;
};
Arc arc_to(Vec2 x, Vec2 a, Vec2 b) {
  const double u = direction_to(x, a), v = direction_to(x, b);
  return {std::min(u, v), std::max(u, v)};
}
double overlap(Arc a, Arc b) { return std::max(0.0, std::min(a.hi, b.hi) - std::max(a.lo, b.lo)); }

RenderedImage render_scalar(const Scene& scene) { return render_or_fail(scene, options_for(Backend::scalar)); }

// A long segment light above a 16 x 12 view, two overlapping blockers between (their shadows
// merge: a union, not a product), and a dark wall over the bottom rows, inside which the light
// is all shadow.
Scene blocker_scene(const Shadow& shadow) {
  Scene scene;
  scene.width = 16;
  scene.height = 12;
  scene.view = {0, 0, 16, 12};
  Light light{Segment{{-200, -30}, {216, -30}}, {1.0, 0.8, 0.6}, 2.0};
  light.shadow = shadow;
  scene.lights.push_back(light);
  scene.occluders.push_back({Segment{{4, -8}, {9, -8}}});
  scene.occluders.push_back({Segment{{7, -8}, {12, -8}}});
  scene.occluders.push_back({Polygon{{{-1, 9}, {17, 9}, {17, 13}, {-1, 13}}}});
  return scene;
}

const Shadow kShadows[] = {
    {1.0, {0.0, 0.0, 0.0}},    // the default: full shadows
    {0.0, {0.0, 0.0, 0.0}},    // none
    {0.5, {0.0, 0.0, 0.0}},    // half
    {1.0, {1.0, 0.25, 0.0}},   // a coloured shadow: red passes, green a quarter
    {0.7, {0.2, 1.0, 0.5}},
};

}  // namespace

TEST_CASE("closed form: a light's shadow strength and colour keep (1 - k) of what occluders block") {
  for (const Shadow& shadow : kShadows) {
    CAPTURE(shadow.strength);
    CAPTURE(shadow.color[0]);
    CAPTURE(shadow.color[1]);
    const Scene scene = blocker_scene(shadow);
    const Rgb e = emission(scene.lights[0]);
    const int compared = check_against_closed_form(scene, render_scalar(scene), [&](int, int, Vec2 x) {
      const Arc arc = arc_to(x, {-200, -30}, {216, -30});
      const double unshadowed = arc.hi - arc.lo;
      // Inside the dark wall every direction is shadow; elsewhere the blockers' union.
      const double shadowed = x.y > 9.0 ? 0.0 : unshadowed - overlap(arc, arc_to(x, {4, -8}, {12, -8}));
      Rgb expected{};
      for (std::size_t c = 0; c < 3; ++c) {
        const double k = shadow.strength * (1.0 - shadow.color[c]);
        expected[c] = e[c] * ((1.0 - k) * unshadowed + k * shadowed) / (2.0 * kPi);
      }
      return expected;
    });
    CHECK(compared >= 16 * 11);
  }
}

TEST_CASE("shadow strength and colour: every SIMD ISA matches the scalar reference, culling on and off") {
  for (const Shadow& shadow : kShadows) {
    CAPTURE(shadow.strength);
    Scene scene = blocker_scene(shadow);
    // A second light that keeps full shadows, and a range, so split and whole lights mix.
    Light torch{Circle{{8, -2}, 1.5}, {0.3, 0.6, 1.0}, 3.0};
    torch.range = 30.0;
    torch.shadow.strength = 1.0 - shadow.strength;
    scene.lights.push_back(torch);
    const RenderedImage ref = render_scalar(scene);
    check_simd_against_scalar(scene, ref, "shadowed lights", [](Vec2) { return false; }, 16 * 12);
  }
}

namespace {

// The Renderer's frame against a one-shot render of its snapshot: equal bit for bit, the
// split light's two parts summed where a load of the snapshot puts them.
void check_renderer_matches_snapshot(Renderer& renderer) { CHECK(renderer_equals_snapshot(renderer)); }

}  // namespace

TEST_CASE("a Renderer splits a light with a partial shadow and keeps one handle, whatever changes" * per_isa()) {
  Renderer renderer;
  REQUIRE(renderer.set_frame(32, 24).ok());
  OccluderHandle wall;
  REQUIRE(renderer.add_occluder(Occluder{Polygon{{{10, 8}, {22, 8}, {22, 12}, {10, 12}}}}, &wall).ok());
  Light plain{Circle{{6, 4}, 2}, {1, 1, 1}, 1.0};
  LightHandle other;
  REQUIRE(renderer.add_light(plain, &other).ok());

  Light light{Circle{{16, 3}, 2}, {1.0, 0.5, 0.25}, 2.0};
  light.shadow = {0.6, {0.5, 0.0, 1.0}};
  LightHandle handle;
  REQUIRE(renderer.add_light(light, &handle).ok());
  CHECK(renderer.light_count() == 2);
  {
    const Scene snapshot = renderer.snapshot();
    REQUIRE(snapshot.lights.size() == 2);
    const auto split = std::find_if(snapshot.lights.begin(), snapshot.lights.end(),
                                    [](const Light& l) { return l.shadow.strength == 0.6; });
    REQUIRE(split != snapshot.lights.end());
    CHECK(split->shadow.color == Rgb{0.5, 0.0, 1.0});
    Light back;
    REQUIRE(renderer.light(handle, &back).ok());
    CHECK(back.shadow.strength == 0.6);
  }
  check_renderer_matches_snapshot(renderer);

  // Moved, same parts (prepared in place); then full shadows (one part); then none (the
  // unshadowed part alone); then split again.
  light.shape = Circle{{15, 2}, 2.5};
  REQUIRE(renderer.update_light(handle, light).ok());
  check_renderer_matches_snapshot(renderer);
  light.shadow = Shadow{};
  REQUIRE(renderer.update_light(handle, light).ok());
  check_renderer_matches_snapshot(renderer);
  light.shadow.strength = 0.0;
  REQUIRE(renderer.update_light(handle, light).ok());
  check_renderer_matches_snapshot(renderer);
  light.shadow = {0.3, {0.0, 1.0, 0.0}};
  REQUIRE(renderer.update_light(handle, light).ok());
  CHECK(renderer.light_count() == 2);
  check_renderer_matches_snapshot(renderer);

  // Emission only: both parts follow; dark and lit again.
  REQUIRE(renderer.set_light_emission(handle, {0.2, 0.9, 0.4}, 3.0).ok());
  check_renderer_matches_snapshot(renderer);
  REQUIRE(renderer.set_light_emission(handle, {0.0, 0.0, 0.0}, 3.0).ok());
  CHECK(renderer.light_count() == 2);
  check_renderer_matches_snapshot(renderer);
  REQUIRE(renderer.set_light_emission(handle, {1.0, 0.0, 0.0}, 1.0).ok());
  check_renderer_matches_snapshot(renderer);
  // A colour channel the shadow colour lets through wholly (green: k = 0) with the others
  // dark leaves the unshadowed part alone.
  REQUIRE(renderer.set_light_emission(handle, {0.0, 1.0, 0.0}, 1.0).ok());
  check_renderer_matches_snapshot(renderer);

  // The total emission counts the light once, not once per part.
  light.intensity = 0.9e38;
  light.color = {1, 1, 1};
  REQUIRE(renderer.update_light(handle, light).ok());
  light.intensity = 0.2e38;
  LightHandle extra;
  const Status refused = renderer.add_light(light, &extra);
  CHECK_FALSE(refused.ok());
  CHECK(refused.message().find("emission too large") != std::string::npos);
  light.intensity = 2.0;
  REQUIRE(renderer.update_light(handle, light).ok());

  REQUIRE(renderer.remove_light(handle).ok());
  CHECK(renderer.light_count() == 1);
  Light gone;
  CHECK_FALSE(renderer.light(handle, &gone).ok());
  CHECK_FALSE(renderer.update_light(handle, light).ok());
  check_renderer_matches_snapshot(renderer);

  // set_scene: handles in the scene's order whatever splits; the snapshot gives the lights back.
  Scene scene = renderer.snapshot();
  scene.lights.insert(scene.lights.begin(), light);
  std::vector<LightHandle> handles;
  REQUIRE(renderer.set_scene(scene, &handles).ok());
  REQUIRE(handles.size() == 2);
  Light first;
  REQUIRE(renderer.light(handles[0], &first).ok());
  CHECK(first.shadow.strength == 0.3);
  CHECK(renderer.light_count() == 2);
  CHECK(renderer.snapshot().lights.size() == 2);
  check_renderer_matches_snapshot(renderer);
}

}  // namespace par2d::test
