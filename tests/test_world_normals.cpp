// Normal map conversion (world axes, unit length, component planes), which also checks every
// normal: against a double-precision reference, the vector body against the scalar tail, and
// bad normals refused wherever they sit, with validate_scene's words.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "par2d/par2d.hpp"
#include "world/world_normals.hpp"
#include "support/test_tiers.hpp"

namespace {

par2d::NormalMap map_of(int width, int height, const std::vector<float>& normals) {
  return par2d::NormalMap{std::string(), width, height, normals};
}

std::uint32_t bits(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("world normals: unit, in world axes, within 3 float ulps of the double-precision value") {
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> component(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-140, 120);
  const int width = 7, height = 5;  // 35 pixels: vector blocks of 4 and a scalar tail
  std::vector<float> normals(3 * width * height);
  for (float& v : normals) v = static_cast<float>(component(rng) * std::ldexp(1.0, exponent(rng) / 10));
  normals[3 * 4 + 0] = 1e-45f;  // a subnormal direction
  normals[3 * 4 + 1] = 0.0f;
  normals[3 * 4 + 2] = 0.0f;
  normals[3 * 9 + 0] = 3e38f;  // squares past float's range
  normals[3 * 9 + 1] = -3e38f;
  normals[3 * 9 + 2] = 1e30f;
  const par2d::NormalMap map = map_of(width, height, normals);
  for (const bool mirrored : {false, true}) {
    const par2d::View view = mirrored ? par2d::View{7, 5, 0, 0} : par2d::View{0, 0, 7, 5};
    const auto converted = par2d::detail::world_normals(map, view);
    const bool converts = converted != nullptr;
    REQUIRE(converts);
    CHECK(converted->width() == width);
    CHECK(converted->height() == height);
    const double sx = mirrored ? -1.0 : 1.0, sy = mirrored ? 1.0 : -1.0;  // y grows downward unless mirrored
    for (int j = 0; j < height; ++j) {
      for (int i = 0; i < width; ++i) {
        const float* n = normals.data() + 3 * (j * width + i);
        const double x = sx * n[0], y = sy * n[1], z = n[2];
        const double m = std::max({std::fabs(x), std::fabs(y), std::fabs(z)});
        const double length = std::sqrt((x / m) * (x / m) + (y / m) * (y / m) + (z / m) * (z / m));
        const double expected[3] = {x / m / length, y / m / length, z / m / length};
        for (int c = 0; c < 3; ++c) {
          CAPTURE(i);
          CAPTURE(j);
          CAPTURE(c);
          CHECK(std::fabs(converted->row(c, j)[i] - expected[c]) <= 3.0 * 0x1p-24);
        }
      }
    }
  }
}

TEST_CASE("world normals: the vector body and the scalar tail give the same bits") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> component(-2.0f, 2.0f);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<float> normals(3 * 5);  // pixels 0-3 in a vector block, pixel 4 in the tail
    for (float& v : normals) v = component(rng);
    const int twin = trial % 4;
    for (int c = 0; c < 3; ++c) normals[3 * 4 + c] = normals[3 * twin + c];
    const auto converted = par2d::detail::world_normals(map_of(5, 1, normals), par2d::View{0, 0, 5, 1});
    const bool converts = converted != nullptr;
    REQUIRE(converts);
    for (int c = 0; c < 3; ++c) CHECK(bits(converted->row(c, 0)[4]) == bits(converted->row(c, 0)[twin]));
  }
}

TEST_CASE("world normals: a zero or non-finite normal anywhere converts to nothing, and render() names it") {
  const float bad_values[][3] = {{0.0f, -0.0f, 0.0f},
                                 {std::numeric_limits<float>::quiet_NaN(), 0.0f, 1.0f},
                                 {0.0f, 0.0f, std::numeric_limits<float>::infinity()},
                                 {1.0f, -std::numeric_limits<float>::infinity(), 1.0f}};
  const int width = 6, height = 3;  // 18 pixels: 16 in vector blocks, 2 in the tail
  for (const auto& bad : bad_values) {
    for (const int pixel : {0, 5, 15, 16, 17}) {
      std::vector<float> normals(3 * width * height, 0.0f);
      for (std::size_t p = 2; p < normals.size(); p += 3) normals[p] = 1.0f;
      for (int c = 0; c < 3; ++c) normals[3 * pixel + c] = bad[c];
      CAPTURE(pixel);
      const bool refused = par2d::detail::world_normals(map_of(width, height, normals), par2d::View{0, 0, 6, 3}) == nullptr;
      CHECK(refused);

      par2d::Scene scene;
      scene.width = width;
      scene.height = height;
      scene.view = {0, 0, 6, 3};
      par2d::Light light;
      light.shape = par2d::Circle{{3.0, 1.5}, 0.5};
      light.elevation = 30.0;
      scene.lights.push_back(light);
      scene.normal_map = map_of(width, height, normals);
      const std::string expected = par2d::validate_scene(scene).message();  // "scene: normal_map: pixel ..."
      REQUIRE(expected.rfind("scene: normal_map: pixel (", 0) == 0);
      std::vector<float> pixels(3 * width * height, -1.0f);
      const par2d::Status status = par2d::render(scene, par2d::RenderOptions{}, par2d::ImageView{pixels.data(), width, height, 3 * width});
      CHECK(status.code() == par2d::StatusCode::invalid_scene);
      CHECK(status.message() == expected);
      par2d::Renderer renderer;
      const par2d::Status set = renderer.set_normal_map(scene.normal_map.value());
      CHECK(set.code() == par2d::StatusCode::invalid_scene);
      CHECK(set.message() == "set_normal_map: " + expected.substr(std::string("scene: ").size()));
    }
  }
}

TEST_CASE("world normals: rows aligned and padded with (0, 0, 1) to whole 64-pixel blocks, read in place by the kernels") {
  // 70 x 3: two rows of 64-pixel blocks across, one block down; every image normal (1, 0, 0)
  // after conversion, so the padding's (0, 0, 1) cannot be mistaken for image pixels.
  const int width = 70, height = 3;
  std::vector<float> normals(3 * width * height, 0.0f);
  for (std::size_t p = 0; p < normals.size(); p += 3) normals[p] = 2.0f;
  const auto converted = par2d::detail::world_normals(map_of(width, height, normals), par2d::View{0, 0, 70, 3});
  const bool converts = converted != nullptr;
  REQUIRE(converts);
  CHECK(converted->stride() == 128);
  for (int c = 0; c < 3; ++c) {
    CHECK(reinterpret_cast<std::uintptr_t>(converted->plane(c)) % 64 == 0);
    for (int j = 0; j < par2d::detail::kNormalPadding; ++j) {
      const float* row = converted->row(c, j);
      for (std::size_t i = 0; i < converted->stride(); ++i) {
        const bool image = j < height && i < static_cast<std::size_t>(width);
        const float expected = image ? (c == 0 ? 1.0f : 0.0f) : (c == 2 ? 1.0f : 0.0f);
        CAPTURE(c);
        CAPTURE(j);
        CAPTURE(i);
        CHECK(row[i] == expected);
      }
    }
  }
}
