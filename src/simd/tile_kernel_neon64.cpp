// The PAR tile kernel compiled for ARM64 Advanced SIMD (NEON, 4 float lanes; baseline on aarch64).
#if !defined(__aarch64__) || !defined(__ARM_NEON)
#error "tile_kernel_neon64.cpp is for aarch64 targets only (see src/CMakeLists.txt)"
#endif
#include <xsimd/xsimd.hpp>

#if XSIMD_VERSION_MAJOR == 8
// xsimd 8.1 computes float division and square root on NEON as a reciprocal (square root)
// estimate refined by Newton-Raphson steps, inherited from 32-bit ARM: not correctly rounded,
// and more instructions than AArch64's own fdiv/fsqrt, which are exact like the x86 kernels'
// divps/sqrtps. These specializations of xsimd's NEON kernels for the neon64 arch restore them;
// they are visible only here, the one file that instantiates anything for neon64.
namespace xsimd::kernel {
template <>
inline batch<float, neon64> div<neon64>(batch<float, neon64> const& lhs, batch<float, neon64> const& rhs,
                                        requires_arch<neon>) noexcept {
  return vdivq_f32(lhs, rhs);
}
template <>
inline batch<float, neon64> sqrt<neon64>(batch<float, neon64> const& arg, requires_arch<neon>) noexcept {
  return vsqrtq_f32(arg);
}
}  // namespace xsimd::kernel
#endif

#define PAR2D_KERNEL_ARCH xsimd::neon64
#define PAR2D_KERNEL_SUFFIX neon64
#include "simd/tile_kernel_entry.hpp"
