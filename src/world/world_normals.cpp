// Normal map conversion: world axes, unit length, component planes, checked in the same pass.
#include "world/world_normals.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace par2d::detail {

namespace {

std::size_t padded(int n) noexcept {
  const auto m = static_cast<std::size_t>(n < 0 ? 0 : n);
  return (m + kNormalPadding - 1) / kNormalPadding * kNormalPadding;
}

}  // namespace

WorldNormals::WorldNormals(int width, int height)
    : width_(width), height_(height), stride_(padded(width)), plane_size_(stride_ * padded(height)) {
  // 16 spare floats align the planes to 64 bytes (kNormalPadding floats keep every row so).
  storage_.reset(new float[3 * plane_size_ + 16]);  // no fill: the conversion writes the image part
  const auto address = reinterpret_cast<std::uintptr_t>(storage_.get());
  values_ = storage_.get() + (64 - address % 64) % 64 / sizeof(float);
  // The padding: right of each row, then the rows below the image.
  const auto columns = static_cast<std::size_t>(width_ < 0 ? 0 : width_);
  const int rows = static_cast<int>(plane_size_ / (stride_ == 0 ? 1 : stride_));
  for (int c = 0; c < 3; ++c) {
    const float fill = c == 2 ? 1.0f : 0.0f;
    for (int j = 0; j < rows; ++j) {
      float* r = row(c, j);
      std::fill(r + (j < height_ ? columns : 0), r + stride_, fill);
    }
  }
}

namespace {

// One normal, in float. Divided by its largest component first, so that no square overflows
// or underflows for any finite input; the SSE2 path below runs the same operations in the
// same order (no FMA: the build turns contraction off), so both give the same bits. A normal
// that is not finite or is zero gives a length that is NaN (inf/inf, NaN/m, 0/0): refused.
inline bool unit_normal(float x, float y, float z, float* out_x, float* out_y, float* out_z) noexcept {
  const float largest = std::max(std::fabs(x), std::max(std::fabs(y), std::fabs(z)));
  const float ux = x / largest, uy = y / largest, uz = z / largest;
  const float length = std::sqrt(ux * ux + uy * uy + uz * uz);
  *out_x = ux / length;
  *out_y = uy / length;
  *out_z = uz / length;
  return length >= 1.0f;  // in [1, sqrt(3)] for any finite non-zero normal
}

}  // namespace

std::shared_ptr<const WorldNormals> world_normals(const NormalMap& map, const View& view) {
  const float sx = view.x1 > view.x0 ? 1.0f : -1.0f;
  // Image up is world -y in a view whose y grows downward.
  const float sy = view.y1 > view.y0 ? -1.0f : 1.0f;
  auto out = std::make_shared<WorldNormals>(map.width, map.height);
  const auto count = static_cast<std::size_t>(map.width);  // per row
  bool good = true;
#if defined(__SSE2__)
  const __m128 sign_x = _mm_set1_ps(sx), sign_y = _mm_set1_ps(sy);
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  __m128 all_good = _mm_castsi128_ps(_mm_set1_epi32(-1));
#endif
  for (int j = 0; j < map.height; ++j) {
    const float* in = map.normals.data() + 3 * count * static_cast<std::size_t>(j);
    float* px = out->row(0, j);
    float* py = out->row(1, j);
    float* pz = out->row(2, j);
    std::size_t p = 0;
#if defined(__SSE2__)
    // Four pixels at a time: three loads of 12 interleaved floats, split into x, y, z lanes.
    for (; p + 4 <= count; p += 4) {
      const float* src = in + 3 * p;
      const __m128 a = _mm_loadu_ps(src), b = _mm_loadu_ps(src + 4), c = _mm_loadu_ps(src + 8);
      // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3
      const __m128 x = _mm_shuffle_ps(a, _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2)), _MM_SHUFFLE(2, 0, 3, 0));
      const __m128 y = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                                      _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)), _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 z = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                                      _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)), _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 wx = _mm_mul_ps(x, sign_x), wy = _mm_mul_ps(y, sign_y);
      const __m128 largest =
          _mm_max_ps(_mm_and_ps(wx, magnitude), _mm_max_ps(_mm_and_ps(wy, magnitude), _mm_and_ps(z, magnitude)));
      const __m128 ux = _mm_div_ps(wx, largest), uy = _mm_div_ps(wy, largest), uz = _mm_div_ps(z, largest);
      const __m128 length =
          _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(ux, ux), _mm_mul_ps(uy, uy)), _mm_mul_ps(uz, uz)));
      _mm_storeu_ps(px + p, _mm_div_ps(ux, length));
      _mm_storeu_ps(py + p, _mm_div_ps(uy, length));
      _mm_storeu_ps(pz + p, _mm_div_ps(uz, length));
      all_good = _mm_and_ps(all_good, _mm_cmpge_ps(length, _mm_set1_ps(1.0f)));
    }
#endif
    for (; p < count; ++p) {
      const float* n = in + 3 * p;
      good &= unit_normal(sx * n[0], sy * n[1], n[2], px + p, py + p, pz + p);
    }
  }
#if defined(__SSE2__)
  good &= _mm_movemask_ps(all_good) == 0xf;
#endif
  if (!good) return nullptr;
  return out;
}

}  // namespace par2d::detail
