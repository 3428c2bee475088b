// The table of compiled tile kernels, one entry per ISA, and the SIMD render driver.
#pragma once

#include <cstddef>

#include "par2d/isa.hpp"
#include "par2d/render.hpp"
#include <vector>

#include "render/frame_output.hpp"
#include "culling/light_reach.hpp"
#include "world/prepared_scene.hpp"
#include "render/scheduler.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

struct KernelSet {
  Isa isa;
  int lanes;
  void (*render_tile)(const TileWork& work, float* scratch, TileResult& out) noexcept;
  // Kernel-level hooks for tests: per lane, the measure of the union of `count` intervals
  // (lo/hi hold pow2(count) * lanes floats, lane-minor, and are sorted in place), of
  // [0, reach0], padded with `width`; and the vector atan2 over `lanes` values, in the form
  // the kernel uses for a domain: 0 any (y, x), 1 y >= 0 (fast_atan2_upper), 2 x, y >= 0
  // (fast_atan2_first_quadrant).
  void (*union_measure)(float* lo, float* hi, std::size_t count, const float* width, const float* reach0,
                        float* out) noexcept;
  void (*atan2)(const float* y, const float* x, float* out, int domain) noexcept;
  // Vector tile stores into the host's pixel formats (the buckets of 8-bit sRGB come with
  // each frame's exposure).
  VectorTileStores stores;
};

// The kernels compiled for the target architecture, least capable first (none on
// architectures without a SIMD kernel). Defined in kernel_table_<arch>.cpp.
struct CompiledKernels {
  const KernelSet* kernels;
  std::size_t count;
};
CompiledKernels compiled_kernels() noexcept;

// The kernels for `isa`, or null for Isa::scalar (the scalar path is the reference renderer)
// and for levels not compiled for this architecture.
const KernelSet* kernels_for(Isa isa) noexcept;

// What one frame computes: samples per pixel, culling, and the kernel ISA (Isa::scalar:
// the reference path, pixel by pixel).
struct FrameSettings {
  int spp = 1;
  bool culling = true;
  Isa isa = Isa::scalar;
  bool shaded = false;  // RenderOptions::shaded (docs/contract.md section 6)
  bool sample_needs = false;  // fill FrameStats' sampled counts (one exact pixel per tile)
};

// Renders frames of prepared scenes into host buffers, tile by tile, keeping every
// per-thread buffer from frame to frame: after the first frame at a size (and worker
// count) a frame allocates nothing.
class FrameEngine {
 public:
  FrameEngine();
  ~FrameEngine();
  FrameEngine(FrameEngine&&) noexcept;
  FrameEngine& operator=(FrameEngine&&) noexcept;

  // The pixels of target.region, each tile computed whole and stored straight into the
  // target's format. Tiles and blocks are those of the whole frame, so a region's pixels
  // equal the same pixels of a whole frame bit for bit. `reach` (with culling): per light.
  // `stats`, when given, receives the frame's culling and kernel work (FrameStats).
  void render(const PreparedScene& scene, const std::vector<LightReach>* reach, const FrameSettings& settings,
              const Scheduler& scheduler, const FrameTarget& target, FrameStats* stats = nullptr);

 private:
  struct ThreadState;
  FrameStats sum_counts(int lanes) const noexcept;
  std::vector<ThreadState> states_;
  SrgbBuckets srgb_;  // the last 8-bit sRGB target's exposure's, rebuilt when it changes
};

}  // namespace par2d::detail
