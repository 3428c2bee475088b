// Bitwise comparison of scene values (same_values.hpp).
#include "scene/same_values.hpp"

#include <cstdint>
#include <cstring>

namespace par2d::detail {
namespace {

bool same_point(const Vec2& a, const Vec2& b) noexcept { return same_value(a.x, b.x) && same_value(a.y, b.y); }

bool same_ring(const std::vector<Vec2>& a, const std::vector<Vec2>& b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_point(a[i], b[i])) return false;
  return true;
}

template <class T, class Same>
bool same_optional(const std::optional<T>& a, const std::optional<T>& b, Same same) noexcept {
  if (a.has_value() != b.has_value()) return false;
  return !a || same(*a, *b);
}

bool same_cone(const Cone& a, const Cone& b) noexcept {
  return same_value(a.direction, b.direction) && same_value(a.half_angle, b.half_angle) && same_value(a.fade, b.fade);
}

bool same_cookie(const Cookie& a, const Cookie& b) noexcept {
  if (!same_value(a.rotation, b.rotation) || a.knots.size() != b.knots.size()) return false;
  for (std::size_t i = 0; i < a.knots.size(); ++i)
    if (!same_value(a.knots[i].direction, b.knots[i].direction) || !same_value(a.knots[i].weight, b.knots[i].weight))
      return false;
  return true;
}

}  // namespace

bool same_value(double a, double b) noexcept {
  std::uint64_t x = 0, y = 0;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x == y;
}

bool same_rgb(const Rgb& a, const Rgb& b) noexcept {
  return same_value(a[0], b[0]) && same_value(a[1], b[1]) && same_value(a[2], b[2]);
}

bool same_view(const View& a, const View& b) noexcept {
  return same_value(a.x0, b.x0) && same_value(a.y0, b.y0) && same_value(a.x1, b.x1) && same_value(a.y1, b.y1);
}

bool same_shape(const Shape& a, const Shape& b) noexcept {
  if (a.index() != b.index()) return false;
  if (const auto* p = std::get_if<Polygon>(&a)) {
    const Polygon& q = std::get<Polygon>(b);
    if (!same_ring(p->vertices, q.vertices) || p->holes.size() != q.holes.size()) return false;
    for (std::size_t h = 0; h < p->holes.size(); ++h)
      if (!same_ring(p->holes[h], q.holes[h])) return false;
    return true;
  }
  if (const auto* c = std::get_if<Circle>(&a)) {
    const Circle& d = std::get<Circle>(b);
    return same_point(c->center, d.center) && same_value(c->radius, d.radius);
  }
  const Segment& s = std::get<Segment>(a);
  const Segment& t = std::get<Segment>(b);
  return same_point(s.a, t.a) && same_point(s.b, t.b);
}

bool same_light(const Light& a, const Light& b) noexcept {
  return same_rgb(a.color, b.color) && same_value(a.intensity, b.intensity) &&
         same_optional(a.range, b.range, same_value) && same_value(a.falloff, b.falloff) &&
         same_optional(a.normalize, b.normalize, same_value) && same_optional(a.cone, b.cone, same_cone) &&
         same_optional(a.cookie, b.cookie, same_cookie) && a.mask == b.mask && same_value(a.elevation, b.elevation) &&
         same_value(a.shadow.strength, b.shadow.strength) && same_rgb(a.shadow.color, b.shadow.color) &&
         same_shape(a.shape, b.shape);
}

bool same_occluder(const Occluder& a, const Occluder& b) noexcept {
  return same_rgb(a.transmittance, b.transmittance) && a.mask == b.mask && a.interior == b.interior &&
         same_rgb(a.albedo, b.albedo) && same_shape(a.shape, b.shape);
}

bool same_directional_lights(const std::vector<DirectionalLight>& a, const std::vector<DirectionalLight>& b) noexcept {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const DirectionalLight& p = a[i];
    const DirectionalLight& q = b[i];
    if (!same_value(p.angle0, q.angle0) || !same_value(p.angle1, q.angle1) || !same_rgb(p.color, q.color) ||
        !same_value(p.intensity, q.intensity) || p.mask != q.mask || !same_value(p.elevation, q.elevation))
      return false;
  }
  return true;
}

}  // namespace par2d::detail
