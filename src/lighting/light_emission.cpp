// A light's emission: see light_emission.hpp.
#include "lighting/light_emission.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace par2d::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

double reference_radius(const Shape& shape) noexcept {
  if (const auto* c = std::get_if<Circle>(&shape)) return c->radius;
  if (const auto* s = std::get_if<Segment>(&shape)) return 0.5 * std::hypot(s->b.x - s->a.x, s->b.y - s->a.y);
  const auto& vertices = std::get<Polygon>(shape).vertices;
  if (vertices.empty()) return 0.0;
  double cx = 0.0, cy = 0.0;
  for (const Vec2& v : vertices) {
    cx += v.x;
    cy += v.y;
  }
  cx /= static_cast<double>(vertices.size());
  cy /= static_cast<double>(vertices.size());
  double farthest = 0.0;
  for (const Vec2& v : vertices) farthest = std::max(farthest, std::hypot(v.x - cx, v.y - cy));
  return farthest;
}

double emission_scale(const Light& light) noexcept {
  if (!light.normalize) return 1.0;
  const double ratio = std::min(1.0, reference_radius(light.shape) / *light.normalize);
  return kPi / std::asin(ratio);
}

Rgb light_emission(const Rgb& color, double intensity, double scale) noexcept {
  Rgb e{};
  for (std::size_t c = 0; c < 3; ++c) {
    const double raw = intensity * color[c];
    e[c] = raw == 0.0 ? 0.0 : raw * scale;
  }
  return e;
}

namespace {

// The fraction of the light its shadows remove, per channel.
double shadow_fraction(const Light& light, std::size_t c) noexcept {
  return light.shadow.strength * (1.0 - light.shadow.color[c]);
}

}  // namespace

LightParts light_parts(const Light& light) noexcept {
  const Rgb e = light_emission(light);
  bool shadowed = false, unshadowed = false;
  for (std::size_t c = 0; c < 3; ++c) {
    if (!(e[c] > 0.0)) continue;
    const double k = shadow_fraction(light, c);
    shadowed = shadowed || k > 0.0;
    unshadowed = unshadowed || k < 1.0;
  }
  if (shadowed && unshadowed) return {LightPart::shadowed, true};
  return {unshadowed ? LightPart::unshadowed : LightPart::whole, false};
}

Rgb part_emission(const Light& light, LightPart part) noexcept {
  Rgb e = light_emission(light);
  if (part == LightPart::whole) return e;
  for (std::size_t c = 0; c < 3; ++c) {
    const double k = shadow_fraction(light, c);
    e[c] *= part == LightPart::shadowed ? k : 1.0 - k;
  }
  return e;
}

}  // namespace par2d::detail
