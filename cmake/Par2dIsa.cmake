# Target architecture and per-ISA kernel files: each `*_<isa>.cpp` gets its own target flags,
# and optimisation even in Debug (at -O0 shared inline helpers are emitted in the AVX object
# too, and the linker may hand that copy to SSE callers).
#
# PAR2D_ARCH: x86, aarch64, wasm (WebAssembly with SIMD128) or generic (scalar only), from the target (not the host) processor,
# so a cross build (cmake/toolchains/) picks the target's kernels, CPU probe and kernel table.
# PAR2D_ISA_NAMES: the PAR2D_ISA values worth a test run on that architecture.
# WebAssembly (emscripten): PAR2D_WASM_SIMD (default ON) compiles the SSE4.2 kernel to SIMD128
# through emscripten's SSE intrinsics headers and picks it statically (there is no CPUID: a
# module with SIMD128 instructions only loads where the engine has them). OFF builds the scalar
# path alone, with no SIMD128 instruction anywhere in the module.
option(PAR2D_WASM_SIMD "WebAssembly: compile the SSE4.2 kernel to SIMD128" ON)
if(CMAKE_SYSTEM_NAME STREQUAL "Emscripten")
  if(PAR2D_WASM_SIMD)
    set(PAR2D_ARCH wasm)
    set(PAR2D_ISA_NAMES scalar sse4)
  else()
    set(PAR2D_ARCH generic)
    set(PAR2D_ISA_NAMES scalar)
  endif()
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64|x64|i[3-6]86|x86)$")
  set(PAR2D_ARCH x86)
  set(PAR2D_ISA_NAMES scalar sse4 avx2 avx512)
elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64|ARM64|armv8.*64)$")
  set(PAR2D_ARCH aarch64)
  set(PAR2D_ISA_NAMES scalar neon64)
else()
  set(PAR2D_ARCH generic)
  set(PAR2D_ISA_NAMES scalar)
endif()
message(STATUS "par2d: target architecture ${PAR2D_ARCH} (${CMAKE_SYSTEM_PROCESSOR}), kernels: ${PAR2D_ISA_NAMES}")

if(PAR2D_ARCH STREQUAL "wasm")
  # emscripten maps the SSE4.2 intrinsics onto SIMD128 (it needs -msimd128 with -msse4.2).
  set(PAR2D_ISA_FLAGS_sse4_2 -msimd128 -msse4.2)
else()
  set(PAR2D_ISA_FLAGS_sse4_2 -msse4.2 -mpopcnt)
endif()
# -Wmaybe-uninitialized is GCC's alone (clang warns about the unknown option).
set(PAR2D_NO_UNINIT_WARNINGS -Wno-uninitialized $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
set(PAR2D_ISA_FLAGS_avx2 -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt ${PAR2D_NO_UNINIT_WARNINGS})
set(PAR2D_ISA_FLAGS_avx512 -mavx512f -mavx512bw -mavx512dq -mavx512vl -mavx512cd -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt ${PAR2D_NO_UNINIT_WARNINGS})
# NEON (Advanced SIMD) is baseline on AArch64: no flag adds it, none must remove it.
set(PAR2D_ISA_FLAGS_neon64 "")
set(PAR2D_ISAS_x86 sse4_2 avx2 avx512)
set(PAR2D_ISAS_aarch64 neon64)
set(PAR2D_ISAS_wasm sse4_2)

# The kernel files' optimisation level: -O3 for every build a user makes. (The sanitizer builds
# once took -O1 here because one instrumented kernel file took minutes at -O3; the cause was
# forced inlining, which instrumented builds now leave to the compiler: PAR2D_KERNEL_INLINE_HINTS
# in CMakeLists.txt.) -O1 at least: -O0 (and -Og, which inlines as little) would emit the shared
# inline helpers out of line with the ISA's instructions.
set(PAR2D_KERNEL_OPTIMIZATION "-O3" CACHE STRING "Optimisation flag of the per-ISA kernel files: -O1, -O2 or -O3")
if(NOT PAR2D_KERNEL_OPTIMIZATION MATCHES "^-O[123]$")
  message(FATAL_ERROR "PAR2D_KERNEL_OPTIMIZATION must be -O1, -O2 or -O3, got '${PAR2D_KERNEL_OPTIMIZATION}'")
endif()

function(par2d_isa_source file isa)
  if(NOT DEFINED PAR2D_ISA_FLAGS_${isa})
    message(FATAL_ERROR "unknown ISA ${isa} for ${file}")
  endif()
  set_source_files_properties(${file} PROPERTIES COMPILE_OPTIONS "${PAR2D_ISA_FLAGS_${isa}};${PAR2D_KERNEL_OPTIMIZATION}")
endfunction()
