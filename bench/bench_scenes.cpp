// Google Benchmark: the example scenes at 1920x1080, per path (scalar and each supported SIMD ISA) and thread count.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.hpp"
#include "par2d/par2d.hpp"

namespace {

// Pixels of one 1920x1080 frame, in millions: "frames/s" counts 1080p frame equivalents so the
// scalar path, measured at a smaller size, reads on the same scale as the SIMD paths.
// The scalar reference takes seconds per 1080p frame; a quarter-size frame (same view) keeps the
// suite short and per-pixel throughput comparable.
constexpr int kScalarWidth = 480;
constexpr int kScalarHeight = 270;

// Loads an example scene and resizes it, keeping the world rectangle it showed: the loader stores
// the view explicitly, so changing width and height alone keeps the view.
par2d::Scene load_example(const std::string& name, int width, int height) {
  par2d::Scene scene;
  const std::string path = std::string(PAR2D_SOURCE_DIR) + "/examples/" + name + ".json";
  const par2d::Status status = par2d::load_scene_file(path, scene);
  if (!status.ok()) {
    std::fprintf(stderr, "bench_scenes: %s\n", status.message().c_str());
    std::exit(1);
  }
  const par2d::View original = scene.view;
  scene.width = width;
  scene.height = height;
  scene.view = original;
  return scene;
}


void register_scene(const std::string& name, const std::vector<par2d::Isa>& isas, const std::vector<int>& thread_counts) {
  for (const int threads : thread_counts) {
    const std::string suffix = "/threads:" + std::to_string(threads);
    par2d::RenderOptions scalar;
    scalar.backend = par2d::Backend::scalar;
    scalar.threads = threads;
    auto* b = benchmark::RegisterBenchmark(
        ("scenes/" + name + "/scalar@480x270" + suffix).c_str(),
        [name, scalar](benchmark::State& s) { par2d::bench::run_render(s, load_example(name, kScalarWidth, kScalarHeight), scalar); });
    // Wall time for every thread count, so that 1- and N-thread results divide into a speed-up
    // (CPU time of the calling thread would flatter multi-threaded runs).
    b->Unit(benchmark::kMillisecond)->UseRealTime();

    for (const par2d::Isa isa : isas) {
      par2d::RenderOptions simd;
      simd.backend = par2d::Backend::simd;
      simd.isa = isa;
      simd.threads = threads;
      auto* s = benchmark::RegisterBenchmark(
          ("scenes/" + name + "/" + par2d::isa_name(isa) + suffix).c_str(),
          [name, simd](benchmark::State& st) { par2d::bench::run_render(st, load_example(name, 1920, 1080), simd); });
      s->Unit(benchmark::kMillisecond)->UseRealTime();
    }
  }
}

// What per-tile culling saves on the dungeon (16 lights, ~200 occluders): same image both ways.
void register_dungeon_culling(int threads) {
  for (const bool culling : {true, false}) {
    par2d::RenderOptions options;
    options.backend = par2d::Backend::simd;
    options.threads = threads;
    options.culling = culling;
    auto* b = benchmark::RegisterBenchmark(
        (std::string("scenes/dungeon/culling/") + (culling ? "culled" : "unculled") + "/threads:" +
         std::to_string(threads))
            .c_str(),
        [options](benchmark::State& s) { par2d::bench::run_render(s, load_example("dungeon", 1920, 1080), options); });
    b->Unit(benchmark::kMillisecond)->UseRealTime();
  }
}

// Registration happens before benchmark_main parses the command line, so --benchmark_list_tests
// shows exactly the paths this CPU can run. Scenes are loaded inside each benchmark (outside the
// timed loop), not here, so nothing depends on the library's static initialisation order.
const bool registered = [] {
  std::vector<par2d::Isa> isas;
  for (const par2d::Isa isa : par2d::kSimdIsas) {
    if (par2d::isa_supported(isa)) isas.push_back(isa);
  }
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::vector<int> thread_counts{1};
  if (hardware > 1) thread_counts.push_back(hardware);
  for (const char* name : {"paper", "colored_lights", "dungeon"}) register_scene(name, isas, thread_counts);
  register_dungeon_culling(hardware);
  return true;
}();

}  // namespace
