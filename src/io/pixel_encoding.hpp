// Pixel encodings shared by the frame stores and the PNG writer: 8-bit sRGB (rounded, or with
// an ordered dither) and IEEE half floats. One definition each, so that a PNG and an 8-bit
// frame of the same light hold the same codes.
#pragma once

#include <array>
#include <cstdint>

namespace par2d::detail {

// Linear values at which the rounded 8-bit sRGB code steps from k-1 to k, k = 1..255: the
// inverse transfer function at (k - 0.5) / 255. The code of v is the number of them <= v.
const std::array<double, 255>& srgb8_thresholds() noexcept;

// round(255 * srgb(clamp(v, 0, 1))), NaN and negatives to 0, from a table (no pow per channel).
unsigned char encode_srgb8(double linear) noexcept;
// The same by a binary search over the 255 thresholds: the table's reference in tests.
unsigned char encode_srgb8_search(double linear) noexcept;
// The ordered dither's code (PixelFormat::rgba8_srgb_dithered): floor(255 * srgb(clamp(v, 0,
// 1)) + t), t = (bayer + 0.5) / 64, NaN and negatives to 0, by a search of the 255 values at
// which the code steps for that t.
unsigned char encode_srgb8_dithered(double linear, int bayer) noexcept;
// The 8x8 Bayer matrix's entry (0 .. 63) at frame pixel (x, y): every 2x2, 4x4 and 8x8
// aligned square holds evenly spread thresholds.
int bayer8(int x, int y) noexcept;
// IEEE half of `v`, rounded to nearest even; magnitudes past 65504 (the largest finite half,
// infinities included) saturate to it, NaN to 0 (PixelFormat::rgba16f).
std::uint16_t half_of(float v) noexcept;

}  // namespace par2d::detail
