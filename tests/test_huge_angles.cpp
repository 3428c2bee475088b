// Angles of any finite size (docs/contract.md section 6): a cone's direction, a cookie's
// rotation and knots and a directional light's angles of 1e14 .. 1e20 degrees light the scene
// exactly as their residues modulo 360 do, bit for bit, on the scalar path, every SIMD level
// and the ray caster.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"

namespace par2d::test {
namespace {

// d modulo 360 with d's sign, for an integer-valued double d, in integer arithmetic (so the
// test does not lean on the std::fmod the library uses): |d| = m 2^s with an integer m < 2^53.
double residue(double d) {
  int exponent = 0;
  const double fraction = std::frexp(std::fabs(d), &exponent);
  auto m = static_cast<std::uint64_t>(std::ldexp(fraction, 53));
  int shift = exponent - 53;
  for (; shift < 0; ++shift) {
    REQUIRE((m & 1u) == 0u);  // an integer
    m >>= 1;
  }
  std::uint64_t r = m % 360u;
  for (; shift > 0; --shift) r = 2u * r % 360u;
  return d < 0.0 ? -static_cast<double>(r) : static_cast<double>(r);
}

// The knots' offsets from the first (degrees): multiples of 64, so that a first knot of up to
// 2^58 degrees (its ulp 64) plus each offset is an exact double.
constexpr double kKnotOffsets[] = {0.0, 64.0, 128.0, 256.0};
constexpr double kKnotWeights[] = {0.1, 1.0, 0.0, 0.6};
constexpr double kSunWidth = 64.0;

struct Angles {
  double cone;      // a circle light's cone direction
  double rotation;  // a segment light's cookie rotation (knots 10 .. 250)
  double knots;     // a polygon light's first cookie knot (rotation 0)
  double sun;       // a directional light's angle0 (angle1 = angle0 + 64)
};

Scene angle_scene(const Angles& a) {
  Scene s;
  s.width = 24;
  s.height = 16;
  s.view = {0.0, 0.0, 24.0, 16.0};
  Light spot;
  spot.shape = Circle{{6.0, 8.0}, 1.0};
  spot.intensity = 2.0;
  spot.cone = Cone{a.cone, 35.0, 10.0};
  s.lights.push_back(spot);
  Light bar;
  bar.shape = Segment{{16.0, 3.0}, {18.5, 4.0}};
  bar.intensity = 1.5;
  bar.color = {1.0, 0.5, 0.25};
  bar.cookie = Cookie{a.rotation, {{10.0, 0.0}, {60.0, 1.0}, {150.0, 0.3}, {250.0, 1.0}}};
  s.lights.push_back(bar);
  Light tile;
  tile.shape = Polygon{{{17.0, 11.0}, {20.0, 11.5}, {18.0, 13.5}}};
  tile.intensity = 1.0;
  tile.color = {0.25, 1.0, 0.5};
  Cookie cookie;
  for (int k = 0; k < 4; ++k) cookie.knots.push_back({a.knots + kKnotOffsets[k], kKnotWeights[k]});
  tile.cookie = cookie;
  s.lights.push_back(tile);
  DirectionalLight sun;
  sun.angle0 = a.sun;
  sun.angle1 = a.sun + kSunWidth;
  sun.intensity = 0.4;
  s.directional_lights.push_back(sun);
  s.occluders.push_back(Occluder{Polygon{{{10.0, 6.0}, {12.0, 6.0}, {12.0, 10.0}, {10.0, 10.0}}}});
  s.occluders.push_back(Occluder{Segment{{14.0, 12.0}, {15.0, 14.0}}});
  return s;
}

// The angles' residues: the same directions within a turn.
Angles reduced(const Angles& a) { return {residue(a.cone), residue(a.rotation), residue(a.knots), residue(a.sun)}; }

struct Render {
  std::string what;
  RenderOptions options;
  bool raycast = false;  // by render_raycast
};

std::vector<Render> every_backend() {
  std::vector<Render> out;
  RenderOptions o;
  o.threads = 1;
  o.backend = Backend::scalar;
  out.push_back({"scalar", o});
  for (const Isa isa : simd_isas_here()) {
    o.backend = Backend::simd;
    o.isa = isa;
    out.push_back({std::string("simd ") + isa_name(isa), o});
  }
  o = RenderOptions{};
  o.threads = 1;
  o.rays = 256;
  out.push_back({"raycast", o, true});
  return out;
}

}  // namespace

TEST_CASE("huge angles: cone, cookie rotation, cookie knots and sky angles of 1e14 .. 1e20 degrees render as their residues, bit for bit, on every backend") {
  // Exact doubles far past a turn (ulps of 1/64 to 16384 degrees), both signs; the knots and
  // the sky need their offsets (multiples of 64) to stay exact, so they stop at 2^58.
  const Angles cases[] = {
      {1e20, 1e16 + 2.0, 1e17 + 48.0, 1e17 + 16.0},
      {-(1e17 + 80.0), -1e20, -(1e14 + 7.0), 1e14 + 7.0},
      {1e14 + 7.0, 4e19 + 8192.0 * 5.0, std::ldexp(1.0, 58) + 192.0, -(1e16 + 2.0)},
      {std::ldexp(3.0, 60), 1e17 + 16.0, -(1e16 + 6.0), std::ldexp(1.0, 58) - 64.0 * 7.0},
  };
  const std::vector<Render> backends = every_backend();
  for (const Angles& huge : cases) {
    const Angles small = reduced(huge);
    CHECK(std::fabs(small.cone) < 360.0);
    CHECK(std::fabs(small.knots) < 360.0);
    const Scene big_scene = angle_scene(huge), small_scene = angle_scene(small);
    REQUIRE(validate_scene(big_scene).ok());
    REQUIRE(validate_scene(small_scene).ok());
    for (const Render& r : backends) {
      CAPTURE(r.what);
      CAPTURE(huge.cone);
      const RenderedImage a = render_or_fail(big_scene, r.options, r.raycast),
                          b = render_or_fail(small_scene, r.options, r.raycast);
      int differing = 0;
      double worst = 0.0;
      for (std::size_t k = 0; k < a.pixels.size(); ++k) {
        if (a.pixels[k] == b.pixels[k]) continue;
        ++differing;
        worst = std::max(worst, std::fabs(double(a.pixels[k]) - double(b.pixels[k])));
      }
      CAPTURE(worst);
      CHECK(differing == 0);
    }
  }
}

TEST_CASE("huge angles: each angle of the test scene changes its image (the comparison above can fail)") {
  const Angles base = reduced({1e20, 1e16 + 2.0, 1e17 + 48.0, 1e17 + 16.0});
  RenderOptions o;
  o.backend = Backend::scalar;
  const RenderedImage reference = render_or_fail(angle_scene(base), o);
  for (int term = 0; term < 4; ++term) {
    Angles turned = base;
    double* angle[] = {&turned.cone, &turned.rotation, &turned.knots, &turned.sun};
    *angle[term] += 90.0;
    const RenderedImage image = render_or_fail(angle_scene(turned), o);
    CAPTURE(term);
    CHECK(!same_bits(image.pixels, reference.pixels));
  }
}

}  // namespace par2d::test
