// The pixel encodings (pixel_encoding.hpp): sRGB code tables, the ordered dither's tables, halves.
#include "io/pixel_encoding.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace par2d::detail {
namespace {

// Linear values at which the rounded 8-bit sRGB code steps from k-1 to k, k = 1..255: the
// inverse transfer function at (k - 0.5) / 255 (the PNG writer encodes the same way). The
// code of v is the number of thresholds <= v. A search over them costs ~10 ns a channel,
// as much as the lighting of a simple pixel, so the table below answers in one look-up:
// [0, 1) is cut into kBuckets equal buckets; the thresholds are more than 1/kBuckets apart
// (the steepest slope of the encoding is 12.92 * 255 codes per unit < kBuckets), so a bucket
// holds at most one, and code(v) = below[b] + (v >= inside[b]) exactly.
struct SrgbTable {
  static constexpr int kBuckets = 4096;
  std::array<double, 255> thresholds{};
  std::array<unsigned char, kBuckets> below{};
  std::array<double, kBuckets> inside{};
  SrgbTable() {
    for (int k = 1; k <= 255; ++k) {
      const double s = (k - 0.5) / 255.0;
      thresholds[static_cast<std::size_t>(k - 1)] = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    }
    for (int b = 0; b < kBuckets; ++b) {
      const double lo = static_cast<double>(b) / kBuckets, hi = static_cast<double>(b + 1) / kBuckets;
      const auto first = std::lower_bound(thresholds.begin(), thresholds.end(), lo);
      below[static_cast<std::size_t>(b)] = static_cast<unsigned char>(first - thresholds.begin());
      inside[static_cast<std::size_t>(b)] =
          first != thresholds.end() && *first < hi ? *first : std::numeric_limits<double>::infinity();
    }
  }
};
const SrgbTable kSrgb;

// The ordered dither's steps: for each of the 64 offsets t = (b + 0.5) / 64, the linear values
// at which floor(255 * srgb(v) + t) steps from k-1 to k, k = 1..255: the inverse transfer
// function at (k - t) / 255 (in (0, 1): t < 1). b = 31.5 would be the undithered rounding.
struct DitherTable {
  std::array<std::array<double, 255>, 64> thresholds{};
  DitherTable() {
    for (int b = 0; b < 64; ++b) {
      const double t = (b + 0.5) / 64.0;
      for (int k = 1; k <= 255; ++k) {
        const double s = (k - t) / 255.0;
        thresholds[static_cast<std::size_t>(b)][static_cast<std::size_t>(k - 1)] =
            s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
      }
    }
  }
};
const DitherTable kDither;

}  // namespace

const std::array<double, 255>& srgb8_thresholds() noexcept { return kSrgb.thresholds; }

unsigned char encode_srgb8(double linear) noexcept {
  if (!(linear > 0.0)) return 0;
  if (linear >= 1.0) return 255;
  // linear * kBuckets is exact (a power of two), so the bucket is exactly floor of it.
  const auto b = static_cast<std::size_t>(linear * SrgbTable::kBuckets);
  return static_cast<unsigned char>(kSrgb.below[b] + (linear >= kSrgb.inside[b] ? 1 : 0));
}

unsigned char encode_srgb8_dithered(double linear, int bayer) noexcept {
  if (!(linear > 0.0)) return 0;
  const std::array<double, 255>& steps = kDither.thresholds[static_cast<std::size_t>(bayer & 63)];
  return static_cast<unsigned char>(std::upper_bound(steps.begin(), steps.end(), linear) - steps.begin());
}

int bayer8(int x, int y) noexcept {
  // The recursive Bayer matrix M(2n) = [[4M, 4M + 2], [4M + 3, 4M + 1]] in closed form: the
  // bits of (x xor y) and y interleaved, least significant level first, then reversed.
  const unsigned u = static_cast<unsigned>(x) & 7u, v = static_cast<unsigned>(y) & 7u, w = u ^ v;
  unsigned m = 0;
  for (int level = 0; level < 3; ++level) {
    m = (m << 2) | (((w >> level) & 1u) << 1) | ((v >> level) & 1u);
  }
  return static_cast<int>(m);
}

std::uint16_t half_of(float v) noexcept {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  const std::uint32_t sign = (bits >> 16) & 0x8000u;
  std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude > 0x7f800000u) return 0;  // NaN
  if (magnitude >= 0x477fe000u) return static_cast<std::uint16_t>(sign | 0x7bffu);  // rounds past 65504: saturate
  if (magnitude < 0x38800000u) {
    // Below the smallest normal half (2^-14): a subnormal or zero, in units of 2^-24. Adding
    // 0.5 (2^-1) lines the units up with the float's last mantissa bit, so the float addition
    // itself rounds to nearest even.
    float f = 0.0f;
    std::memcpy(&f, &magnitude, sizeof f);
    f += 0.5f;
    std::uint32_t sum = 0;
    std::memcpy(&sum, &f, sizeof sum);
    return static_cast<std::uint16_t>(sign | (sum - 0x3f000000u));
  }
  // Normal: rebias the exponent (127 -> 15) and round the 13 dropped mantissa bits to nearest
  // even (0xfff plus the kept lowest bit: a carry into the exponent is the right result).
  const std::uint32_t odd = (magnitude >> 13) & 1u;
  magnitude += 0xc8000fffu + odd;  // (15 - 127) << 23, wrapped, plus the rounding
  return static_cast<std::uint16_t>(sign | (magnitude >> 13));
}

unsigned char encode_srgb8_search(double linear) noexcept {
  if (!(linear > 0.0)) return 0;
  if (linear >= 1.0) return 255;
  return static_cast<unsigned char>(std::upper_bound(kSrgb.thresholds.begin(), kSrgb.thresholds.end(), linear) -
                                    kSrgb.thresholds.begin());
}

}  // namespace par2d::detail
