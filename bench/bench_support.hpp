// Shared by the benchmarks: the timed render loop (and, via scattered_scene.hpp, synthetic levels).
#pragma once

#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "scattered_scene.hpp"

namespace par2d::bench {

// A zero-filled float buffer starting on a 64-byte boundary, as the README recommends for
// frames large enough to take non-temporal stores (a std::vector's large blocks start 16
// bytes past a page, so none of their rows would).
class AlignedFloats {
 public:
  explicit AlignedFloats(std::size_t count);
  ~AlignedFloats();
  AlignedFloats(const AlignedFloats&) = delete;
  AlignedFloats& operator=(const AlignedFloats&) = delete;
  float* data() const noexcept { return data_; }

 private:
  float* data_;
  std::size_t count_;
};

// Renders `scene` once per iteration into a buffer allocated outside the timed loop and
// reports "Mpixel/s" and "frames/s" (1920 x 1080 frame equivalents) counters.
void run_render(benchmark::State& state, const Scene& scene, const RenderOptions& options);

}  // namespace par2d::bench
