// Pixel loops of the per-pixel backends: sample positions, averaging, storing floats.
#include "render/scalar_tiles.hpp"

#include <cstdint>
#include <optional>

namespace par2d::detail {
namespace {

// A stable per-sample hash, so the ray caster's jitter is the same on every run and thread count.
double hash_to_unit(std::uint64_t v) noexcept {
  v ^= v >> 33;
  v *= 0xff51afd7ed558ccdULL;
  v ^= v >> 33;
  v *= 0xc4ceb9fe1a85ec53ULL;
  v ^= v >> 33;
  return static_cast<double>(v >> 11) * (1.0 / 9007199254740992.0);
}

// Calls put(i, j, channel, value) with each pixel's mean over its samples; pixel (i, j) is the
// grid's (grid_x + i, grid_y + j) (sample_position).
template <class SampleFn, class PutFn>
void average_samples(const View& view, int width, int height, std::int64_t grid_x, std::int64_t grid_y, int spp,
                     const TileRect& rect, SampleFn&& sample, PutFn&& put) {
  const double inv_spp = 1.0 / spp;
  for (int j = rect.y0; j < rect.y1; ++j) {
    for (int i = rect.x0; i < rect.x1; ++i) {
      Rgb sum{0.0, 0.0, 0.0};
      for (int k = 0; k < spp; ++k) {
        double sx, sy;
        sample_offset(k, spp, sx, sy);
        const Rgb e = sample(sample_position(view, width, height, grid_x + i, grid_y + j, sx, sy), i, j, k);
        for (int c = 0; c < 3; ++c) sum[c] += e[c];
      }
      for (int c = 0; c < 3; ++c) put(i, j, c, static_cast<float>(sum[c] * inv_spp));
    }
  }
}

// The scalar reference at sample x of pixel (i, j): shaded by the pixel's normal when shading
// is active (docs/contract.md section 6: every sample of a pixel has the pixel's normal).
Rgb scalar_sample(const PreparedScene& scene, bool shade, Vec2 x, int i, int j, ScalarScratch& scratch) {
  if (!shade) return scalar_irradiance(scene, x, nullptr, scratch);
  const Vec3 normal = scene.normal_at(i, j);
  return scalar_irradiance(scene, x, &normal, scratch);
}

}  // namespace

void render_rect_scalar(const PreparedScene& scene, int spp, const TileRect& rect, ScalarScratch& scratch,
                        const ImageView& image, bool shaded) {
  const bool shade = shading_active(scene, shaded);
  average_samples(
      scene.view, scene.width, scene.height, scene.grid_x, scene.grid_y, spp, rect,
      [&](Vec2 x, int i, int j, int) { return scalar_sample(scene, shade, x, i, j, scratch); },
      [&](int i, int j, int c, float v) { image.data[static_cast<std::ptrdiff_t>(j) * image.row_stride + 3 * i + c] = v; });
}

void render_tile_scalar(const PreparedScene& scene, int spp, const TileRect& rect, int tile_x0, int tile_y0,
                        ScalarScratch& scratch, TileResult& out, bool shaded) {
  const bool shade = shading_active(scene, shaded);
  average_samples(
      scene.view, scene.width, scene.height, scene.grid_x, scene.grid_y, spp, rect,
      [&](Vec2 x, int i, int j, int) { return scalar_sample(scene, shade, x, i, j, scratch); },
      [&](int i, int j, int c, float v) {
        out.rgb[c][static_cast<std::size_t>(j - tile_y0) * kTileSize + static_cast<std::size_t>(i - tile_x0)] = v;
      });
}

void render_rect_raycast(const Scene& scene, const RaycastRenderer& caster, int spp, int rays, const TileRect& rect,
                         const ImageView& image, bool shaded) {
  average_samples(scene.view, scene.width, scene.height, 0, 0, spp, rect, [&](Vec2 x, int i, int j, int k) {
    const std::uint64_t id = ((static_cast<std::uint64_t>(j) * static_cast<std::uint64_t>(scene.width) +
                               static_cast<std::uint64_t>(i))
                              << 8) |
                             static_cast<std::uint64_t>(k);
    const std::optional<Vec3> normal = shaded ? caster.normal_at(i, j) : std::nullopt;
    return caster.irradiance(x, rays, hash_to_unit(id), normal ? &*normal : nullptr);
  }, [&](int i, int j, int c, float v) { image.data[static_cast<std::ptrdiff_t>(j) * image.row_stride + 3 * i + c] = v; });
}

}  // namespace par2d::detail
