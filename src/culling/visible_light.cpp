// The visible part of a light clipped by the occluder it sits in: see visible_light.hpp.
#include "culling/visible_light.hpp"

#include <algorithm>
#include <cmath>

namespace par2d::detail {
namespace {

// A circle light's stand-in: the circumscribed regular polygon with this many sides (grown a
// little past its rounding), so that it holds the whole disc. The proofs take circle lights
// as octagons too; more sides cost the proofs more light points than they gain.
constexpr int kCircleSides = 8;

struct UnitPolygon {
  double x[kCircleSides], y[kCircleSides];
  UnitPolygon() {
    for (int k = 0; k < kCircleSides; ++k) {
      x[k] = std::cos(kTwoPi * k / kCircleSides);
      y[k] = std::sin(kTwoPi * k / kCircleSides);
    }
  }
};

}  // namespace

int designated_clip(const PreparedScene& scene, const PreparedLight& light) noexcept {
  for (std::size_t i = 0; i < light.overlaps.size(); ++i) {
    if (!light.overlaps[i].clips || light.overlaps[i].contained) continue;
    if (scene.model) {
      const OccluderTerms& t = scene.occluder_terms[light.overlapping_occluders[i]];
      if (!(t.opaque() && !t.lit_interior && t.acts_on(light.terms.mask))) continue;
    }
    return static_cast<int>(i);
  }
  return -1;
}

bool visible_part(const ConvexShape& light, const LightClip& clip, ConvexShape& out, std::vector<Vec2>& points) {
  if (light.kind == ShapeKind::segment) return false;
  points.clear();
  double size = 0.0;
  if (light.kind == ShapeKind::circle) {
    static const UnitPolygon kUnit;
    const double grown = light.radius / std::cos(kPi / kCircleSides) * (1.0 + 1e-12);
    const Vec2 c = light.vertices[0];
    for (int k = 0; k < kCircleSides; ++k) points.push_back(c + grown * Vec2{kUnit.x[k], kUnit.y[k]});
    size = grown;
  } else {
    points.assign(light.vertices.begin(), light.vertices.end());
    for (const Vec2 v : points) size = std::max(size, length(v - light.centroid));
  }
  // Keep side <= a hair past the line (rounding of the crossing points must not cut into
  // the light's part on the line's negative side).
  const double slack = 1e-12 * size;
  const std::size_t n = points.size();
  std::vector<Vec2>& kept = out.vertices;
  kept.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = points[i], b = points[(i + 1) % n];
    const double fa = clip.line.side(a) - slack, fb = clip.line.side(b) - slack;
    if (fa <= 0.0) kept.push_back(a);
    if ((fa <= 0.0) != (fb <= 0.0)) {
      const double t = fa / (fa - fb);
      kept.push_back(a + t * (b - a));
    }
  }
  // Drop points that repeat or make straight turns (a canonical polygon has neither).
  const double tiny = 1e-9 * size;
  for (bool removed = true; removed && kept.size() > 3;) {
    removed = false;
    for (std::size_t i = 0; i < kept.size() && kept.size() > 3; ++i) {
      const Vec2 prev = kept[(i + kept.size() - 1) % kept.size()], next = kept[(i + 1) % kept.size()];
      const Vec2 e1 = kept[i] - prev, e2 = next - kept[i];
      if (length(e1) <= tiny || std::abs(cross(e1, e2)) <= 1e-9 * length(e1) * length(e2)) {
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(i));
        removed = true;
        --i;
      }
    }
  }
  if (kept.size() < 3) return false;
  out.kind = ShapeKind::polygon;
  out.radius = 0.0;
  out.edge_normals.clear();
  out.bounds_min = kept[0];
  out.bounds_max = kept[0];
  Vec2 sum{0.0, 0.0};
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const Vec2 e = kept[(i + 1) % kept.size()] - kept[i];
    const double len = length(e);
    out.edge_normals.push_back({-e.y / len, e.x / len});
    out.bounds_min = {std::min(out.bounds_min.x, kept[i].x), std::min(out.bounds_min.y, kept[i].y)};
    out.bounds_max = {std::max(out.bounds_max.x, kept[i].x), std::max(out.bounds_max.y, kept[i].y)};
    sum = sum + (kept[i] - kept[0]);
  }
  out.centroid = kept[0] + (1.0 / static_cast<double>(kept.size())) * sum;
  return true;
}

void VisibleLights::reserve_for(std::size_t lights, std::size_t max_vertices) {
  const std::size_t points_most = std::max<std::size_t>(max_vertices, kCircleSides);
  if (entries.size() < lights) entries.resize(lights);
  for (Entry& e : entries) {
    e.made_from.reserve(max_vertices);
    e.shape.vertices.reserve(points_most + 1);
    e.shape.edge_normals.reserve(points_most + 1);
  }
  points.reserve(points_most);
}

std::size_t VisibleLights::reserved_bytes() const noexcept {
  std::size_t bytes = entries.capacity() * sizeof(Entry) + points.capacity() * sizeof(Vec2);
  for (const Entry& e : entries)
    bytes += (e.made_from.capacity() + e.shape.vertices.capacity() + e.shape.edge_normals.capacity()) * sizeof(Vec2);
  return bytes;
}

void VisibleLights::update(const PreparedScene& scene) {
  if (entries.size() < scene.lights.size()) entries.resize(scene.lights.size());
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    Entry& e = entries[l];
    e.clip = -1;
    const PreparedLight& light = scene.lights[l];
    if (light.overlaps.empty()) continue;
    const int clip = designated_clip(scene, light);
    if (clip < 0) continue;
    const LightClip& c = light.overlaps[static_cast<std::size_t>(clip)].clip;
    const bool same = e.made_radius == light.shape.radius && e.made_line.normal.x == c.line.normal.x &&
                      e.made_line.normal.y == c.line.normal.y && e.made_line.point.x == c.line.point.x &&
                      e.made_line.point.y == c.line.point.y && e.made_from.size() == light.shape.vertices.size() &&
                      std::equal(e.made_from.begin(), e.made_from.end(), light.shape.vertices.begin(),
                                 [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; });
    if (!same) {
      e.made_from.assign(light.shape.vertices.begin(), light.shape.vertices.end());
      e.made_radius = light.shape.radius;
      e.made_line = c.line;
      if (!visible_part(light.shape, c, e.shape, points)) e.made_radius = -2.0;  // none: the light stays whole
    }
    if (e.made_radius == -2.0) continue;
    e.clip = clip;
    e.occluder = light.overlapping_occluders[static_cast<std::size_t>(clip)];
    e.line = light.overlaps[static_cast<std::size_t>(clip)].clip.line;
  }
}

}  // namespace par2d::detail
