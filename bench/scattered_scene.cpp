// Synthetic levels of many small scattered occluders and lights, for the scaling benchmarks and par2d_make_field.
#include "scattered_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace par2d::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Gap kept between a light's and an occluder's bounding circles, so no light touches an occluder
// even after float32 rounding in the SIMD path.
constexpr double kLightMargin = 2.0;
// Gives up looking for a clear spot for a light after this many rejected ones (only in levels
// whose occluders cover nearly the whole view) and takes the spot that overlapped least.
constexpr int kMaxPlacementTries = 20000;

// Uniform double in [0, 1) from 53 random bits; std::mt19937's output sequence is fixed by the
// standard, so the scenes are identical everywhere.
class Random {
 public:
  explicit Random(uint32_t seed) : engine_(seed) {}

  double unit() {
    const uint64_t hi = engine_() >> 5;  // 27 bits
    const uint64_t lo = engine_() >> 6;  // 26 bits
    return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);
  }
  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }
  int below(int n) { return static_cast<int>(unit() * n); }

 private:
  std::mt19937 engine_;
};

struct Disc {
  Vec2 center;
  double radius;
};

// Occluders' bounding circles bucketed in square cells at least as wide as the largest
// distance at which a light can conflict with one, so a light's placement test looks at 3x3
// cells instead of every occluder (dense levels try many spots per light).
class DiscGrid {
 public:
  DiscGrid(std::vector<Disc> discs, double cell, int width, int height)
      : discs_(std::move(discs)),
        cell_(cell),
        columns_(std::max(1, static_cast<int>(std::ceil(width / cell)))),
        rows_(std::max(1, static_cast<int>(std::ceil(height / cell)))),
        cells_(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_)) {
    for (std::size_t k = 0; k < discs_.size(); ++k) cells_[index(column(discs_[k].center.x), row(discs_[k].center.y))].push_back(k);
  }

  // The least of |c - b.center| - (radius + b.radius + margin) over the occluders within one
  // cell of c; +inf when none is (every other occluder is at least a cell away, clear).
  double least_gap(Vec2 c, double radius, double margin) const {
    double least = std::numeric_limits<double>::infinity();
    const int ci = column(c.x), cj = row(c.y);
    for (int j = std::max(0, cj - 1); j <= std::min(rows_ - 1, cj + 1); ++j) {
      for (int i = std::max(0, ci - 1); i <= std::min(columns_ - 1, ci + 1); ++i) {
        for (const std::size_t k : cells_[index(i, j)]) {
          const Disc& b = discs_[k];
          least = std::min(least, std::hypot(c.x - b.center.x, c.y - b.center.y) - (radius + b.radius + margin));
        }
      }
    }
    return least;
  }

 private:
  int column(double x) const { return std::clamp(static_cast<int>(std::floor(x / cell_)), 0, columns_ - 1); }
  int row(double y) const { return std::clamp(static_cast<int>(std::floor(y / cell_)), 0, rows_ - 1); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(i); }

  std::vector<Disc> discs_;
  double cell_;
  int columns_, rows_;
  std::vector<std::vector<std::size_t>> cells_;
};

// A regular-ish convex polygon: `n` vertices on a circle, angles jittered by less than half a
// step so the vertices stay in order (convex, non-degenerate).
Polygon jittered_polygon(Random& rng, Vec2 c, double radius, int n) {
  Polygon p;
  const double step = 2.0 * kPi / n;
  const double start = rng.range(0.0, 2.0 * kPi);
  for (int k = 0; k < n; ++k) {
    const double a = start + step * (k + rng.range(-0.3, 0.3));
    p.vertices.push_back({c.x + radius * std::cos(a), c.y + radius * std::sin(a)});
  }
  return p;
}

// A rotated rectangle with sides `w` x `h`.
Polygon rotated_rect(Random& rng, Vec2 c, double w, double h) {
  const double a = rng.range(0.0, kPi);
  const double ux = std::cos(a), uy = std::sin(a);
  const double hw = 0.5 * w, hh = 0.5 * h;
  Polygon p;
  p.vertices = {{c.x - ux * hw + uy * hh, c.y - uy * hw - ux * hh},
                {c.x + ux * hw + uy * hh, c.y + uy * hw - ux * hh},
                {c.x + ux * hw - uy * hh, c.y + uy * hw + ux * hh},
                {c.x - ux * hw - uy * hh, c.y - uy * hw + ux * hh}};
  return p;
}

}  // namespace

Scene scattered_scene(int lights, int occluders, uint32_t seed, int width, int height, const ScatteredSizes& sizes) {
  Random rng(seed);
  Scene scene;
  scene.width = width;
  scene.height = height;
  scene.view = {0.0, 0.0, static_cast<double>(width), static_cast<double>(height)};

  std::vector<Disc> bounds;  // one bounding circle per occluder, for the light placement test
  bounds.reserve(occluders);
  for (int i = 0; i < occluders; ++i) {
    const double size = rng.range(sizes.occluder_min, sizes.occluder_max);  // across, in pixels
    const Vec2 c{rng.range(0.0, width), rng.range(0.0, height)};
    Occluder occ;
    double radius = 0.5 * size;
    switch (rng.below(3)) {
      case 0: {
        const double w = size, h = size * rng.range(0.4, 1.0);
        occ.shape = rotated_rect(rng, c, w, h);
        radius = 0.5 * std::hypot(w, h);
        break;
      }
      case 1:
        occ.shape = jittered_polygon(rng, c, radius, 3);
        break;
      default:
        occ.shape = Circle{c, radius};
        break;
    }
    scene.occluders.push_back(std::move(occ));
    bounds.push_back({c, radius});
  }

  double largest_bound = 0.0;
  for (const Disc& b : bounds) largest_bound = std::max(largest_bound, b.radius);
  const double largest_light = 0.5 * sizes.light_max;
  const DiscGrid grid(std::move(bounds), std::max(1.0, largest_light + largest_bound + kLightMargin), width, height);

  for (int i = 0; i < lights; ++i) {
    const double radius = 0.5 * rng.range(sizes.light_min, sizes.light_max);
    Vec2 c{}, best{};
    double best_gap = -std::numeric_limits<double>::infinity();
    for (int tries = 0;; ++tries) {
      c = {rng.range(radius, width - radius), rng.range(radius, height - radius)};
      const double gap = grid.least_gap(c, radius, kLightMargin);
      if (gap > best_gap) {
        best_gap = gap;
        best = c;
      }
      if (gap >= 0.0) break;
      if (tries >= kMaxPlacementTries) {
        c = best;
        break;
      }
    }
    Light light;
    if (rng.below(2) == 0) {
      light.shape = Circle{c, radius};
    } else {
      light.shape = jittered_polygon(rng, c, radius, 4 + rng.below(3));
    }
    // Warm-to-cool tints so overlapping penumbrae stay distinguishable in a rendered image.
    const double t = rng.unit();
    light.color = {1.0, 0.6 + 0.3 * t, 0.3 + 0.7 * t};
    light.intensity = rng.range(2.0, 8.0);
    scene.lights.push_back(std::move(light));
  }
  return scene;
}

}  // namespace par2d::bench
