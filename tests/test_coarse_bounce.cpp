// The coarse bounce (docs/contract.md section 7, "Coarse bounce"): the bounce term at every
// step-th grid pixel, interpolated bilinearly between, never across an occluder. Checked against
// the definition written out here with its own segment tests, for light leaking through a wall,
// for culled and SIMD frames against the reference, and for pixels that depend on their grid
// place alone.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "par2d/par2d.h"
#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "scalar/bounce_reference.hpp"
#include "world/world.hpp"
#include "support/bounce_scenes.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

// The mixed bounce scene (every kind of shape a segment to a node can meet) at 48 x 36, its
// view moved off the shapes' round coordinates so few segments to nodes graze a vertex exactly.
Scene coarse_scene(int step) {
  Scene s = bounce_mixed_scene();
  s.width = 48;
  s.height = 36;
  s.view = {-80.1234, -60.0771, 79.8766, 59.9229};
  s.bounce.step = step;
  return s;
}

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Distance from point p to segment [a, b].
double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d{b.x - a.x, b.y - a.y};
  const double len2 = d.x * d.x + d.y * d.y;
  double t = len2 > 0 ? ((p.x - a.x) * d.x + (p.y - a.y) * d.y) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(a.x + t * d.x - p.x, a.y + t * d.y - p.y);
}

// Signed distance-like gap between segments [a, b] and [c, d]: negative when they cross
// properly, else their distance.
double segment_gap(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = cross({b.x - a.x, b.y - a.y}, {c.x - a.x, c.y - a.y});
  const double d2 = cross({b.x - a.x, b.y - a.y}, {d.x - a.x, d.y - a.y});
  const double d3 = cross({d.x - c.x, d.y - c.y}, {a.x - c.x, a.y - c.y});
  const double d4 = cross({d.x - c.x, d.y - c.y}, {b.x - c.x, b.y - c.y});
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return -1.0;
  return std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d), point_segment_distance(c, a, b),
                   point_segment_distance(d, a, b)});
}

// How far segment [p, q] stays from a shape of these test scenes (convex polygons, circles,
// segments): negative or 0 when it meets the closed shape.
double clearance(const Shape& shape, Vec2 p, Vec2 q) {
  if (const auto* c = std::get_if<Circle>(&shape)) return point_segment_distance(c->center, p, q) - c->radius;
  if (const auto* s = std::get_if<Segment>(&shape)) return segment_gap(p, q, s->a, s->b);
  const auto& poly = std::get<Polygon>(shape);
  const auto& v = poly.vertices;
  bool inside = true;  // p inside the (convex, either orientation) polygon
  double sign = 0.0;
  double gap = 1e300;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % v.size()];
    gap = std::min(gap, segment_gap(p, q, a, b));
    const double side = cross({b.x - a.x, b.y - a.y}, {p.x - a.x, p.y - a.y});
    if (side != 0.0) {
      if (sign == 0.0) sign = side;
      else if ((side > 0) != (sign > 0)) inside = false;
    }
  }
  return inside ? -1.0 : gap;
}

// World position of grid pixel (i, j)'s point (sx, sy) for the scene's view.
Vec2 world_at(const Scene& s, double i, double j) {
  return {s.view.x0 + i * (s.view.x1 - s.view.x0) / s.width, s.view.y0 + j * (s.view.y1 - s.view.y0) / s.height};
}

}  // namespace

TEST_CASE("coarse bounce: the reference renders the definition, node by node") {
  for (const int step : {3, 4, 8}) {
    CAPTURE(step);
    const Scene scene = coarse_scene(step);
    RenderOptions options = options_for(Backend::scalar);
    options.bounce = BounceTerm::only;
    const RenderedImage image = render_or_fail(scene, options);
    // The exact bounce at any point, from the reference's own evaluation.
    const detail::PreparedScene prepared = detail::prepare_scene(scene);
    detail::BounceFrame frame;
    detail::BounceScratch scratch;
    detail::prepare_bounce_frame(prepared, frame, scratch.scalar);
    auto exact = [&](Vec2 world) {
      return detail::bounce_irradiance(prepared, frame, {world.x * prepared.scale, world.y * prepared.scale}, nullptr,
                                       scratch);
    };
    const double e_max = emission_max_sum(scene);
    int checked = 0, undecided = 0, interpolated = 0, fallback = 0;
    double worst = 0.0;
    for (int j = 0; j < scene.height; ++j) {
      for (int i = 0; i < scene.width; ++i) {
        // Pixel centers sit at grid coordinates (i, j); nodes at multiples of the step.
        const int n0 = static_cast<int>(std::floor(static_cast<double>(i) / step)) * step;
        const int m0 = static_cast<int>(std::floor(static_cast<double>(j) / step)) * step;
        const double fx = static_cast<double>(i - n0) / step, fy = static_cast<double>(j - m0) / step;
        const Vec2 x = world_at(scene, i + 0.5, j + 0.5);
        Rgb want{0, 0, 0};
        double weights = 0.0;
        bool near_touch = false;
        for (int corner = 0; corner < 4; ++corner) {
          const int dc = corner & 1, dr = corner >> 1;
          const double w = (dc ? fx : 1 - fx) * (dr ? fy : 1 - fy);
          if (w <= 0.0) continue;
          const Vec2 node = world_at(scene, n0 + dc * step + 0.5, m0 + dr * step + 0.5);
          double clear = 1e300;
          for (const Occluder& o : scene.occluders) clear = std::min(clear, clearance(o.shape, x, node));
          if (std::fabs(clear) < 1e-9) near_touch = true;
          if (clear <= 0.0) continue;
          const Rgb v = exact(node);
          for (int c = 0; c < 3; ++c) want[c] += w * v[c];
          weights += w;
        }
        if (near_touch) {
          ++undecided;
          continue;
        }
        if (weights > 0.0) {
          for (int c = 0; c < 3; ++c) want[c] /= weights;
          if (weights < 1.0) ++interpolated;
        } else {
          want = exact(x);
          ++fallback;
        }
        for (int c = 0; c < 3; ++c) {
          const double got = image.pixels[(static_cast<std::size_t>(j) * scene.width + i) * 3 + c];
          worst = std::max(worst, std::fabs(got - want[c]) / e_max);
        }
        ++checked;
      }
    }
    MESSAGE("step " << step << ": " << checked << " pixels, " << interpolated << " with some node hidden, " << fallback
                    << " with none seen, " << undecided << " grazing; worst " << worst << " e_max");
    CHECK(undecided < checked / 100 + 1);
    CHECK(interpolated > 20);  // occluders hide nodes from many pixels
    CHECK(fallback > 0);       // pixels inside occluders see no node
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("coarse bounce: no light leaks through a thin wall" * per_isa()) {
  // A bright reflector above a wall 0.2 px thick that spans the view; below it no piece is
  // seen, so the exact bounce is 0 there, and nodes just above the wall are bright.
  Scene scene;
  scene.width = 64;
  scene.height = 64;
  scene.view = {0, 0, 64, 64};
  Light torch;
  torch.shape = Circle{{20, 12}, 3};
  torch.intensity = 4;
  scene.lights.push_back(torch);
  scene.occluders.push_back(reflector(Polygon{{{30, 20}, {50, 20}, {50, 30}, {30, 30}}}, {1, 1, 1}));
  Occluder wall;
  wall.shape = Polygon{{{-1000, 33.4}, {1000, 33.4}, {1000, 33.6}, {-1000, 33.6}}};
  scene.occluders.push_back(wall);
  scene.bounce.piece = 2;
  for (const int step : {1, 8, 16}) {
    CAPTURE(step);
    scene.bounce.step = step;
    for (const Backend backend : {Backend::scalar, Backend::automatic}) {
      RenderOptions options = options_for(backend);
      options.bounce = BounceTerm::only;
      const RenderedImage image = render_or_fail(scene, options);
      float above = 0.0f, below = 0.0f;
      for (int j = 0; j < scene.height; ++j)
        for (int i = 0; i < scene.width; ++i)
          for (int c = 0; c < 3; ++c) {
            const float v = image.pixels[(static_cast<std::size_t>(j) * scene.width + i) * 3 + c];
            (j < 33 ? above : below) = std::max(j < 33 ? above : below, v);
          }
      CHECK(above > 0.05f);
      CHECK(below == 0.0f);
    }
  }
}

TEST_CASE("coarse bounce: culled SIMD frames within 1e-4 e_max of the reference") {
  for (const int step : {2, 5, 16}) {
    CAPTURE(step);
    const Scene scene = coarse_scene(step);
    const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
    // Culling only leaves out what adds nothing: the culled scalar frame is the same.
    const RenderedImage culled = render_or_fail(scene, options_for(Backend::scalar, std::nullopt, true));
    const RenderedImage unculled = render_or_fail(scene, options_for(Backend::scalar, std::nullopt, false));
    CHECK(culled.pixels == unculled.pixels);
    // The coarse image is not the exact one (it is an approximation), but close on this scene.
    Scene exact_scene = scene;
    exact_scene.bounce.step = 1;
    const RenderedImage exact = render_or_fail(exact_scene, options_for(Backend::scalar));
    CHECK(exact.pixels != ref.pixels);
    const double pixel = 160.0 / scene.width;
    check_simd_against_scalar(
        scene, ref, "coarse bounce step " + std::to_string(step),
        [&](Vec2 p) { return near_boundary(scene, p, 0.05 * pixel); }, 1000);
  }
}

TEST_CASE("coarse bounce: a pixel's value depends on its grid place alone" * per_isa()) {
  Scene scene = coarse_scene(4);
  Renderer whole;
  REQUIRE(whole.set_scene(scene).ok());
  std::vector<float> full(static_cast<std::size_t>(scene.width) * scene.height * 3);
  REQUIRE(whole.render(ImageView{full.data(), scene.width, scene.height, scene.width * 3}).ok());
  Renderer moved;
  REQUIRE(moved.set_scene(scene).ok());
  REQUIRE(moved.set_view_offset(5, 3).ok());
  std::vector<float> part(full.size());
  REQUIRE(moved.render(ImageView{part.data(), scene.width, scene.height, scene.width * 3}).ok());
  int compared = 0;
  for (int j = 0; j + 3 < scene.height; ++j)
    for (int i = 0; i + 5 < scene.width; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::size_t a = (static_cast<std::size_t>(j + 3) * scene.width + i + 5) * 3 + c;
        const std::size_t b = (static_cast<std::size_t>(j) * scene.width + i) * 3 + c;
        CHECK_MESSAGE(full[a] == part[b], "pixel " << i << ", " << j);
        ++compared;
      }
  CHECK(compared > 0);
}

TEST_CASE("coarse bounce: bounce.step in scene files and the C API") {
  const std::string base = R"({"width": 8, "height": 8, "lights": [], "occluders": [], "bounce": )";
  Scene scene;
  REQUIRE(parse_scene(base + R"({"piece": 2, "step": 4}})", "t.json", scene).ok());
  CHECK(scene.bounce.step == 4);
  CHECK(scene.bounce.piece == 2.0);
  for (const char* bad : {R"({"step": 0})", R"({"step": 65})", R"({"step": 2.5})", R"({"step": "4"})"}) {
    CAPTURE(bad);
    Scene refused;
    const Status status = parse_scene(base + bad + "}", "t.json", refused);
    CHECK_FALSE(status.ok());
    CHECK(status.message().find("bounce.step") != std::string::npos);
  }
  // Written and read back.
  scene.bounce.step = 6;
  Scene again;
  REQUIRE(parse_scene(scene_to_json(scene), "t.json", again).ok());
  CHECK(again.bounce.step == 6);

  par2d_renderer* r = nullptr;
  REQUIRE(par2d_renderer_create(nullptr, &r) == PAR2D_OK);
  int step = 0;
  CHECK(par2d_get_bounce_step(r, &step) == PAR2D_OK);
  CHECK(step == 1);
  CHECK(par2d_set_bounce_step(r, 8) == PAR2D_OK);
  CHECK(par2d_set_bounce(r, 3.0) == PAR2D_OK);  // keeps the step
  CHECK(par2d_get_bounce_step(r, &step) == PAR2D_OK);
  CHECK(step == 8);
  CHECK(par2d_set_bounce_step(r, 65) != PAR2D_OK);
  CHECK(par2d_set_bounce_step(r, 0) != PAR2D_OK);
  CHECK(par2d_get_bounce_step(r, &step) == PAR2D_OK);
  CHECK(step == 8);
  double piece = 0;
  CHECK(par2d_get_bounce(r, &piece) == PAR2D_OK);
  CHECK(piece == 3.0);
  par2d_renderer_destroy(r);
}

}  // namespace par2d::test

namespace par2d::test {

TEST_CASE("coarse bounce: a node is shaded with its own pixel's normal") {
  // A normal map of varied in-plane slopes: on a node row, pixels between two nodes that both
  // see them blend the nodes' exact bounce as the exact (step 1) frame has it at those nodes,
  // each shaded by its own normal, not by the pixel's.
  Scene scene = coarse_scene(4);
  NormalMap map;
  map.width = scene.width;
  map.height = scene.height;
  map.normals.resize(static_cast<std::size_t>(scene.width) * scene.height * 3);
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) {
      const double a = 0.7 * i + 1.3 * j;
      const double nx = 0.8 * std::cos(a), ny = 0.8 * std::sin(a), nz = 0.6;
      float* n = &map.normals[(static_cast<std::size_t>(j) * scene.width + i) * 3];
      n[0] = static_cast<float>(nx);
      n[1] = static_cast<float>(ny);
      n[2] = static_cast<float>(nz);
    }
  scene.normal_map = map;
  RenderOptions options = options_for(Backend::scalar);
  options.bounce = BounceTerm::only;
  const RenderedImage coarse = render_or_fail(scene, options);
  Scene exact_scene = scene;
  exact_scene.bounce.step = 1;
  const RenderedImage exact = render_or_fail(exact_scene, options);
  const double e_max = emission_max_sum(scene);
  auto at = [&](const RenderedImage& img, int i, int j, int c) {
    return static_cast<double>(img.pixels[(static_cast<std::size_t>(j) * scene.width + i) * 3 + c]);
  };
  int checked = 0;
  double worst = 0.0;
  for (int j = 0; j < scene.height; j += 4)
    for (int i = 0; i + 4 < scene.width; ++i) {
      if (i % 4 == 0) continue;
      const int n0 = i / 4 * 4;
      const Vec2 x = world_at(scene, i + 0.5, j + 0.5);
      const Vec2 a = world_at(scene, n0 + 0.5, j + 0.5), b = world_at(scene, n0 + 4.5, j + 0.5);
      double clear = 1e300;
      for (const Occluder& o : scene.occluders)
        clear = std::min({clear, clearance(o.shape, x, a), clearance(o.shape, x, b)});
      if (clear <= 1e-6) continue;  // a node hidden (or nearly): not the blend this case checks
      const double f = (i - n0) / 4.0;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(at(coarse, i, j, c) - ((1 - f) * at(exact, n0, j, c) + f * at(exact, n0 + 4, j, c))) / e_max);
      ++checked;
    }
  MESSAGE(checked << " pixels between two seen nodes; worst " << worst << " e_max");
  CHECK(checked > 100);
  CHECK(worst <= 1e-6);
}

}  // namespace par2d::test
