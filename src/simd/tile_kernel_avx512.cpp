// The PAR tile kernel compiled for AVX-512 F/BW/DQ/VL (16 float lanes).
#if !defined(__AVX512F__) || !defined(__AVX512BW__)
#error "tile_kernel_avx512.cpp must be built with -mavx512f -mavx512bw (see cmake/Par2dIsa.cmake)"
#endif
#define PAR2D_KERNEL_ARCH xsimd::avx512bw
#define PAR2D_KERNEL_SUFFIX avx512
#include "simd/tile_kernel_entry.hpp"
