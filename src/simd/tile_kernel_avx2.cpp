// The PAR tile kernel compiled for AVX2 + FMA (8 float lanes).
#if !defined(__AVX2__) || !defined(__FMA__)
#error "tile_kernel_avx2.cpp must be built with -mavx2 -mfma (see cmake/Par2dIsa.cmake)"
#endif
#define PAR2D_KERNEL_ARCH xsimd::fma3<xsimd::avx2>
#define PAR2D_KERNEL_SUFFIX avx2
#include "simd/tile_kernel_entry.hpp"
