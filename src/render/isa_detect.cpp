// CPU feature detection for the kernel table. xsimd 8.1's own detection misreads SSE2
// and skips the OS (XGETBV) check, so we ask the compiler's cpu model instead.
#include <cstdlib>
#include <cstring>
#include <string>

#include "par2d/isa.hpp"

namespace par2d {

Isa detect_isa() noexcept {
#if defined(__x86_64__) || defined(__i386__)
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
#endif
  return Isa::scalar;
}

bool isa_supported(Isa isa) noexcept { return static_cast<int>(isa) <= static_cast<int>(detect_isa()); }

Isa default_isa() noexcept {
  Isa best = detect_isa();
  if (const char* env = std::getenv("PAR2D_ISA")) {
    if (auto forced = parse_isa(env)) {
      if (static_cast<int>(*forced) < static_cast<int>(best)) best = *forced;
    }
  }
  return best;
}

const char* isa_name(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse4_2: return "sse4";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "unknown";
}

std::optional<Isa> parse_isa(std::string_view name) noexcept {
  if (name == "scalar") return Isa::scalar;
  if (name == "sse4" || name == "sse4.2" || name == "sse4_2") return Isa::sse4_2;
  if (name == "avx2") return Isa::avx2;
  if (name == "avx512") return Isa::avx512;
  return std::nullopt;
}

int isa_lanes(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return 1;
    case Isa::sse4_2: return 4;
    case Isa::avx2: return 8;
    case Isa::avx512: return 16;
  }
  return 1;
}

}  // namespace par2d
