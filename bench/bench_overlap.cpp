// Google Benchmark: what lights overlapping walls cost on the SIMD path. The same 1280x720
// level with 8 torches each poking 1 px into its wall, and with the torches 2 px off the
// walls; per supported ISA, one thread. Their ratio is the price of the general pairs.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_support.hpp"
#include "par2d/par2d.hpp"
#include "world/world.hpp"
#include "torch_level.hpp"

namespace {

// The level as benchmarked, checked once: every torch must overlap a wall in the overlap
// variant and none in the other, or the comparison would not measure what it says.
par2d::Scene checked_level(bool overlapping) {
  const par2d::Scene scene = par2d::bench::torch_level(overlapping ? -1.0 : 2.0);
  const par2d::detail::PreparedScene prepared = par2d::detail::prepare_scene(scene);
  for (const par2d::detail::PreparedLight& light : prepared.lights) {
    if (light.overlapping_occluders.empty() == overlapping) {
      std::fprintf(stderr, "bench_overlap: torch level (overlapping=%d) is not as intended\n", overlapping ? 1 : 0);
      std::exit(1);
    }
  }
  return scene;
}

const bool registered = [] {
  for (const par2d::Isa isa : {par2d::Isa::sse4_2, par2d::Isa::avx2, par2d::Isa::avx512}) {
    if (!par2d::isa_supported(isa)) continue;
    for (const bool overlapping : {true, false}) {
      par2d::RenderOptions options;
      options.backend = par2d::Backend::simd;
      options.isa = isa;
      options.threads = 1;
      const std::string name = std::string("overlap/torches_") + (overlapping ? "in_walls_1px" : "off_walls_2px") +
                               "/" + par2d::isa_name(isa) + "/threads:1";
      benchmark::RegisterBenchmark(name.c_str(), [overlapping, options](benchmark::State& s) {
        par2d::bench::run_render(s, checked_level(overlapping), options);
      })->Unit(benchmark::kMillisecond)->UseRealTime();
    }
  }
  return true;
}();

}  // namespace
