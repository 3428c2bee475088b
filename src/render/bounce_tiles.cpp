// Sources culled per tile by the occlusion proofs that cull lights, then the exact reference.
#include "render/bounce_tiles.hpp"

#include "render/block_culling.hpp"
#include "render/kernel_shapes.hpp"
#include "render/model_terms.hpp"
#include "world/occluder_bvh.hpp"

namespace par2d::detail {
namespace {

// The occluders whose boxes meet the hull of the tile and the source, in scratch.candidates
// (every occluder that may stand between a point of the tile and the source); then whether
// those other than the source's own prove every segment from the tile's box to the
// source's shape blocked. A piece's light reaches x along a direction only where that
// direction enters the source's occluder at the piece, and the segment from x to that entry
// point then meets an opaque occluder first: only opaque, dark-inside occluders acting on the
// source's mask may prove it (the same rule as for lights; section 7 gives a piece its
// occluder's mask).
bool source_hidden(const PreparedScene& scene, const BounceSource& source, const std::array<Vec2, 4>& corners,
                   const Aabb& box, BounceTileScratch& scratch) {
  const ConvexShape& shape = scene.occluders[source.occluder];
  const std::uint32_t mask = scene.occluder_terms[source.occluder].mask;
  hull_with_shape(corners.data(), 4, shape, scratch.hull_points, scratch.hull);
  scratch.candidates.clear();
  scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), scratch.candidates);
  scratch.provers.clear();
  for (const std::uint32_t k : scratch.candidates)
    if (k != source.occluder && proves_shadow(scene, k, mask)) scratch.provers.push_back(k);
  if (scratch.provers.empty()) return false;
  return rect_hidden_from_light({box.min_x, box.min_y}, {box.max_x, box.max_y}, shape, scene.occluders,
                                scratch.provers.data(), scratch.provers.size(), kTileStripBudget, scratch.occlusion);
}

}  // namespace

void add_bounce_tile(const PreparedScene& scene, const BounceFrame& bounce, int spp, bool shaded, bool cull,
                     const TileRect& tile, const TileRect& part, BounceTileScratch& scratch, TileResult& out,
                     FrameCounters& counts) {
  scratch.sources.clear();
  scratch.first.assign(1, 0);
  scratch.blockers.clear();
  const std::array<Vec2, 4> corners = tile_corners(scene, tile);
  const Aabb box = bounds_of(corners);
  for (std::uint32_t s = 0; s < bounce.sources.size(); ++s) {
    const BounceSource& source = bounce.sources[s];
    if (!source.lit) continue;
    ++counts.bounce_tile_sources;
    if (!cull) continue;
    if (source_hidden(scene, source, corners, box, scratch)) {
      ++counts.bounce_tile_sources_hidden;
      continue;
    }
    scratch.sources.push_back(s);
    scratch.blockers.insert(scratch.blockers.end(), scratch.candidates.begin(), scratch.candidates.end());
    scratch.first.push_back(static_cast<std::uint32_t>(scratch.blockers.size()));
  }
  if (cull && scratch.sources.empty()) return;
  const BounceSourceSubset subset{scratch.sources.data(), scratch.sources.size(), scratch.first.data(),
                                  scratch.blockers.data()};
  const bool shade = shading_active(scene, shaded);
  const double inv_spp = 1.0 / spp;
  BounceScratch& reference = scratch.reference;
  reference.source_walks = reference.depth_tests = 0;
  for (int j = part.y0; j < part.y1; ++j) {
    for (int i = part.x0; i < part.x1; ++i) {
      const Vec3 normal = scene.normal_at(i, j);
      Rgb sum{0.0, 0.0, 0.0};
      for (int k = 0; k < spp; ++k) {
        double sx, sy;
        sample_offset(k, spp, sx, sy);
        const Rgb e = bounce_irradiance(scene, bounce, sample_position(scene, i, j, sx, sy), shade ? &normal : nullptr,
                                        reference, cull ? &subset : nullptr);
        for (int c = 0; c < 3; ++c) sum[c] += e[c];
      }
      const std::size_t at = static_cast<std::size_t>(j - tile.y0) * kTileSize + static_cast<std::size_t>(i - tile.x0);
      for (int c = 0; c < 3; ++c) out.rgb[c][at] += static_cast<float>(sum[c] * inv_spp);
    }
  }
  counts.bounce_source_walks += reference.source_walks;
  counts.bounce_depth_tests += reference.depth_tests;
}

}  // namespace par2d::detail
