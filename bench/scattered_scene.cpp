// Synthetic levels of many small scattered occluders and lights, for the scaling benchmarks and par2d_make_field.
#include "scattered_scene.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace par2d::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Gap kept between a light's and an occluder's bounding circles, so no light touches an occluder
// even after float32 rounding in the SIMD path.
constexpr double kLightMargin = 2.0;
// Gives up on a light after this many rejected spots; only reachable when occluders cover
// nearly the whole view, which no benchmark asks for.
constexpr int kMaxPlacementTries = 100000;

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

Scene scattered_scene(int lights, int occluders, uint32_t seed, int width, int height) {
  Random rng(seed);
  Scene scene;
  scene.width = width;
  scene.height = height;
  scene.view = {0.0, 0.0, static_cast<double>(width), static_cast<double>(height)};

  std::vector<Disc> bounds;  // one bounding circle per occluder, for the light placement test
  bounds.reserve(occluders);
  for (int i = 0; i < occluders; ++i) {
    const double size = rng.range(4.0, 12.0);  // across, in pixels
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

  for (int i = 0; i < lights; ++i) {
    const double radius = rng.range(3.0, 6.0);
    Vec2 c{};
    for (int tries = 0;; ++tries) {
      c = {rng.range(radius, width - radius), rng.range(radius, height - radius)};
      bool clear = true;
      for (const Disc& b : bounds) {
        const double gap = radius + b.radius + kLightMargin;
        const double dx = c.x - b.center.x, dy = c.y - b.center.y;
        if (dx * dx + dy * dy < gap * gap) {
          clear = false;
          break;
        }
      }
      if (clear || tries >= kMaxPlacementTries) break;
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
