// Benchmark support: the timed render loop, and synthetic scenes of scattered small occluders and lights.
#include "bench_support.hpp"

#include <algorithm>
#include <cstddef>
#include <new>
#include <string>

namespace par2d::bench {

namespace {
constexpr std::align_val_t kFrameAlignment{64};
}  // namespace

AlignedFloats::AlignedFloats(std::size_t count)
    : data_(static_cast<float*>(::operator new[](count * sizeof(float), kFrameAlignment))), count_(count) {
  std::fill(data_, data_ + count_, 0.0f);  // pages touched here, outside any timed loop
}

AlignedFloats::~AlignedFloats() { ::operator delete[](data_, kFrameAlignment); }

void run_render(benchmark::State& state, const Scene& scene, const RenderOptions& options) {
  constexpr double kFrameMpixels = 1920.0 * 1080.0 / 1e6;
  const AlignedFloats pixels(static_cast<size_t>(scene.width) * scene.height * 3);
  const ImageView image{pixels.data(), scene.width, scene.height, std::ptrdiff_t{3} * scene.width};
  for (auto _ : state) {
    const Status status = render(scene, options, image);
    if (!status.ok()) {
      state.SkipWithError(status.message().c_str());
      break;
    }
    benchmark::DoNotOptimize(pixels.data());
    benchmark::ClobberMemory();
  }
  const double mpixels = static_cast<double>(scene.width) * scene.height / 1e6 * static_cast<double>(state.iterations());
  state.counters["Mpixel/s"] = benchmark::Counter(mpixels, benchmark::Counter::kIsRate);
  state.counters["frames/s"] = benchmark::Counter(mpixels / kFrameMpixels, benchmark::Counter::kIsRate);
  state.SetLabel(std::string(isa_name(resolved_isa(options))) + ", " + std::to_string(scene.width) + "x" +
                 std::to_string(scene.height));
}
}  // namespace par2d::bench
