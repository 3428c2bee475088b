// Cost of preparing polygons with many vertices against their vertex count (docs/performance.md):
// a concave comb light (validation, partition, its pieces and shared boundaries prepared as
// lights) and a triangle carrying collinear vertices (validation and the straight-vertex
// cleanup). Near-linear cost shows as time roughly proportional to the vertex count.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "comb_outline.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "world/world.hpp"

namespace {

using namespace par2d;

Polygon comb(int teeth, bool sideways) { return Polygon{par2d::bench::comb_outline(teeth, sideways)}; }

Scene light_scene(Polygon shape, double extent) {
  Scene s;
  s.width = s.height = 8;
  s.view = {-1.0, -1.0, extent + 1.0, extent + 1.0};
  Light light;
  light.shape = std::move(shape);
  s.lights.push_back(std::move(light));
  return s;
}

// Validation and preparation of a scene holding one comb light (what a render does before its
// first pixel).
void BM_CombLightPreparation(benchmark::State& state) {
  const int teeth = static_cast<int>(state.range(0));
  const Scene s = light_scene(comb(teeth, state.range(1) != 0), 2.0 * teeth);
  for (auto _ : state) {
    if (!validate_scene(s).ok()) state.SkipWithError("refused");
    benchmark::DoNotOptimize(detail::prepare_scene(s));
  }
  state.counters["vertices"] = static_cast<double>(4 * teeth + 2);
}
BENCHMARK(BM_CombLightPreparation)
    ->ArgsProduct({{1000, 4000, 16383}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// A star: n vertices at random radii in 0.2 .. 1 around the origin (fixed seed), scaled by 100.
Polygon star(int n) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(n));
  std::vector<Vec2> v;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * 3.14159265358979323846 * k / n, r = 20.0 + 80.0 * static_cast<double>(rng() >> 11) * 0x1p-53;
    v.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return Polygon{std::move(v)};
}

// A spiral strip of eight turns, 3 wide, n vertices (half along each side).
Polygon spiral(int n) {
  std::vector<Vec2> v;
  const int m = n / 2;
  for (int k = 0; k < m; ++k) {
    const double t = 16.0 * 3.14159265358979323846 * k / m;
    v.push_back({(1.0 + t) * std::cos(t), (1.0 + t) * std::sin(t)});
  }
  for (int k = m - 1; k >= 0; --k) {
    const double t = 16.0 * 3.14159265358979323846 * k / m;
    v.push_back({(4.0 + t) * std::cos(t), (4.0 + t) * std::sin(t)});
  }
  return Polygon{std::move(v)};
}

// A square with k x k square holes (4k^2 + 4 vertices).
Polygon holed(int k) {
  Polygon p{{{0.0, 0.0}, {3.0 * k + 1.0, 0.0}, {3.0 * k + 1.0, 3.0 * k + 1.0}, {0.0, 3.0 * k + 1.0}}};
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const double x = 3.0 * i + 1.0, y = 3.0 * j + 1.0;
      p.holes.push_back({{x, y}, {x + 2.0, y}, {x + 2.0, y + 2.0}, {x, y + 2.0}});
    }
  return p;
}

// Validation and preparation of one concave light of another shape: `shape` 0 a random star,
// 1 a spiral (n vertices each), 2 a square with k x k holes (n = k).
void BM_ConcaveLightPreparation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int shape = static_cast<int>(state.range(1));
  Polygon p = shape == 0 ? star(n) : (shape == 1 ? spiral(n) : holed(n));
  double extent = 0.0;
  for (const Vec2 v : p.vertices) extent = std::max({extent, std::abs(v.x), std::abs(v.y)});
  std::size_t vertices = p.vertices.size();
  for (const auto& hole : p.holes) vertices += hole.size();
  Scene s = light_scene(std::move(p), extent);
  s.view = {-extent - 1.0, -extent - 1.0, extent + 1.0, extent + 1.0};
  for (auto _ : state) {
    if (!validate_scene(s).ok()) state.SkipWithError("refused");
    benchmark::DoNotOptimize(detail::prepare_scene(s));
  }
  state.counters["vertices"] = static_cast<double>(vertices);
}
BENCHMARK(BM_ConcaveLightPreparation)
    ->Args({4000, 0})
    ->Args({16000, 0})
    ->Args({64000, 0})
    ->Args({4000, 1})
    ->Args({16000, 1})
    ->Args({64000, 1})
    ->Args({32, 2})
    ->Args({64, 2})
    ->Args({127, 2})
    ->Unit(benchmark::kMillisecond);

// A comb light moved by update_light in a Renderer holding it (validation, partition and the
// pieces laid out anew).
void BM_CombLightMove(benchmark::State& state) {
  const int teeth = static_cast<int>(state.range(0));
  Renderer renderer;
  Scene s = light_scene(Polygon{}, 2.0 * teeth);
  s.lights.clear();
  if (!renderer.set_scene(s).ok()) state.SkipWithError("set_scene");
  Light light;
  light.shape = comb(teeth, false);
  LightHandle handle;
  if (!renderer.add_light(light, &handle).ok()) state.SkipWithError("add_light");
  double dx = 0.0;
  for (auto _ : state) {
    dx = dx == 0.0 ? 0.5 : 0.0;
    Transform t;
    t.position = {dx, 0.0};
    if (!renderer.update_light(handle, light, t).ok()) state.SkipWithError("update_light");
  }
  state.counters["vertices"] = static_cast<double>(4 * teeth + 2);
}
BENCHMARK(BM_CombLightMove)->Arg(250)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond);

// A triangle light with `n` collinear vertices on one edge: validation and preparation.
void BM_CollinearTrianglePreparation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<Vec2> v;
  for (int k = 0; k < n; ++k) v.push_back({static_cast<double>(k), 0.0});
  v.insert(v.end(), {{static_cast<double>(n), 0.0}, {0.0, static_cast<double>(n)}});
  const Scene s = light_scene(Polygon{std::move(v)}, n);
  for (auto _ : state) {
    if (!validate_scene(s).ok()) state.SkipWithError("refused");
    benchmark::DoNotOptimize(detail::prepare_scene(s));
  }
}
BENCHMARK(BM_CollinearTrianglePreparation)->Arg(20000)->Arg(50000)->Arg(200000)->Unit(benchmark::kMillisecond);

}  // namespace
