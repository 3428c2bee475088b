// Test-case helpers that report through doctest. Kept apart from random_scenes.cpp because the
// fuzz targets link random_scenes.cpp without doctest's runtime.
#include "support/random_scenes.hpp"

#include <doctest/doctest.h>

namespace par2d::test {

RenderedImage render_or_fail(const Scene& scene, const RenderOptions& options) {
  Status status;
  RenderedImage image = render_image(scene, options, status);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
}

}  // namespace par2d::test
