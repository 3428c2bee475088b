// Exact linear-to-sRGB8 encoding for display (same rounding as the library's PNG writer).
#include "srgb8.hpp"

#include <cmath>
#include <limits>

namespace par2d::viewer {

Srgb8Encoder::Srgb8Encoder() {
  for (int k = 1; k <= 255; ++k) {
    const double s = (k - 0.5) / 255.0;
    steps_[static_cast<std::size_t>(k - 1)] = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  }
  steps_[255] = std::numeric_limits<double>::infinity();
  int code = 0;
  for (int b = 0; b < kBuckets; ++b) {
    const double lo = static_cast<double>(b) / kBuckets;
    while (code < 255 && steps_[static_cast<std::size_t>(code)] <= lo) ++code;
    first_code_[static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(code);
  }
}

std::uint8_t Srgb8Encoder::encode(double linear) const noexcept {
  if (!(linear > 0.0)) return 0;  // NaN and negatives show black, as in the PNG
  if (linear >= 1.0) return 255;
  int code = first_code_[static_cast<std::size_t>(linear * kBuckets)];
  while (linear >= steps_[static_cast<std::size_t>(code)]) ++code;  // steps_[255] = inf stops it
  return static_cast<std::uint8_t>(code);
}

void Srgb8Encoder::encode_image(const ImageView& image, double exposure, std::uint8_t* out, int pitch) const noexcept {
  for (int j = 0; j < image.height; ++j) {
    const float* row = image.data + j * image.row_stride;
    std::uint8_t* dst = out + static_cast<std::ptrdiff_t>(j) * pitch;
    for (int c = 0; c < 3 * image.width; ++c) dst[c] = encode(exposure * static_cast<double>(row[c]));
  }
}

}  // namespace par2d::viewer
