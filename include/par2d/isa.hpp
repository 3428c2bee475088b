// Instruction-set levels the fast path is compiled for, their detection and names.
#pragma once

#include <optional>
#include <string_view>

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// Ordered from least to most capable. `scalar` is the double-precision reference path.
enum class Isa {
  scalar = 0,
  sse4_2 = 1,  // SSE4.2, 4 float lanes
  avx2 = 2,    // AVX2 + FMA, 8 float lanes
  avx512 = 3,  // AVX-512 F/BW/DQ/VL, 16 float lanes
};

// The best level this CPU and OS support (CPUID and XGETBV), ignoring PAR2D_ISA.
Isa detect_isa() noexcept;

// The level the fast path uses by default: detect_isa(), capped by the PAR2D_ISA
// environment variable (scalar|sse4|avx2|avx512) when it is set to a valid name.
Isa default_isa() noexcept;

// Whether this CPU can run kernels of `isa`.
bool isa_supported(Isa isa) noexcept;

// "scalar", "sse4", "avx2", "avx512".
const char* isa_name(Isa isa) noexcept;

// Inverse of isa_name; also accepts "sse4.2", "sse4_2". Empty for unknown names.
std::optional<Isa> parse_isa(std::string_view name) noexcept;

// Number of float lanes of the kernel for `isa` (1 for scalar).
int isa_lanes(Isa isa) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
