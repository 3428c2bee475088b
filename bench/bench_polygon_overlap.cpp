// Cost of two overlapping many-vertex polygons against their vertex count (issue 10: it was quadratic).
#include <benchmark/benchmark.h>

#include <cmath>

#include "bench_support.hpp"

namespace {

using namespace par2d;

// A light n-gon and an occluder (0.37·n)-gon on the same circle: their boundaries cross
// ~0.74·n times, every crossing a direction where the nearer shape may change.
Scene overlapping_polygons(int n) {
  auto ngon = [](double cx, double cy, double r, int count, double phase) {
    Polygon p;
    for (int k = 0; k < count; ++k) {
      const double a = phase + 2.0 * 3.14159265358979323846 * k / count;
      p.vertices.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
    }
    return p;
  };
  Scene s;
  s.width = s.height = 8;
  s.view = {0, 0, 24, 24};
  Light light;
  light.shape = ngon(12, 12, 5, n, 0.0);
  s.lights.push_back(light);
  s.occluders.push_back({ngon(12, 12, 5, static_cast<int>(0.37 * n), 0.3)});
  return s;
}

void BM_OverlappingPolygons(benchmark::State& state) {
  RenderOptions options;
  options.backend = Backend::scalar;
  options.threads = 1;
  bench::run_render(state, overlapping_polygons(static_cast<int>(state.range(0))), options);
}
// Linear cost shows as time proportional to n (it was proportional to n^2: 27 s at 7300).
BENCHMARK(BM_OverlappingPolygons)->Arg(900)->Arg(1800)->Arg(3600)->Arg(7300)->Unit(benchmark::kMillisecond);

}  // namespace
