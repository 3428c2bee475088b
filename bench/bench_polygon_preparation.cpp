// Cost of preparing polygons with many vertices against their vertex count (docs/performance.md):
// a concave comb light (validation, partition, its pieces and shared boundaries prepared as
// lights) and a triangle carrying collinear vertices (validation and the straight-vertex
// cleanup). Near-linear cost shows as time roughly proportional to the vertex count.
#include <benchmark/benchmark.h>

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
