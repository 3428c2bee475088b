// Re-sending what the world already holds changes nothing: an engine that syncs every light and
// occluder from its entities each frame (plain values, values placed by a transform, emission,
// ambient, directional lights, bounce, frame) gets frames that cost what actually changed.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "par2d/renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

Shape box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// A sprite placed by a transform: what the host sends each frame.
struct Placed {
  Occluder local;
  Transform transform;
};

// A level with every kind of entry the World keeps apart: merged tilemap boxes, a concave
// occluder with a hole, a circle, a translucent box; ranged, coned, cookied, split-shadow,
// dark and concave lights; sprites and a torch placed by transforms; ambient, a directional
// light and a reflecting wall (one bounce).
struct Level {
  static constexpr int kWidth = 160, kHeight = 96;
  Scene scene;
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  std::vector<Placed> sprites;
  std::vector<OccluderHandle> sprite_handles;
  Light torch_local;
  Transform torch_transform;
  LightHandle torch;

  Level() {
    scene.width = kWidth;
    scene.height = kHeight;
    scene.view = View{0.0, 0.0, double(kWidth), double(kHeight)};
    for (int i = 0; i < 5; ++i)  // one row of tiles: merged into one entry
      scene.occluders.push_back(Occluder{box(40.0 + 8.0 * i, 60.0, 48.0 + 8.0 * i, 68.0)});
    scene.occluders.push_back(Occluder{Polygon{{{100, 20}, {130, 20}, {130, 50}, {115, 35}, {100, 50}},
                                               {{{110, 24}, {112, 24}, {112, 26}, {110, 26}}}}});
    scene.occluders.push_back(Occluder{Circle{{30.0, 30.0}, 5.0}});
    Occluder glass{box(70.0, 10.0, 74.0, 40.0)};
    glass.transmittance = {0.5, 0.7, 0.9};
    scene.occluders.push_back(glass);
    Occluder mirror{box(10.0, 80.0, 60.0, 84.0)};
    mirror.albedo = {0.6, 0.6, 0.6};
    scene.occluders.push_back(mirror);
    scene.bounce.piece = 6.0;

    scene.lights.push_back(Light{Circle{{20.0, 50.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0, 45.0});
    Light cone{Circle{{90.0, 80.0}, 1.5}, {0.6, 0.8, 1.0}, 1.5};
    cone.cone = Cone{-90.0, 40.0, 10.0};
    scene.lights.push_back(cone);
    Light cookie{Segment{{140.0, 70.0}, {146.0, 76.0}}, {1.0, 1.0, 1.0}, 1.0};
    cookie.cookie = Cookie{15.0, {{0.0, 1.0}, {90.0, 0.2}, {200.0, 0.8}}};
    scene.lights.push_back(cookie);
    Light split{Circle{{60.0, 30.0}, 3.0}, {0.9, 0.9, 0.5}, 1.0};
    split.shadow.strength = 0.6;
    split.shadow.color = {0.1, 0.0, 0.2};
    scene.lights.push_back(split);
    scene.lights.push_back(Light{Circle{{150.0, 10.0}, 2.0}, {1.0, 1.0, 1.0}, 0.0});  // dark
    scene.lights.push_back(Light{Polygon{{{4, 4}, {16, 4}, {16, 16}, {10, 8}, {4, 16}}}, {0.4, 0.9, 0.4}, 1.0});
    scene.ambient = {0.01, 0.02, 0.03};
    scene.directional_lights.push_back(DirectionalLight{200.0, 230.0, {0.2, 0.2, 0.3}, 0.5});

    sprites.push_back(Placed{Occluder{box(-3.0, -2.0, 3.0, 2.0)}, Transform{{85.0, 55.0}, 33.0, {1.5, 0.75}}});
    sprites.push_back(Placed{Occluder{Circle{{0.0, 0.0}, 1.0}}, Transform{{120.0, 75.0}, 0.0, {2.5, -2.5}}});
    torch_local = Light{Circle{{0.0, 0.0}, 1.0}, {1.0, 0.5, 0.2}, 3.0, 30.0};
    torch_transform = Transform{{110.0, 65.0}, 17.0, {1.25, 1.25}};
  }

  void load(Renderer& r) {
    REQUIRE(r.set_scene(scene, &lights, &occluders).ok());
    sprite_handles.resize(sprites.size());
    for (std::size_t i = 0; i < sprites.size(); ++i)
      REQUIRE(r.add_occluder(sprites[i].local, sprites[i].transform, &sprite_handles[i]).ok());
    REQUIRE(r.add_light(torch_local, torch_transform, &torch).ok());
  }

  // Every value the host holds, sent again as an engine's sync does.
  void resync(Renderer& r) const {
    REQUIRE(r.set_frame(kWidth, kHeight, scene.view).ok());
    for (std::size_t i = 0; i < lights.size(); ++i) {
      REQUIRE(r.update_light(lights[i], scene.lights[i]).ok());
      REQUIRE(r.set_light_emission(lights[i], scene.lights[i].color, scene.lights[i].intensity).ok());
    }
    for (std::size_t i = 0; i < occluders.size(); ++i) REQUIRE(r.update_occluder(occluders[i], scene.occluders[i]).ok());
    for (std::size_t i = 0; i < sprites.size(); ++i)
      REQUIRE(r.update_occluder(sprite_handles[i], sprites[i].local, sprites[i].transform).ok());
    REQUIRE(r.update_light(torch, torch_local, torch_transform).ok());
    REQUIRE(r.set_ambient(scene.ambient).ok());
    REQUIRE(r.set_directional_lights(scene.directional_lights).ok());
    REQUIRE(r.set_bounce(scene.bounce).ok());
  }
};

std::vector<float> one_shot(const Renderer& r) {
  const Scene snap = r.snapshot();
  std::vector<float> pixels(static_cast<std::size_t>(snap.width) * snap.height * 3, -1.0f);
  const Status s = render(snap, RenderOptions{}, ImageView{pixels.data(), snap.width, snap.height, snap.width * 3});
  REQUIRE_MESSAGE(s.ok(), s.message());
  return pixels;
}

bool same_rects(const std::vector<PixelRect>& a, const std::vector<PixelRect>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const PixelRect& p, const PixelRect& q) {
    return p.x0 == q.x0 && p.y0 == q.y0 && p.x1 == q.x1 && p.y1 == q.y1;
  });
}

}  // namespace

TEST_CASE("re-sending every value the world holds marks nothing: no pixel written, no tile computed" * per_isa()) {
  for (const bool layers : {false, true}) {
    CAPTURE(layers);
    Level level;
    Renderer r;
    level.load(r);
    REQUIRE(r.set_incremental(true).ok());
    if (layers) REQUIRE(r.set_light_layer_budget(std::size_t{64} << 20).ok());
    std::vector<float> buffer(static_cast<std::size_t>(Level::kWidth) * Level::kHeight * 3, -1.0f);
    const ImageView image{buffer.data(), Level::kWidth, Level::kHeight, Level::kWidth * 3};
    REQUIRE(r.render(image).ok());
    const std::vector<float> first = buffer;
    for (int frame = 0; frame < 3; ++frame) {
      level.resync(r);
      std::fill(buffer.begin(), buffer.end(), -7.0f);  // canary: a written pixel is >= 0
      REQUIRE(r.render(image).ok());
      CHECK(r.dirty_rects().empty());
      CHECK(r.frame_stats().pixels == 0u);
      CHECK(std::all_of(buffer.begin(), buffer.end(), [](float v) { return v == -7.0f; }));
    }
    // The world is what it was: a forced frame gives the first frame's pixels again.
    r.force_full_frame();
    REQUIRE(r.render(image).ok());
    CHECK(buffer == first);
  }
}

TEST_CASE("re-syncing everything with two real changes costs what sending only the two costs" * per_isa()) {
  Level all, only;
  Renderer synced, told;
  all.load(synced);
  only.load(told);
  for (Renderer* r : {&synced, &told}) REQUIRE(r->set_incremental(true).ok());
  std::vector<float> a(static_cast<std::size_t>(Level::kWidth) * Level::kHeight * 3, -1.0f), b = a;
  const ImageView image_a{a.data(), Level::kWidth, Level::kHeight, Level::kWidth * 3};
  const ImageView image_b{b.data(), Level::kWidth, Level::kHeight, Level::kWidth * 3};
  PortableRandom rng(20261207);
  for (int frame = 0; frame < 12; ++frame) {
    CAPTURE(frame);
    REQUIRE(synced.render(image_a).ok());
    REQUIRE(told.render(image_b).ok());
    REQUIRE(a == b);
    if (frame > 0) {
      REQUIRE(same_rects(synced.dirty_rects(), told.dirty_rects()));
      CHECK(synced.frame_stats().pixels == told.frame_stats().pixels);
    }
    // Two real changes: the ranged torch moves and a sprite turns.
    const Vec2 to{rng.uniform(10.0, 150.0), rng.uniform(10.0, 90.0)};
    const double turn = rng.uniform(0.0, 360.0);
    for (Level* level : {&all, &only}) {
      std::get<Circle>(level->scene.lights[0].shape).center = to;
      level->sprites[0].transform.rotation = turn;
    }
    for (auto [level, r] : {std::pair<Level*, Renderer*>{&all, &synced}, {&only, &told}}) {
      REQUIRE(r->update_light(level->lights[0], level->scene.lights[0]).ok());
      REQUIRE(r->update_occluder(level->sprite_handles[0], level->sprites[0].local, level->sprites[0].transform).ok());
    }
    all.resync(synced);
  }
  REQUIRE(synced.render(image_a).ok());
  CHECK(a == one_shot(synced));
}

}  // namespace par2d::test

namespace par2d::test {

TEST_CASE("an update that changes any one value of a light or an occluder is computed" * per_isa()) {
  // Each edit changes one field, bit for bit; a comparison that forgot the field would skip it.
  Light light{Circle{{40.0, 40.0}, 2.0}, {1.0, 0.8, 0.6}, 2.0};
  light.range = 60.0;
  const std::vector<void (*)(Light&)> light_edits = {
      [](Light& l) { l.color[1] = 0.5; },
      [](Light& l) { l.intensity = 3.0; },
      [](Light& l) { l.range = 61.0; },
      [](Light& l) { l.falloff = 3.0; },
      [](Light& l) { l.normalize = 30.0; },
      [](Light& l) { l.cone = Cone{0.0, 90.0, 10.0}; },
      [](Light& l) { l.cookie = Cookie{0.0, {{0.0, 1.0}, {180.0, 0.5}}}; },
      [](Light& l) { l.mask = 2u; },
      [](Light& l) { l.elevation = 30.0; },
      [](Light& l) { l.shadow.strength = 0.5; },
      [](Light& l) { l.shadow = Shadow{0.5, {0.0, 0.2, 0.0}}; },
      [](Light& l) { std::get<Circle>(l.shape).radius = 2.5; },
      [](Light& l) { std::get<Circle>(l.shape).center.y = 41.0; },
  };
  Occluder wall{box(60.0, 20.0, 64.0, 70.0)};
  const std::vector<void (*)(Occluder&)> occluder_edits = {
      [](Occluder& o) { o.transmittance = {0.5, 0.5, 0.5}; },
      [](Occluder& o) { o.mask = 2u; },
      [](Occluder& o) { o.interior = Interior::lit; },
      [](Occluder& o) { o.albedo = {0.3, 0.3, 0.3}; },
      [](Occluder& o) { std::get<Polygon>(o.shape).vertices[2].x = 65.0; },
  };
  const auto check = [](Renderer& r, std::vector<float>& buffer) {
    REQUIRE(r.render(ImageView{buffer.data(), 100, 80, 300}).ok());
    CHECK(!r.dirty_rects().empty());
    CHECK(buffer == one_shot(r));
  };
  for (std::size_t e = 0; e < light_edits.size() + occluder_edits.size(); ++e) {
    CAPTURE(e);
    Scene scene;
    scene.width = 100;
    scene.height = 80;
    scene.view = View{0.0, 0.0, 100.0, 80.0};
    scene.lights.push_back(light);
    scene.occluders.push_back(wall);
    Renderer r;
    std::vector<LightHandle> lights;
    std::vector<OccluderHandle> occluders;
    REQUIRE(r.set_scene(scene, &lights, &occluders).ok());
    REQUIRE(r.set_incremental(true).ok());
    std::vector<float> buffer(100 * 80 * 3, -1.0f);
    REQUIRE(r.render(ImageView{buffer.data(), 100, 80, 300}).ok());
    if (e < light_edits.size()) {
      Light edited = light;
      light_edits[e](edited);
      REQUIRE(r.update_light(lights[0], edited).ok());
    } else {
      Occluder edited = wall;
      occluder_edits[e - light_edits.size()](edited);
      REQUIRE(r.update_occluder(occluders[0], edited).ok());
    }
    check(r, buffer);
  }
  // A sign of zero is a change too (angle code may branch on it).
  Renderer r;
  Scene scene;
  scene.width = 100;
  scene.height = 80;
  scene.view = View{0.0, 0.0, 100.0, 80.0};
  Light zero = light;
  std::get<Circle>(zero.shape).center = {0.0, 40.0};
  scene.lights.push_back(zero);
  std::vector<LightHandle> lights;
  REQUIRE(r.set_scene(scene, &lights).ok());
  REQUIRE(r.set_incremental(true).ok());
  std::vector<float> buffer(100 * 80 * 3, -1.0f);
  REQUIRE(r.render(ImageView{buffer.data(), 100, 80, 300}).ok());
  std::get<Circle>(zero.shape).center.x = -0.0;
  REQUIRE(r.update_light(lights[0], zero).ok());
  check(r, buffer);
}

}  // namespace par2d::test
