// Every pixel format through a Renderer: a region's bytes are the whole frame's bytes there (the
// dither follows the pixel's place in the frame, not in the buffer), and incremental frames
// with dirty rectangles write exactly the bytes of a full frame, on every ISA.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "par2d/renderer.hpp"
#include "support/test_tiers.hpp"

namespace par2d::test {
namespace {

constexpr PixelFormat kFormats[] = {PixelFormat::rgb_f32,    PixelFormat::rgba_f32,
                                    PixelFormat::rgba8_srgb, PixelFormat::bgra8_srgb,
                                    PixelFormat::rgba16f,    PixelFormat::rgba8_srgb_dithered,
                                    PixelFormat::bgra8_srgb_dithered};
constexpr int kWidth = 150, kHeight = 90;

Scene level() {
  Scene scene;
  scene.width = kWidth;
  scene.height = kHeight;
  scene.view = View{0.0, 0.0, double(kWidth), double(kHeight)};
  scene.lights.push_back(Light{Circle{{30.0, 40.0}, 2.0}, {1.0, 0.8, 0.6}, 0.3, 80.0});  // dark gradients
  scene.lights.push_back(Light{Circle{{120.0, 20.0}, 3.0}, {0.2, 0.5, 1.0}, 4000.0});       // past 65504 near it
  scene.occluders.push_back(Occluder{Polygon{{{60, 10}, {66, 10}, {66, 70}, {60, 70}}}});
  scene.occluders.push_back(Occluder{Circle{{95.0, 60.0}, 6.0}});
  return scene;
}

std::vector<unsigned char> whole_frame(const Scene& scene, PixelFormat format, double exposure) {
  Renderer r;
  REQUIRE(r.set_scene(scene).ok());
  const int bpp = bytes_per_pixel(format);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(kWidth) * kHeight * bpp, 0x5A);
  REQUIRE(r.render(FrameBuffer{bytes.data(), format, kWidth * bpp, exposure}).ok());
  return bytes;
}

}  // namespace

TEST_CASE("every pixel format: a region holds the whole frame's bytes, at odd offsets" * per_isa()) {
  const Scene scene = level();
  for (const PixelFormat format : kFormats) {
    CAPTURE(static_cast<int>(format));
    const int bpp = bytes_per_pixel(format);
    REQUIRE(bpp > 0);
    const std::vector<unsigned char> whole = whole_frame(scene, format, 6.0);
    Renderer r;
    REQUIRE(r.set_scene(scene).ok());
    for (const PixelRect rect : {PixelRect{3, 5, 77, 41}, PixelRect{61, 17, 150, 90}, PixelRect{1, 1, 2, 2}}) {
      const int w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
      const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(w) * bpp + 3;
      std::vector<unsigned char> part(static_cast<std::size_t>(stride) * h, 0x5A);
      REQUIRE(r.render(FrameBuffer{part.data(), format, stride, 6.0}, rect).ok());
      int mismatches = 0;
      for (int y = 0; y < h; ++y)
        mismatches += std::memcmp(part.data() + y * stride,
                                  whole.data() + (static_cast<std::size_t>(rect.y0 + y) * kWidth + rect.x0) * bpp,
                                  static_cast<std::size_t>(w) * bpp) != 0;
      CHECK(mismatches == 0);
    }
  }
}

TEST_CASE("every pixel format: incremental frames write the bytes of a full frame into their dirty rectangles" * per_isa()) {
  for (const PixelFormat format : kFormats) {
    CAPTURE(static_cast<int>(format));
    Scene scene = level();
    Renderer r;
    std::vector<LightHandle> lights;
    REQUIRE(r.set_scene(scene, &lights).ok());
    REQUIRE(r.set_incremental(true).ok());
    const int bpp = bytes_per_pixel(format);
    std::vector<unsigned char> bytes(static_cast<std::size_t>(kWidth) * kHeight * bpp, 0x5A);
    const FrameBuffer buffer{bytes.data(), format, kWidth * bpp, 6.0};
    REQUIRE(r.render(buffer).ok());
    for (int frame = 0; frame < 4; ++frame) {
      std::get<Circle>(scene.lights[0].shape).center = {20.0 + 7.0 * frame, 30.0 + 3.0 * frame};
      REQUIRE(r.update_light(lights[0], scene.lights[0]).ok());
      REQUIRE(r.render(buffer).ok());
      // The rectangles are what the frame wrote: a part of it where culling proves the
      // rest unchanged (the scalar reference culls nothing, so it computes every block).
      std::uint64_t area = 0;
      for (const PixelRect& rect : r.dirty_rects())
        area += static_cast<std::uint64_t>(rect.x1 - rect.x0) * static_cast<std::uint64_t>(rect.y1 - rect.y0);
      CHECK(area == r.frame_stats().pixels);
      if (resolved_isa(RenderOptions{}) != Isa::scalar) CHECK(area < static_cast<std::uint64_t>(kWidth) * kHeight);
      CHECK(bytes == whole_frame(scene, format, 6.0));
    }
  }
}

}  // namespace par2d::test
