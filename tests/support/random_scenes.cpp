// Deterministic random scenes for tests and pixel helpers (see random_scenes.hpp).
#include "support/random_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "geometry/convex_shape.hpp"

namespace par2d::test {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

struct Placed {
  Vec2 center;
  double radius;  // bounding circle of the shape
};

bool apart(const Placed& a, const Placed& b, double gap) {
  return std::hypot(a.center.x - b.center.x, a.center.y - b.center.y) > a.radius + b.radius + gap;
}

// A power of two bringing the largest of the magnitudes to 2^500 or below (products of
// scaled coordinates of 1e307 then fit a double), or tiny ones up to about 1 (their products
// would underflow); scaling is exact.
double product_scale(std::initializer_list<double> values) noexcept {
  double largest = 0.0;
  for (double v : values) largest = std::max(largest, std::fabs(v));
  int exponent = 0;
  std::frexp(largest, &exponent);
  if (exponent > 500) return std::ldexp(1.0, 500 - exponent);
  // Tiny coordinates (views of 1e-200 per pixel): squared lengths underflow to 0 below 1e-154.
  if (exponent < -500 && largest > 0.0) return std::ldexp(1.0, -exponent);
  return 1.0;
}

double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) noexcept {
  const double f = product_scale({p.x, p.y, a.x, a.y, b.x, b.y});
  p = {f * p.x, f * p.y};
  a = {f * a.x, f * a.y};
  b = {f * b.x, f * b.y};
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double wx = p.x - a.x, wy = p.y - a.y;
  const double ee = ex * ex + ey * ey;
  double s = ee > 0.0 ? (wx * ex + wy * ey) / ee : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  // With the foot inside, the distance to the line from an exactly expanded cross product: the
  // foot point itself rounds to the end points' magnitude (units, on a segment 1e17 long).
  if (s > 0.0 && s < 1.0) return std::fabs(detail::cross_from(a, b, p)) / std::sqrt(ee) / f;
  return std::hypot(wx - s * ex, wy - s * ey) / f;
}

// A shape whose bounding circle is (center, radius).
Shape random_shape(PortableRandom& rng, const RandomSceneOptions& o, Vec2 c, double radius) {
  int kinds[3];
  int n = 0;
  if (o.polygons) kinds[n++] = 0;
  if (o.circles) kinds[n++] = 1;
  if (o.segments) kinds[n++] = 2;
  const int kind = n == 0 ? 1 : kinds[rng.integer(0, n - 1)];
  if (kind == 1) return Circle{c, radius};
  if (kind == 2) {
    const double a = rng.uniform(0.0, kTwoPi);
    const double dx = radius * std::cos(a), dy = radius * std::sin(a);
    return Segment{{c.x - dx, c.y - dy}, {c.x + dx, c.y + dy}};
  }
  // Points on an ellipse in angular order are in convex position; a jittered
  // stratified choice of angles keeps them at least 0.2 * 2pi/n apart so that no
  // corner is nearly straight and the area is never close to zero.
  const int count = rng.integer(3, std::max(3, o.max_polygon_vertices));
  const double minor = radius * rng.uniform(0.3, 1.0);
  const double rotation = rng.uniform(0.0, kTwoPi);
  const double phase = rng.uniform(0.0, kTwoPi);
  const double cr = std::cos(rotation), sr = std::sin(rotation);
  Polygon poly;
  for (int k = 0; k < count; ++k) {
    const double t = phase + (k + 0.8 * rng.uniform()) * kTwoPi / count;
    const double ex = radius * std::cos(t), ey = minor * std::sin(t);
    poly.vertices.push_back({c.x + cr * ex - sr * ey, c.y + sr * ex + cr * ey});
  }
  if (rng.chance(0.5)) std::reverse(poly.vertices.begin(), poly.vertices.end());
  return poly;
}

// A random unit vector: uniform on the sphere, or in the upper hemisphere (z >= 0).
Vec3 random_unit(PortableRandom& rng, bool upper) {
  const double z = upper ? rng.uniform() : rng.uniform(-1.0, 1.0);
  const double a = rng.uniform(0.0, kTwoPi), r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(a), r * std::sin(a), z};
}

std::uint32_t random_mask(PortableRandom& rng) {
  // A few bits, so that some pairs share one and some do not; now and then all of them.
  constexpr std::uint32_t kMasks[] = {0xFFFFFFFFu, 1u, 2u, 3u, 4u, 6u};
  return kMasks[rng.integer(0, 5)];
}

double random_elevation(PortableRandom& rng) {
  const int pick = rng.integer(0, 4);
  return pick == 0 ? 0.0 : pick == 1 ? 90.0 : rng.uniform(0.0, 90.0);
}

// The section 6 terms RandomSceneOptions asks for, from their own generator.
void add_model_terms(std::uint32_t seed, const RandomSceneOptions& o, Scene& scene) {
  PortableRandom rng(seed ^ 0x6d2b79f5u);
  const double size = std::min(std::fabs(scene.view.x1 - scene.view.x0), std::fabs(scene.view.y1 - scene.view.y0));
  for (Light& light : scene.lights) {
    if (o.ranges && rng.chance(0.5)) {
      light.range = size * rng.uniform(0.2, 1.5);
      if (o.falloffs) {
        const int pick = rng.integer(0, 5);
        light.falloff = pick <= 2 ? pick : rng.uniform(0.0, 6.0);
      }
    }
    if (o.cones && rng.chance(0.5)) {
      Cone cone;
      cone.direction = rng.uniform(-360.0, 360.0);
      const int pick = rng.integer(0, 3);
      cone.half_angle = pick == 0 ? 180.0 : rng.uniform(10.0, 170.0);
      cone.fade = pick == 1 ? 0.0 : pick == 2 ? cone.half_angle : cone.half_angle * rng.uniform();
      light.cone = cone;
    }
    if (o.masks) light.mask = random_mask(rng);
    if (o.elevations) light.elevation = random_elevation(rng);
    if (o.normalizes && rng.chance(0.35)) light.normalize = size * rng.uniform(0.1, 2.0);
  }
  for (Occluder& occluder : scene.occluders) {
    if (o.translucent && rng.chance(0.5)) occluder.transmittance = {rng.uniform(), rng.uniform(), rng.uniform()};
    if (o.masks) occluder.mask = random_mask(rng);
    if (o.lit_interiors && rng.chance(0.35)) occluder.interior = Interior::lit;
  }
  for (int k = 0; k < o.directional_lights; ++k) {
    DirectionalLight sun;
    sun.angle0 = rng.uniform(-360.0, 360.0);
    sun.angle1 = sun.angle0 + (rng.chance(0.3) ? rng.uniform(1.0, 10.0) : rng.uniform(10.0, 350.0));
    sun.color = {rng.uniform(), rng.uniform(), rng.uniform()};
    sun.intensity = rng.uniform(o.min_intensity, o.max_intensity);
    if (o.masks) sun.mask = random_mask(rng);
    if (o.elevations) sun.elevation = random_elevation(rng);
    scene.directional_lights.push_back(sun);
  }
  if (o.ambient) scene.ambient = {0.2 * rng.uniform(), 0.2 * rng.uniform(), 0.2 * rng.uniform()};
  if (o.normals == RandomSceneOptions::Normals::constant) {
    scene.normal = random_unit(rng, false);
  } else if (o.normals == RandomSceneOptions::Normals::map) {
    NormalMap map;
    map.width = scene.width;
    map.height = scene.height;
    for (int p = 0; p < scene.width * scene.height; ++p) {
      // Mostly toward the viewer, as normal maps are; some facing away.
      const Vec3 n = random_unit(rng, !rng.chance(0.2));
      const double length = rng.uniform(0.5, 2.0);  // any non-zero length is allowed
      map.normals.insert(map.normals.end(), {static_cast<float>(length * n.x), static_cast<float>(length * n.y),
                                             static_cast<float>(length * n.z)});
    }
    scene.normal_map = std::move(map);
  }
}

// A value from the classes where arithmetic breaks, as a multiple of 1 (callers scale it).
double extreme_scale(PortableRandom& rng) {
  constexpr double kScales[] = {1e-300, 4e-310, 5e-324, 2.2250738585072014e-308, 1e-40, 1e-30, 1e-12, 1e300, 1e200};
  return kScales[rng.integer(0, 8)];
}

// The pass RandomSceneOptions::extreme_values asks for, from its own generator.
// Cookies, from a generator of their own after the other terms (which stay as they were):
// on lights without a cone, 1 to 6 knots over a random span, weights 0, 1 or between; with
// About 40 % of the lights: a shadow strength (some 0, some 1), half of them with a colour
// (some channels 0 or 1), from their own generator.
void add_shadows(std::uint32_t seed, const RandomSceneOptions& o, Scene& scene) {
  if (!o.shadows) return;
  PortableRandom rng(seed ^ 0x165667b1u);
  for (Light& light : scene.lights) {
    if (!rng.chance(0.4)) continue;
    const int pick = rng.integer(0, 3);
    light.shadow.strength = pick == 0 ? 0.0 : pick == 1 ? 1.0 : rng.uniform();
    if (rng.chance(0.5))
      for (double& c : light.shadow.color) {
        const int p = rng.integer(0, 3);
        c = p == 0 ? 0.0 : p == 1 ? 1.0 : rng.uniform();
      }
  }
}

// extreme_values, two knots 1 ulp to 1e-4 degrees apart, or a span just under 360.
void add_cookies(std::uint32_t seed, const RandomSceneOptions& o, Scene& scene) {
  if (!o.cookies) return;
  PortableRandom rng(seed ^ 0x27d4eb2fu);
  for (Light& light : scene.lights) {
    if (light.cone || !rng.chance(0.6)) continue;
    Cookie cookie;
    cookie.rotation = rng.uniform(-720.0, 720.0);
    const int count = rng.integer(1, 6);
    const double first = rng.uniform(-360.0, 360.0), span = rng.uniform(10.0, 350.0);
    for (int k = 0; k < count; ++k) {
      const int pick = rng.integer(0, 3);
      const double weight = pick == 0 ? 0.0 : pick == 1 ? 1.0 : rng.uniform();
      cookie.knots.push_back({first + span * (k + 0.8 * rng.uniform()) / count, weight});
    }
    if (o.extreme_values && count >= 2 && rng.chance(0.6)) {
      constexpr double kTinyAngles[] = {0.0, 1e-300, 1e-40, 1e-20, 1e-9, 1e-6, 1e-4};
      const int k = rng.integer(0, count - 2);
      const double d = cookie.knots[static_cast<std::size_t>(k)].direction;
      const double close = std::max(std::nextafter(d, 1e300), d + kTinyAngles[rng.integer(0, 6)]);
      const std::size_t next = static_cast<std::size_t>(k) + 1;
      if (next + 1 == cookie.knots.size() || close < cookie.knots[next + 1].direction) cookie.knots[next].direction = close;
    } else if (o.extreme_values && count >= 2 && rng.chance(0.5)) {
      cookie.knots.back().direction = std::nextafter(first + 360.0, -1e300);
      if (!(cookie.knots.back().direction - first < 360.0)) cookie.knots.back().direction = first + 359.999999;
    }
    light.cookie = std::move(cookie);
  }
}

void add_extreme_values(std::uint32_t seed, const RandomSceneOptions& o, Scene& scene) {
  if (!o.extreme_values) return;
  PortableRandom rng(seed ^ 0x1b873593u);
  const double size = std::min(std::fabs(scene.view.x1 - scene.view.x0), std::fabs(scene.view.y1 - scene.view.y0));
  constexpr double kTinyAngles[] = {5e-324, 1e-300, 1e-40, 1e-20, 1e-9, 1e-6, 1e-4};
  for (Light& light : scene.lights) {
    if (light.range && rng.chance(0.6)) light.range = std::clamp(size * extreme_scale(rng), 5e-324, 1e300);
    if (light.cone && rng.chance(0.7)) {
      Cone& cone = *light.cone;
      const int pick = rng.integer(0, 4);
      if (pick == 0) cone.fade = kTinyAngles[rng.integer(0, 6)];
      if (pick == 1) cone.fade = cone.half_angle - kTinyAngles[rng.integer(4, 6)] * cone.half_angle;
      if (pick == 2) {
        cone.half_angle = std::nextafter(180.0, 0.0);
        cone.fade = kTinyAngles[rng.integer(0, 6)];
      }
      if (pick == 3) {  // a cone narrower than float resolves, fade all of it or none
        cone.half_angle = kTinyAngles[rng.integer(0, 6)];
        cone.fade = rng.chance(0.5) ? cone.half_angle : 0.0;
      }
      if (pick == 4) cone.fade = std::max(0.0, cone.half_angle * (1.0 - 1e-12));
      cone.fade = std::min(cone.fade, cone.half_angle);
    }
    if (rng.chance(0.5)) {
      constexpr double kElevations[] = {0.0, 1e-300, 5e-324, 89.99999999999999, 90.0};
      light.elevation = kElevations[rng.integer(0, 4)];
    }
  }
  for (Occluder& occluder : scene.occluders) {
    if (occluder.transmittance != Rgb{0.0, 0.0, 0.0} && rng.chance(0.5)) {
      const int c = rng.integer(0, 2);
      occluder.transmittance[static_cast<std::size_t>(c)] = rng.chance(0.5) ? 5e-324 : std::nextafter(1.0, 0.0);
    }
  }
  for (DirectionalLight& sun : scene.directional_lights) {
    const int pick = rng.integer(0, 2);
    if (pick == 0) sun.angle1 = sun.angle0 + 1e-9 * std::max(1.0, std::fabs(sun.angle0));
    if (pick == 1) {  // just under 360 wide, as the validator measures the width (a1 - a0, rounded)
      sun.angle1 = std::nextafter(sun.angle0 + 360.0, sun.angle0);
      while (!(sun.angle1 - sun.angle0 < 360.0)) sun.angle1 = std::nextafter(sun.angle1, sun.angle0);
    }
    if (!(sun.angle1 > sun.angle0)) sun.angle1 = std::nextafter(sun.angle0, 1e300);
  }
  if (scene.ambient != Rgb{0.0, 0.0, 0.0} && rng.chance(0.5)) scene.ambient[0] = 5e-324;
  if (scene.normal) {
    const double k = extreme_scale(rng);
    Vec3 n = *scene.normal;
    if (rng.chance(0.3)) n.x = n.y = 0.0;  // only z left (a normal straight at or away from the viewer)
    scene.normal = Vec3{n.x * k, n.y * k, n.z * k};
    if (!(std::max({std::fabs(scene.normal->x), std::fabs(scene.normal->y), std::fabs(scene.normal->z)}) > 0.0))
      scene.normal = Vec3{0.0, 0.0, 5e-324};
  }
  if (scene.normal_map) {
    constexpr float kLengths[] = {1e-40f, 1e-30f, 1e-20f, 1e20f, 1e30f, 3e38f};
    std::vector<float>& v = scene.normal_map->normals;
    for (std::size_t p = 0; p + 2 < v.size(); p += 3) {
      if (!rng.chance(0.5)) continue;
      const float k = kLengths[rng.integer(0, 5)];
      // Scaled so the largest component is k (v's components are at most 2 in size).
      const float largest = std::max({std::fabs(v[p]), std::fabs(v[p + 1]), std::fabs(v[p + 2])});
      for (int c = 0; c < 3; ++c) v[p + c] = v[p + c] / largest * k;
      if (!(std::max({std::fabs(v[p]), std::fabs(v[p + 1]), std::fabs(v[p + 2])}) > 0.0f)) v[p + 2] = k;
    }
  }
}

}  // namespace

double PortableRandom::uniform() noexcept {
  // genrand_res53 from the reference Mersenne Twister: 27 + 26 bits.
  const double a = static_cast<double>(engine_() >> 5);
  const double b = static_cast<double>(engine_() >> 6);
  return (a * 67108864.0 + b) * (1.0 / 9007199254740992.0);
}

int PortableRandom::integer(int lo, int hi) noexcept {
  const int v = lo + static_cast<int>(std::floor(uniform() * (static_cast<double>(hi) - lo + 1.0)));
  return std::min(v, hi);
}

Scene random_scene(std::uint32_t seed, const RandomSceneOptions& o) {
  PortableRandom rng(seed);
  Scene scene;
  scene.width = o.width;
  scene.height = o.height;
  scene.view = o.view ? *o.view : View{0.0, 0.0, static_cast<double>(o.width), static_cast<double>(o.height)};
  const double x_lo = std::min(scene.view.x0, scene.view.x1), x_hi = std::max(scene.view.x0, scene.view.x1);
  const double y_lo = std::min(scene.view.y0, scene.view.y1), y_hi = std::max(scene.view.y0, scene.view.y1);
  const double w = x_hi - x_lo, h = y_hi - y_lo;
  const double size = std::min(w, h);
  const double gap = o.gap * size;

  const int n_lights = rng.integer(o.min_lights, std::max(o.min_lights, o.max_lights));
  const int n_occluders = rng.integer(o.min_occluders, std::max(o.min_occluders, o.max_occluders));

  auto draw_place = [&] {
    Placed p;
    p.center = {rng.uniform(x_lo - o.outside * w, x_hi + o.outside * w),
                rng.uniform(y_lo - o.outside * h, y_hi + o.outside * h)};
    p.radius = size * rng.uniform(o.min_size, o.max_size);
    return p;
  };

  std::vector<Placed> occluder_places;
  for (int k = 0; k < n_occluders; ++k) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      const Placed p = draw_place();
      const bool ok = o.occluders_may_overlap ||
                      std::all_of(occluder_places.begin(), occluder_places.end(),
                                  [&](const Placed& q) { return apart(p, q, gap); });
      if (!ok) continue;
      occluder_places.push_back(p);
      scene.occluders.push_back({random_shape(rng, o, p.center, p.radius)});
      break;
    }
  }
  for (int k = 0; k < n_lights; ++k) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      const Placed p = draw_place();
      const bool ok = !o.lights_disjoint_from_occluders ||
                      std::all_of(occluder_places.begin(), occluder_places.end(),
                                  [&](const Placed& q) { return apart(p, q, gap); });
      if (!ok) continue;
      Light light;
      light.shape = random_shape(rng, o, p.center, p.radius);
      light.color = {rng.uniform(), rng.uniform(), rng.uniform()};
      light.intensity = rng.uniform(o.min_intensity, o.max_intensity);
      scene.lights.push_back(light);
      break;
    }
  }
  add_model_terms(seed, o, scene);
  add_cookies(seed, o, scene);
  add_shadows(seed, o, scene);
  add_extreme_values(seed, o, scene);
  return scene;
}

RandomSceneOptions with_every_model_term(RandomSceneOptions o) {
  o.ranges = o.falloffs = o.normalizes = o.cones = o.cookies = o.shadows = o.masks = o.translucent = o.lit_interiors = o.ambient = o.elevations = true;
  o.directional_lights = 2;
  o.normals = RandomSceneOptions::Normals::map;
  return o;
}

double distance_to_boundary(const Shape& shape, Vec2 p) noexcept {
  if (const auto* c = std::get_if<Circle>(&shape)) {
    // |p - c|^2 - r^2 expanded exactly, over |p - c| + r: no cancellation for radii of 1e17.
    const double f = product_scale({p.x, p.y, c->center.x, c->center.y, c->radius});
    const Vec2 q{f * p.x, f * p.y}, m{f * c->center.x, f * c->center.y};
    const double power = detail::circle_power(m, f * c->radius, q);
    return std::fabs(power) / (std::hypot(q.x - m.x, q.y - m.y) + f * c->radius) / f;
  }
  if (const auto* s = std::get_if<Segment>(&shape)) return point_segment_distance(p, s->a, s->b);
  const auto& v = std::get<Polygon>(shape).vertices;
  double d = HUGE_VAL;
  for (std::size_t i = 0; i < v.size(); ++i)
    d = std::min(d, point_segment_distance(p, v[i], v[(i + 1) % v.size()]));
  return d;
}

bool near_boundary(const Scene& scene, Vec2 p, double dist) noexcept {
  for (const auto& l : scene.lights)
    if (distance_to_boundary(l.shape, p) <= dist) return true;
  for (const auto& o : scene.occluders)
    if (distance_to_boundary(o.shape, p) <= dist) return true;
  return false;
}

Vec2 pixel_center(const Scene& scene, int i, int j) noexcept {
  const View& v = scene.view;
  return {v.x0 + (i + 0.5) * (v.x1 - v.x0) / scene.width, v.y0 + (j + 0.5) * (v.y1 - v.y0) / scene.height};
}

double pixel_width(const Scene& scene) noexcept {
  const View& v = scene.view;
  return std::min(std::fabs(v.x1 - v.x0) / scene.width, std::fabs(v.y1 - v.y0) / scene.height);
}

double normalize_scale(const Light& l) noexcept {
  if (!l.normalize) return 1.0;
  double rho = 0.0;
  if (const auto* c = std::get_if<Circle>(&l.shape)) {
    rho = c->radius;
  } else if (const auto* s = std::get_if<Segment>(&l.shape)) {
    rho = std::hypot(s->b.x - s->a.x, s->b.y - s->a.y) / 2.0;
  } else {
    const auto& v = std::get<Polygon>(l.shape).vertices;
    double mx = 0.0, my = 0.0;
    for (const Vec2& p : v) mx += p.x, my += p.y;
    mx /= static_cast<double>(v.size());
    my /= static_cast<double>(v.size());
    for (const Vec2& p : v) rho = std::max(rho, std::hypot(p.x - mx, p.y - my));
  }
  return 3.14159265358979323846 / std::asin(std::min(1.0, rho / *l.normalize));
}

double emission_max_sum(const Scene& scene) noexcept {
  double sum = 0.0;
  for (const auto& l : scene.lights)
    sum += l.intensity * std::max({l.color[0], l.color[1], l.color[2]}) * normalize_scale(l);
  for (const auto& d : scene.directional_lights)
    sum += d.intensity * std::max({d.color[0], d.color[1], d.color[2]});
  return sum + std::max({scene.ambient[0], scene.ambient[1], scene.ambient[2]});
}

RenderedImage render_image(const Scene& scene, const RenderOptions& options, Status& status, bool raycast) {
  RenderedImage image;
  image.width = scene.width;
  image.height = scene.height;
  image.pixels.assign(static_cast<std::size_t>(scene.width) * scene.height * 3, -1.0f);
  const ImageView view{image.pixels.data(), scene.width, scene.height,
                       static_cast<std::ptrdiff_t>(scene.width) * 3};
  status = raycast ? render_raycast(scene, options, view) : render(scene, options, view);
  return image;
}

std::vector<Isa> simd_isas_here() {
  std::vector<Isa> isas;
  for (Isa isa : kSimdIsas)
    if (isa_supported(isa)) isas.push_back(isa);
  return isas;
}

RenderOptions options_for(Backend backend, std::optional<Isa> isa, bool culling) {
  RenderOptions o;
  o.backend = backend;
  o.isa = isa;
  o.culling = culling;
  o.threads = 2;
  return o;
}

}  // namespace par2d::test
