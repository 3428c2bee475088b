// CPU probe for architectures without a SIMD kernel: only the scalar reference path runs.
#include "par2d/isa.hpp"

namespace par2d {

Isa detect_isa() noexcept { return Isa::scalar; }

}  // namespace par2d
