// The WebAssembly kernel table (PAR2D_ARCH wasm): the SSE4.2 kernel, compiled to SIMD128.
#include "render/kernel_table.hpp"
#include "render/kernel_test_hooks.hpp"
#include "simd/tile_kernel_entries.hpp"

PAR2D_DECLARE_TILE_KERNELS(sse4_2)

namespace par2d::detail {
namespace {

constexpr KernelSet kKernels[] = {
    {Isa::sse4_2, 4, simd::render_tile_sse4_2, simd::add_light_layer_sse4_2, PAR2D_TILE_STORES(sse4_2)},
};

constexpr KernelTestHooks kTestHooks[] = {
    {Isa::sse4_2, 4, simd::union_measure_sse4_2, simd::atan2_sse4_2},
};

}  // namespace

const KernelTestHooks* kernel_test_hooks_for(Isa isa) noexcept { return find_test_hooks(kTestHooks, isa); }

CompiledKernels compiled_kernels() noexcept { return compiled_kernels_of(kKernels); }

}  // namespace par2d::detail
