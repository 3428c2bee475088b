// CPU probe for x86 (compiled only there). xsimd 8.1's own detection misreads SSE2 and
// skips the OS (XGETBV) check, so we ask the compiler's cpu model instead.
#if !defined(__x86_64__) && !defined(__i386__)
#error "isa_detect_x86.cpp is for x86 targets only (see src/CMakeLists.txt)"
#endif
#include "par2d/isa.hpp"

namespace par2d {

Isa detect_isa() noexcept {
  __builtin_cpu_init();
  // GCC's cpu model checks OSXSAVE/XGETBV before reporting AVX and AVX-512 usable.
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("fma") &&
      __builtin_cpu_supports("bmi2"))
    return Isa::avx512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
      __builtin_cpu_supports("bmi2"))
    return Isa::avx2;
  if (__builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt")) return Isa::sse4_2;
  return Isa::scalar;
}

}  // namespace par2d
