// Contact cases (docs/contract.md: visible only when t_L < t_occ): lights on occluder edges, collinear overlaps, touching shapes.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "world/prepared_scene.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"

namespace {

using namespace par2d;
using test::RenderedImage;

constexpr double kPi = 3.14159265358979323846;

RenderOptions backend_options(Backend backend, std::optional<Isa> isa = std::nullopt) {
  RenderOptions o;
  o.backend = backend;
  o.isa = isa;
  o.threads = 1;
  o.rays = 512;
  return o;
}

// Every backend this CPU runs and the ray caster, by name: scalar, SIMD at each ISA, "raycast"
// (render_raycast, which reads the rays and not the backend).
std::vector<std::pair<std::string, RenderOptions>> all_backends() {
  std::vector<std::pair<std::string, RenderOptions>> out{{"scalar", backend_options(Backend::scalar)},
                                                         {"raycast", backend_options(Backend::scalar)}};
  for (Isa isa : par2d::kSimdIsas)
    if (isa_supported(isa)) out.emplace_back(std::string("simd ") + isa_name(isa), backend_options(Backend::simd, isa));
  return out;
}

RenderedImage render_ok(const Scene& scene, const RenderOptions& options, bool raycast = false) {
  Status status;
  RenderedImage image = test::render_image(scene, options, status, raycast);
  REQUIRE_MESSAGE(status.ok(), status.message());
  return image;
}

// Largest channel value over the image, and where.
double image_max(const RenderedImage& image, int& at_i, int& at_j) {
  double best = 0.0;
  at_i = at_j = -1;
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i)
      for (int c = 0; c < 3; ++c)
        if (image.at(i, j, c) > best) best = image.at(i, j, c), at_i = i, at_j = j;
  return best;
}

void check_black_everywhere(const Scene& scene) {
  for (const auto& backend : all_backends()) {
    const std::string& name = backend.first;  // not a structured binding: clang's INFO cannot capture those
    const RenderOptions& options = backend.second;
    const RenderedImage image = render_ok(scene, options, backend.first == "raycast");
    int i = 0, j = 0;
    const double worst = image_max(image, i, j);
    INFO(name, ": largest value ", worst, " at pixel (", i, ", ", j, ")");
    CHECK(worst == 0.0);
  }
}

Light white_light(Shape shape) {
  Light l;
  l.shape = std::move(shape);
  return l;
}

Scene base_scene(int size = 32) {
  Scene s;
  s.width = s.height = size;
  s.view = {0, 0, double(size), double(size)};
  return s;
}

Polygon rect(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// Angle subtended by segment [a, b] seen from x.
double subtended(Vec2 x, Vec2 a, Vec2 b) {
  const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y;
  return std::fabs(std::atan2(ax * by - ay * bx, ax * bx + ay * by));
}

}  // namespace

TEST_CASE("contact: a segment light lying on a polygon occluder's edge is hidden everywhere (issue case, 32x32)") {
  Scene scene = base_scene();
  scene.lights.push_back(white_light(Segment{{8, 10}, {24, 10}}));
  scene.occluders.push_back({Polygon{{{6, 10}, {26, 10}, {26, 20}, {6, 20}}}});
  check_black_everywhere(scene);
  // The same with the light reversed, the polygon wound the other way and a segment occluder
  // on the same line.
  scene.lights[0].shape = Segment{{24, 10}, {8, 10}};
  scene.occluders[0].shape = Polygon{{{6, 20}, {26, 20}, {26, 10}, {6, 10}}};
  check_black_everywhere(scene);
  scene.occluders[0].shape = Segment{{4, 10}, {28, 10}};
  check_black_everywhere(scene);
}

TEST_CASE("contact: a polygon light inside an occluder, sharing its edge, is hidden everywhere") {
  Scene scene = base_scene();
  scene.lights.push_back(white_light(rect(8, 10, 24, 14)));
  scene.occluders.push_back({rect(6, 10, 26, 20)});
  check_black_everywhere(scene);
  // Identical shapes: every ray meets both at the same point.
  scene.lights[0].shape = rect(6, 10, 26, 20);
  check_black_everywhere(scene);
  scene.lights[0].shape = Circle{{16, 16}, 5};
  scene.occluders[0].shape = Circle{{16, 16}, 5};
  check_black_everywhere(scene);
  // A circle light inside a circle occluder, touching it from inside.
  scene.lights[0].shape = Circle{{13, 16}, 2};
  check_black_everywhere(scene);
}

TEST_CASE("contact: a segment light half on a collinear segment occluder shows exactly its free half") {
  // From any pixel off the line, rays to [8, 16] meet both at one point (hidden), rays to
  // [16, 24] cross the line only on the light: E = angle subtended by [16, 24] / 2pi.
  Scene scene = base_scene();
  scene.lights.push_back(white_light(Segment{{8, 10}, {24, 10}}));
  scene.occluders.push_back({Segment{{4, 10}, {16, 10}}});
  for (const auto& backend : all_backends()) {
    const std::string& name = backend.first;
    const RenderOptions& options = backend.second;
    if (name == "raycast") continue;  // noisy at 512 rays; checked below
    const RenderedImage image = render_ok(scene, options);
    const double bound = options.backend == Backend::scalar ? 1e-6 : 1e-4;
    double worst = 0.0;
    for (int j = 0; j < scene.height; ++j)
      for (int i = 0; i < scene.width; ++i) {
        const Vec2 x = test::pixel_center(scene, i, j);
        const double expected = subtended(x, {16, 10}, {24, 10}) / (2 * kPi);
        worst = std::max(worst, std::fabs(image.at(i, j, 0) - expected));
      }
    INFO(name);
    CHECK(worst <= bound);
  }
  // The ray caster agrees within its sampling error (a 16-unit segment at >= 0.5 units).
  const RenderedImage rays = render_ok(scene, backend_options(Backend::scalar), /*raycast=*/true);
  const RenderedImage scalar = render_ok(scene, backend_options(Backend::scalar));
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) CHECK(std::fabs(rays.at(i, j, 0) - scalar.at(i, j, 0)) <= 2.0 / 512);
}

TEST_CASE("contact: touching shapes and a light vertex on an occluder edge are continuous with their separated versions") {
  // Where the contact is a single point, the contract's value is the limit of the separated
  // scene: moving the occluder 1e-9 away changes no pixel by more than the scalar bound.
  struct Case {
    const char* name;
    Shape light;
    Shape occluder;
    Vec2 away;  // direction that separates them
  };
  const Case cases[] = {
      {"touching circles", Circle{{10, 16}, 4}, Circle{{18, 16}, 4}, {1, 0}},
      {"light vertex on occluder edge", Polygon{{{12, 4}, {20, 4}, {16, 10}}}, rect(6, 10, 26, 20), {0, 1}},
      {"segment light end on occluder edge", Segment{{16, 2}, {16, 10}}, rect(6, 10, 26, 20), {0, 1}},
      {"circle light on occluder edge", Circle{{16, 6}, 4}, rect(6, 10, 26, 20), {0, 1}},
      {"polygon light corner on occluder corner", rect(4, 4, 10, 10), rect(10, 10, 20, 20), {1, 1}},
  };
  for (const Case& c : cases) {
    Scene touching = base_scene();
    touching.lights.push_back(white_light(c.light));
    touching.occluders.push_back({c.occluder});
    Scene apart = touching;
    auto move = [&](Vec2 p) { return Vec2{p.x + 1e-9 * c.away.x, p.y + 1e-9 * c.away.y}; };
    if (auto* p = std::get_if<Polygon>(&apart.occluders[0].shape))
      for (Vec2& v : p->vertices) v = move(v);
    if (auto* k = std::get_if<Circle>(&apart.occluders[0].shape)) k->center = move(k->center);
    const RenderedImage a = render_ok(touching, backend_options(Backend::scalar));
    const RenderedImage b = render_ok(apart, backend_options(Backend::scalar));
    const RenderedImage rays = render_ok(touching, backend_options(Backend::scalar), /*raycast=*/true);
    double worst = 0.0, worst_rays = 0.0;
    for (int j = 0; j < touching.height; ++j)
      for (int i = 0; i < touching.width; ++i) {
        if (test::near_boundary(touching, test::pixel_center(touching, i, j), 1e-3)) continue;
        worst = std::max(worst, double(std::fabs(a.at(i, j, 0) - b.at(i, j, 0))));
        worst_rays = std::max(worst_rays, double(std::fabs(a.at(i, j, 0) - rays.at(i, j, 0))));
      }
    INFO(c.name, ": touching vs 1e-9 apart ", worst, ", scalar vs raycast ", worst_rays);
    CHECK(worst <= 1e-6);
    CHECK(worst_rays <= 4.0 / 512);
  }
}

TEST_CASE("contact property: sub-segments of random polygon edges as lights are hidden everywhere, every backend") {
  // Rotated polygons: the light's end points are rounded onto the edge's line, so exact
  // collinearity is not what makes this work; the contact tolerance is.
  std::mt19937 rng(20261201);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 3 + trial % 6;
    const Vec2 center{16 + 4 * (unit(rng) - 0.5), 16 + 4 * (unit(rng) - 0.5)};
    const double r = 6 + 4 * unit(rng), phase = 2 * kPi * unit(rng);
    Polygon poly;
    for (int k = 0; k < n; ++k) {
      const double a = phase + 2 * kPi * k / n;
      poly.vertices.push_back({center.x + r * std::cos(a), center.y + r * std::sin(a)});
    }
    Scene scene = base_scene();
    scene.occluders.push_back({poly});
    // One light on each edge of the polygon, covering a random part of it.
    for (int k = 0; k < n; ++k) {
      const Vec2 a = poly.vertices[k], b = poly.vertices[(k + 1) % n];
      const double s0 = 0.4 * unit(rng), s1 = 0.6 + 0.4 * unit(rng);
      scene.lights.push_back(white_light(Segment{{a.x + s0 * (b.x - a.x), a.y + s0 * (b.y - a.y)},
                                                 {a.x + s1 * (b.x - a.x), a.y + s1 * (b.y - a.y)}}));
    }
    INFO("trial ", trial, " with ", n, " vertices");
    check_black_everywhere(scene);
  }
}

TEST_CASE("overlapping many-vertex polygons: key rays found by walking the boundary equal a scan of every edge") {
  // The scalar reference walks from the last ray's entry edge (O(1) per ray instead of O(n));
  // every decision must be the one the full scan gives.
  auto ngon = [](Vec2 c, double r, int n, double phase) {
    Polygon p;
    for (int k = 0; k < n; ++k)
      p.vertices.push_back({c.x + r * std::cos(phase + 2 * kPi * k / n), c.y + r * std::sin(phase + 2 * kPi * k / n)});
    return detail::make_convex_shape(p);
  };
  const detail::ConvexShape light = ngon({12, 12}, 5, 900, 0.0), occluder = ngon({12, 12}, 5, 333, 0.3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int decisions = 0, blocked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Vec2 x{12 + 9 * std::cos(trial * 0.7), 12 + 9 * std::sin(trial * 0.7)};
    detail::EntryHints hints;
    const double start = std::atan2(12 - x.y, 12 - x.x) - 0.6;
    for (int k = 0; k < 400; ++k) {
      const double a = start + 1.2 * (k + unit(rng)) / 400;
      const Vec2 dir{std::cos(a), std::sin(a)};
      const bool walked = detail::occluder_first(occluder, light, x, dir, hints);
      const bool scanned = detail::occluder_first(occluder, light, x, dir);
      REQUIRE(walked == scanned);
      ++decisions;
      blocked += walked;
    }
  }
  CHECK(decisions == 16000);
  CHECK(blocked > 1000);            // both answers occur
  CHECK(blocked < decisions - 1000);
}

TEST_CASE("overlapping many-vertex polygons: scalar matches the ray caster") {
  // Boundaries that cross twice (on the same circle they cross hundreds of times, and the
  // visible set splits into as many arcs as the ray caster's error bound then allows).
  Scene scene = base_scene(12);
  scene.view = {0, 0, 24, 24};
  auto ngon = [](double cx, double r, int n, double phase) {
    Polygon p;
    for (int k = 0; k < n; ++k)
      p.vertices.push_back({cx + r * std::cos(phase + 2 * kPi * k / n), 12 + r * std::sin(phase + 2 * kPi * k / n)});
    return p;
  };
  scene.lights.push_back(white_light(ngon(10, 5, 900, 0.0)));
  scene.occluders.push_back({ngon(15, 4, 333, 0.3)});
  const RenderedImage scalar = render_ok(scene, backend_options(Backend::scalar));
  RenderOptions rays = backend_options(Backend::scalar);
  rays.rays = 4096;
  const RenderedImage cast = render_ok(scene, rays, /*raycast=*/true);
  double worst = 0.0;
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) worst = std::max(worst, double(std::fabs(scalar.at(i, j, 0) - cast.at(i, j, 0))));
  INFO("worst |scalar - raycast| ", worst);
  CHECK(worst <= 3.0 / 4096);
}

TEST_CASE("distance between many-vertex polygons (pruned search) equals the full vertex-by-edge search") {
  // core_distance skips edges outside the other core's box and vertices beyond its bounding
  // circle; every answer must be the full search's: min over vertices of the distance to the
  // other shape, or 0 where edges cross.
  auto ngon = [](Vec2 c, double rx, double ry, int n, double phase) {
    Polygon p;
    for (int k = 0; k < n; ++k)
      p.vertices.push_back({c.x + rx * std::cos(phase + 2 * kPi * k / n), c.y + ry * std::sin(phase + 2 * kPi * k / n)});
    return detail::make_convex_shape(p);
  };
  auto cross = [](Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  auto edges_cross = [&](const detail::ConvexShape& a, const detail::ConvexShape& b) {
    const std::size_t n = a.vertices.size(), m = b.vertices.size();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < m; ++j) {
        const Vec2 p = a.vertices[i], q = a.vertices[(i + 1) % n], r = b.vertices[j], s = b.vertices[(j + 1) % m];
        const double d1 = cross(p, q, r), d2 = cross(p, q, s), d3 = cross(r, s, p), d4 = cross(r, s, q);
        if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0) return true;
      }
    return false;
  };
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int disjoint = 0, meeting = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const detail::ConvexShape a = ngon({0, 0}, 3 + 4 * unit(rng), 2 + 4 * unit(rng), 50 + trial * 20, unit(rng));
    const double angle = 2 * kPi * unit(rng), gap = 14 * unit(rng);
    const detail::ConvexShape b =
        ngon({gap * std::cos(angle), gap * std::sin(angle)}, 1 + 5 * unit(rng), 1 + 5 * unit(rng), 30 + trial * 7, unit(rng));
    double brute = edges_cross(a, b) ? 0.0 : 1e300;
    for (Vec2 v : a.vertices) brute = std::min(brute, detail::point_distance(b, v));
    for (Vec2 v : b.vertices) brute = std::min(brute, detail::point_distance(a, v));
    INFO("trial ", trial);
    CHECK(detail::shape_distance(a, b) == brute);
    CHECK(detail::separating_line(a, b).has_value() == (brute > 0.0));
    (brute > 0.0 ? disjoint : meeting) += 1;
  }
  CHECK(disjoint >= 10);
  CHECK(meeting >= 10);
}

TEST_CASE("pair separators: a checked line for every disjoint light and occluder, across the discs' gap when far apart") {
  // The tile setup orders a pair by any line that strictly separates it; far apart (centroids
  // more than twice the sum of their bounding radii) it takes the line normal to the
  // centroids' axis in the middle of the discs' gap, nearer the closest points' bisector.
  std::mt19937 rng(1207);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto random_shape = [&](Vec2 c, double size) {
    const int kind = static_cast<int>(unit(rng) * 3.0);
    if (kind == 0) return detail::make_convex_shape(Circle{c, 0.5 * size});
    if (kind == 1) {
      const double a = 2 * kPi * unit(rng);
      return detail::make_convex_shape(Segment{{c.x - 0.5 * size * std::cos(a), c.y - 0.5 * size * std::sin(a)},
                                               {c.x + 0.5 * size * std::cos(a), c.y + 0.5 * size * std::sin(a)}});
    }
    Polygon p;
    const int n = 3 + static_cast<int>(unit(rng) * 4.0);
    const double phase = unit(rng);
    for (int k = 0; k < n; ++k)
      p.vertices.push_back({c.x + 0.5 * size * std::cos(phase + 2 * kPi * k / n),
                            c.y + 0.5 * size * std::sin(phase + 2 * kPi * k / n)});
    return detail::make_convex_shape(p);
  };
  constexpr int kPairs = 400;
  detail::PairSeparators separators;
  separators.reset(kPairs, 1);
  int far = 0, near_disjoint = 0, meeting = 0;
  for (int trial = 0; trial < kPairs; ++trial) {
    const detail::ConvexShape light = random_shape({0.0, 0.0}, 1.0 + 6.0 * unit(rng));
    const double angle = 2 * kPi * unit(rng), gap = 40.0 * unit(rng) * unit(rng);
    const detail::ConvexShape occluder =
        random_shape({gap * std::cos(angle), gap * std::sin(angle)}, 1.0 + 6.0 * unit(rng));
    const std::optional<detail::Line> line = separators.get(static_cast<std::size_t>(trial), 0, light, occluder);
    const double distance = detail::shape_distance(light, occluder);
    INFO("trial ", trial, " distance ", distance);
    REQUIRE(line.has_value() == (distance > 0.0));
    if (!line) {
      ++meeting;
      continue;
    }
    for (const Vec2 v : occluder.vertices) CHECK(line->side(v) - occluder.radius > 0.0);
    for (const Vec2 v : light.vertices) CHECK(line->side(v) + light.radius < 0.0);
    const Vec2 axis{occluder.centroid.x - light.centroid.x, occluder.centroid.y - light.centroid.y};
    const double centroids = std::sqrt(axis.x * axis.x + axis.y * axis.y);
    const double across = std::abs(line->normal.x * axis.y - line->normal.y * axis.x) / centroids;
    if (centroids > 2.0 * (detail::centroid_radius(light) + detail::centroid_radius(occluder))) {
      ++far;
      CHECK(across < 1e-12);
    } else {
      ++near_disjoint;
    }
    // Known from then on: the same line again.
    const std::optional<detail::Line> again = separators.get(static_cast<std::size_t>(trial), 0, light, occluder);
    REQUIRE(again.has_value());
    CHECK(again->normal.x == line->normal.x);
    CHECK(again->normal.y == line->normal.y);
    CHECK(again->point.x == line->point.x);
    CHECK(again->point.y == line->point.y);
  }
  CHECK(far >= 50);
  CHECK(near_disjoint >= 50);
  CHECK(meeting >= 20);
}
