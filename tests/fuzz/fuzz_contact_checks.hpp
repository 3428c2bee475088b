// Properties of the contact fuzz target (lights on occluder edges, touching shapes, huge emissions), shared with the corpus replay.
#pragma once

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz/fuzz_checks.hpp"

namespace par2d::fuzz {

// A scene decoded from bytes in which every light lies on an occluder's boundary: a piece of
// one of its edges (segment light), the polygon itself or a copy sharing one edge line from
// inside, or a circle equal to a circle occluder. docs/contract.md: with t_occ == t_L the
// light is not visible, so every backend must give 0 at every pixel. Emissions reach 1e37
// each (the total limit is 1e38) and views go from 1e-300 to 1e300 per pixel.
struct ContactScene {
  Scene scene;
  bool all_hidden = true;  // every light is in contact (the extra light, if any, is not)
};

inline ContactScene decode_contact_scene(ByteReader& in) {
  static constexpr double kScales[] = {1.0, 1e-300, 1e-3, 1e7, 1e300, 0.37};
  ContactScene c;
  Scene& s = c.scene;
  s.width = 1 + static_cast<int>(in.byte() % 20);
  s.height = 1 + static_cast<int>(in.byte() % 20);
  const double scale = kScales[in.byte() % 6];
  const double origin = scale * in.signed_byte() * 3.0;
  s.view = {origin, origin, origin + scale * s.width, origin + scale * s.height};
  auto grid = [&] { return origin + scale * (10.0 + in.signed_byte() / 8.0); };
  const unsigned occluders = 1 + in.byte() % 3;
  for (unsigned k = 0; k < occluders; ++k) {
    const unsigned kind = in.byte() % 3;
    if (kind == 0) {  // circle; its light is an equal circle
      const Circle circle{{grid(), grid()}, scale * (0.5 + in.byte() / 32.0)};
      s.occluders.push_back({circle});
      if (in.byte() & 1) {
        Light l;
        l.shape = circle;
        l.intensity = std::ldexp(1.0 + in.byte(), static_cast<int>(in.byte() % 116));  // up to ~1e37
        s.lights.push_back(l);
      }
      continue;
    }
    // A convex polygon: a regular n-gon (rotated, so its edges are not axis-aligned) or a rectangle.
    Polygon p;
    const Vec2 center{grid(), grid()};
    const double r = scale * (1.0 + in.byte() / 16.0);
    if (kind == 1) {
      const unsigned n = 3 + in.byte() % 9;
      const double phase = in.byte() * (2.0 * detail::kPi / 256.0);
      for (unsigned v = 0; v < n; ++v) {
        const double a = phase + 2.0 * detail::kPi * v / n;
        p.vertices.push_back({center.x + r * std::cos(a), center.y + r * std::sin(a)});
      }
    } else {
      const double w = scale * (0.5 + in.byte() / 16.0);
      p.vertices = {{center.x - r, center.y - w}, {center.x + r, center.y - w}, {center.x + r, center.y + w},
                    {center.x - r, center.y + w}};
    }
    s.occluders.push_back({p});
    const unsigned lights = in.byte() % 3;
    for (unsigned l = 0; l < lights; ++l) {
      Light light;
      light.intensity = std::ldexp(1.0 + in.byte(), static_cast<int>(in.byte() % 116));
      light.color = {in.byte() / 255.0, 1.0, in.byte() / 255.0};
      const std::size_t e = in.byte() % p.vertices.size();
      const Vec2 a = p.vertices[e], b = p.vertices[(e + 1) % p.vertices.size()];
      const unsigned how = in.byte() % 3;
      if (how == 0) {  // a piece of the edge
        const double t0 = in.byte() / 512.0, t1 = 1.0 - in.byte() / 512.0;
        light.shape = Segment{{a.x + t0 * (b.x - a.x), a.y + t0 * (b.y - a.y)},
                              {a.x + t1 * (b.x - a.x), a.y + t1 * (b.y - a.y)}};
      } else if (how == 1) {  // the polygon itself
        light.shape = p;
      } else {  // the triangle of the edge and the centroid: inside, sharing the edge
        light.shape = Polygon{{a, b, center}};
      }
      s.lights.push_back(light);
    }
  }
  return c;
}

inline std::string check_contact_bytes(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const ContactScene c = decode_contact_scene(in);
  if (!validate_scene(c.scene).ok()) return {};  // e.g. emissions over the total limit: refused, fine
  const Scene& scene = c.scene;
  RenderOptions base;
  base.threads = 1;
  std::vector<RenderOptions> backends;
  RenderOptions o = base;
  o.backend = Backend::scalar;
  backends.push_back(o);
  o.rays = 64;
  backends.push_back(o);  // the ray caster's (backends[1])
  for (Isa isa : par2d::kSimdIsas) {
    if (!isa_supported(isa)) continue;
    o = base;
    o.backend = Backend::simd;
    o.isa = isa;
    backends.push_back(o);
  }
  for (std::size_t b = 0; b < backends.size(); ++b) {
    const RenderOptions& options = backends[b];
    const bool raycast = b == 1;
    Status status;
    const test::RenderedImage image = test::render_image(scene, options, status, raycast);
    const std::string what = std::string(raycast ? "raycast" : backend_name(options.backend)) +
                             (options.isa ? std::string(" ") + isa_name(*options.isa) : std::string());
    if (!status.ok()) return what + " render failed: " + status.message();
    if (std::string p = check_bounds(scene, image, what.c_str()); !p.empty()) return p;
    if (!c.all_hidden) continue;
    // The contract's value is 0 everywhere; the scalar path and the ray caster must be within
    // the scalar bound (1e-6 e_max: where a pixel is collinear with a light edge, rounding
    // leaves a sliver of ~1e-17 of it), the SIMD path within its bound away from 0.05 pixel
    // widths of any boundary (the contact bug gave 0.475 e).
    const bool simd = options.backend == Backend::simd;
    const double bound = (simd ? 1e-4 : 1e-6) * test::emission_max_sum(scene);
    const double near = 0.05 * test::pixel_width(scene);
    for (std::size_t k = 0; k < image.pixels.size(); ++k) {
      const int i = static_cast<int>((k / 3) % static_cast<std::size_t>(scene.width));
      const int j = static_cast<int>((k / 3) / static_cast<std::size_t>(scene.width));
      if (!(image.pixels[k] > bound)) continue;
      if (simd && test::near_boundary(scene, test::pixel_center(scene, i, j), near)) continue;
      std::ostringstream out;
      out.precision(17);
      out << what << ": a light in contact with an occluder is visible at pixel " << i << ", " << j << ": "
          << image.pixels[k] << " (bound " << bound << ")";
      return out.str();
    }
  }
  return {};
}

}  // namespace par2d::fuzz
