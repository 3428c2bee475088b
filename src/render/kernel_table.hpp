// The table of compiled tile kernels, one entry per ISA.
#pragma once

#include <cstddef>

#include "par2d/isa.hpp"
#include "render/frame_output.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

struct KernelSet {
  Isa isa;
  int lanes;
  void (*render_tile)(const TileWork& work, float* scratch, TileResult& out) noexcept;
  // out += emission[c] x layer plane c (plane 0 for every channel when `mono`): the light-layer
  // cache's recombination (render/light_layers.hpp).
  void (*add_light_layer)(const float* layer, bool mono, const float* emission, TileResult& out) noexcept;
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

// A kernel_table_<arch>.cpp's table as CompiledKernels.
template <std::size_t N>
constexpr CompiledKernels compiled_kernels_of(const KernelSet (&table)[N]) noexcept {
  return {table, N};
}

// The kernels for `isa`, or null for Isa::scalar (the scalar path is the reference renderer)
// and for levels not compiled for this architecture.
const KernelSet* kernels_for(Isa isa) noexcept;

}  // namespace par2d::detail
