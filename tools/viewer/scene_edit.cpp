// The viewer's scene edits: picking by distance to the shape, translations and scalings that stay valid.
#include "scene_edit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace par2d::viewer {
namespace {

double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
Vec2 sub(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = sub(b, a);
  const double len2 = dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(dot(sub(p, a), ab) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * ab.x), p.y - (a.y + t * ab.y));
}

// Distance from p to the closed shape (0 inside). A polygon (convex or a concave simple
// outline, with or without holes) holds p when a ray from p toward +x crosses its rings'
// edges an odd number of times.
double distance_to_shape(const Shape& shape, Vec2 p) {
  return std::visit(
      [p](const auto& s) -> double {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Circle>) {
          return std::max(0.0, std::hypot(p.x - s.center.x, p.y - s.center.y) - s.radius);
        } else if constexpr (std::is_same_v<T, Segment>) {
          return distance_to_segment(p, s.a, s.b);
        } else {
          const auto& v = s.vertices;
          double best = std::numeric_limits<double>::infinity();
          bool odd = false;
          const auto ring = [&](const std::vector<Vec2>& r) {
            for (std::size_t i = 0; i < r.size(); ++i) {
              const Vec2 a = r[i], b = r[(i + 1) % r.size()];
              best = std::min(best, distance_to_segment(p, a, b));
              if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) odd = !odd;
            }
          };
          ring(v);
          for (const std::vector<Vec2>& hole : s.holes) ring(hole);  // a hole's inside is outside
          return odd ? 0.0 : best;
        }
      },
      shape);
}

Vec2 shape_center(const Shape& shape) {
  return std::visit(
      [](const auto& s) -> Vec2 {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Circle>) {
          return s.center;
        } else if constexpr (std::is_same_v<T, Segment>) {
          return {0.5 * (s.a.x + s.b.x), 0.5 * (s.a.y + s.b.y)};
        } else {
          Vec2 c;
          for (const Vec2& q : s.vertices) c = {c.x + q.x, c.y + q.y};
          const double n = static_cast<double>(s.vertices.size());
          return {c.x / n, c.y / n};
        }
      },
      shape);
}

// Applies `edit` to a copy and keeps it only when the copy is still a valid scene.
template <class Edit>
bool edit_validated(Scene& scene, Edit edit) {
  Scene copy = scene;
  edit(copy);
  if (!validate_scene(copy).ok()) return false;
  scene = std::move(copy);
  return true;
}

}  // namespace

Vec2 WindowMapping::to_world(double px, double py) const noexcept {
  return {view.x0 + px * (view.x1 - view.x0) / win_w, view.y0 + py * (view.y1 - view.y0) / win_h};
}

Vec2 WindowMapping::to_window(Vec2 world) const noexcept {
  return {(world.x - view.x0) * win_w / (view.x1 - view.x0), (world.y - view.y0) * win_h / (view.y1 - view.y0)};
}

std::vector<Vec2> outline(const Shape& shape, int circle_points) {
  if (const auto* c = std::get_if<Circle>(&shape)) {
    std::vector<Vec2> points;
    for (int k = 0; k <= circle_points; ++k) {
      const double a = 2.0 * 3.14159265358979323846 * k / circle_points;
      points.push_back({c->center.x + c->radius * std::cos(a), c->center.y + c->radius * std::sin(a)});
    }
    return points;
  }
  if (const auto* s = std::get_if<Segment>(&shape)) return {s->a, s->b};
  std::vector<Vec2> points = std::get<Polygon>(shape).vertices;
  points.push_back(points.front());
  return points;
}

double WindowMapping::pixel_size() const noexcept {
  return std::min(std::abs(view.x1 - view.x0) / win_w, std::abs(view.y1 - view.y0) / win_h);
}

Vec2 WindowMapping::delta_to_world(double dx, double dy) const noexcept {
  return {dx * (view.x1 - view.x0) / win_w, dy * (view.y1 - view.y0) / win_h};
}

std::optional<std::size_t> pick_light(const Scene& scene, Vec2 p, double radius) noexcept {
  std::optional<std::size_t> best;
  double best_distance = radius;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const double d = distance_to_shape(scene.lights[i].shape, p);
    if (d <= best_distance) {
      best = i;
      best_distance = d;
    }
  }
  return best;
}

void translate(Shape& shape, Vec2 d) noexcept {
  auto move = [d](Vec2& q) { q = {q.x + d.x, q.y + d.y}; };
  std::visit(
      [&move](auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Circle>) {
          move(s.center);
        } else if constexpr (std::is_same_v<T, Segment>) {
          move(s.a);
          move(s.b);
        } else {
          for (Vec2& q : s.vertices) move(q);
          for (std::vector<Vec2>& hole : s.holes)
            for (Vec2& q : hole) move(q);
        }
      },
      shape);
}

void scale(Shape& shape, double factor) noexcept {
  const Vec2 c = shape_center(shape);
  auto about_center = [c, factor](Vec2& q) { q = {c.x + (q.x - c.x) * factor, c.y + (q.y - c.y) * factor}; };
  std::visit(
      [&](auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Circle>) {
          s.radius *= factor;
        } else if constexpr (std::is_same_v<T, Segment>) {
          about_center(s.a);
          about_center(s.b);
        } else {
          for (Vec2& q : s.vertices) about_center(q);
          for (std::vector<Vec2>& hole : s.holes)
            for (Vec2& q : hole) about_center(q);
        }
      },
      shape);
}

bool move_light(Scene& scene, std::size_t index, Vec2 d) {
  if (index >= scene.lights.size()) return false;
  return edit_validated(scene, [&](Scene& s) { translate(s.lights[index].shape, d); });
}

bool scale_light(Scene& scene, std::size_t index, double factor) {
  if (index >= scene.lights.size() || !(factor > 0.0)) return false;
  return edit_validated(scene, [&](Scene& s) { scale(s.lights[index].shape, factor); });
}

bool add_light(Scene& scene, Vec2 p, double radius, const Light* like) {
  Light light;
  light.shape = Circle{p, radius};
  if (like) {
    light.color = like->color;
    light.intensity = like->intensity;
  }
  return edit_validated(scene, [&](Scene& s) { s.lights.push_back(light); });
}

bool delete_light(Scene& scene, std::size_t index) {
  if (index >= scene.lights.size()) return false;
  scene.lights.erase(scene.lights.begin() + static_cast<std::ptrdiff_t>(index));
  return true;
}

}  // namespace par2d::viewer
