// Shared by the benchmarks: the timed render loop (and, via scattered_scene.hpp, synthetic levels).
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "scattered_scene.hpp"

namespace par2d::bench {

// Renders `scene` once per iteration into a buffer allocated outside the timed loop and
// reports "Mpixel/s" and "frames/s" (1920 x 1080 frame equivalents) counters.
void run_render(benchmark::State& state, const Scene& scene, const RenderOptions& options);

}  // namespace par2d::bench
