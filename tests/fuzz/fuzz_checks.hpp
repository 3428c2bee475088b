// The properties the fuzz targets check, shared with the corpus replay in tests/test_edge_cases.cpp.
//
// Each check takes arbitrary bytes and returns an empty string when every property holds,
// otherwise one line saying what broke. The libFuzzer targets abort on a non-empty answer;
// the doctest replay turns it into a failed CHECK, so every corpus file is a regression test.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "geometry/polygon_partition.hpp"
#include "scene/scene_validate.hpp"
#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"

namespace par2d::fuzz {

// Loader: any bytes give either a scene that validate_scene accepts, or a refusal whose
// message is one non-empty line naming the file.
inline std::string check_scene_text(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  const Status parsed = parse_scene(text, "fuzz.json", scene);
  if (parsed.ok()) {
    const Status valid = validate_scene(scene, "fuzz.json");
    if (!valid.ok()) return "parse_scene accepted a scene that validate_scene refuses: " + valid.message();
    return {};
  }
  const std::string& m = parsed.message();
  if (parsed.code() != StatusCode::invalid_scene && parsed.code() != StatusCode::out_of_memory)
    return "parse_scene failed with an unexpected code: " + std::string(status_code_name(parsed.code()));
  if (m.rfind("fuzz.json: ", 0) != 0) return "refusal does not name the file: " + m;
  if (m.size() <= 11) return "refusal without a reason: " + m;
  if (m.find('\n') != std::string::npos || m.find('\r') != std::string::npos)
    return "refusal message is not one line";
  return {};
}

// Reads the fuzz input as a stream of small numbers; past its end every read is 0, so any
// input, however short, decodes to some scene.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  unsigned byte() noexcept { return pos_ < size_ ? data_[pos_++] : 0u; }
  unsigned u16() noexcept { return byte() | (byte() << 8); }
  int signed_byte() noexcept { return static_cast<int>(byte()) - 128; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Scene decoded from fuzz bytes. Coordinates sit on a quarter-pixel grid around a chosen
// origin, so coincident, collinear and touching shapes are common; scale (world units per
// pixel) and origin reach 1e-3 .. 1e15 and far from zero.
struct FuzzScene {
  Scene scene;
  std::size_t polygon_vertices = 0;  // total, to keep the ray caster's cost bounded
  int threads = 1;
  int spp = 1;
  int rays = 16;
};

inline Shape decode_shape(ByteReader& in, double origin_x, double origin_y, double scale) {
  auto grid_x = [&] { return origin_x + scale * in.signed_byte() / 4.0; };
  auto grid_y = [&] { return origin_y + scale * in.signed_byte() / 4.0; };
  switch (in.byte() % 11) {
    case 0: {  // ordinary circle
      const Vec2 c{grid_x(), grid_y()};
      return Circle{c, scale * (in.byte() + 1) / 8.0};
    }
    case 1: {  // tiny circle
      const Vec2 c{grid_x(), grid_y()};
      return Circle{c, scale * 1e-7 * (in.byte() + 1)};
    }
    case 2: {
      const Vec2 a{grid_x(), grid_y()};
      const Vec2 b{grid_x(), grid_y()};
      return Segment{a, b};
    }
    case 3: {  // free polygon: often not convex (then an occluder only) or not simple (left out)
      Polygon p;
      const unsigned n = 3 + in.byte() % 6;
      for (unsigned k = 0; k < n; ++k) {
        const double x = grid_x();
        p.vertices.push_back({x, grid_y()});
      }
      return p;
    }
    case 4: {  // regular n-gon, up to thousands of vertices, maybe repeated or collinear ones
      const unsigned n = 3 + in.u16() % 4000;
      const Vec2 c{grid_x(), grid_y()};
      const double r = scale * (in.byte() + 1) / 4.0;
      const double phase = in.byte() * (2.0 * detail::kPi / 256.0);
      const unsigned flags = in.byte();
      Polygon p;
      for (unsigned k = 0; k < n; ++k) {
        const double a = phase + 2.0 * detail::kPi * k / n;
        const Vec2 v{c.x + r * std::cos(a), c.y + r * std::sin(a)};
        p.vertices.push_back(v);
        if (flags & 1) p.vertices.push_back(v);  // repeated vertex
        if (flags & 2) {                          // midpoint: a collinear vertex
          const double b = phase + 2.0 * detail::kPi * (k + 1) / n;
          const Vec2 w{c.x + r * std::cos(b), c.y + r * std::sin(b)};
          p.vertices.push_back({0.5 * (v.x + w.x), 0.5 * (v.y + w.y)});
        }
      }
      if (flags & 4) std::reverse(p.vertices.begin(), p.vertices.end());
      return p;
    }
    case 5: {  // axis-aligned rectangle: shared edges and corners with its neighbours
      const double x0 = grid_x(), y0 = grid_y(), x1 = grid_x(), y1 = grid_y();
      return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
    }
    case 6: {  // huge circle, far larger than the view
      const Vec2 c{grid_x(), grid_y()};
      return Circle{c, scale * 1e6 * (in.byte() + 1)};
    }
    case 7: {  // far away circle
      const Vec2 c{origin_x + scale * 1e6 * in.signed_byte(), origin_y + scale * 1e6 * in.signed_byte()};
      return Circle{c, scale * (in.byte() + 1)};
    }
    case 9: {  // comb: a ray along its base enters every tooth (a concave light counts each entry)
      const unsigned teeth = 2 + in.byte() % 40;
      const double w = scale * (in.byte() % 8 + 1) / 4.0, gap = scale * (in.byte() % 8 + 1) / 4.0;
      const double base = scale * (in.byte() % 8 + 1) / 4.0, height = scale * (in.byte() + 1) / 4.0;
      const Vec2 o{grid_x(), grid_y()};
      const bool transpose = in.byte() & 1;
      const auto at = [&](double x, double y) { return transpose ? Vec2{o.x + y, o.y + x} : Vec2{o.x + x, o.y + y}; };
      const double right = teeth * w + (teeth - 1) * gap;
      Polygon p;
      p.vertices = {at(0, 0), at(right, 0), at(right, base + height)};
      for (unsigned k = teeth - 1; k >= 1; --k) {
        const double x = k * (w + gap);
        p.vertices.insert(p.vertices.end(), {at(x, base + height), at(x, base), at(x - gap, base), at(x - gap, base + height)});
      }
      p.vertices.push_back(at(0, base + height));
      return p;
    }
    case 10: {  // a chain of near-straight turns (each within the 1e-9 tolerance) that add up
      // to a dent (against the winding) or a bulge, a few pixels deep, closed far away.
      const unsigned n = 3 + in.u16() % 2000;
      const double turn = (in.signed_byte() + 0.5) / 128.0 * 1e-9;
      const double depth = scale * (in.byte() + 1) / 16.0;
      const double total = turn * (n - 1);
      const double length = 8.0 * depth / std::fabs(total);
      const Vec2 o{grid_x(), grid_y()};
      Polygon p;
      Vec2 v{o.x - 0.5 * length, o.y};
      double heading = 0.5 * total;
      for (unsigned k = 0; k < n; ++k) {
        p.vertices.push_back(v);
        v = {v.x + length / (n - 1) * std::cos(heading), v.y + length / (n - 1) * std::sin(heading)};
        heading -= turn;
      }
      p.vertices.push_back({p.vertices.back().x, o.y + 0.25 * length});
      p.vertices.push_back({p.vertices.front().x, o.y + 0.25 * length});
      if (in.byte() & 1) std::reverse(p.vertices.begin(), p.vertices.end());
      return p;
    }
    default: {  // thin sliver triangle
      const Vec2 a{grid_x(), grid_y()};
      const Vec2 b{grid_x(), grid_y()};
      const double t = scale * 1e-6 * (in.byte() + 1);
      return Polygon{{a, b, {b.x + t, b.y - t}}};
    }
  }
}

// The lighting model's terms (docs/contract.md section 6), after the shapes: one byte of flags,
// then each term's values from the classes where arithmetic breaks (subnormals, 1e-300 and
// 1e300 next to ordinary values, the keys' own boundaries). An input that ends before the flags
// reads 0 there: no term, so the corpus from before the terms decodes as it did.
inline void decode_model_terms(ByteReader& in, double scale, Scene& s) {
  const unsigned flags = in.byte();
  if (flags == 0) return;
  // Multiples of the pixel size; 1e300 and beyond are taken as they are (not times the scale).
  static constexpr double kRanges[] = {5e-324, 4e-310, 1e-300, 1e-40, 1e-6, 0.5, 4.0, 64.0, 1e6, 1e300};
  static constexpr double kAngles[] = {5e-324, 1e-300, 1e-40, 1e-9, 1e-6, 1e-4, 0.5, 10.0, 45.0, 90.0, 179.0, 180.0};
  static constexpr double kFadeParts[] = {0.0, 5e-324, 1e-300, 1e-12, 1e-6, 0.25, 1.0 - 1e-15, 1.0};
  static constexpr double kElevations[] = {0.0, 5e-324, 1e-300, 30.0, 60.0, 89.99999999999999, 90.0};
  static constexpr double kParts[] = {0.0, 5e-324, 1e-300, 0.25, 0.5, 0.9999999999999999, 1.0};
  static constexpr double kNormalScales[] = {5e-324, 1e-310, 1e-300, 1.0, 1e300, 1e307};
  static constexpr std::uint32_t kMasks[] = {0xFFFFFFFFu, 1u, 2u, 3u, 0u};
  const auto pick = [&in](const auto& table) { return table[in.byte() % (sizeof(table) / sizeof(table[0]))]; };
  for (Light& light : s.lights) {
    if (flags & 1) {
      const double r = pick(kRanges);
      if (in.byte() & 1) light.range = r >= 1e300 ? r : std::max(r * scale, 5e-324);
    }
    if ((flags & 2) && (in.byte() & 1)) {
      Cone cone;
      cone.direction = (static_cast<double>(in.u16()) - 32768.0) * (360.0 / 4096.0);
      cone.half_angle = pick(kAngles);
      cone.fade = std::min(cone.half_angle, cone.half_angle * pick(kFadeParts));
      light.cone = cone;
    }
    if (flags & 4) light.elevation = pick(kElevations);
    if (flags & 16) light.mask = pick(kMasks);
  }
  for (Occluder& occluder : s.occluders) {
    if (flags & 8) {
      for (double& t : occluder.transmittance) t = pick(kParts);
      if (in.byte() & 1) occluder.interior = Interior::lit;
    }
    if (flags & 16) occluder.mask = pick(kMasks);
  }
  if (flags & 32) {
    for (double& a : s.ambient) a = pick(kParts);
  }
  if (flags & 64) {
    DirectionalLight sun;
    sun.angle0 = (static_cast<double>(in.u16()) - 32768.0) * (360.0 / 4096.0);
    static constexpr double kWidths[] = {1e-9, 1e-3, 10.0, 180.0, 359.0, 359.99999999999};
    sun.angle1 = sun.angle0 + pick(kWidths);
    sun.color = {in.byte() / 255.0, in.byte() / 255.0, in.byte() / 255.0};
    sun.intensity = in.byte() / 16.0;
    if (flags & 4) sun.elevation = pick(kElevations);
    if (flags & 16) sun.mask = pick(kMasks);
    s.directional_lights.push_back(sun);
  }
  if (flags & 128) {
    const double k = pick(kNormalScales);
    Vec3 n{in.signed_byte() / 128.0 * k, in.signed_byte() / 128.0 * k, in.signed_byte() / 128.0 * k};
    if (!(std::max({std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)}) > 0.0)) n = {0.0, 0.0, k};
    s.normal = n;
  }
  // Cookies and shadows, from a second flags byte at the end (inputs from before them read 0
  // here). Cookies: on lights without a cone, 1 to 6 knots, 1 ulp to a quarter turn apart
  // within a turn.
  const unsigned more = in.byte();
  if (more & 1) {
    static constexpr double kSteps[] = {0.0, 1e-300, 1e-9, 1e-4, 0.5, 10.0, 45.0, 90.0};
    for (Light& light : s.lights) {
      if (light.cone || !(in.byte() & 1)) continue;
      Cookie cookie;
      cookie.rotation = (static_cast<double>(in.u16()) - 32768.0) * (360.0 / 4096.0);
      const double first = (static_cast<double>(in.u16()) - 32768.0) * (360.0 / 4096.0);
      double direction = first;
      const int count = 1 + in.byte() % 6;
      for (int k = 0; k < count; ++k) {
        if (k > 0) direction = std::max(std::nextafter(direction, 1e300), direction + pick(kSteps));
        if (!(direction - first < 360.0)) break;
        cookie.knots.push_back({direction, pick(kParts)});
      }
      light.cookie = std::move(cookie);
    }
  }
  // Shadow strength and colour at their boundaries and 1 ulp inside them (a light split into
  // a shadowed part and one with a subnormal emission).
  if (more & 2) {
    for (Light& light : s.lights) {
      light.shadow.strength = pick(kParts);
      for (double& c : light.shadow.color) c = pick(kParts);
    }
  }
  // Angles of 7e13 .. 2e21 degrees, either sign, in place of the cone directions, cookie
  // rotations and first knots and the directional angles drawn above (the knots keep their
  // offsets, the sky its width, where those stay exact): check_angle_residues.
  if (more & 4) {
    const auto huge = [&in] {
      const double a = std::ldexp(1.0 + in.byte() / 256.0 + in.byte() / 65536.0, 46 + static_cast<int>(in.byte() % 25));
      return (in.byte() & 1) ? -a : a;
    };
    for (Light& light : s.lights) {
      if (light.cone) light.cone->direction = huge();
      if (!light.cookie) continue;
      light.cookie->rotation = huge();
      std::vector<CookieKnot> moved = light.cookie->knots;
      const double first = huge();
      bool valid = true;
      for (std::size_t k = 0; k < moved.size(); ++k) {
        moved[k].direction = first + (light.cookie->knots[k].direction - light.cookie->knots[0].direction);
        valid = valid && (k == 0 || moved[k].direction > moved[k - 1].direction);
      }
      if (valid && moved.back().direction - moved.front().direction < 360.0) light.cookie->knots = std::move(moved);
    }
    for (DirectionalLight& sun : s.directional_lights) {
      const double a0 = huge(), a1 = a0 + (sun.angle1 - sun.angle0);
      if (a0 < a1 && a1 - a0 < 360.0) sun.angle0 = a0, sun.angle1 = a1;
    }
  }
}

// Shapes with many vertices, from a byte after the terms (inputs from before them read 0): a
// comb of up to 4096 teeth (16,386 vertices) along x, along y or slanted, and a triangle with
// up to 65,535 collinear vertices on each edge; each a light or an occluder.
inline void decode_many_vertices(ByteReader& in, double origin, double scale, Scene& s) {
  const unsigned flags = in.byte();
  if (flags & 1) {
    const unsigned teeth = 1 + in.u16() % 4096;
    const double pitch = scale * (1 + in.byte() % 8) / 16.0, height = scale * (1 + in.byte() % 32) / 4.0;
    const Vec2 at{origin + scale * in.signed_byte() / 4.0, origin + scale * in.signed_byte() / 4.0};
    const unsigned axis = in.byte() % 3;  // teeth pointing along y, along x, or along (4, 3) / 5
    Polygon comb;
    auto put = [&](double u, double v) {
      const Vec2 p = axis == 0 ? Vec2{u, v} : axis == 1 ? Vec2{v, u} : Vec2{0.8 * u - 0.6 * v, 0.6 * u + 0.8 * v};
      comb.vertices.push_back({at.x + p.x, at.y + p.y});
    };
    put(0.0, 0.0);
    for (unsigned k = 0; k < teeth; ++k) {
      const double u = 2.0 * pitch * k;
      put(u, height);
      put(u + pitch, height);
      put(u + pitch, 0.25 * height);
      put(u + 2.0 * pitch, 0.25 * height);
    }
    put(2.0 * pitch * teeth, 0.0);
    if (flags & 2) {
      Light light;
      light.shape = std::move(comb);
      light.intensity = (1 + in.byte()) / 64.0;
      s.lights.push_back(std::move(light));
    } else {
      s.occluders.push_back(Occluder{std::move(comb)});
    }
  }
  if (flags & 4) {
    const unsigned n = in.u16();
    const Vec2 a{origin + scale * in.signed_byte() / 4.0, origin + scale * in.signed_byte() / 4.0};
    const Vec2 b{origin + scale * in.signed_byte() / 4.0, origin + scale * in.signed_byte() / 4.0};
    const Vec2 c{origin + scale * in.signed_byte() / 4.0, origin + scale * in.signed_byte() / 4.0};
    Polygon triangle;
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      for (unsigned k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / (n + 1.0);
        triangle.vertices.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
      }
    if (flags & 8) {
      Light light;
      light.shape = std::move(triangle);
      light.intensity = (1 + in.byte()) / 64.0;
      s.lights.push_back(std::move(light));
    } else {
      s.occluders.push_back(Occluder{std::move(triangle)});
    }
  }
}

inline FuzzScene decode_scene(ByteReader& in) {
  static constexpr double kScales[] = {1.0, 1e-3, 0.05, 1e3, 1e7, 1e15};
  static constexpr double kOrigins[] = {0.0, 0.0, 1e5, -1e7, 1e7, 1e15};
  FuzzScene f;
  Scene& s = f.scene;
  s.width = 1 + static_cast<int>(in.byte() % 24);
  s.height = 1 + static_cast<int>(in.byte() % 24);
  const double scale = kScales[in.byte() % 6];
  const double origin = kOrigins[in.byte() % 6];
  const unsigned view_flags = in.byte();
  f.threads = (view_flags & 4) ? 2 : 1;
  f.spp = (view_flags & 8) ? 1 + static_cast<int>(in.byte() % 4) : 1;
  f.rays = 1 + static_cast<int>(in.byte() % 64);
  // A shape that validate_scene refuses is left out, so that most inputs still render.
  // (A light must be convex; an occluder may be concave.)
  auto accepted = [&](const Shape& shape, bool light) {
    Scene probe;
    probe.width = probe.height = 1;
    probe.view = {0, 0, 1, 1};
    if (light) probe.lights.push_back({shape});
    else probe.occluders.push_back({shape});
    return validate_scene(probe).ok();
  };
  const unsigned lights = in.byte() % 5, occluders = in.byte() % 7;
  for (unsigned k = 0; k < lights; ++k) {
    Light light;
    light.shape = decode_shape(in, origin, origin, scale);
    light.color = {in.byte() / 255.0, in.byte() / 255.0, in.byte() / 255.0};
    light.intensity = in.byte() / 16.0;
    if (accepted(light.shape, true)) s.lights.push_back(light);
  }
  for (unsigned k = 0; k < occluders; ++k) {
    Occluder occluder{decode_shape(in, origin, origin, scale)};
    if (accepted(occluder.shape, false)) s.occluders.push_back(occluder);
  }
  decode_model_terms(in, scale, s);
  {
    Scene many;
    decode_many_vertices(in, origin, scale, many);
    for (Light& light : many.lights)
      if (accepted(light.shape, true)) s.lights.push_back(std::move(light));
    for (Occluder& occluder : many.occluders)
      if (accepted(occluder.shape, false)) s.occluders.push_back(std::move(occluder));
  }
  for (const Light& l : s.lights)
    if (const auto* p = std::get_if<Polygon>(&l.shape)) f.polygon_vertices += p->vertices.size();
  for (const Occluder& o : s.occluders)
    if (const auto* p = std::get_if<Polygon>(&o.shape)) f.polygon_vertices += p->vertices.size();
  // One input's work kept within what the gate's timeout allows under the sanitizers: the
  // scalar reference measures every polygon vertex at every sample (FINDINGS.md #14: eleven
  // 12000-vertex polygons at 24x24 pixels and 4 samples took over 25 s). Fewer samples, then
  // fewer pixels (the same units per pixel), until samples x vertices fit.
  constexpr double kMaxSampleVertices = 2e7;
  const auto work = [&] {
    return static_cast<double>(s.width) * s.height * f.spp * static_cast<double>(std::max<std::size_t>(f.polygon_vertices, 1));
  };
  if (work() > kMaxSampleVertices) f.spp = 1;
  while (work() > kMaxSampleVertices && (s.width > 1 || s.height > 1)) {
    s.width = (s.width + 1) / 2;
    s.height = (s.height + 1) / 2;
  }
  s.view = {origin, origin, origin + scale * s.width, origin + scale * s.height};
  if (view_flags & 1) std::swap(s.view.x0, s.view.x1);
  if (view_flags & 2) std::swap(s.view.y0, s.view.y1);
  return f;
}

// Whether every light is apart from every occluder by more than the contact tolerance
// (meets_within_contact: closer pairs count as touching): docs/contract.md section 5 needs it.
// Shapes are scaled by one power of two (exact) that brings every coordinate to 2^500 or
// below, as the renderers do: the distance code squares coordinates, and 1e300 squared is inf.
inline bool lights_disjoint_from_occluders(const Scene& scene) {
  double largest = 0.0;
  auto grow = [&](const Shape& shape) {
    if (const auto* c = std::get_if<Circle>(&shape))
      largest = std::max({largest, std::fabs(c->center.x) + c->radius, std::fabs(c->center.y) + c->radius});
    else if (const auto* g = std::get_if<Segment>(&shape))
      largest = std::max({largest, std::fabs(g->a.x), std::fabs(g->a.y), std::fabs(g->b.x), std::fabs(g->b.y)});
    else
      for (Vec2 v : std::get<Polygon>(shape).vertices) largest = std::max({largest, std::fabs(v.x), std::fabs(v.y)});
  };
  for (const Light& l : scene.lights) grow(l.shape);
  for (const Occluder& o : scene.occluders) grow(o.shape);
  int exponent = 0;
  std::frexp(largest, &exponent);
  const double f = exponent > 500 ? std::ldexp(1.0, 500 - exponent) : 1.0;
  auto scaled = [f](Shape shape) {
    if (auto* c = std::get_if<Circle>(&shape)) {
      c->center = {f * c->center.x, f * c->center.y};
      c->radius *= f;
    } else if (auto* g = std::get_if<Segment>(&shape)) {
      g->a = {f * g->a.x, f * g->a.y};
      g->b = {f * g->b.x, f * g->b.y};
    } else {
      for (Vec2& v : std::get<Polygon>(shape).vertices) v = {f * v.x, f * v.y};
    }
    return detail::make_convex_shape(shape);
  };
  // A concave (or holed) shape meets another where one of its convex pieces does.
  const auto pieces_of = [](const Shape& shape, std::vector<Shape>& out) {
    std::vector<Polygon> pieces;
    std::string error;
    if (detail::needs_partition(shape) && detail::partition_polygon(std::get<Polygon>(shape), pieces, error))
      out.insert(out.end(), pieces.begin(), pieces.end());
    else
      out.push_back(shape);
  };
  std::vector<Shape> occluder_pieces, light_pieces;
  for (const Occluder& o : scene.occluders) pieces_of(o.shape, occluder_pieces);
  for (const Light& l : scene.lights) pieces_of(l.shape, light_pieces);
  for (const Shape& l : light_pieces) {
    const detail::ConvexShape ls = scaled(l);
    for (const Shape& o : occluder_pieces)
      if (detail::meets_within_contact(ls, scaled(o))) return false;
  }
  return true;
}

// Finite, 0 <= E <= sum of e_L per channel, a concave light's times the most entries a ray
// can make into it (float rounding allowed).
inline std::string check_bounds(const Scene& scene, const test::RenderedImage& image, const char* what) {
  // Every weight of the lighting model (window, cone, shading, transmittance) is in [0, 1]. A
  // concave light counts once per entry (docs/contract.md section 3): a ray crosses each of
  // its edges at most once and enters at every other crossing, or at 0 from inside it.
  double sum[3] = {scene.ambient[0], scene.ambient[1], scene.ambient[2]};
  for (const Light& l : scene.lights) {
    double entries = 1.0;
    if (detail::needs_partition(l.shape)) {
      const Polygon& p = std::get<Polygon>(l.shape);
      double edges = static_cast<double>(p.vertices.size());
      for (const std::vector<Vec2>& hole : p.holes) edges += static_cast<double>(hole.size());
      entries = 1.0 + std::floor(0.5 * edges);
    }
    for (int c = 0; c < 3; ++c) sum[c] += entries * l.intensity * l.color[c];
  }
  for (const DirectionalLight& d : scene.directional_lights)
    for (int c = 0; c < 3; ++c) sum[c] += d.intensity * d.color[c];
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i)
      for (int c = 0; c < 3; ++c) {
        const float e = image.at(i, j, c);
        if (!std::isfinite(e) || e < 0.0f || e > sum[c] * (1.0 + 1e-5) + 1e-6) {
          std::ostringstream out;
          out.precision(17);
          out << what << ": pixel (" << i << ", " << j << ") channel " << c << " is " << e
              << ", outside [0, " << sum[c] << "]";
          return out.str();
        }
      }
  return {};
}

// Renders a decoded scene with every backend (scalar, SIMD at each ISA this CPU has,
// ray casting) and checks status, bounds and SIMD-vs-scalar agreement (docs/contract.md section 5).
// `compare_simd`: false leaves out the SIMD-vs-scalar comparison (bounds and finiteness are
// still checked on every backend).
inline std::string check_render_scene(const FuzzScene& f, bool compare_simd = true) {
  const Scene& scene = f.scene;
  const Status valid = validate_scene(scene);
  if (!valid.ok()) return {};  // only scenes validate_scene accepts are rendered

  RenderOptions base;
  base.threads = f.threads;
  base.spp = f.spp;
  Status status;
  RenderOptions scalar_options = base;
  scalar_options.backend = Backend::scalar;
  const test::RenderedImage scalar = test::render_image(scene, scalar_options, status);
  if (!status.ok()) return "scalar render failed: " + status.message();
  if (std::string p = check_bounds(scene, scalar, "scalar"); !p.empty()) return p;

  // Both paths sample the same double-rounded pixel centers (FINDINGS.md #3, fixed), but
  // where a pixel is narrower than ~1e-9 of the view's coordinates (0.04-unit pixels at 1e15)
  // segment lights still differ beyond the bound (FINDINGS.md #6, open): the comparison is
  // skipped there; bounds and finiteness are still checked.
  const double magnitude = std::max({std::fabs(scene.view.x0), std::fabs(scene.view.x1), std::fabs(scene.view.y0),
                                     std::fabs(scene.view.y1)});
  const bool resolvable = test::pixel_width(scene) >= 1e-9 * magnitude;
  const bool compare = compare_simd && f.spp == 1 && resolvable && lights_disjoint_from_occluders(scene);
  // docs/contract.md section 5: a concave (or holed) light adds 2e-6 e_L per vertex of its
  // rings to the bound (its pieces and their shared boundaries each carry float error; FINDINGS.md #18).
  double tolerance = 1e-4 * test::emission_max_sum(scene);
  for (const Light& l : scene.lights) {
    if (!detail::needs_partition(l.shape)) continue;
    const Polygon& p = std::get<Polygon>(l.shape);
    double vertices = static_cast<double>(p.vertices.size());
    for (const std::vector<Vec2>& hole : p.holes) vertices += static_cast<double>(hole.size());
    tolerance += 2e-6 * vertices * std::max({l.intensity * l.color[0], l.intensity * l.color[1], l.intensity * l.color[2]});
  }
  const double near = 0.05 * test::pixel_width(scene);
  for (Isa isa : kSimdIsas) {
    if (!isa_supported(isa)) continue;
    RenderOptions o = base;
    o.backend = Backend::simd;
    o.isa = isa;
    const test::RenderedImage simd = test::render_image(scene, o, status);
    const std::string what = std::string("simd ") + isa_name(isa);
    if (!status.ok()) return what + " render failed: " + status.message();
    if (std::string p = check_bounds(scene, simd, what.c_str()); !p.empty()) return p;
    if (!compare) continue;
    for (int j = 0; j < scene.height; ++j)
      for (int i = 0; i < scene.width; ++i) {
        if (test::near_boundary(scene, test::pixel_center(scene, i, j), near)) continue;
        for (int c = 0; c < 3; ++c) {
          const double diff = std::fabs(double(simd.at(i, j, c)) - double(scalar.at(i, j, c)));
          if (!(diff <= tolerance)) {
            std::ostringstream out;
            out.precision(17);
            out << what << " differs from scalar at pixel (" << i << ", " << j << ") channel " << c << ": "
                << simd.at(i, j, c) << " vs " << scalar.at(i, j, c) << ", bound " << tolerance;
            return out.str();
          }
        }
      }
  }

  if (f.polygon_vertices <= 256) {  // the ray caster is O(rays * vertices) per pixel
    RenderOptions o = base;
    o.rays = f.rays;
    const test::RenderedImage rays = test::render_image(scene, o, status, /*raycast=*/true);
    if (!status.ok()) return "raycast render failed: " + status.message();
    if (std::string p = check_bounds(scene, rays, "raycast"); !p.empty()) return p;
  }
  return {};
}

// Angles past a turn light a scene exactly as their residues modulo 360 (std::fmod, exact) do:
// the scalar path, the SIMD path at each level here and, for few vertices, the ray caster give
// the same bits for both. The reduced cookie keeps its knots' offsets from the first and the
// reduced sky its width; a scene where those would round is not compared.
inline std::string check_angle_residues(const FuzzScene& f) {
  Scene reduced = f.scene;
  bool changed = false, exact = true;
  const auto reduce = [&changed](double& angle) {
    const double r = std::fmod(angle, 360.0);
    changed = changed || r != angle;
    angle = r;
  };
  for (Light& light : reduced.lights) {
    if (light.cone) reduce(light.cone->direction);
    if (!light.cookie) continue;
    reduce(light.cookie->rotation);
    std::vector<CookieKnot>& knots = light.cookie->knots;
    const double first = knots[0].direction;
    double start = first;
    reduce(start);
    for (CookieKnot& knot : knots) {
      const double offset = knot.direction - first;
      knot.direction = start + offset;
      exact = exact && knot.direction - start == offset;
    }
  }
  for (DirectionalLight& sun : reduced.directional_lights) {
    const double width = sun.angle1 - sun.angle0;
    reduce(sun.angle0);
    sun.angle1 = sun.angle0 + width;
    exact = exact && sun.angle1 - sun.angle0 == width;
  }
  if (!changed || !exact || !validate_scene(f.scene).ok() || !validate_scene(reduced).ok()) return {};
  std::vector<RenderOptions> backends;
  RenderOptions o;
  o.threads = f.threads;
  o.spp = f.spp;
  o.backend = Backend::scalar;
  backends.push_back(o);
  for (Isa isa : kSimdIsas) {
    if (!isa_supported(isa)) continue;
    o.backend = Backend::simd;
    o.isa = isa;
    backends.push_back(o);
  }
  const std::size_t renderers = backends.size();  // the ray caster's options follow
  if (f.polygon_vertices <= 256) {  // the ray caster is O(rays * vertices) per pixel
    o.backend = Backend::scalar;
    o.rays = f.rays;
    backends.push_back(o);
  }
  for (std::size_t b = 0; b < backends.size(); ++b) {
    const RenderOptions& options = backends[b];
    const bool raycast = b >= renderers;
    Status status;
    const test::RenderedImage huge = test::render_image(f.scene, options, status, raycast);
    if (!status.ok()) return "render failed: " + status.message();
    const test::RenderedImage small = test::render_image(reduced, options, status, raycast);
    if (!status.ok()) return "render of the reduced angles failed: " + status.message();
    for (std::size_t k = 0; k < huge.pixels.size(); ++k)
      if (!(huge.pixels[k] == small.pixels[k] || (std::isnan(huge.pixels[k]) && std::isnan(small.pixels[k])))) {
        std::ostringstream out;
        out.precision(17);
        out << (raycast ? "raycast" : backend_name(options.backend))
            << (!raycast && options.backend == Backend::simd ? std::string(" ") + isa_name(*options.isa) : "")
            << ": angles past a turn differ from their residues at value " << k << ": " << huge.pixels[k] << " vs "
            << small.pixels[k];
        return out.str();
      }
  }
  return {};
}

inline std::string check_render_bytes(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const FuzzScene f = decode_scene(in);
  if (std::string p = check_render_scene(f); !p.empty()) return p;
  return check_angle_residues(f);
}

}  // namespace par2d::fuzz
