// Kernel-level entry points for tests only, one row per compiled ISA, apart from the
// production table (render/kernel_table.hpp) so that no renderer can reach them.
#pragma once

#include <cstddef>

#include "par2d/isa.hpp"

namespace par2d::detail {

struct KernelTestHooks {
  Isa isa;
  int lanes;
  // Per lane, the measure of the union of `count` intervals (lo/hi hold pow2(count) * lanes
  // floats, lane-minor, and are sorted in place), of [0, reach0], padded with `width`.
  void (*union_measure)(float* lo, float* hi, std::size_t count, const float* width, const float* reach0,
                        float* out) noexcept;
  // The vector atan2 over `lanes` values, in the form the kernel uses for a domain: 0 any
  // (y, x), 1 y >= 0 (fast_atan2_upper), 2 x, y >= 0 (fast_atan2_first_quadrant).
  void (*atan2)(const float* y, const float* x, float* out, int domain) noexcept;
};

// The hooks of `isa`'s kernel, or null where kernels_for(isa) is null. Defined next to the
// kernel table in kernel_table_<arch>.cpp.
const KernelTestHooks* kernel_test_hooks_for(Isa isa) noexcept;

// The row of `isa` in a kernel_table_<arch>.cpp's table of hooks, or null.
template <std::size_t N>
const KernelTestHooks* find_test_hooks(const KernelTestHooks (&table)[N], Isa isa) noexcept {
  for (const KernelTestHooks& hooks : table)
    if (hooks.isa == isa) return &hooks;
  return nullptr;
}

}  // namespace par2d::detail
