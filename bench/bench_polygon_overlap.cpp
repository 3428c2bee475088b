// Cost of two overlapping or nested many-vertex polygons against their vertex count (issue 10: it was quadratic).
#include <benchmark/benchmark.h>

#include <cmath>
#include <utility>

#include "bench_support.hpp"

namespace {

using namespace par2d;

// A regular `count`-gon of radius r about (cx, cy), its first vertex at angle `phase`.
Polygon ngon(double cx, double cy, double r, int count, double phase) {
  Polygon p;
  for (int k = 0; k < count; ++k) {
    const double a = phase + 2.0 * 3.14159265358979323846 * k / count;
    p.vertices.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return p;
}

// One light polygon and one occluder polygon in a 24-unit view at 8x8 pixels, rendered
// on the scalar path with one thread.
void render_pair(benchmark::State& state, Polygon light_shape, Polygon occluder_shape) {
  Scene s;
  s.width = s.height = 8;
  s.view = {0, 0, 24, 24};
  Light light;
  light.shape = std::move(light_shape);
  s.lights.push_back(light);
  s.occluders.push_back({std::move(occluder_shape)});
  RenderOptions options;
  options.backend = Backend::scalar;
  options.threads = 1;
  bench::run_render(state, s, options);
}

// A light n-gon and an occluder (0.37·n)-gon on the same circle: their boundaries cross
// ~0.74·n times, every crossing a direction where the nearer shape may change.
void BM_OverlappingPolygons(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  render_pair(state, ngon(12, 12, 5, n, 0.0), ngon(12, 12, 5, static_cast<int>(0.37 * n), 0.3));
}
// Linear cost shows as time proportional to n (it was proportional to n^2: 27 s at 7300).
BENCHMARK(BM_OverlappingPolygons)->Arg(900)->Arg(1800)->Arg(3600)->Arg(7300)->Unit(benchmark::kMillisecond);

// A light (0.37 n)-gon nested in an occluder n-gon without touching it: distance 0 with no
// boundary crossing, which cost n * 0.37 n point-edge distances before the containment test.
void BM_NestedPolygons(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  render_pair(state, ngon(12, 12, 3, static_cast<int>(0.37 * n), 0.3), ngon(12, 12, 9, n, 0.0));
}
BENCHMARK(BM_NestedPolygons)->Arg(900)->Arg(1800)->Arg(3600)->Arg(7300)->Unit(benchmark::kMillisecond);

}  // namespace
