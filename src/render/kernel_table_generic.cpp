// The kernel table of architectures without a SIMD kernel: empty, so only the scalar path runs.
#include "render/kernel_table.hpp"
#include "render/kernel_test_hooks.hpp"

namespace par2d::detail {

const KernelTestHooks* kernel_test_hooks_for(Isa) noexcept { return nullptr; }

CompiledKernels compiled_kernels() noexcept { return {nullptr, 0}; }

}  // namespace par2d::detail
