// Tile stores into each pixel format against a pixel-by-pixel reference: every part shape of a
// tile, through the generic store and through each ISA's vector stores of the float formats.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "render/frame_output.hpp"
#include "render/kernel_table.hpp"
#include "support/random_scenes.hpp"

using namespace par2d;
using par2d::detail::FrameTarget;
using par2d::detail::kTileSize;
using par2d::detail::TileRect;
using par2d::detail::TileResult;
using par2d::test::simd_isas_here;

namespace {

// IEEE half bits of `v` by the definition, apart from the store's bit manipulation: the
// nearest of the finite halves (ties to the even one), saturating at 65504, NaN to 0.
std::uint16_t reference_half(float v) {
  if (std::isnan(v)) return 0;
  const std::uint16_t sign = std::signbit(v) ? 0x8000 : 0;
  const double a = std::fabs(static_cast<double>(v));
  if (a >= 65504.0) return static_cast<std::uint16_t>(sign | 0x7bff);
  // Halves below 2^-14 are steps of 2^-24; above, 11 significant bits.
  const int exponent = a < 0x1p-14 ? -14 : std::ilogb(a);
  const double step = std::ldexp(1.0, exponent - 10);
  const double units = a / step;  // exact: a power-of-two division
  double whole = std::floor(units);
  const double rest = units - whole;
  if (rest > 0.5 || (rest == 0.5 && std::fmod(whole, 2.0) != 0.0)) whole += 1.0;
  const double rounded = whole * step;
  if (rounded >= 65536.0) return static_cast<std::uint16_t>(sign | 0x7bff);
  if (rounded < 0x1p-14) return static_cast<std::uint16_t>(sign | static_cast<std::uint16_t>(rounded / 0x1p-24));
  const int e = std::ilogb(rounded);
  const auto mantissa = static_cast<std::uint16_t>(rounded / std::ldexp(1.0, e - 10) - 1024.0);
  return static_cast<std::uint16_t>(sign | ((e + 15) << 10) | mantissa);
}

// The dithered code by its definition: floor(255 * srgb(clamp(v, 0, 1)) + t).
unsigned char reference_dithered(double v, int x, int y) {
  if (!(v > 0.0)) return 0;
  v = std::min(v, 1.0);
  const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  const double t = (detail::bayer8(x, y) + 0.5) / 64.0;
  return static_cast<unsigned char>(std::min(255.0, std::floor(255.0 * s + t)));
}

// What the store must write for the pixel of `result` at tile pixel (i, j), frame pixel
// (x, y), in `format`.
void reference_pixel(const TileResult& result, int i, int j, int x, int y, PixelFormat format, double exposure,
                     unsigned char* out) {
  const std::size_t k = static_cast<std::size_t>(j) * kTileSize + static_cast<std::size_t>(i);
  const float rgb[3] = {result.rgb[0][k], result.rgb[1][k], result.rgb[2][k]};
  const bool bgra = format == PixelFormat::bgra8_srgb || format == PixelFormat::bgra8_srgb_dithered;
  const bool dithered = format == PixelFormat::rgba8_srgb_dithered || format == PixelFormat::bgra8_srgb_dithered;
  if (format == PixelFormat::rgba8_srgb || bgra || dithered) {
    for (int c = 0; c < 3; ++c) {
      const double v = exposure * static_cast<double>(rgb[c]);
      out[bgra ? 2 - c : c] = dithered ? reference_dithered(v, x, y) : detail::encode_srgb8(v);
    }
    out[3] = 255;
    return;
  }
  if (format == PixelFormat::rgba16f) {
    const std::uint16_t pixel[4] = {reference_half(rgb[0]), reference_half(rgb[1]), reference_half(rgb[2]), 0x3C00};
    std::memcpy(out, pixel, sizeof pixel);
    return;
  }
  const float pixel[4] = {rgb[0], rgb[1], rgb[2], 1.0f};
  std::memcpy(out, pixel, static_cast<std::size_t>(bytes_per_pixel(format)));
}

constexpr PixelFormat kEveryFormat[] = {PixelFormat::rgb_f32,    PixelFormat::rgba_f32,
                                        PixelFormat::rgba8_srgb, PixelFormat::bgra8_srgb,
                                        PixelFormat::rgba16f,    PixelFormat::rgba8_srgb_dithered,
                                        PixelFormat::bgra8_srgb_dithered};

}  // namespace

TEST_CASE("tile store: every format, every part of a tile, at odd offsets and strides, equals the pixel-by-pixel reference") {
  // The generic store, then each ISA's vector stores of the float formats (the ones the
  // frame driver uses with that ISA's kernel).
  detail::SrgbBuckets buckets;
  detail::build_srgb_buckets(0.8, buckets);  // the exposure of every target below
  REQUIRE(buckets.valid);
  std::vector<std::pair<std::string, detail::VectorTileStores>> stores{{"generic", {}}};
  for (Isa isa : simd_isas_here()) {
    const detail::KernelSet* kernels = detail::kernels_for(isa);
    REQUIRE(kernels != nullptr);
    const bool has_stores = kernels->stores.rgb_f32 != nullptr && kernels->stores.rgba_f32 != nullptr &&
                            kernels->stores.rgba8_srgb != nullptr && kernels->stores.bgra8_srgb != nullptr;
    REQUIRE(has_stores);
    detail::VectorTileStores with_buckets = kernels->stores;
    with_buckets.srgb = &buckets;
    stores.emplace_back(std::string(isa_name(isa)), with_buckets);
  }
  for (const auto& named_store : stores) {
    // Not a structured binding: clang cannot capture one in INFO's lambda (C++17).
    const std::string& store_name = named_store.first;
    const detail::VectorTileStores& store = named_store.second;
    INFO("store ", store_name);
    auto result = std::make_unique<TileResult>();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(-0.25f, 1.5f);
    for (auto& plane : result->rgb)
      for (float& v : plane) v = value(rng);
    result->rgb[1][5] = -0.0f;  // signs and special values pass through the float formats unchanged
    result->rgb[2][17] = 1e-40f;
    // Half-float edges: past the largest finite half, the tie that would round to infinity,
    // infinity, a subnormal half and a value below the smallest.
    result->rgb[0][3] = 70000.0f;
    result->rgb[1][7] = 65520.0f;
    result->rgb[2][9] = 65519.0f;
    result->rgb[0][11] = std::numeric_limits<float>::infinity();
    result->rgb[1][13] = 3.0e-6f;
    result->rgb[2][15] = 2.0e-8f;

    const int tile_x0 = 32, tile_y0 = 48;  // the tile's top-left pixel in the frame
    for (PixelFormat format : kEveryFormat) {
      const int bpp = bytes_per_pixel(format);
      int mismatches = 0, padding_changed = 0, parts = 0;
      for (int trial = 0; trial < 400; ++trial) {
        TileRect part;
        part.x0 = tile_x0 + static_cast<int>(rng() % kTileSize);
        part.x1 = part.x0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(tile_x0 + kTileSize - part.x0));
        part.y0 = tile_y0 + static_cast<int>(rng() % kTileSize);
        part.y1 = part.y0 + 1 + static_cast<int>(rng() % static_cast<unsigned>(tile_y0 + kTileSize - part.y0));
        if (trial < kTileSize) part = {tile_x0 + trial, tile_y0, tile_x0 + kTileSize, tile_y0 + kTileSize};  // every start
        if (trial == kTileSize) part = {tile_x0, tile_y0, tile_x0 + kTileSize, tile_y0 + kTileSize};       // whole tile
        // The region starts left of and above the part by a few pixels; rows are padded by an
        // odd byte count, and the buffer starts one byte past an allocation, so rows are never
        // float-aligned.
        FrameTarget target;
        target.format = format;
        target.exposure = 0.8;
        target.region = {part.x0 - 3, part.y0 - 1, part.x1 + 2, part.y1 + 1};
        const int rw = target.region.x1 - target.region.x0, rh = target.region.y1 - target.region.y0;
        target.row_stride = static_cast<std::ptrdiff_t>(rw) * bpp + 5;
        std::vector<unsigned char> storage(static_cast<std::size_t>(target.row_stride) * rh + 1, 0xAB);
        target.data = storage.data() + 1;
        detail::store_tile(*result, tile_x0, tile_y0, part, target, store);
        ++parts;
        for (int y = target.region.y0; y < target.region.y1; ++y) {
          const unsigned char* row = target.data + static_cast<std::ptrdiff_t>(y - target.region.y0) * target.row_stride;
          for (std::ptrdiff_t b = 0; b < target.row_stride; ++b) {
            const int x = target.region.x0 + static_cast<int>(b / bpp);
            const bool in_part = b < static_cast<std::ptrdiff_t>(rw) * bpp && x >= part.x0 && x < part.x1 &&
                                 y >= part.y0 && y < part.y1;
            if (!in_part) {
              padding_changed += row[b] != 0xAB;
              continue;
            }
            if (b % bpp != 0) continue;
            unsigned char expected[16];
            reference_pixel(*result, x - tile_x0, y - tile_y0, x, y, format, target.exposure, expected);
            mismatches += std::memcmp(row + b, expected, static_cast<std::size_t>(bpp)) != 0;
          }
        }
        padding_changed += storage[0] != 0xAB;
      }
      INFO("format ", static_cast<int>(format), " parts ", parts);
      CHECK(mismatches == 0);
      CHECK(padding_changed == 0);
    }
  }
}

TEST_CASE("float frames stream from kStreamingFrameBytes on, never below it, and 8-bit frames never") {
  // The threshold is hit exactly by a region of 1024 x 1024 RGBA floats (16 MiB).
  FrameTarget target;
  target.format = PixelFormat::rgba_f32;
  target.region = {0, 0, 1024, 1024};
  CHECK(detail::streams_float_frame(target));
  target.region = {0, 0, 1024, 1023};  // one row under the threshold
  CHECK_FALSE(detail::streams_float_frame(target));
  target.region = {10, 20, 10 + 1024, 20 + 1024};  // the region's size counts, not its place
  CHECK(detail::streams_float_frame(target));
  target.format = PixelFormat::rgb_f32;  // 12 MiB: under
  CHECK_FALSE(detail::streams_float_frame(target));
  target.region = {0, 0, 1920, 1080};  // 1080p float RGB, 25 MB
  CHECK(detail::streams_float_frame(target));
  target.format = PixelFormat::rgba8_srgb;
  target.region = {0, 0, 4096, 4096};  // 64 MiB of 8-bit pixels: ordinary stores still
  CHECK_FALSE(detail::streams_float_frame(target));
}

TEST_CASE("tile store: frames over kStreamingFrameBytes (non-temporal stores on aligned rows) write the same bytes") {
  // Frames this large take each ISA's non-temporal stores for whole tile rows that start on
  // a register boundary. Two strides of a 64-byte-aligned frame: a multiple of 64 bytes
  // (every row aligned: whole tiles take the path without a test per row at every register
  // width), and 64 bytes times an odd number plus 32 (with 64-byte registers aligned and
  // unaligned rows alternate). The region's width puts whole tiles and one part tile in
  // each row of tiles.
  auto result = std::make_unique<TileResult>();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(-0.25f, 1.5f);
  for (auto& plane : result->rgb)
    for (float& v : plane) v = value(rng);
  for (const bool every_row_aligned : {true, false})
  for (PixelFormat format : {PixelFormat::rgb_f32, PixelFormat::rgba_f32}) {
    const int bpp = bytes_per_pixel(format);
    FrameTarget target;
    target.format = format;
    const int width = 1360 + 8;  // 85 whole tiles and 8 columns of an 86th
    target.row_stride = static_cast<std::ptrdiff_t>(width) * bpp;
    target.row_stride += (64 - target.row_stride % 64) % 64 + 64 * 3 + (every_row_aligned ? 0 : 32);
    const int height = static_cast<int>(detail::kStreamingFrameBytes / (static_cast<std::size_t>(width) * bpp)) + 1;
    target.region = {0, 0, width, height};
    REQUIRE(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(bpp) >=
            detail::kStreamingFrameBytes);
    const std::size_t bytes = static_cast<std::size_t>(target.row_stride) * static_cast<std::size_t>(height);
    std::vector<unsigned char> storage(bytes + 64);
    unsigned char* aligned = storage.data() + (64 - reinterpret_cast<std::uintptr_t>(storage.data()) % 64) % 64;
    target.data = aligned;
    // Tiles along the top rows (aligned and unaligned rows, whole and part tiles) and one
    // tile cut by the frame's bottom edge.
    std::vector<TileRect> tiles;
    for (int x0 = 0; x0 < width; x0 += kTileSize)
      for (int y0 : {0, kTileSize, 7 * kTileSize})
        tiles.push_back({x0, y0, std::min(x0 + kTileSize, width), y0 + kTileSize});
    const int last_row = (height - 1) / kTileSize * kTileSize;
    tiles.push_back({0, last_row, kTileSize, height});
    for (Isa isa : simd_isas_here()) {
      INFO("ISA ", std::string(isa_name(isa)), " format ", static_cast<int>(format), " every row aligned ",
           every_row_aligned);
      const detail::KernelSet* kernels = detail::kernels_for(isa);
      REQUIRE(kernels != nullptr);
      std::fill(storage.begin(), storage.end(), static_cast<unsigned char>(0xAB));
      for (const TileRect& tile : tiles) detail::store_tile(*result, tile.x0, tile.y0, tile, target, kernels->stores);
      int mismatches = 0, checked = 0;
      for (const TileRect& tile : tiles)
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x) {
            unsigned char expected[16];
            reference_pixel(*result, x - tile.x0, y - tile.y0, x, y, format, 1.0, expected);
            const unsigned char* at = aligned + static_cast<std::ptrdiff_t>(y) * target.row_stride +
                                      static_cast<std::ptrdiff_t>(x) * bpp;
            mismatches += std::memcmp(at, expected, static_cast<std::size_t>(bpp)) != 0;
            ++checked;
          }
      // Past the last pixel of the first row (the stride's padding) nothing was written.
      int padding_changed = 0;
      for (std::ptrdiff_t b = static_cast<std::ptrdiff_t>(width) * bpp; b < target.row_stride; ++b)
        padding_changed += aligned[b] != 0xAB;
      CHECK(checked > 0);
      CHECK(mismatches == 0);
      CHECK(padding_changed == 0);
    }
  }
}

TEST_CASE("8-bit sRGB vector store: every code's first value and the float before it, specials, many exposures, "
          "each ISA equals the scalar encoder") {
  const auto isas = simd_isas_here();
  REQUIRE(!isas.empty());
  for (double exposure : {1.0, 0.8, 1.5, 3.7, 1e-3, 700.0, 0x1p-20, 0x1p20, 0.1 + 0.2}) {
    INFO("exposure ", exposure);
    detail::SrgbBuckets buckets;
    detail::build_srgb_buckets(exposure, buckets);
    REQUIRE(buckets.valid);
    // Values: for each code k, the least float whose product with the exposure reaches the
    // code's start and its float neighbours (found here by the scalar encoder itself), then
    // specials and random values; tile after tile of them.
    std::vector<float> values = {0.0f, -0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                                 std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                 std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                                 std::numeric_limits<float>::min()};
    float v = 0.0f;
    for (int k = 1; k <= 255; ++k) {
      // The first float at or above the last one whose code is k (a doubling walk, then bisection).
      float lo = v, hi = v > 0.0f ? v : std::numeric_limits<float>::min();
      while (detail::encode_srgb8(exposure * static_cast<double>(hi)) < k) hi *= 2.0f;
      while (std::nextafter(lo, hi) < hi) {
        const float mid = 0.5f * (lo + hi);
        const float probe = mid > lo && mid < hi ? mid : std::nextafter(lo, hi);
        if (detail::encode_srgb8(exposure * static_cast<double>(probe)) >= k) hi = probe;
        else lo = probe;
      }
      v = hi;
      values.insert(values.end(), {std::nextafter(v, 0.0f), v, std::nextafter(v, 2.0f * v + 1.0f)});
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> linear(-0.1f, 1.2f / static_cast<float>(exposure));
    while (values.size() % detail::kTilePixels != 0) values.push_back(linear(rng));
    for (Isa isa : isas) {
      INFO("isa ", std::string(isa_name(isa)));
      const detail::KernelSet* kernels = detail::kernels_for(isa);
      REQUIRE(kernels != nullptr);
      int mismatches = 0;
      for (std::size_t first = 0; first < values.size(); first += detail::kTilePixels) {
        auto result = std::make_unique<TileResult>();
        for (int c = 0; c < 3; ++c)  // each channel sees every value, at a different pixel
          for (std::size_t p = 0; p < detail::kTilePixels; ++p)
            result->rgb[c][p] = values[first + (p + 37 * static_cast<std::size_t>(c)) % detail::kTilePixels];
        std::vector<unsigned char> out(static_cast<std::size_t>(detail::kTilePixels) * 4);
        // Whole rows, then a part whose rows end in the scalar tail.
        for (int width : {kTileSize, kTileSize - 3}) {
          kernels->stores.rgba8_srgb(*result, 0, 0, kTileSize, width, out.data(), kTileSize * 4, buckets);
          for (int j = 0; j < kTileSize; ++j)
            for (int i = 0; i < width; ++i) {
              const int p = j * kTileSize + i;
              for (int c = 0; c < 3; ++c)
                mismatches += out[static_cast<std::size_t>(p) * 4 + static_cast<std::size_t>(c)] !=
                              detail::encode_srgb8(exposure * static_cast<double>(result->rgb[c][p]));
              mismatches += out[static_cast<std::size_t>(p) * 4 + 3] != 255;
            }
        }
      }
      CHECK(mismatches == 0);
    }
  }
  // Exposures the buckets do not cover: not valid, so frames keep the scalar encoder.
  for (double exposure : {0.0, -1.0, 0x1p-21, 0x1p21, std::numeric_limits<double>::infinity()}) {
    detail::SrgbBuckets buckets;
    detail::build_srgb_buckets(exposure, buckets);
    CHECK_FALSE(buckets.valid);
  }
}

TEST_CASE("half floats: every finite half converts to itself, midpoints to the even neighbour, saturating at 65504") {
  int mismatches = 0;
  for (std::uint32_t h = 0; h < 0x7c00u; ++h) {  // every finite non-negative half
    const double value = h < 0x400u ? h * 0x1p-24 : std::ldexp(1.0 + (h & 0x3ffu) / 1024.0, static_cast<int>(h >> 10) - 15);
    const auto v = static_cast<float>(value);  // exact: 11 significant bits
    mismatches += detail::half_of(v) != h;
    mismatches += detail::half_of(-v) != (h | 0x8000u);
    mismatches += detail::half_of(v) != reference_half(v);
    if (h + 1 < 0x7c00u) {
      const double next = (h + 1) < 0x400u ? (h + 1) * 0x1p-24
                                           : std::ldexp(1.0 + ((h + 1) & 0x3ffu) / 1024.0, static_cast<int>((h + 1) >> 10) - 15);
      const auto middle = static_cast<float>(0.5 * (value + next));  // exact: 12 significant bits
      const std::uint32_t even = (h & 1u) == 0 ? h : h + 1;
      mismatches += detail::half_of(middle) != even;
      mismatches += detail::half_of(std::nextafter(middle, 0.0f)) != h;
      mismatches += detail::half_of(std::nextafter(middle, 1e9f)) != h + 1;
    }
  }
  CHECK(mismatches == 0);
  CHECK(detail::half_of(65504.0f) == 0x7bff);
  CHECK(detail::half_of(65519.99f) == 0x7bff);
  CHECK(detail::half_of(65520.0f) == 0x7bff);  // a tie that rounds to infinity: saturated
  CHECK(detail::half_of(1e30f) == 0x7bff);
  CHECK(detail::half_of(std::numeric_limits<float>::infinity()) == 0x7bff);
  CHECK(detail::half_of(-std::numeric_limits<float>::infinity()) == 0xfbff);
  CHECK(detail::half_of(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(detail::half_of(0x1p-25f) == 0);       // half the smallest subnormal: ties to even 0
  CHECK(detail::half_of(0x1.0p-25f * 1.5f) == 1);
  std::mt19937 rng(16);
  std::uniform_real_distribution<float> wide(-8.0f, 17.0f);
  int random_mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    const float v = std::exp2(wide(rng)) * (i % 2 ? 1.0f : -1.0f);
    random_mismatches += detail::half_of(v) != reference_half(v);
  }
  CHECK(random_mismatches == 0);
}

TEST_CASE("ordered dither: the 8x8 Bayer matrix, and the mean code of every 8x8 square within 1/128 of 255 srgb(v)") {
  // The recursive construction, M(2n) = [[4M, 4M + 2], [4M + 3, 4M + 1]].
  std::vector<std::vector<int>> m{{0}};
  while (m.size() < 8) {
    const std::size_t n = m.size();
    std::vector<std::vector<int>> next(2 * n, std::vector<int>(2 * n));
    for (std::size_t y = 0; y < n; ++y)
      for (std::size_t x = 0; x < n; ++x) {
        next[y][x] = 4 * m[y][x];
        next[y][x + n] = 4 * m[y][x] + 2;
        next[y + n][x] = 4 * m[y][x] + 3;
        next[y + n][x + n] = 4 * m[y][x] + 1;
      }
    m = next;
  }
  for (int y = -8; y < 16; ++y)
    for (int x = -8; x < 16; ++x) CHECK(detail::bayer8(x, y) == m[static_cast<std::size_t>(y & 7)][static_cast<std::size_t>(x & 7)]);
  std::mt19937 rng(64);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double v = trial < 2 ? trial : std::pow(unit(rng), 3.0);
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    double sum = 0.0;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const unsigned char code = detail::encode_srgb8_dithered(v, detail::bayer8(x, y));
        // Never more than one code from the rounded one.
        REQUIRE(std::abs(static_cast<int>(code) - static_cast<int>(detail::encode_srgb8(v))) <= 1);
        REQUIRE(code == reference_dithered(v, x, y));
        sum += code;
      }
    worst = std::max(worst, std::fabs(sum / 64.0 - 255.0 * s));
  }
  CHECK(worst <= 1.0 / 128.0 + 1e-9);
  CHECK(detail::encode_srgb8_dithered(std::numeric_limits<double>::quiet_NaN(), 5) == 0);
  CHECK(detail::encode_srgb8_dithered(-1.0, 5) == 0);
  CHECK(detail::encode_srgb8_dithered(std::numeric_limits<double>::infinity(), 63) == 255);
}
