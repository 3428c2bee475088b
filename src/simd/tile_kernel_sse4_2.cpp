// The PAR tile kernel compiled for SSE4.2 (4 float lanes).
#if !defined(__SSE4_2__)
#error "tile_kernel_sse4_2.cpp must be built with -msse4.2 (see cmake/Par2dIsa.cmake)"
#endif
#define PAR2D_KERNEL_ARCH xsimd::sse4_2
#define PAR2D_KERNEL_SUFFIX sse4_2
#include "simd/tile_kernel_entry.hpp"
