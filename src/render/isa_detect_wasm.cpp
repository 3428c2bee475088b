// CPU probe of WebAssembly builds with SIMD128 (cmake/Par2dIsa.cmake, PAR2D_WASM_SIMD): there is
// no CPUID, and a module holding SIMD128 instructions is refused at load time by an engine
// without them, so a module that runs has them. The level reported is the kernel compiled for
// it: the SSE4.2 one, its intrinsics mapped onto SIMD128 by emscripten.
#include "par2d/isa.hpp"

#if !defined(__EMSCRIPTEN__)
#error "isa_detect_wasm.cpp is for emscripten builds (PAR2D_ARCH wasm)"
#endif

namespace par2d {

Isa detect_isa() noexcept { return Isa::sse4_2; }

}  // namespace par2d
