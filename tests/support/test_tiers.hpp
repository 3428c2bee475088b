// Where each test case runs (doctest test suites; tests/CMakeLists.txt turns them into ctest
// entries):
//   (none)    once, in the ctest entry of its source file, at the CPU's best ISA;
//   per_isa   also once more with the default ISA forced to every level (PAR2D_ISA=scalar,
//             sse4, avx2, ...), because it renders with the automatic backend;
//   long      only in the `long` ctest label: the exhaustive sweeps, whose seeds and scenes
//             the default cases sample.
// The listener in tests/main.cpp keeps `per_isa` honest: a case that resolves the default
// ISA without the tag fails, and so does a tagged case that never resolves it.
#pragma once

#include <doctest/doctest.h>

namespace par2d::test {

inline constexpr const char* kPerIsaSuite = "per_isa";
inline constexpr const char* kLongSuite = "long";

inline doctest::test_suite per_isa() { return doctest::test_suite(kPerIsaSuite); }
inline doctest::test_suite long_tier() { return doctest::test_suite(kLongSuite); }

}  // namespace par2d::test
