// Slanted segments, polygons and circles far larger than the view (extents 1e3 to 1e307):
// the scalar reference against closed forms and the ray caster, the SIMD path (every ISA,
// culling on and off) against the scalar reference. Every shape is exact in double: lines
// through the origin with slope 3/8 and circles of center (3K, -4K) and radius 5K through
// the origin, so that the part near the view is known without cancellation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "raycast/raycast_renderer.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
const double kExtents[] = {1e3, 1e6, 1e10, 1e17, 1e25, 1e30, 1e38, 1e41, 1e60, 1e100, 1e200, 1e300, 1e307};

// A power of two: the largest coordinate of a scene built from it is below the extent.
double unit_for(double extent) { return std::ldexp(1.0, std::ilogb(extent) - 3); }

// 16 x 16 pixels, one unit each, around the origin, which every huge shape's boundary passes.
Scene blank() {
  Scene s;
  s.width = 16;
  s.height = 16;
  s.view = View{-4.0, -6.0, 12.0, 10.0};
  return s;
}

Light light_of(Shape shape) {
  Light l;
  l.shape = std::move(shape);
  l.color = {1.0, 0.7, 0.4};
  l.intensity = 1.0;
  return l;
}

// Signed distance of p from the line 3x - 8y = 0 (positive below it, where y < 3x/8).
double below_line(Vec2 p) { return (3.0 * p.x - 8.0 * p.y) / std::sqrt(73.0); }

// Signed distance of p from the circle of center (3K, -4K), radius 5K (negative inside), in
// a form without cancellation: |p - c|^2 - 25K^2 = |p|^2 + K (8 p.y - 6 p.x).
double from_circle(Vec2 p, double k) {
  const double px = p.x / k, py = p.y / k;  // scaled: K up to 2^1016 squared would overflow
  const double power = (p.x * px + p.y * py) + (8.0 * p.y - 6.0 * p.x);
  const double dist = std::hypot(px - 3.0, py + 4.0) + 5.0;
  return power / dist;
}

// A circle light (center c, radius 1) seen whole from p: color * asin(1 / d) / pi.
double open_circle(const Scene& s, Vec2 c, Vec2 p, int channel) {
  const double d = std::hypot(p.x - c.x, p.y - c.y);
  return s.lights[0].color[static_cast<std::size_t>(channel)] * (d <= 1.0 ? 1.0 : std::asin(1.0 / d) / kPi);
}

std::string named(const char* what, double extent) {
  std::ostringstream s;
  s << what << " at extent " << extent;
  return s.str();
}

// Pixels at least `margin` pixels from every boundary: `boundary(p)` gives the distance to
// the huge shape's boundary near the view (exact), the small shapes are checked directly.
struct Exempt {
  std::function<double(Vec2)> huge;
  double margin = 0.05;
  bool operator()(const Scene& s, Vec2 p) const {
    if (std::abs(huge(p)) <= margin) return true;
    Scene small = s;
    auto is_small = [](const Shape& shape) {
      if (const auto* c = std::get_if<Circle>(&shape)) return c->radius < 1e3;
      if (const auto* g = std::get_if<Segment>(&shape)) return std::abs(g->a.x) + std::abs(g->b.x) < 1e3;
      return false;
    };
    small.lights.erase(std::remove_if(small.lights.begin(), small.lights.end(),
                                      [&](const Light& l) { return !is_small(l.shape); }),
                       small.lights.end());
    small.occluders.erase(std::remove_if(small.occluders.begin(), small.occluders.end(),
                                         [&](const Occluder& o) { return !is_small(o.shape); }),
                          small.occluders.end());
    return near_boundary(small, p, margin);
  }
};

// The scalar reference against the ray caster (4096 rays: section 5's bound plus the
// stratification bound) and, where given, a closed form to 1e-6 e_max.
void check_scalar(const Scene& scene, const std::string& what, const Exempt& exempt,
                  const std::function<double(Vec2, int)>& closed = nullptr) {
  REQUIRE(validate_scene(scene).ok());
  const RenderedImage ref = render_or_fail(scene, options_for(Backend::scalar));
  const par2d::detail::RaycastRenderer caster(scene);
  constexpr int kRays = 4096;
  const Rgb bound = stratification_bound(scene, kRays, false);
  const double e_max = emission_max_sum(scene);
  int checked = 0, over_ray = 0, over_closed = 0;
  std::string first_ray, first_closed;
  Exempt tight = exempt;
  tight.margin = 1e-6;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      if (tight(scene, p)) continue;
      ++checked;
      const Rgb ray = caster.irradiance(p, kRays, 0.5);
      for (int c = 0; c < 3; ++c) {
        const double got = ref.at(i, j, c);
        if (!(std::abs(got - ray[c]) <= bound[c]) && over_ray++ == 0) {
          std::ostringstream s;
          s << "pixel (" << i << ", " << j << ") channel " << c << ": scalar " << got << ", ray caster " << ray[c];
          first_ray = s.str();
        }
        if (!closed) continue;
        const double want = closed(p, c);
        if (!(std::abs(got - want) <= 1e-6 * e_max) && over_closed++ == 0) {
          std::ostringstream s;
          s << "pixel (" << i << ", " << j << ") channel " << c << ": scalar " << got << ", closed form " << want;
          first_closed = s.str();
        }
      }
    }
  }
  INFO(what << " checked=" << checked);
  CHECK_MESSAGE(over_ray == 0, "against the ray caster: " << over_ray << " values, first " << first_ray);
  CHECK_MESSAGE(over_closed == 0, "against the closed form: " << over_closed << " values, first " << first_closed);
  CHECK(checked >= scene.width * scene.height / 2);
}

// The SIMD path on every ISA, culling on and off, within 1e-4 e_max of the scalar reference
// away from 0.05 pixel of every boundary.
void check_simd(const Scene& scene, const std::string& what, const Exempt& exempt) {
  check_simd_against_scalar(scene, render_or_fail(scene, options_for(Backend::scalar)), what,
                            [&](Vec2 p) { return exempt(scene, p); }, scene.width * scene.height / 2);
}

}  // namespace

namespace {

// Every other extent of kExtents, from `first`: the default tier takes the even ones, the
// long tier the odd ones.
void check_huge_slanted(std::size_t first) {
  for (std::size_t e = first; e < std::size(kExtents); e += 2) {
    const double extent = kExtents[e];
    const double d = unit_for(extent);
    const Vec2 a{-8.0 * d, -3.0 * d}, b{8.0 * d, 3.0 * d};  // on the line 3x = 8y
    const Exempt line{[](Vec2 p) { return below_line(p); }};
    {
      // A wall along the line; the light above it: dark below, the whole light above.
      Scene s = blank();
      const Vec2 c{6.0, 8.0};
      s.lights.push_back(light_of(Circle{c, 1.0}));
      s.occluders.push_back(Occluder{Segment{a, b}});
      const std::string what = named("slanted segment wall", extent);
      check_scalar(s, what, line, [&](Vec2 p, int ch) { return below_line(p) > 0.0 ? 0.0 : open_circle(s, c, p, ch); });
      check_simd(s, what, line);
    }
    {
      // A triangle filling the side above the line; the light below.
      Scene s = blank();
      const Vec2 c{6.0, -3.0};
      s.lights.push_back(light_of(Circle{c, 1.0}));
      s.occluders.push_back(Occluder{Polygon{{a, b, {-8.0 * d, 3.0 * d}}}});
      const std::string what = named("slanted triangle occluder", extent);
      check_scalar(s, what, line, [&](Vec2 p, int ch) { return below_line(p) < 0.0 ? 0.0 : open_circle(s, c, p, ch); });
      check_simd(s, what, line);
    }
    {
      // A triangle light filling the side below the line, a short wall above it.
      Scene s = blank();
      s.lights.push_back(light_of(Polygon{{a, {8.0 * d, -3.0 * d}, b}}));
      s.occluders.push_back(Occluder{Segment{{-2.0, 7.0}, {4.0, 6.0}}});
      const std::string what = named("slanted triangle light", extent);
      check_scalar(s, what, line);
      check_simd(s, what, line);
    }
    {
      // A segment light along the line, a short wall above it.
      Scene s = blank();
      s.lights.push_back(light_of(Segment{a, b}));
      s.occluders.push_back(Occluder{Segment{{-2.0, 7.0}, {4.0, 6.0}}});
      const std::string what = named("slanted segment light", extent);
      check_scalar(s, what, line);
      check_simd(s, what, line);
    }
  }
}

}  // namespace

TEST_CASE("huge slanted segments and polygons: scalar against closed forms and the ray caster, SIMD against scalar") {
  check_huge_slanted(0);
}

TEST_CASE("huge slanted segments and polygons at the other extents" * par2d::test::long_tier()) {
  check_huge_slanted(1);
}

TEST_CASE("huge circles through the view: scalar against closed forms and the ray caster, SIMD against scalar") {
  for (double extent : kExtents) {
    const double k = unit_for(extent);
    const Circle huge{{3.0 * k, -4.0 * k}, 5.0 * k};
    const Exempt edge{[k](Vec2 p) { return from_circle(p, k); }};
    {
      // A huge circle occluder; the light outside it: dark inside, the whole light outside
      // (the disc lies in the half-plane 3x - 4y >= 0, the light and every outside pixel
      // near the view on the other side of its tangent or as near as the view allows).
      Scene s = blank();
      const Vec2 c{-2.0, 6.0};
      s.lights.push_back(light_of(Circle{c, 1.0}));
      s.occluders.push_back(Occluder{huge});
      const std::string what = named("huge circle occluder", extent);
      const bool curved = extent < 1e5;  // the circle departs from its tangent in the view
      check_scalar(s, what, edge,
                   curved ? std::function<double(Vec2, int)>()
                          : [&](Vec2 p, int ch) { return from_circle(p, k) < 0.0 ? 0.0 : open_circle(s, c, p, ch); });
      check_simd(s, what, edge);
    }
    {
      // A huge circle light, a short wall outside it.
      Scene s = blank();
      s.lights.push_back(light_of(huge));
      s.occluders.push_back(Occluder{Segment{{-3.0, 6.0}, {2.0, 7.0}}});
      const std::string what = named("huge circle light", extent);
      check_scalar(s, what, edge);
      check_simd(s, what, edge);
    }
  }
}

TEST_CASE("huge shapes whose boundary passes 2^6 to 2^40 pixels from the view: SIMD against scalar, scalar against rays") {
  // The SIMD tile setup clips shapes reaching far from a tile to a box around it. A box of
  // fixed size (2^18 pixels) cut a half-plane light whose edge passed 2^17 pixels away down to
  // a strip, seen 8 % of the emission smaller; a huge circle light 1e106 pixels off was 2 %
  // short. Each shape's boundary runs along the line 3x - 8y = 8H (2^k pixels below the
  // origin), out to 2^(k + span) pixels both ways, where the shapes are exact in double; a
  // huge circle's nearest point is H below the origin.
  for (int k : {6, 12, 17, 24, 33, 40}) {
    for (int span : {40, 50}) {
      const double h = std::ldexp(1.0, k), d = std::ldexp(1.0, k + span);
      const Vec2 a{-8.0 * d, -3.0 * d - h}, b{8.0 * d, 3.0 * d - h}, c{8.0 * d, -3.0 * d - h};
      // Only the short wall's ends and line are boundaries near the view.
      const Exempt wall{[](Vec2) { return 1e300; }};
      const Occluder short_wall{Segment{{-2.0, 7.0}, {4.0, 6.0}}};
      std::ostringstream tag;
      tag << ": 2^" << k << " pixels below the view, 2^" << k + span << " long";
      {
        Scene s = blank();
        s.lights.push_back(light_of(Polygon{{a, c, b}}));
        s.occluders.push_back(short_wall);
        check_scalar(s, "half-plane light" + tag.str(), wall);
        check_simd(s, "half-plane light" + tag.str(), wall);
      }
      {
        Scene s = blank();
        s.lights.push_back(light_of(Segment{a, b}));
        s.occluders.push_back(short_wall);
        check_simd(s, "segment light" + tag.str(), wall);
      }
      {
        // A strip occluder along the line, 2^k thick, in front of a half-plane light below
        // it: every ray to the light crosses the strip, so the scene is dark.
        Scene s = blank();
        auto down = [h](Vec2 p, double times) { return Vec2{p.x, p.y - times * h}; };
        s.occluders.push_back(Occluder{Polygon{{down(a, 1.0), down(b, 1.0), b, a}}});
        s.lights.push_back(light_of(Polygon{{down(a, 3.0), down(c, 3.0), down(b, 3.0)}}));
        check_simd(s, "strip occluder over a half-plane light" + tag.str(), wall);
      }
      {
        Scene s = blank();
        s.lights.push_back(light_of(Circle{{0.0, -(h + 4.0 * d)}, 4.0 * d}));
        s.occluders.push_back(short_wall);
        check_simd(s, "huge circle light" + tag.str(), wall);
      }
    }
  }
}

TEST_CASE("overlapping many-gons: boundary crossings and render match the all-pairs answer and the ray caster") {
  // Edge pairs are indexed by x-monotone runs above 4096 pairs: the crossings must be those
  // of every edge pair (generic position, so each crossing is one proper intersection).
  auto ngon = [](double cx, double cy, double r, int count, double phase) {
    Polygon p;
    for (int k = 0; k < count; ++k) {
      const double a = phase + 2.0 * kPi * k / count;
      p.vertices.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    }
    return p;
  };
  for (int n : {90, 300, 1200}) {
    const Polygon pa = ngon(8.0, 8.0, 5.0, n, 0.0), pb = ngon(8.7, 7.6, 4.6, n * 3 / 4, 0.3);
    const auto a = par2d::detail::make_convex_shape(pa), b = par2d::detail::make_convex_shape(pb);
    std::vector<Vec2> got;
    par2d::detail::boundary_intersections(a, b, got);
    std::vector<Vec2> want;
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
      for (std::size_t j = 0; j < b.vertices.size(); ++j) {
        const Vec2 p = a.vertices[i], q = a.vertices[(i + 1) % a.vertices.size()];
        const Vec2 r = b.vertices[j], s = b.vertices[(j + 1) % b.vertices.size()];
        const double ex = q.x - p.x, ey = q.y - p.y, fx = s.x - r.x, fy = s.y - r.y;
        const double den = ex * fy - ey * fx;
        if (den == 0.0) continue;
        const double t = ((r.x - p.x) * fy - (r.y - p.y) * fx) / den, u = ((r.x - p.x) * ey - (r.y - p.y) * ex) / den;
        if (t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0) want.push_back({p.x + t * ex, p.y + t * ey});
      }
    auto by_xy = [](Vec2 l, Vec2 r) { return l.x < r.x || (l.x == r.x && l.y < r.y); };
    std::sort(got.begin(), got.end(), by_xy);
    std::sort(want.begin(), want.end(), by_xy);
    INFO("n = " << n);
    REQUIRE(got.size() == want.size());
    CHECK(want.size() >= 2);
    for (std::size_t k = 0; k < got.size(); ++k)
      CHECK(std::hypot(got[k].x - want[k].x, got[k].y - want[k].y) <= 1e-12);
    CHECK(par2d::detail::shape_distance(a, b) == 0.0);
  }
  // The render: a 1200-gon light and a 900-gon occluder overlapping, against the ray caster
  // (overlapping bound: every boundary crossing is a visibility change).
  Scene s = blank();
  s.lights.push_back(light_of(ngon(4.0, 2.0, 5.0, 1200, 0.0)));
  s.occluders.push_back(Occluder{ngon(4.7, 1.6, 4.6, 900, 0.3)});
  REQUIRE(validate_scene(s).ok());
  const RenderedImage ref = render_or_fail(s, options_for(Backend::scalar));
  const par2d::detail::RaycastRenderer caster(s);
  constexpr int kRays = 4096;
  const Rgb bound = stratification_bound(s, kRays, true);
  int checked = 0;
  for (int j = 0; j < s.height; ++j)
    for (int i = 0; i < s.width; ++i) {
      const Vec2 p = pixel_center(s, i, j);
      if (near_boundary(s, p, 1e-6)) continue;
      ++checked;
      const Rgb ray = caster.irradiance(p, kRays, 0.5);
      for (int c = 0; c < 3; ++c)
        CHECK_MESSAGE(std::abs(ref.at(i, j, c) - ray[c]) <= bound[c], "pixel " << i << "," << j << " channel " << c);
    }
  CHECK(checked >= s.width * s.height / 2);
}

TEST_CASE("fuzz_huge findings, huge lights seen from views off the origin: SIMD against scalar") {
  // Each found by fuzz_huge (tests/fuzz/FINDINGS.md #7), one light each:
  // - a band light 5e8 pixels across: the tile setup clipped shapes only beyond 2^40 pixels,
  //   so the kernel got its vertices 5e8 units away in float, tens of units off, and the edge
  //   passing half a pixel from the view moved (scalar 0.609, SIMD 0.457 at pixel (0, 5));
  // - a band light 1e217 across whose edge passes 100 units from the view: clipped with its
  //   edge line's offset n.a formed from vertices 1e217 away, the line moved by 1e201
  //   (scalar 0.656, SIMD 1.3125);
  // - a circle light of radius 1e127 (1e122 pixels) whose boundary passes 1e106 pixels from
  //   the view: capped to a radius of 2^59 pixels at 2^50 pixels off, it subtended 0.125 rad
  //   less than the half-plane it looks like (scalar 1.09375, SIMD 1.0466);
  // - a triangle light 20 pixels across at 1e202: its one differing pixel (scalar 1.14,
  //   SIMD 0.57) is centered on an edge (within rounding), which the contract exempts.
  for (const char* name : {"simd_band_light_5e8_pixels_off_origin.json", "simd_band_light_1e217_edge_100_units_off.json",
                           "simd_circle_light_radius_1e127_1e106_pixels_off.json",
                           "simd_triangle_light_view_at_1e202.json"}) {
    Scene scene;
    const std::string path = std::string(PAR2D_SOURCE_DIR) + "/tests/fuzz/corpus/huge/" + name;
    REQUIRE(load_scene_file(path, scene).ok());
    REQUIRE(scene.lights.size() == 1);
    REQUIRE(scene.occluders.empty());
    const double pixel = std::abs(scene.view.x1 - scene.view.x0) / scene.width;
    const Shape light = scene.lights[0].shape;
    check_simd(scene, name, Exempt{[&](Vec2 p) { return distance_to_boundary(light, p) / pixel; }});
  }
}
