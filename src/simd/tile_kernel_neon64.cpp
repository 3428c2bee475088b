// The PAR tile kernel compiled for ARM64 Advanced SIMD (NEON, 4 float lanes; baseline on aarch64).
#if !defined(__aarch64__) || !defined(__ARM_NEON)
#error "tile_kernel_neon64.cpp is for aarch64 targets only (see src/CMakeLists.txt)"
#endif
#define PAR2D_KERNEL_ARCH xsimd::neon64
#define PAR2D_KERNEL_SUFFIX neon64
#include "simd/tile_kernel_entry.hpp"
