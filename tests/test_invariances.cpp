// Scalar renderer: the image must not depend on how the same scene is written down.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "support/random_scenes.hpp"

namespace par2d::test {
namespace {

RenderedImage render_scalar(const Scene& scene) {
  RenderOptions options;
  options.backend = Backend::scalar;
  options.threads = 2;
  Status status;
  RenderedImage image = render_image(scene, options, status);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
}

// The scenes every invariance is checked on: default, far from the origin, mirrored,
// and with overlapping occluders; lights disjoint from occluders (docs/contract.md section 5).
Scene invariance_scene(std::uint32_t seed) {
  RandomSceneOptions o;
  o.width = 32;
  o.height = 24;
  o.max_lights = 3;
  o.max_occluders = 8;
  switch (seed % 4) {
    case 1: o.view = View{1e5, 1e5, 1e5 + 32, 1e5 + 24}; break;
    case 2: o.view = View{32, 24, 0, 0}; break;
    case 3: o.view = View{-40, -30, 88, 66}; break;
    default: break;
  }
  return random_scene(seed, o);
}

// |a - b| <= 1e-6 * e_max at every pixel of `reference_scene` farther than 1e-6 pixel
// widths from every boundary; `map(i, j)` gives the pixel of b that shows a's (i, j).
void check_same_image(const Scene& reference_scene, const RenderedImage& a, const RenderedImage& b,
                      const std::function<std::pair<int, int>(int, int)>& map = nullptr) {
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  const double tol = 1e-6 * emission_max_sum(reference_scene);
  const double skip = 1e-6 * pixel_width(reference_scene);
  double worst = -1.0;
  std::string where;
  for (int j = 0; j < a.height; ++j) {
    for (int i = 0; i < a.width; ++i) {
      if (near_boundary(reference_scene, pixel_center(reference_scene, i, j), skip)) continue;
      const auto [bi, bj] = map ? map(i, j) : std::pair<int, int>{i, j};
      for (int c = 0; c < 3; ++c) {
        const double err = std::fabs(static_cast<double>(a.at(i, j, c)) - b.at(bi, bj, c));
        if (err > worst) {
          worst = err;
          std::ostringstream s;
          s.precision(10);
          s << "pixel (" << i << ", " << j << ") channel " << c << ": " << a.at(i, j, c) << " vs "
            << b.at(bi, bj, c);
          where = s.str();
        }
      }
    }
  }
  INFO("worst: " << where << " (tolerance " << tol << ")");
  CHECK(worst <= tol);
}

template <class F>
void for_each_polygon(Scene& scene, F&& f) {
  for (auto& l : scene.lights)
    if (auto* p = std::get_if<Polygon>(&l.shape)) f(*p);
  for (auto& o : scene.occluders)
    if (auto* p = std::get_if<Polygon>(&o.shape)) f(*p);
}

int polygon_count(Scene scene) {
  int n = 0;
  for_each_polygon(scene, [&](Polygon&) { ++n; });
  return n;
}

constexpr std::uint32_t kFirstSeed = 300;
constexpr std::uint32_t kSeeds = 12;

}  // namespace

TEST_CASE("reversing polygon winding leaves the image unchanged") {
  int polygons = 0;
  for (std::uint32_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    CAPTURE(seed);
    const Scene scene = invariance_scene(seed);
    Scene reversed = scene;
    for_each_polygon(reversed, [](Polygon& p) { std::reverse(p.vertices.begin(), p.vertices.end()); });
    polygons += polygon_count(scene);
    check_same_image(scene, render_scalar(scene), render_scalar(reversed));
  }
  CHECK(polygons > 10);  // the check is not vacuous
}

TEST_CASE("rotating polygon vertex lists leaves the image unchanged") {
  for (std::uint32_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    CAPTURE(seed);
    const Scene scene = invariance_scene(seed);
    Scene rotated = scene;
    int k = 0;
    for_each_polygon(rotated, [&](Polygon& p) {
      const std::size_t shift = 1 + static_cast<std::size_t>(k++) % (p.vertices.size() - 1);
      std::rotate(p.vertices.begin(), p.vertices.begin() + static_cast<std::ptrdiff_t>(shift), p.vertices.end());
    });
    check_same_image(scene, render_scalar(scene), render_scalar(rotated));
  }
}

TEST_CASE("translating scene and view together leaves the image unchanged") {
  const Vec2 shift{1000.0, -2000.0};
  auto move = [&](Vec2& v) {
    v.x += shift.x;
    v.y += shift.y;
  };
  auto move_shape = [&](Shape& shape) {
    if (auto* p = std::get_if<Polygon>(&shape))
      for (Vec2& v : p->vertices) move(v);
    else if (auto* c = std::get_if<Circle>(&shape))
      move(c->center);
    else if (auto* s = std::get_if<Segment>(&shape)) {
      move(s->a);
      move(s->b);
    }
  };
  for (std::uint32_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    CAPTURE(seed);
    const Scene scene = invariance_scene(seed);
    Scene moved = scene;
    for (auto& l : moved.lights) move_shape(l.shape);
    for (auto& o : moved.occluders) move_shape(o.shape);
    moved.view = {scene.view.x0 + shift.x, scene.view.y0 + shift.y, scene.view.x1 + shift.x, scene.view.y1 + shift.y};
    // Translation rounds coordinates, so pixels right at a boundary may flip: the
    // near-boundary exemption (checked on the original scene) covers them.
    check_same_image(scene, render_scalar(scene), render_scalar(moved));
  }
}

TEST_CASE("permuting lights and occluders leaves the image unchanged") {
  for (std::uint32_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    CAPTURE(seed);
    const Scene scene = invariance_scene(seed);
    Scene permuted = scene;
    std::reverse(permuted.lights.begin(), permuted.lights.end());
    // A seeded Fisher-Yates shuffle with the portable generator, not std::shuffle.
    PortableRandom rng(seed);
    for (int k = static_cast<int>(permuted.occluders.size()) - 1; k > 0; --k)
      std::swap(permuted.occluders[static_cast<std::size_t>(k)],
                permuted.occluders[static_cast<std::size_t>(rng.integer(0, k))]);
    check_same_image(scene, render_scalar(scene), render_scalar(permuted));
  }
}

TEST_CASE("mirroring the view mirrors the image") {
  for (std::uint32_t seed = kFirstSeed; seed < kFirstSeed + kSeeds; ++seed) {
    CAPTURE(seed);
    RandomSceneOptions o;
    o.width = 32;
    o.height = 24;
    const Scene scene = random_scene(seed, o);
    Scene mirrored = scene;
    mirrored.view = {scene.view.x1, scene.view.y1, scene.view.x0, scene.view.y0};
    // Pixel (i, j) of the mirrored view has its center exactly at pixel
    // (W-1-i, H-1-j) of the original one.
    check_same_image(scene, render_scalar(scene), render_scalar(mirrored),
                     [&](int i, int j) { return std::pair<int, int>{scene.width - 1 - i, scene.height - 1 - j}; });
  }
}

}  // namespace par2d::test
