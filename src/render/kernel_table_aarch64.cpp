// The ARM64 kernel table (compiled only on aarch64): the NEON kernel.
#include "render/kernel_table.hpp"
#include "render/kernel_test_hooks.hpp"
#include "simd/tile_kernel_entries.hpp"

PAR2D_DECLARE_TILE_KERNELS(neon64)

namespace par2d::detail {
namespace {

constexpr KernelSet kKernels[] = {
    {Isa::neon64, 4, simd::render_tile_neon64, simd::add_light_layer_neon64, PAR2D_TILE_STORES(neon64)},
};

constexpr KernelTestHooks kTestHooks[] = {
    {Isa::neon64, 4, simd::union_measure_neon64, simd::atan2_neon64},
};

}  // namespace

const KernelTestHooks* kernel_test_hooks_for(Isa isa) noexcept { return find_test_hooks(kTestHooks, isa); }

CompiledKernels compiled_kernels() noexcept { return compiled_kernels_of(kKernels); }

}  // namespace par2d::detail
