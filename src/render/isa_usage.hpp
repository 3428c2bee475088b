// How often the default ISA has been resolved in this process: the test suite's listener
// (tests/main.cpp) reads it around each case to know which cases depend on PAR2D_ISA and so
// must run again with every level forced.
#pragma once

#include <cstdint>

namespace par2d::detail {

// Calls of default_isa() so far (relaxed; only differences around a test case matter).
std::uint64_t default_isa_queries() noexcept;

}  // namespace par2d::detail
