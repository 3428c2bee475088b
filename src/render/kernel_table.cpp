// Kernel lookup: the tables themselves are per architecture (kernel_table_<arch>.cpp).
#include "render/kernel_table.hpp"

namespace par2d::detail {

const KernelSet* kernels_for(Isa isa) noexcept {
  const CompiledKernels compiled = compiled_kernels();
  for (std::size_t i = 0; i < compiled.count; ++i) {
    if (compiled.kernels[i].isa == isa) return &compiled.kernels[i];
  }
  return nullptr;
}

}  // namespace par2d::detail
