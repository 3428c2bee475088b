// Shapes far larger than the view (extents 1e3 to 1e307, as far as the contract accepts
// coordinates) on the SIMD path, every ISA forced in turn, against the scalar reference;
// pins the values of the cases that used to come out wrong (lit shadows, dark lights).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "par2d/render.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"

using namespace par2d;
using namespace par2d::test;
using par2d::detail::kPi;

namespace {

const double kExtents[] = {1e3, 1e6, 1e10, 1e17, 1e25, 1e30, 1e38, 1e41, 1e60, 1e100, 1e200, 1e300, 1e307};

Scene blank() {
  Scene s;
  s.width = 16;
  s.height = 16;
  s.view = View{0.0, 0.0, 16.0, 16.0};
  return s;
}

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

Light light_of(Shape shape) {
  Light l;
  l.shape = std::move(shape);
  l.color = {1.0, 0.7, 0.4};
  l.intensity = 1.0;
  return l;
}

// The contract's SIMD bound (1e-4 e_max away from 0.05 pixel of every boundary), for every
// ISA with culling on and off (unless !against_scalar); `pin(i, j, channel, value)` checks
// each SIMD pixel further.
void check_far_scene(const Scene& scene, const std::string& what, bool against_scalar,
                     const std::function<void(int, int, int, float)>& pin = nullptr) {
  REQUIRE(validate_scene(scene).ok());
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  const double exempt = 0.05 * pixel_width(scene);
  const auto pin_all = [&](const RenderedImage& got) {
    if (!pin) return;
    for (int j = 0; j < scene.height; ++j)
      for (int i = 0; i < scene.width; ++i)
        for (int c = 0; c < 3; ++c) pin(i, j, c, got.at(i, j, c));
  };
  // Near a huge circle the double boundary test exempts more pixels; a quarter must remain.
  check_simd_against_scalar(
      scene, ref, what, [&](Vec2 p) { return !against_scalar || near_boundary(scene, p, exempt); },
      against_scalar ? scene.width * scene.height / 4 : 0, pin_all);
}

std::string named(const char* what, double extent) {
  std::ostringstream s;
  s << what << " at extent " << extent;
  return s.str();
}

}  // namespace

TEST_CASE("a wall far longer than the view shadows everything behind it on the SIMD path, extents 1e3 to 1e307") {
  // The scene: rows 12 and below (pixel centers at y >= 12.5) lie behind the wall y = 12.
  for (double extent : kExtents) {
    Scene s = blank();
    s.lights.push_back(light_of(Circle{{8.0, 4.0}, 1.0}));
    s.occluders.push_back(Occluder{Segment{{-extent, 12.0}, {extent, 12.0}}});
    check_far_scene(s, named("segment wall", extent), true, [&](int, int j, int, float v) {
      if (j >= 12) CHECK_MESSAGE(v == 0.0f, named("segment wall", extent) << " row " << j);
    });
    // The same wall as a polygon reaching down to the extent (pixels behind it are inside).
    Scene p = blank();
    p.lights.push_back(light_of(Circle{{8.0, 4.0}, 1.0}));
    p.occluders.push_back(Occluder{box(-extent, 12.0, extent, extent)});
    p.occluders.push_back(Occluder{Segment{{-extent, 1.25}, {extent, 1.25}}});
    check_far_scene(p, named("polygon wall", extent), true, [&](int, int j, int, float v) {
      if (j >= 12 || j <= 0) CHECK_MESSAGE(v == 0.0f, named("polygon wall", extent) << " row " << j);
    });
  }
}

// The light circle (12, 4) of radius 1, seen whole: E = color * asin(r / d) / pi (all of
// its color inside it).
double open_circle_light(const Scene& s, int i, int j, int c) {
  const double d = std::hypot(i + 0.5 - 12.0, j + 0.5 - 4.0);
  return s.lights[0].color[static_cast<std::size_t>(c)] * (d < 1.0 ? 1.0 : std::asin(1.0 / d) / kPi);
}

bool near_light(int i, int j) { return std::abs(std::hypot(i + 0.5 - 12.0, j + 0.5 - 4.0) - 1.0) <= 0.05; }

TEST_CASE("a diagonal wall far longer than the view: dark behind it, the closed form in front") {
  // The line y = x through the origin is exact at every extent; the light lies below it, wholly
  // on one side, so below the line it is seen whole and above it not at all. Against the
  // scalar reference too, at every extent (its segment tests once cancelled for a slanted
  // segment 1e17 long and lit pixels above the line).
  for (double extent : kExtents) {
    Scene s = blank();
    s.lights.push_back(light_of(Circle{{12.0, 4.0}, 1.0}));
    s.occluders.push_back(Occluder{Segment{{-extent, -extent}, {extent, extent}}});
    const std::string what = named("diagonal wall", extent);
    check_far_scene(s, what, true, [&](int i, int j, int c, float v) {
      if (std::abs(j - i) * std::sqrt(0.5) <= 0.05 || near_light(i, j)) return;
      const double want = j > i ? 0.0 : open_circle_light(s, i, j, c);
      CHECK_MESSAGE(std::abs(v - want) <= 1e-4, what << " pixel " << i << "," << j << ": " << v << " want " << want);
    });
    // A triangle filling y > x up to the extent: its long edge lies on the same line.
    Scene t = blank();
    t.lights.push_back(light_of(Circle{{12.0, 4.0}, 1.0}));
    t.occluders.push_back(Occluder{Polygon{{{-extent, -extent}, {extent, extent}, {-extent, extent}}}});
    const std::string twhat = named("diagonal triangle", extent);
    check_far_scene(t, twhat, true, [&](int i, int j, int c, float v) {
      if (std::abs(j - i) * std::sqrt(0.5) <= 0.05 || near_light(i, j)) return;
      const double want = j > i ? 0.0 : open_circle_light(t, i, j, c);
      CHECK_MESSAGE(std::abs(v - want) <= 1e-4, twhat << " pixel " << i << "," << j << ": " << v << " want " << want);
    });
  }
}

TEST_CASE("segment, polygon and circle lights far larger than the view give half their emission in the open") {
  // Each light is the half-plane y < 0 seen from the view, up to its extent: from a point at
  // height y the open light spans pi - 2 atan(y / extent), so E -> emission / 2. A short
  // occluder at y = 8 shadows part of the rows below it; rows above see the whole light.
  // Against scalar at every extent (the scalar's distances to a circle of radius 1e17 and
  // beyond once cancelled), and the closed form pinned too.
  for (double extent : kExtents) {
    // A circle through the origin: center (8, -R), radius R, with R a power of two (exact).
    const double radius = std::ldexp(1.0, std::ilogb(extent));
    const Shape lights[] = {Segment{{-extent, 0.0}, {extent, 0.0}}, box(-extent, -extent, extent, 0.0),
                            Circle{{8.0, -radius}, radius}};
    const char* names[] = {"segment light", "polygon light", "circle light"};
    for (int k = 0; k < 3; ++k) {
      Scene s = blank();
      s.lights.push_back(light_of(lights[k]));
      s.occluders.push_back(Occluder{Segment{{4.0, 8.0}, {12.0, 8.0}}});
      const std::string what = named(names[k], extent);
      check_far_scene(s, what, true, [&](int, int j, int c, float v) {
        // Between the light and the occluder, at most 8 units from a light at least 1e10 long.
        if (extent >= 1e10 && j < 8) {
          const double want = 0.5 * s.lights[0].color[static_cast<std::size_t>(c)];
          CHECK_MESSAGE(std::abs(v - want) <= 1e-4 * 1.0, what << " row " << j << " channel " << c << ": " << v);
        }
      });
    }
  }
}

TEST_CASE("circle occluders far larger than the view hide nothing in front of them") {
  // Centers (-R, 8) and (8, -R), radius R (a power of two): tangent to the view's left and
  // top edges, filling x < 0 and y < 0. Light and pixels lie in x, y > 0, so every pixel sees
  // the light whole. Against scalar at every extent (its distances to such a circle once
  // cancelled beyond 1e10).
  for (double extent : kExtents) {
    const double radius = std::ldexp(1.0, std::ilogb(extent));
    Scene s = blank();
    s.lights.push_back(light_of(Circle{{12.0, 4.0}, 1.0}));
    s.occluders.push_back(Occluder{Circle{{-radius, 8.0}, radius}});
    s.occluders.push_back(Occluder{Circle{{8.0, -radius}, radius}});
    const std::string what = named("circle occluders", extent);
    check_far_scene(s, what, true, [&](int i, int j, int c, float v) {
      if (near_light(i, j)) return;
      const double want = open_circle_light(s, i, j, c);
      CHECK_MESSAGE(std::abs(v - want) <= 1e-4, what << " pixel " << i << "," << j << ": " << v << " want " << want);
    });
  }
}
