// CPU probe for ARM64 (compiled only there): Advanced SIMD (NEON) is part of the AArch64
// baseline that every compiler targets, so the only question is whether the OS says so too.
#if !defined(__aarch64__)
#error "isa_detect_aarch64.cpp is for aarch64 targets only (see src/CMakeLists.txt)"
#endif
#include "par2d/isa.hpp"

#if defined(__linux__)
#include <sys/auxv.h>
#ifndef HWCAP_ASIMD
#define HWCAP_ASIMD (1UL << 1)  // the kernel's <asm/hwcap.h> value
#endif
#endif

namespace par2d {

Isa detect_isa() noexcept {
#if defined(__linux__)
  // Linux reports the feature in the auxiliary vector; a kernel that hid it (none does on
  // AArch64 today) would make NEON code fault, so believe it.
  if ((getauxval(AT_HWCAP) & HWCAP_ASIMD) == 0) return Isa::scalar;
#endif
  return Isa::neon64;
}

}  // namespace par2d
