// Test-case helpers that report through doctest (render_checks.cpp; doctest binaries only).
#pragma once

#include <string>

#include "support/random_scenes.hpp"

namespace par2d::test {

// A render compared with a reference at the pixels docs/contract.md section 5 covers.
struct Comparison {
  double max_error = 0.0;  // over the checked pixels
  int checked = 0;         // pixels farther than `exempt` from every shape boundary
  int over = 0;            // channel values off by more than the bound
  std::string first_failure;
};

// Compares `got` with `ref` channel by channel at the pixels whose centers are farther than
// `exempt` world units from every shape boundary.
Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           double exempt);

}  // namespace par2d::test
