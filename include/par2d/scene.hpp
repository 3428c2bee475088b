// Scene model: lights and occluders as convex shapes, image size and view (docs/contract.md sections 2-3).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "par2d/status.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// World coordinates: x to the right, y down (docs/contract.md section 2).
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

// A closed convex polygon. Either winding; repeated and collinear vertices are tolerated.
struct Polygon {
  std::vector<Vec2> vertices;
};

// A closed disc.
struct Circle {
  Vec2 center;
  double radius = 0.0;  // > 0
};

// A closed line segment between two distinct points.
struct Segment {
  Vec2 a;
  Vec2 b;
};

using Shape = std::variant<Polygon, Circle, Segment>;

// Linear RGB triple.
using Rgb = std::array<double, 3>;

// A uniform emitter: every point of its shape emits `intensity * color` in every direction.
struct Light {
  Shape shape;
  Rgb color{1.0, 1.0, 1.0};  // each channel >= 0. Default: white.
  double intensity = 1.0;    // >= 0. Default: 1.
};

// An opaque shape: blocks light, emits nothing.
struct Occluder {
  Shape shape;
};

// The world rectangle the image shows: pixel (i, j) is sampled at
// (x0 + (i + 0.5) * (x1 - x0) / width, y0 + (j + 0.5) * (y1 - y0) / height).
// x0 > x1 or y0 > y1 mirrors the image.
struct View {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

// Hard limits from docs/contract.md section 3.
inline constexpr int kMaxImageSide = 16384;

struct Scene {
  int width = 0;   // 1 .. kMaxImageSide
  int height = 0;  // 1 .. kMaxImageSide
  View view;       // Default (as loaded from JSON): [0, 0, width, height].
  std::vector<Light> lights;
  std::vector<Occluder> occluders;
};

// Checks a scene built in code against docs/contract.md section 3 (sizes, finite numbers,
// convex non-degenerate shapes, non-negative colors). `name` prefixes messages.
Status validate_scene(const Scene& scene, std::string_view name = "scene");

// Parses and validates a JSON scene. `name` (usually the file name) prefixes every
// message, e.g. `level.json: lights[2].polygon: not convex at vertex 3`.
Status parse_scene(std::string_view json_text, std::string_view name, Scene& out);

// Reads, parses and validates a JSON scene file.
Status load_scene_file(const std::string& path, Scene& out);

// Sum over lights of the largest channel of intensity * color (docs/contract.md section 5's e_max).
double max_emission_sum(const Scene& scene) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
