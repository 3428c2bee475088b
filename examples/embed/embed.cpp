// Embedding example: build a scene in code, render it into your own buffer, read a pixel back.
#include <cmath>
#include <cstdio>
#include <vector>

#include <par2d/par2d.hpp>

constexpr double kPi = 3.14159265358979323846;

int main() {
  // One warm circle light and a square occluder to its right, 256 x 256 pixels,
  // world units = pixels (the default view), y down.
  par2d::Scene scene;
  scene.width = 256;
  scene.height = 256;
  scene.view = {0, 0, 256, 256};
  scene.lights.push_back({par2d::Circle{{64, 128}, 8}, {1.0, 0.8, 0.6}, 10.0});
  scene.occluders.push_back({par2d::Polygon{{{150, 118}, {170, 118}, {170, 138}, {150, 138}}}});

  // The caller owns the pixels: float RGB, row-major, row 0 at the top.
  std::vector<float> pixels(static_cast<std::size_t>(scene.width) * scene.height * 3);
  par2d::ImageView image{pixels.data(), scene.width, scene.height, scene.width * 3};

  par2d::RenderOptions options;  // auto backend, all hardware threads, 1 sample per pixel
  if (par2d::Status s = par2d::render(scene, options, image); !s) {
    std::fprintf(stderr, "render failed: %s\n", s.message().c_str());
    return 1;
  }

  // Pixel (20, 128) sees the whole light: E = e * 2 asin(r / d) / (2 pi).
  const int i = 20, j = 128;
  const float* px = &pixels[(static_cast<std::size_t>(j) * scene.width + i) * 3];
  const double d = std::hypot(i + 0.5 - 64.0, j + 0.5 - 128.0);
  const double expected_red = 10.0 * 1.0 * 2.0 * std::asin(8.0 / d) / (2.0 * kPi);
  std::printf("pixel (%d, %d): E = (%.6f, %.6f, %.6f), expected red %.6f\n", i, j, px[0], px[1],
              px[2], expected_red);

  // Pixel (240, 128) lies in the occluder's umbra.
  const float* shadow = &pixels[(static_cast<std::size_t>(128) * scene.width + 240) * 3];
  std::printf("pixel (240, 128) behind the occluder: E = (%.6f, %.6f, %.6f)\n", shadow[0],
              shadow[1], shadow[2]);

  // Exit non-zero if the library disagrees with the closed form, so this doubles as a test.
  const bool ok = std::fabs(px[0] - expected_red) <= 1e-4 * 10.0 && shadow[0] == 0.0f;
  return ok ? 0 : 1;
}
