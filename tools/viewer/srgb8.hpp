// Linear float RGB to 8-bit sRGB for the window, rounding exactly as par2d::write_png does.
#pragma once

#include <array>
#include <cstdint>

#include "par2d/render.hpp"

namespace par2d::viewer {

// code(v) = round(255 * srgb(clamp(exposure * v, 0, 1))), found from the 255 linear values at
// which the code steps (the inverse transfer function at (k - 0.5) / 255, as the PNG writer
// computes them), so the window shows the same bytes as `par2d render -o`. A table of 4096
// buckets gives each value its first candidate code; at most one step lies in a bucket.
class Srgb8Encoder {
 public:
  Srgb8Encoder();
  std::uint8_t encode(double linear) const noexcept;
  // Writes `image` as packed RGB bytes (pitch bytes per row).
  void encode_image(const ImageView& image, double exposure, std::uint8_t* out, int pitch) const noexcept;

 private:
  static constexpr int kBuckets = 4096;
  std::array<double, 256> steps_{};  // steps_[k - 1]: smallest linear value with code >= k; steps_[255] = inf
  std::array<std::uint8_t, kBuckets> first_code_{};
};

}  // namespace par2d::viewer
