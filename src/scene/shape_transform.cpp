// Sprite transforms (par2d/scene.hpp Transform): a shape from its local frame into the world.
#include <cmath>
#include <string>
#include <variant>

#include "par2d/scene.hpp"
#include "scene/scene_validate.hpp"

namespace par2d {

namespace {

constexpr double kPi = 3.14159265358979323846;

// cos and sin of `degrees`, exact at multiples of 90 (cos(pi / 2) in double is 6e-17, which
// would move a quarter-turned tile's corners off its grid).
void turn(double degrees, double& c, double& s) noexcept {
  double q = std::fmod(degrees, 360.0);
  if (q < 0.0) q += 360.0;
  if (q == 0.0 || q == 360.0) {
    c = 1.0, s = 0.0;
  } else if (q == 90.0) {
    c = 0.0, s = 1.0;
  } else if (q == 180.0) {
    c = -1.0, s = 0.0;
  } else if (q == 270.0) {
    c = 0.0, s = -1.0;
  } else {
    c = std::cos(q * (kPi / 180.0));
    s = std::sin(q * (kPi / 180.0));
  }
}

Status refused(const std::string& field, const std::string& what) {
  return Status(StatusCode::invalid_scene, "transform." + field + ": " + what);
}

}  // namespace

Status transform_shape(const Shape& local, const Transform& t, Shape& out) {
  const std::pair<const char*, double> values[] = {{"position[0]", t.position.x}, {"position[1]", t.position.y},
                                                   {"rotation", t.rotation},      {"scale[0]", t.scale.x},
                                                   {"scale[1]", t.scale.y}};
  for (const auto& [field, value] : values) {
    if (!std::isfinite(value)) return refused(field, "not a finite number (" + detail::format_number(value) + ")");
  }
  if (t.scale.x == 0.0 || t.scale.y == 0.0)
    return refused(t.scale.x == 0.0 ? "scale[0]" : "scale[1]", "must be non-zero, got 0");
  const auto* circle = std::get_if<Circle>(&local);
  if (circle && std::fabs(t.scale.x) != std::fabs(t.scale.y)) {
    return refused("scale", "a circle takes the same scale on both axes, got [" + detail::format_number(t.scale.x) +
                                ", " + detail::format_number(t.scale.y) + "]");
  }
  double c = 1.0, s = 0.0;
  turn(t.rotation, c, s);
  const auto place = [&](Vec2 p) {
    const double x = t.scale.x * p.x, y = t.scale.y * p.y;
    return Vec2{t.position.x + (c * x - s * y), t.position.y + (s * x + c * y)};
  };
  if (circle) {
    out = Circle{place(circle->center), std::fabs(t.scale.x) * circle->radius};
  } else if (const auto* segment = std::get_if<Segment>(&local)) {
    out = Segment{place(segment->a), place(segment->b)};
  } else {
    const std::vector<Vec2>& from = std::get<Polygon>(local).vertices;
    if (&out != &local && !std::holds_alternative<Polygon>(out)) out = Polygon{};
    std::vector<Vec2>& to = std::get<Polygon>(out).vertices;
    if (&to != &from) to.resize(from.size());  // within capacity after the first placement
    for (std::size_t k = 0; k < from.size(); ++k) to[k] = place(from[k]);
    // Holes move with the outline (copied first unless placed in place).
    Polygon& placed = std::get<Polygon>(out);
    if (&out != &local) placed.holes = std::get<Polygon>(local).holes;
    for (std::vector<Vec2>& hole : placed.holes)
      for (Vec2& v : hole) v = place(v);
  }
  return {};
}

}  // namespace par2d
