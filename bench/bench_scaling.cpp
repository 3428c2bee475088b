// Google Benchmark: how a 1920x1080 frame scales with occluder and light counts, culled and unculled.
//
// Names are parsed by tools/plot_bench.py:
//   scaling/<sweep>/occluders:<N>/lights:<M>/<culled|unculled>[/skipped:over_pair_budget]/real_time
// with <sweep> one of occluder_sweep (16 lights), light_sweep (256 occluders) or target (the
// two points of the 16x goal), and
//   scaling/size_grid/occluder_size:<MIN>-<MAX>/light_size:<MIN>-<MAX>/occluders:<N>/lights:<M>/culled/real_time
// for the 16 + 256 and 256 + 4096 levels over a grid of occluder and light sizes (pixels
// across). Every run uses the default SIMD ISA and all hardware threads.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <utility>
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

void run_scaling(benchmark::State& state, int lights, int occluders, bool culling,
                 const par2d::bench::ScatteredSizes& sizes = {}) {
  const par2d::Scene scene = par2d::bench::scattered_scene(lights, occluders, kSeed, kWidth, kHeight, sizes);
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

// A size band as its name in benchmark names and tables: "1.5-4".
std::string band_name(double lo, double hi) {
  const auto text = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return std::string(buffer);
  };
  return text(lo) + "-" + text(hi);
}

// Occluder sizes from rubble (1.5-4 px) to crates and pillars (12-40 px), light sizes from
// sparks (3-5 px) to lamps (6-12 px, the sweeps' default): the distributions that decide how
// many lights a tile sees against how many its pixels see.
void register_size_grid() {
  const std::pair<double, double> occluder_bands[] = {{1.5, 4.0}, {4.0, 12.0}, {12.0, 40.0}};
  const std::pair<double, double> light_bands[] = {{3.0, 5.0}, {6.0, 12.0}};
  for (const auto& [omin, omax] : occluder_bands) {
    for (const auto& [lmin, lmax] : light_bands) {
      const par2d::bench::ScatteredSizes sizes{omin, omax, lmin, lmax};
      for (const auto& [lights, occluders] : {std::pair{16, 256}, std::pair{256, 4096}}) {
        const std::string name = "scaling/size_grid/occluder_size:" + band_name(omin, omax) +
                                 "/light_size:" + band_name(lmin, lmax) + "/occluders:" + std::to_string(occluders) +
                                 "/lights:" + std::to_string(lights) + "/culled";
        benchmark::RegisterBenchmark(name.c_str(),
                                     [lights = lights, occluders = occluders, sizes](benchmark::State& state) {
                                       run_scaling(state, lights, occluders, true, sizes);
                                     })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

const bool registered = [] {
  for (const bool culling : {true, false}) {
    for (const int occluders : {16, 64, 256, 1024, 4096}) register_point("occluder_sweep", 16, occluders, culling);
    for (const int lights : {1, 4, 16, 64, 256}) register_point("light_sweep", lights, 256, culling);
  }
  register_point("target", 16, 256, true);
  register_point("target", 256, 4096, true);
  register_size_grid();
  return true;
}();

}  // namespace
