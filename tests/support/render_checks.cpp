// Test-case helpers that report through doctest. Kept apart from random_scenes.cpp because the
// fuzz targets link random_scenes.cpp without doctest's runtime.
#include "support/render_checks.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

namespace par2d::test {

RenderedImage render_or_fail(const Scene& scene, const RenderOptions& options) {
  Status status;
  RenderedImage image = render_image(scene, options, status);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
}

Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           double exempt) {
  Comparison c;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      if (near_boundary(scene, pixel_center(scene, i, j), exempt)) continue;
      ++c.checked;
      for (int ch = 0; ch < 3; ++ch) {
        const double err = std::abs(static_cast<double>(ref.at(i, j, ch)) - got.at(i, j, ch));
        c.max_error = std::max(c.max_error, err);
        if (!(err <= bound) && c.over++ == 0)
          c.first_failure = "pixel (" + std::to_string(i) + "," + std::to_string(j) + ") channel " +
                            std::to_string(ch) + ": reference " + std::to_string(ref.at(i, j, ch)) + ", got " +
                            std::to_string(got.at(i, j, ch));
      }
    }
  }
  return c;
}

}  // namespace par2d::test
