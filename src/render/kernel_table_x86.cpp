// The x86 kernel table (compiled only on x86): SSE4.2, AVX2 and AVX-512 kernels.
#include "render/kernel_table.hpp"
#include "render/kernel_test_hooks.hpp"
#include "simd/tile_kernel_entries.hpp"

PAR2D_DECLARE_TILE_KERNELS(sse4_2)
PAR2D_DECLARE_TILE_KERNELS(avx2)
PAR2D_DECLARE_TILE_KERNELS(avx512)

namespace par2d::detail {
namespace {

constexpr KernelSet kKernels[] = {
    {Isa::sse4_2, 4, simd::render_tile_sse4_2, simd::add_light_layer_sse4_2, PAR2D_TILE_STORES(sse4_2)},
    {Isa::avx2, 8, simd::render_tile_avx2, simd::add_light_layer_avx2, PAR2D_TILE_STORES(avx2)},
    {Isa::avx512, 16, simd::render_tile_avx512, simd::add_light_layer_avx512, PAR2D_TILE_STORES(avx512)},
};

constexpr KernelTestHooks kTestHooks[] = {
    {Isa::sse4_2, 4, simd::union_measure_sse4_2, simd::atan2_sse4_2},
    {Isa::avx2, 8, simd::union_measure_avx2, simd::atan2_avx2},
    {Isa::avx512, 16, simd::union_measure_avx512, simd::atan2_avx512},
};

}  // namespace

const KernelTestHooks* kernel_test_hooks_for(Isa isa) noexcept { return find_test_hooks(kTestHooks, isa); }

CompiledKernels compiled_kernels() noexcept { return compiled_kernels_of(kKernels); }

}  // namespace par2d::detail
