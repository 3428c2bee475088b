// Instruction-set levels the fast path is compiled for, their detection and names.
#pragma once

#include <optional>
#include <string_view>

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// `scalar` is the double-precision reference path and runs everywhere. The x86 levels are
// ordered from least to most capable, each a superset of the one before; neon64 is the
// ARM64 level (a different architecture: an x86 CPU never supports it, nor the reverse).
enum class Isa {
  scalar = 0,
  sse4_2 = 1,  // SSE4.2, 4 float lanes (x86)
  avx2 = 2,    // AVX2 + FMA, 8 float lanes (x86)
  avx512 = 3,  // AVX-512 F/BW/DQ/VL, 16 float lanes (x86)
  neon64 = 4,  // ARM64 Advanced SIMD (NEON), 4 float lanes (aarch64)
};

// Every vectorized level of every architecture, for loops over "each level this CPU has"
// (filter with isa_supported).
inline constexpr Isa kSimdIsas[] = {Isa::sse4_2, Isa::avx2, Isa::avx512, Isa::neon64};

// The best level this CPU and OS support, ignoring PAR2D_ISA: on x86 from CPUID and
// XGETBV, on aarch64 NEON (baseline there), scalar on other architectures.
Isa detect_isa() noexcept;

// The level that runs when `wanted` is asked for: `wanted` if this CPU supports it,
// otherwise detect_isa(). Since the x86 levels nest, on x86 this caps `wanted` at the
// best level the CPU has; a level of another architecture falls back to that best level.
Isa capped_isa(Isa wanted) noexcept;

// The level the fast path uses by default: detect_isa(), or capped_isa() of the PAR2D_ISA
// environment variable (scalar|sse4|avx2|avx512|neon64) when it is set to a valid name.
Isa default_isa() noexcept;

// Whether this CPU can run kernels of `isa` (always true for scalar).
bool isa_supported(Isa isa) noexcept;

// "scalar", "sse4", "avx2", "avx512", "neon64".
const char* isa_name(Isa isa) noexcept;

// Inverse of isa_name; also accepts "sse4.2", "sse4_2", "neon". Empty for unknown names.
std::optional<Isa> parse_isa(std::string_view name) noexcept;

// Number of float lanes of the kernel for `isa` (1 for scalar).
int isa_lanes(Isa isa) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
