// Benchmarks one bounce's piece radiances (docs/contract.md section 7): the scalar reference's
// evaluation (every light against every occluder at each piece midpoint) against the culled one
// the SIMD backends use (lights behind a piece and occluders off the segments to a light left
// out), on the example levels with albedo 0.5 on every occluder.
#include <benchmark/benchmark.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "par2d/scene.hpp"
#include "render/bounce_tiles.hpp"
#include "scalar/bounce_reference.hpp"
#include "world/world.hpp"

namespace {

par2d::Scene reflecting_example(const char* name) {
  par2d::Scene scene;
  const std::string path = std::string(PAR2D_SOURCE_DIR) + "/examples/" + name + ".json";
  if (!par2d::load_scene_file(path, scene).ok()) throw std::runtime_error("cannot load " + path);
  for (par2d::Occluder& o : scene.occluders) o.albedo = {0.5, 0.5, 0.5};
  return scene;
}

// cull: the culled evaluation; reach: also the lights' reach as the frame proves it for its view
// (computed once, outside the timing, as a frame has it from its culling).
void BM_BounceRadiances(benchmark::State& state, const char* name, bool cull, bool reach) {
  const par2d::Scene scene = reflecting_example(name);
  const par2d::detail::PreparedScene prepared = par2d::detail::prepare_scene(scene);
  par2d::detail::BounceFrame frame;
  par2d::detail::build_bounce_sources(prepared, frame);
  par2d::detail::ScalarScratch scratch;
  std::vector<par2d::detail::LightReach> reaches;
  if (reach) {
    par2d::detail::LightReachScratch reach_scratch;
    for (std::size_t l = 0; l < prepared.lights.size(); ++l)
      reaches.push_back(par2d::detail::compute_light_reach(prepared, l, reach_scratch));
  }
  const par2d::detail::ReachHidesLights hidden(reaches.data());
  for (auto _ : state) {
    par2d::detail::bounce_radiances(prepared, frame, 0, frame.pieces.size(), scratch, cull,
                                    reach ? &hidden : nullptr);
    benchmark::DoNotOptimize(frame.radiance.data());
  }
  state.counters["pieces"] = static_cast<double>(frame.pieces.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * frame.pieces.size()));
}

BENCHMARK_CAPTURE(BM_BounceRadiances, paper_reference, "paper", false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BounceRadiances, paper_culled, "paper", true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BounceRadiances, paper_culled_reach, "paper", true, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BounceRadiances, dungeon_reference, "dungeon", false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BounceRadiances, dungeon_culled, "dungeon", true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BounceRadiances, dungeon_culled_reach, "dungeon", true, true)->Unit(benchmark::kMillisecond);

}  // namespace
