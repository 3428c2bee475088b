// Convex polygons carrying many collinear or nearly collinear vertices: make_convex_shape drops
// the straight ones in linear passes and keeps exactly the vertices the one-at-a-time erasure
// kept (written out below as the reference), and a triangle with 200,000 collinear vertices
// loads, prepares and renders as the triangle.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

// The straight-vertex cleanup as it was (each straight vertex erased on its own, passes
// repeated while one is erased), on vertices already wound counter-clockwise and scaled.
std::vector<Vec2> erase_one_at_a_time(std::vector<Vec2> v) {
  const auto cross = [](Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; };
  for (bool removed = true; removed && v.size() > 3;) {
    removed = false;
    for (std::size_t i = 0; i < v.size() && v.size() > 3; ++i) {
      const Vec2 prev = v[(i + v.size() - 1) % v.size()], next = v[(i + 1) % v.size()];
      const Vec2 e1{v[i].x - prev.x, v[i].y - prev.y}, e2{next.x - v[i].x, next.y - v[i].y};
      if (std::abs(cross(e1, e2)) <= 1e-9 * detail::length(e1) * detail::length(e2)) {
        v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
        removed = true;
        --i;
      }
    }
  }
  return v;
}

double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// A counter-clockwise convex polygon in [-0.5, 0.5]^2 (no rescaling in make_convex_shape) with
// runs of collinear vertices, vertices bent off their edge by turns near the 1e-9 tolerance
// either way (so that erasing one can straighten or bend its neighbours), and repeats.
std::vector<Vec2> collinear_runs(std::mt19937_64& rng) {
  const int corners = 3 + static_cast<int>(rng() % 6);
  std::vector<Vec2> out;
  for (int c = 0; c < corners; ++c) {
    const double a0 = 2.0 * 3.14159265358979323846 * c / corners, a1 = 2.0 * 3.14159265358979323846 * (c + 1) / corners;
    const Vec2 p{0.4 * std::cos(a0), 0.4 * std::sin(a0)}, q{0.4 * std::cos(a1), 0.4 * std::sin(a1)};
    const Vec2 normal{q.y - p.y, p.x - q.x};  // outward
    out.push_back(p);
    const int run = static_cast<int>(rng() % 40);
    for (int k = 1; k <= run; ++k) {
      const double t = static_cast<double>(k) / (run + 1);
      const double bend = (static_cast<int>(rng() % 5) - 2) * 0.4e-9 * uniform(rng) * t * (1.0 - t);
      out.push_back({p.x + t * (q.x - p.x) + bend * normal.x, p.y + t * (q.y - p.y) + bend * normal.y});
      if (rng() % 16 == 0) out.push_back(out.back());
    }
  }
  return out;
}

}  // namespace

TEST_CASE("make_convex_shape drops straight vertices exactly as erasing them one at a time did") {
  std::mt19937_64 rng(20261207);
  int kept_fewer = 0;
  for (int round = 0; round < 400; ++round) {
    const std::vector<Vec2> ring = collinear_runs(rng);
    // The reference runs on the ring make_convex_shape cleans: repeats dropped, counter-clockwise.
    std::vector<Vec2> distinct;
    for (const Vec2 p : ring)
      if (distinct.empty() || p.x != distinct.back().x || p.y != distinct.back().y) distinct.push_back(p);
    while (distinct.size() > 1 && distinct.front().x == distinct.back().x && distinct.front().y == distinct.back().y)
      distinct.pop_back();
    const std::vector<Vec2> expected = erase_one_at_a_time(distinct);
    const detail::ConvexShape shape = detail::make_convex_shape(Polygon{ring});
    CAPTURE(round);
    REQUIRE(shape.vertices.size() == expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      CHECK(shape.vertices[k].x == expected[k].x);
      CHECK(shape.vertices[k].y == expected[k].y);
    }
    if (expected.size() < distinct.size()) ++kept_fewer;
  }
  CHECK(kept_fewer > 300);  // the rings do carry straight vertices
}

TEST_CASE("a triangle light carrying 200,000 collinear vertices renders as the triangle on every backend" * per_isa()) {
  const int n = 200000;
  std::vector<Vec2> v;
  for (int k = 0; k < n; ++k) v.push_back({static_cast<double>(k) / n * 20.0, 0.0});
  v.insert(v.end(), {{20.0, 0.0}, {0.0, 20.0}});
  Scene many;
  many.width = many.height = 16;
  many.view = {-2.0, -2.0, 22.0, 22.0};
  Light light;
  light.shape = Polygon{v};
  many.lights.push_back(light);
  many.occluders.push_back(Occluder{Circle{{12.0, 12.0}, 1.5}});
  REQUIRE(validate_scene(many).ok());
  Scene three = many;
  three.lights[0].shape = Polygon{{{0.0, 0.0}, {20.0, 0.0}, {0.0, 20.0}}};
  RenderOptions o;
  o.threads = 1;
  for (const Backend backend : {Backend::scalar, Backend::simd}) {
    o.backend = backend;
    CAPTURE(backend_name(backend));
    CHECK(same_bits(render_or_fail(many, o).pixels, render_or_fail(three, o).pixels));
  }
  const detail::ConvexShape shape = detail::make_convex_shape(many.lights[0].shape);
  CHECK(shape.vertices.size() == 3);
}

}  // namespace par2d::test
