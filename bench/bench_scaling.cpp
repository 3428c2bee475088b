// Google Benchmark: how a 1920x1080 frame scales with occluder and light counts, culled and unculled.
//
// Names are parsed by tools/plot_bench.py:
//   scaling/<sweep>/occluders:<N>/lights:<M>/<culled|unculled>[/skipped:over_pair_budget]/real_time
// with <sweep> one of occluder_sweep (16 lights), light_sweep (256 occluders) or target (the
// issue's two target points). Every run uses the default SIMD ISA and all hardware threads.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "par2d/par2d.hpp"
#include "bench_support.hpp"

namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;
constexpr uint32_t kSeed = 20240611;
// Unculled work grows with lights x occluders per pixel, so points above a pair budget are listed
// but skipped: they would only show the quadratic cost that culling removes, at minutes per run.
// On the 2-core development machine (load average 4-8 from parallel builds) the kept points took
// 1.2 s (16 x 16), 3.9 s (1 x 256), 6.9 s (16 x 64) and 11.7 s (4 x 256) wall per frame, with
// 0.3-2.7 s CPU on the calling thread (wall times there are inflated by the load). The budget
// keeps two unculled points per sweep, enough for a slope; the next one (16 x 256) took 36 s. PAR2D_BENCH_UNCULLED_MAX_PAIRS overrides the budget for a faster
// renderer or a bigger machine.
constexpr long kDefaultUnculledMaxPairs = 1024;

long unculled_max_pairs() {
  if (const char* env = std::getenv("PAR2D_BENCH_UNCULLED_MAX_PAIRS")) {
    char* end = nullptr;
    const long v = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && v >= 0) return v;
    std::fprintf(stderr, "bench_scaling: ignoring PAR2D_BENCH_UNCULLED_MAX_PAIRS=\"%s\" (not a count)\n", env);
  }
  return kDefaultUnculledMaxPairs;
}

void run_scaling(benchmark::State& state, int lights, int occluders, bool culling) {
  const par2d::Scene scene = par2d::bench::scattered_scene(lights, occluders, kSeed, kWidth, kHeight);
  par2d::RenderOptions options;
  options.backend = par2d::Backend::simd;  // at the default ISA: what an embedding engine gets
  options.threads = 0;
  options.culling = culling;
  par2d::bench::run_render(state, scene, options);
}

void register_point(const char* sweep, int lights, int occluders, bool culling) {
  std::string name = std::string("scaling/") + sweep + "/occluders:" + std::to_string(occluders) +
                     "/lights:" + std::to_string(lights) + (culling ? "/culled" : "/unculled");
  const bool skip = !culling && static_cast<long>(lights) * occluders > unculled_max_pairs();
  if (skip) {
    // Still registered, so --benchmark_list_tests and the JSON say which points were left out.
    name += "/skipped:over_pair_budget";
    benchmark::RegisterBenchmark(name.c_str(), [](benchmark::State& state) {
      state.SkipWithError("unculled lights x occluders above PAR2D_BENCH_UNCULLED_MAX_PAIRS (frame > ~3 s); skipped");
    })->UseRealTime();
    return;
  }
  benchmark::RegisterBenchmark(name.c_str(),
                               [lights, occluders, culling](benchmark::State& state) {
                                 run_scaling(state, lights, occluders, culling);
                               })
      ->Unit(benchmark::kMillisecond)
      // The frame is rendered by TBB workers; the calling thread's CPU time would understate it.
      ->UseRealTime();
}

const bool registered = [] {
  for (const bool culling : {true, false}) {
    for (const int occluders : {16, 64, 256, 1024, 4096}) register_point("occluder_sweep", 16, occluders, culling);
    for (const int lights : {1, 4, 16, 64, 256}) register_point("light_sweep", lights, 256, culling);
  }
  register_point("target", 16, 256, true);
  register_point("target", 256, 4096, true);
  return true;
}();

}  // namespace
