// Scenes for the huge-shape fuzz target (shapes 1e3..1e306 times the view, huge emissions), shared with the corpus replay.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz/fuzz_checks.hpp"

namespace par2d::fuzz {

// A scene decoded from bytes whose shapes are mostly far larger than the view and pass
// through it or near it: slanted segments, half-plane-like triangles and quadrilaterals, and
// circles of radius 2^10 .. 2^1000 pixels (coordinates stay within the contract's ~1e307),
// each through a quarter-pixel grid point of the view, so that their edges cross pixels at
// every angle; lights and occluders touch or lie along each other often (the same huge line
// shared by a light and an occluder). Emissions reach 2^123 (~1e37) each; the total limit
// refuses some scenes, which are skipped. Views are 1e-200 .. 1e200 units per pixel.
inline FuzzScene decode_huge_scene(ByteReader& in) {
  static constexpr double kScales[] = {1.0, 1e-3, 0.37, 1e5, 1e-200, 1e200};
  FuzzScene f;
  Scene& s = f.scene;
  s.width = 1 + static_cast<int>(in.byte() % 16);
  s.height = 1 + static_cast<int>(in.byte() % 16);
  const double scale = kScales[in.byte() % 6];
  const double origin = scale * in.signed_byte() * 2.0;
  const unsigned view_flags = in.byte();
  s.view = {origin, origin, origin + scale * s.width, origin + scale * s.height};
  if (view_flags & 1) std::swap(s.view.x0, s.view.x1);
  if (view_flags & 2) std::swap(s.view.y0, s.view.y1);
  f.threads = (view_flags & 4) ? 2 : 1;
  f.rays = 1 + static_cast<int>(in.byte() % 32);
  // Extents up to scale * 2^top: at most ~1e305, so that vertices (up to 16 extents from
  // the view) stay within the contract's ~1e307; at most 2^1010 pixels.
  const int top = std::min(std::ilogb(1e305) - std::ilogb(scale), 1010);
  auto grid = [&] { return Vec2{origin + scale * (8.0 + in.signed_byte() / 16.0), origin + scale * (8.0 + in.signed_byte() / 16.0)}; };
  auto extent = [&] { return scale * std::ldexp(1.0, 10 + static_cast<int>(in.byte() * 4 % static_cast<unsigned>(top - 9))); };
  // A direction from a small integer pair (never zero): slopes are exact rationals.
  auto direction = [&] {
    const int x = static_cast<int>(in.byte() % 17) - 8, y = static_cast<int>(in.byte() % 17) - 8;
    return (x == 0 && y == 0) ? Vec2{3.0, 1.0} : Vec2{static_cast<double>(x), static_cast<double>(y)};
  };
  Vec2 last_p{origin, origin}, last_u{1.0, 0.0};
  double last_e = scale;
  auto shape = [&]() -> Shape {
    const unsigned kind = in.byte() % 7;
    // Kind 6 reuses the previous huge line: shapes along each other (contact at huge extent).
    const bool reuse = kind == 6;
    const Vec2 p = reuse ? last_p : grid();
    const Vec2 u = reuse ? last_u : direction();
    const double e = reuse ? last_e : extent();
    last_p = p, last_u = u, last_e = e;
    const Vec2 a{p.x - e * u.x, p.y - e * u.y}, b{p.x + e * u.x, p.y + e * u.y};
    const Vec2 side{-u.y, u.x};
    const double flip = (in.byte() & 1) ? 1.0 : -1.0;
    switch (reuse ? 1 + in.byte() % 2 : kind) {
      case 0: return Segment{a, b};  // a line through the view
      case 1:  // a triangle with one edge along that line
        return Polygon{{a, b, {p.x + flip * e * side.x, p.y + flip * e * side.y}}};
      case 2:  // a quadrilateral: a huge band on one side of the line
        return Polygon{{a, b, {b.x + flip * e * side.x, b.y + flip * e * side.y}, {a.x + flip * e * side.x, a.y + flip * e * side.y}}};
      case 3: {  // a circle through p, of radius e, centered along the side direction
        const double len = std::hypot(side.x, side.y);
        return Circle{{p.x + flip * e * side.x / len, p.y + flip * e * side.y / len}, e};
      }
      case 4: {  // a small circle near the view
        const Vec2 c = grid();
        return Circle{c, scale * (in.byte() + 1) / 32.0};
      }
      default: {  // a short segment near the view
        const Vec2 c = grid(), d = grid();
        return Segment{c, d};
      }
    }
  };
  auto accepted = [&](const Shape& sh) {
    Scene probe;
    probe.width = probe.height = 1;
    probe.view = {0, 0, 1, 1};
    probe.occluders.push_back({sh});
    return validate_scene(probe).ok();
  };
  const unsigned lights = 1 + in.byte() % 3, occluders = in.byte() % 4;
  for (unsigned k = 0; k < lights; ++k) {
    Light light;
    light.shape = shape();
    light.color = {in.byte() / 255.0, 1.0, in.byte() / 255.0};
    const unsigned power = in.byte();
    // Mostly ordinary emissions, one in four up to 2^123 (the total limit is 1e38).
    light.intensity = power < 192 ? (power + 1) / 64.0 : std::ldexp(1.0 + in.byte(), static_cast<int>(power % 116));
    if (accepted(light.shape)) s.lights.push_back(light);
  }
  for (unsigned k = 0; k < occluders; ++k) {
    Occluder occluder{shape()};
    if (accepted(occluder.shape)) s.occluders.push_back(occluder);
  }
  return f;
}

// Every backend finite and within [0, sum e] (check_render_scene), and the scalar reference
// within the stratification bound of a 512-ray ray caster where lights and occluders are
// disjoint (tests/test_raycast.cpp derives it: per light, e_L (2 + 2 * occluders) / rays, plus
// docs/contract.md section 5's 1e-6 e_max), away from 1e-6 pixel of every boundary; the SIMD
// path on every ISA within section 5's 1e-4 e_max of the scalar one, away from 0.05 pixel of
// every boundary (FINDINGS.md #7: it was not, for shapes reaching past 2^18 pixels).
inline std::string check_huge_bytes(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const FuzzScene f = decode_huge_scene(in);
  const Scene& scene = f.scene;
  if (!validate_scene(scene).ok()) return {};
  // Bounds and finiteness on every backend, and (where lights and occluders are apart) SIMD
  // against scalar as for every fuzzed scene.
  if (std::string p = check_render_scene(f); !p.empty()) return p;
  RenderOptions o;
  o.threads = f.threads;
  o.backend = Backend::scalar;
  Status status;
  const test::RenderedImage scalar = test::render_image(scene, o, status);
  if (!status.ok()) return "scalar render failed: " + status.message();
  // docs/contract.md section 5's bounds hold where every light is apart from every occluder
  // by more than the contact tolerance (a circle light 2^38 pixels across cut 2.4e-5 deep by
  // a huge triangle's edge is a contact, which the two paths may resolve differently).
  if (!lights_disjoint_from_occluders(scene)) return {};
  constexpr int kRays = 512;
  o.rays = kRays;
  const test::RenderedImage rays = test::render_image(scene, o, status, /*raycast=*/true);
  if (!status.ok()) return "raycast render failed: " + status.message();
  const double e_max = test::emission_max_sum(scene);
  double bound[3];
  for (int c = 0; c < 3; ++c) {
    bound[c] = 1e-6 * e_max;
    for (const Light& l : scene.lights)
      bound[c] += l.intensity * l.color[static_cast<std::size_t>(c)] * (2.0 + 2.0 * static_cast<double>(scene.occluders.size())) / kRays;
    bound[c] *= 1.0 + 1e-5;  // float storage of both images
  }
  const double near = 1e-6 * test::pixel_width(scene);
  for (int j = 0; j < scene.height; ++j)
    for (int i = 0; i < scene.width; ++i) {
      if (test::near_boundary(scene, test::pixel_center(scene, i, j), near)) continue;
      for (int c = 0; c < 3; ++c) {
        const double diff = std::fabs(double(scalar.at(i, j, c)) - double(rays.at(i, j, c)));
        if (!(diff <= bound[c])) {
          std::ostringstream out;
          out.precision(17);
          out << "scalar differs from the ray caster at pixel (" << i << ", " << j << ") channel " << c << ": "
              << scalar.at(i, j, c) << " vs " << rays.at(i, j, c) << ", bound " << bound[c];
          return out.str();
        }
      }
    }
  return {};
}

}  // namespace par2d::fuzz
