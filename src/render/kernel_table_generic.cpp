// The kernel table of architectures without a SIMD kernel: empty, so only the scalar path runs.
#include "render/kernel_table.hpp"

namespace par2d::detail {

CompiledKernels compiled_kernels() noexcept { return {nullptr, 0}; }

}  // namespace par2d::detail
