// Occlusion proofs (culling/occlusion_proof) and light reach (culling/light_reach): closed
// cases, and every proof checked against a brute-force segment test and the scalar reference
// on random scenes with fixed seeds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

#include "culling/occlusion_proof.hpp"
#include "culling/light_reach.hpp"
#include "world/world.hpp"
#include "scalar/scalar_renderer.hpp"
#include "scattered_scene.hpp"
#include "support/random_scenes.hpp"

using namespace par2d;
using namespace par2d::test;
using detail::ConvexShape;

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Whether the open segments ab and cd cross at one point.
bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = orient(c, d, a), d2 = orient(c, d, b), d3 = orient(a, b, c), d4 = orient(a, b, d);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0;
}

bool inside_convex(const std::vector<Vec2>& poly, Vec2 p) {
  int pos = 0, neg = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const double o = orient(poly[i], poly[(i + 1) % poly.size()], p);
    pos += o > 0;
    neg += o < 0;
  }
  return pos == 0 || neg == 0;
}

// Brute force, independent of the library: whether an occluder meets the segment ab
// (random end points, so grazing contacts have probability zero).
bool blocks(const Shape& shape, Vec2 a, Vec2 b) {
  if (const auto* c = std::get_if<Circle>(&shape)) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    double t = ((c->center.x - a.x) * dx + (c->center.y - a.y) * dy) / (dx * dx + dy * dy);
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(a.x + t * dx - c->center.x, a.y + t * dy - c->center.y) < c->radius;
  }
  if (const auto* s = std::get_if<Segment>(&shape)) return segments_cross(a, b, s->a, s->b);
  const auto& v = std::get<Polygon>(shape).vertices;
  if (inside_convex(v, a) || inside_convex(v, b)) return true;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (segments_cross(a, b, v[i], v[(i + 1) % v.size()])) return true;
  return false;
}

// A uniform random point of a light shape (polygon: a random convex combination of a fan triangle).
Vec2 point_in(const Shape& shape, PortableRandom& rng) {
  if (const auto* c = std::get_if<Circle>(&shape)) {
    const double r = c->radius * std::sqrt(rng.uniform()), a = rng.uniform(0.0, 2.0 * kPi);
    return {c->center.x + r * std::cos(a), c->center.y + r * std::sin(a)};
  }
  const auto& v = std::get<Polygon>(shape).vertices;
  const std::size_t k = 1 + static_cast<std::size_t>(rng.integer(0, static_cast<int>(v.size()) - 3));
  double s = rng.uniform(), t = rng.uniform();
  if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
  return {v[0].x + s * (v[k].x - v[0].x) + t * (v[k + 1].x - v[0].x),
          v[0].y + s * (v[k].y - v[0].y) + t * (v[k + 1].y - v[0].y)};
}

Shape random_occluder(PortableRandom& rng, Vec2 c, double size) {
  switch (rng.integer(0, 2)) {
    case 0: return Circle{c, 0.5 * size};
    case 1: {
      const double a = rng.uniform(0.0, kPi), l = size * rng.uniform(1.0, 6.0);
      return Segment{{c.x - l * std::cos(a), c.y - l * std::sin(a)}, {c.x + l * std::cos(a), c.y + l * std::sin(a)}};
    }
    default: {
      Polygon p;
      const int n = rng.integer(3, 6);
      const double start = rng.uniform(0.0, 2.0 * kPi);
      for (int k = 0; k < n; ++k) {
        const double a = start + 2.0 * kPi * (k + rng.uniform(-0.3, 0.3)) / n;
        p.vertices.push_back({c.x + 0.5 * size * std::cos(a), c.y + 0.5 * size * std::sin(a)});
      }
      return p;
    }
  }
}

std::vector<std::uint32_t> all_ids(std::size_t n) {
  std::vector<std::uint32_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<std::uint32_t>(i);
  return ids;
}

// Radians of light l visible from x by the scalar reference, or -1 when x is in an occluder.
double reference_visible(const detail::PreparedScene& scene, std::size_t l, Vec2 x, detail::ScalarScratch& scratch) {
  std::vector<detail::AngularSpan> spans;
  for (const ConvexShape& o : scene.occluders) {
    if (detail::contains(o, x)) return -1.0;
    spans.push_back(detail::angular_span(o, x));
  }
  return detail::visible_measure(scene, l, x, spans, scratch);
}

// A random field: a 10 x 10 rectangle at the origin, a light 40..120 away in a random
// direction, and 4..40 occluders scattered between (some straddling the rectangle or the
// light), or one or two fences across the way.
struct Field {
  Scene scene;
  Shape light_shape;
  Vec2 lc;
  double lr = 0.0;
  std::vector<Vec2> cracks;  // points inside the fences' gaps
};

Field random_field(PortableRandom& rng, int trial) {
  Field field;
  Scene& scene = field.scene;
  std::vector<Vec2>& cracks = field.cracks;
  const double dist = rng.uniform(40.0, 120.0), dir = rng.uniform(0.0, 2.0 * kPi);
  const Vec2 lc = field.lc = {5.0 + dist * std::cos(dir), 5.0 + dist * std::sin(dir)};
  const double lr = field.lr = rng.uniform(1.0, 5.0);
  Shape& light_shape = field.light_shape = Circle{lc, lr};
  if (rng.chance(0.5)) {
    Polygon p;
    for (int k = 0; k < 5; ++k) p.vertices.push_back({lc.x + lr * std::cos(1.2566 * k), lc.y + lr * std::sin(1.2566 * k)});
    light_shape = p;
  }
  scene.width = 10;
  scene.height = 10;
  scene.view = {0, 0, 10, 10};
  scene.lights.push_back(Light{light_shape, {1, 1, 1}, 1.0});
  if (trial % 2 == 0) {
    const int n = rng.integer(4, 40);
    for (int k = 0; k < n; ++k) {
      const double t = rng.uniform(0.05, 1.05);
      const Vec2 c{5.0 + t * (lc.x - 5.0) + rng.uniform(-25.0, 25.0), 5.0 + t * (lc.y - 5.0) + rng.uniform(-25.0, 25.0)};
      scene.occluders.push_back(Occluder{random_occluder(rng, c, rng.uniform(2.0, 10.0))});
    }
  } else {
    // One or two fences across the way, of boards with gaps of -0.3 .. 0.3, most near 0 (negative:
    // overlapping): proofs must hang on overlaps, not on the width of a crack.
    const Vec2 u{std::cos(dir), std::sin(dir)}, across{-u.y, u.x};
    const int fences = rng.integer(1, 2);
    for (int f = 0; f < fences; ++f) {
      const double t = rng.uniform(0.2, 0.8) * dist, depth = rng.uniform(0.5, 3.0);
      double along = -25.0;
      while (along < 25.0) {
        const double board = rng.uniform(2.0, 8.0);
        const Vec2 o{5.0 + t * u.x + along * across.x, 5.0 + t * u.y + along * across.y};
        const Vec2 e{board * across.x, board * across.y}, d{depth * u.x, depth * u.y};
        scene.occluders.push_back(
            Occluder{Polygon{{o, {o.x + e.x, o.y + e.y}, {o.x + e.x + d.x, o.y + e.y + d.y}, {o.x + d.x, o.y + d.y}}}});
        const double w = rng.uniform(-1.0, 1.0), gap = 0.3 * w * w * w;  // many cracks near zero width
        for (const double at : {0.0, 0.5, 1.0}) {
          if (gap > 0.0)
            cracks.push_back({o.x + (board + 0.5 * gap) * across.x + at * d.x, o.y + (board + 0.5 * gap) * across.y + at * d.y});
        }
        along += board + gap;
      }
    }
  }
  return field;
}

// Segments from the rectangle to the light that meet no occluder, by brute force: 400
// random ones, and from a 21 x 21 grid over the rectangle through each crack point to
// points of the light on the same line. Each one found fails the test case.
int unblocked_segments(const Field& field, PortableRandom& rng, int trial) {
  const Scene& scene = field.scene;
  const Shape& light_shape = field.light_shape;
  const Vec2 lc = field.lc;
  const double lr = field.lr;
  int refuted = 0;
  auto check_segment = [&](Vec2 a, Vec2 b, const char* kind) {
    const bool blocked = std::any_of(scene.occluders.begin(), scene.occluders.end(),
                                     [&](const Occluder& o) { return blocks(o.shape, a, b); });
    refuted += !blocked;
    if (!blocked) {
      INFO("trial ", trial, ": ", kind, " segment (", a.x, ", ", a.y, ") -> (", b.x, ", ", b.y, ") meets no occluder");
      CHECK(blocked);
    }
  };
  for (int s = 0; s < 400; ++s) {
    const Vec2 a{rng.uniform(0.0, 10.0), rng.uniform(0.0, 10.0)};
    check_segment(a, point_in(light_shape, rng), "random");
  }
  // Lines through the cracks: from a 21 x 21 grid over the rectangle through each crack
  // point, to points of the light on the same line.
  const detail::ConvexShape light_exact = detail::make_convex_shape(light_shape);
  for (const Vec2 m : field.cracks) {
    for (int g = 0; g < 441; ++g) {
      const Vec2 a{10.0 * (g % 21) / 20.0, 10.0 * (g / 21) / 20.0};
      const double dx = m.x - a.x, dy = m.y - a.y, len = std::hypot(dx, dy);
      const double to_light = std::hypot(lc.x - a.x, lc.y - a.y);
      for (int t = 0; t <= 8; ++t) {
        const double along = to_light - lr + 2.0 * lr * t / 8.0;
        const Vec2 b{a.x + dx / len * along, a.y + dy / len * along};
        if (detail::contains(light_exact, b)) check_segment(a, b, "through a crack:");
      }
    }
  }
  return refuted;
}

// A tilemap wall across the way: 1..3 columns (mostly one) of axis-aligned cells between the rectangle
// [0, 10]^2 and a light 60..120 to its right, each column's cells touching exactly (most
// seams), overlapping, or apart by a crack of 1e-4..1.5 (its points kept for the brute
// force); then the whole field turned by 0..3 quarter turns about the rectangle's center.
Field random_tilemap_field(PortableRandom& rng) {
  Field field;
  Scene& scene = field.scene;
  const int turn = rng.integer(0, 3);
  auto turned = [&](Vec2 p) {
    for (int k = 0; k < turn; ++k) p = {10.0 - p.y, p.x};
    return p;
  };
  const Vec2 lc{rng.uniform(60.0, 120.0), rng.uniform(-30.0, 40.0)};
  const double lr = field.lr = rng.uniform(1.0, 5.0);
  field.lc = turned(lc);
  if (rng.chance(0.5)) {
    field.light_shape = Circle{field.lc, lr};
  } else {
    Polygon p;
    for (int k = 0; k < 5; ++k) p.vertices.push_back(turned({lc.x + lr * std::cos(1.2566 * k), lc.y + lr * std::sin(1.2566 * k)}));
    field.light_shape = p;
  }
  scene.width = 10;
  scene.height = 10;
  scene.view = {0, 0, 10, 10};
  scene.lights.push_back(Light{field.light_shape, {1, 1, 1}, 1.0});
  auto add_box = [&](Vec2 lo, Vec2 hi) {
    const Vec2 p = turned(lo), q = turned(hi);
    const Vec2 a{std::min(p.x, q.x), std::min(p.y, q.y)}, b{std::max(p.x, q.x), std::max(p.y, q.y)};
    scene.occluders.push_back(Occluder{Polygon{{a, {b.x, a.y}, b, {a.x, b.y}}}});
  };
  double x = rng.integer(20, 40);
  const int columns = rng.chance(0.6) ? 1 : rng.integer(2, 3);
  for (int c = 0; c < columns; ++c) {
    const double width = rng.integer(1, 2);
    double y = -100.0;
    while (y < 100.0) {
      const double height = rng.integer(2, 8);
      add_box({x, y}, {x + width, y + height});
      y += height;
      const double seam = rng.uniform();
      if (seam < 0.1) {
        y -= 0.5;  // the next cell overlaps this one
      } else if (seam < 0.35) {
        const double crack = std::max(1e-4, 1.5 * std::pow(rng.uniform(), 3.0));
        for (const double at : {0.0, 0.5, 1.0}) field.cracks.push_back(turned({x + at * width, y + 0.5 * crack}));
        y += crack;
      }
    }
    x += width;
  }
  return field;
}

}  // namespace

TEST_CASE("two overlapping wall pieces hide a light from a rectangle; a 1-unit gap between them does not") {
  const ConvexShape light = detail::make_convex_shape(Circle{{60.0, 5.0}, 2.0});
  detail::OcclusionProofScratch scratch;
  for (const double gap : {-1.0, 1.0}) {  // overlap by 1, or a gap of 1
    const std::vector<ConvexShape> wall = {
        detail::make_convex_shape(Polygon{{{30, -80}, {33, -80}, {33, 5.0 - gap / 2}, {30, 5.0 - gap / 2}}}),
        detail::make_convex_shape(Polygon{{{30, 5.0 + gap / 2}, {33, 5.0 + gap / 2}, {33, 90}, {30, 90}}})};
    const auto ids = all_ids(wall.size());
    const bool hidden = detail::rect_hidden_from_light({0, 0}, {10, 10}, light, wall, ids.data(), ids.size(), 64, scratch);
    CHECK(hidden == (gap < 0.0));
  }
}

TEST_CASE("two wall boxes that only touch along the grazing line hide the light; a hairline gap between them does not") {
  // The boxes meet along y = 5, the one line from the light's middle to the rectangle's that
  // runs between them: lines close to it cross the wall at a slant and enter one box or the
  // other, so the light is hidden, yet the two shadows only touch, with no slack at all (a
  // tilemap wall face running into the next box's face). A hairline gap lets that line through.
  const ConvexShape light = detail::make_convex_shape(Circle{{60.0, 5.0}, 2.0});
  detail::OcclusionProofScratch scratch;
  for (const double gap : {0.0, 1e-3}) {
    for (const int turn : {0, 1, 2, 3}) {  // the same layout turned by quarter turns about the rectangle's center
      auto turned = [&](Vec2 p) {
        for (int k = 0; k < turn; ++k) p = {10.0 - p.y, p.x};
        return p;
      };
      auto box = [&](Vec2 a, Vec2 b) {
        const Vec2 p = turned(a), q = turned(b);
        const Vec2 lo{std::min(p.x, q.x), std::min(p.y, q.y)}, hi{std::max(p.x, q.x), std::max(p.y, q.y)};
        return detail::make_convex_shape(Polygon{{lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}});
      };
      const std::vector<ConvexShape> wall = {box({30, -80}, {33, 5.0 - gap / 2}), box({30, 5.0 + gap / 2}, {33, 90})};
      const ConvexShape lamp = detail::make_convex_shape(Circle{turned({60.0, 5.0}), 2.0});
      const auto ids = all_ids(wall.size());
      INFO("gap ", gap, ", turned ", turn, " quarter turns");
      CHECK(detail::rect_hidden_from_light({0, 0}, {10, 10}, lamp, wall, ids.data(), ids.size(), 64, scratch) == (gap == 0.0));
    }
  }
  // Touching at a corner only (the upper box moved right by the wall's width): every line
  // across x = 33 near y = 5 enters one box or the other, so the light is hidden; raise the
  // upper box by a hairline and lines just above y = 5 pass between them.
  for (const double gap : {0.0, 1e-3}) {
    const std::vector<ConvexShape> corner = {
        detail::make_convex_shape(Polygon{{{30, -80}, {33, -80}, {33, 5}, {30, 5}}}),
        detail::make_convex_shape(Polygon{{{33, 5 + gap}, {36, 5 + gap}, {36, 90}, {33, 90}}})};
    const auto ids = all_ids(corner.size());
    INFO("corner, gap ", gap);
    CHECK(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, corner, ids.data(), ids.size(), 64, scratch) == (gap == 0.0));
  }
}

TEST_CASE("a wall that stops short of the rectangle's reach is no proof; one occluder beyond the light is ignored") {
  const ConvexShape light = detail::make_convex_shape(Polygon{{{50, 0}, {54, 0}, {54, 4}, {50, 4}}});
  detail::OcclusionProofScratch scratch;
  // Covers lines toward the light's middle only: the rectangle's bottom corner sees the light's bottom past it.
  const std::vector<ConvexShape> short_wall = {detail::make_convex_shape(Polygon{{{25, 1}, {27, 1}, {27, 30}, {25, 30}}})};
  const std::vector<ConvexShape> behind = {detail::make_convex_shape(Polygon{{{60, -50}, {62, -50}, {62, 50}, {60, 50}}})};
  const std::uint32_t id = 0;
  CHECK_FALSE(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, short_wall, &id, 1, 64, scratch));
  CHECK_FALSE(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, behind, &id, 1, 64, scratch));
  const std::vector<ConvexShape> full_wall = {detail::make_convex_shape(Polygon{{{25, -30}, {27, -30}, {27, 30}, {25, 30}}})};
  CHECK(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, full_wall, &id, 1, 64, scratch));
}

TEST_CASE("proofs refused before their setup: a segment to the light's centroid that passes; a pillar beside it is refused by the proof") {
  // Light: a circle of radius 3 at (60, 5); viewer: the rectangle [0, 10]^2. The pillar close
  // to the light blocks every line to the centroid (|y - 5| <= 0.42 at x = 55), not those to
  // the light's top and bottom: the proof itself must refuse it. A full wall there is proven;
  // an occluder off to the side leaves a segment to the centroid free, refused before setup.
  const ConvexShape light = detail::make_convex_shape(Circle{{60.0, 5.0}, 3.0});
  const std::vector<ConvexShape> pillar = {detail::make_convex_shape(Polygon{{{55, 4.4}, {56, 4.4}, {56, 5.6}, {55, 5.6}}})};
  const std::vector<ConvexShape> wall = {detail::make_convex_shape(Polygon{{{55, -50}, {56, -50}, {56, 60}, {55, 60}}})};
  const std::vector<ConvexShape> aside = {detail::make_convex_shape(Polygon{{{30, 20}, {32, 20}, {32, 40}, {30, 40}}})};
  const std::uint32_t id = 0;
  for (const Vec2 v : {Vec2{0, 0}, Vec2{10, 0}, Vec2{10, 10}, Vec2{0, 10}, Vec2{5, 5}})
    CHECK_FALSE(detail::segment_passes(v, light.centroid, pillar, &id, 1));
  detail::OcclusionProofScratch scratch;
  CHECK_FALSE(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, pillar, &id, 1, 64, scratch));
  CHECK(scratch.proofs_probed_out == 0);
  CHECK(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, wall, &id, 1, 64, scratch));
  CHECK(scratch.proofs_probed_out == 0);
  CHECK_FALSE(detail::rect_hidden_from_light({0, 0}, {10, 10}, light, aside, &id, 1, 64, scratch));
  CHECK(scratch.proofs_probed_out == 1);
  CHECK(scratch.proofs_tried == 3);
  CHECK(scratch.proofs_succeeded == 1);
}

// Proves the light of `fields` random fields hidden from the rectangle [0, 10]^2 where it can,
// and checks each proof against brute-force segments and the scalar reference on a 7 x 7
// grid over the rectangle (corners included). Returns how many were proven.
template <class MakeField>
int check_rectangle_proofs(PortableRandom& rng, int fields, MakeField make_field) {
  detail::OcclusionProofScratch scratch;
  detail::ScalarScratch scalar;
  int proven = 0, refuted = 0;
  for (int trial = 0; trial < fields; ++trial) {
    const Field field = make_field(trial);
    const ConvexShape light = detail::make_convex_shape(field.light_shape);
    std::vector<ConvexShape> occluders;
    for (const Occluder& o : field.scene.occluders) occluders.push_back(detail::make_convex_shape(o.shape));
    const auto ids = all_ids(occluders.size());
    if (!detail::rect_hidden_from_light({0, 0}, {10, 10}, light, occluders, ids.data(), ids.size(), 64, scratch)) continue;
    ++proven;
    refuted += unblocked_segments(field, rng, trial);
    const auto prepared = detail::prepare_scene(field.scene);
    const double scale = prepared.view.x1 / field.scene.view.x1;  // prepare_scene scales by a power of two
    for (int s = 0; s < 49; ++s) {
      const Vec2 x{scale * 10.0 * (s % 7) / 6.0, scale * 10.0 * (s / 7) / 6.0};
      const double visible = reference_visible(prepared, 0, x, scalar);
      CHECK(visible <= 0.0);
    }
  }
  CHECK(refuted == 0);
  return proven;
}

TEST_CASE("every rectangle proof holds against brute-force segments and the scalar reference (300 random fields)") {
  PortableRandom rng(4242);
  const int proven = check_rectangle_proofs(rng, 300, [&](int trial) { return random_field(rng, trial); });
  MESSAGE(proven, " of 300 random fields proven to hide the light");
  CHECK(proven >= 30);  // the test must exercise proofs, not only refusals
}

TEST_CASE("every proof over tilemap walls (touching cells, hairline cracks) holds against brute-force segments and the scalar reference") {
  PortableRandom rng(3131);
  const int proven = check_rectangle_proofs(rng, 300, [&](int) { return random_tilemap_field(rng); });
  MESSAGE(proven, " of 300 tilemap walls proven to hide the light");
  CHECK(proven >= 30);
}

TEST_CASE("proofs 1e7 from the origin hold for the same fields at the origin (rounding margin)") {
  // Far from the origin each coordinate is rounded to ~1e-9 and the proof demands overlaps
  // of more than its margin; every proof there must hold for the unrounded field.
  PortableRandom rng(5151);
  detail::OcclusionProofScratch scratch;
  const Vec2 offset{1.25e7, -3.5e7};
  auto moved = [&](const ConvexShape& s) {
    ConvexShape m = s;
    for (Vec2& v : m.vertices) v = {v.x + offset.x, v.y + offset.y};
    m.bounds_min = {s.bounds_min.x + offset.x, s.bounds_min.y + offset.y};
    m.bounds_max = {s.bounds_max.x + offset.x, s.bounds_max.y + offset.y};
    m.centroid = {s.centroid.x + offset.x, s.centroid.y + offset.y};
    return m;
  };
  int proven_far = 0, refuted = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Field field = random_field(rng, trial);
    const ConvexShape light = moved(detail::make_convex_shape(field.light_shape));
    std::vector<ConvexShape> occluders;
    for (const Occluder& o : field.scene.occluders) occluders.push_back(moved(detail::make_convex_shape(o.shape)));
    const auto ids = all_ids(occluders.size());
    if (!detail::rect_hidden_from_light(offset, {offset.x + 10, offset.y + 10}, light, occluders, ids.data(), ids.size(),
                                        64, scratch))
      continue;
    ++proven_far;
    refuted += unblocked_segments(field, rng, trial);
  }
  MESSAGE(proven_far, " of 200 fields proven hidden 1e7 from the origin");
  CHECK(refuted == 0);
  CHECK(proven_far >= 20);
}

TEST_CASE("light reach: points beyond a sector's reach see none of the light (dense random field, scalar reference)") {
  // The scaling benchmark's kind of level: 600 small occluders over 400 x 300 with 6 lights.
  PortableRandom rng(777);
  const Scene scene = bench::scattered_scene(6, 600, 777, 400, 300);
  const auto prepared = detail::prepare_scene(scene);
  const double scale = prepared.view.x1 / scene.view.x1;
  detail::LightReachScratch scratch;
  detail::ScalarScratch scalar;
  int finite = 0, checked = 0, hidden_boxes = 0;
  for (std::size_t l = 0; l < prepared.lights.size(); ++l) {
    const detail::LightReach reach = detail::compute_light_reach(prepared, l, scratch);
    for (int k = 0; k < detail::LightReach::kSectors; ++k) {
      const double r = reach.reach[static_cast<std::size_t>(k)];
      if (!std::isfinite(r)) continue;
      ++finite;
      for (int s = 0; s < 25; ++s) {
        const double a = -kPi + (k + rng.uniform()) * 2.0 * kPi / detail::LightReach::kSectors;
        const double d = r + rng.uniform(0.0, 150.0 * scale);
        const Vec2 x{reach.center.x + d * std::cos(a), reach.center.y + d * std::sin(a)};
        const double visible = reference_visible(prepared, l, x, scalar);
        if (visible < 0.0) continue;  // inside an occluder
        ++checked;
        INFO("light ", l, " sector ", k, " reach ", r, " point at distance ", d);
        CHECK(visible == 0.0);
      }
    }
    // Boxes the reach hides: their corners and random points see none of the light.
    for (int b = 0; b < 200; ++b) {
      const double x0 = scale * rng.uniform(0, 380), y0 = scale * rng.uniform(0, 280);
      const detail::Aabb box{x0, y0, x0 + 16 * scale, y0 + 16 * scale};
      if (!reach.hides(box)) continue;
      ++hidden_boxes;
      for (int s = 0; s < 8; ++s) {
        const Vec2 x{rng.uniform(box.min_x, box.max_x), rng.uniform(box.min_y, box.max_y)};
        const double visible = reference_visible(prepared, l, x, scalar);
        CHECK(visible <= 0.0);
      }
    }
  }
  MESSAGE(finite, " sectors with a proven reach, ", checked, " points checked, ", hidden_boxes, " boxes hidden");
  CHECK(finite >= 30);
  CHECK(hidden_boxes >= 50);
}
