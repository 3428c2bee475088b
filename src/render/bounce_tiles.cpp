// Sources culled per tile by the occlusion proofs that cull lights, then the exact reference.
#include "render/bounce_tiles.hpp"

#include <algorithm>
#include <cmath>

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

// The lit sources that may reach the region `corners` (box `box`), each with the occluders
// that may stand between (scratch.sources, first, blockers); with `cull`, those proven hidden
// from the whole region are left out. Returns the subset for bounce_irradiance (null without
// culling: every lit source is walked, the reference).
const BounceSourceSubset* reachable_sources(const PreparedScene& scene, const BounceFrame& bounce, bool cull,
                                            const std::array<Vec2, 4>& corners, const Aabb& box,
                                            BounceTileScratch& scratch, FrameCounters& counts,
                                            BounceSourceSubset& subset) {
  scratch.sources.clear();
  scratch.first.assign(1, 0);
  scratch.blockers.clear();
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
  if (!cull) return nullptr;
  subset = BounceSourceSubset{scratch.sources.data(), scratch.sources.size(), scratch.first.data(),
                              scratch.blockers.data()};
  return &subset;
}

// floor(a / n) * n for a grid coordinate a and a step n >= 1.
std::int64_t node_below(double a, int n) noexcept {
  return static_cast<std::int64_t>(std::floor(a / n)) * n;
}

// The coarse bounce (docs/contract.md section 7, "Coarse bounce") of the samples of `part`:
// the nodes' exact bounce (computed before the tiles, compute_bounce_nodes) around each sample,
// weighted bilinearly, over the nodes whose segment to the sample meets no occluder; the exact
// bounce at the sample where no node with a weight is seen.
void add_coarse_bounce_tile(const PreparedScene& scene, const BounceFrame& bounce, const BounceNodes& nodes, int spp,
                            bool shade, bool cull, const TileRect& tile, const TileRect& part,
                            BounceTileScratch& scratch, TileResult& out, FrameCounters& counts) {
  const int n = nodes.step;
  // The pixels spanning the part and its samples' nodes: every segment from a sample to one
  // of its nodes lies inside, so only occluders whose boxes meet it may meet a segment.
  const std::int64_t gx0 = node_below(static_cast<double>(scene.grid_x + part.x0) - 0.5, n);
  const std::int64_t gy0 = node_below(static_cast<double>(scene.grid_y + part.y0) - 0.5, n);
  const std::int64_t gx1 = node_below(static_cast<double>(scene.grid_x + part.x1) - 0.5, n) + n;
  const std::int64_t gy1 = node_below(static_cast<double>(scene.grid_y + part.y1) - 0.5, n) + n;
  const TileRect region{static_cast<int>(std::min<std::int64_t>(gx0 - scene.grid_x, part.x0)),
                        static_cast<int>(std::min<std::int64_t>(gy0 - scene.grid_y, part.y0)),
                        static_cast<int>(std::max<std::int64_t>(gx1 - scene.grid_x + 1, part.x1)),
                        static_cast<int>(std::max<std::int64_t>(gy1 - scene.grid_y + 1, part.y1))};
  const std::array<Vec2, 4> corners = tile_corners(scene, region);
  const Aabb box = bounds_of(corners);
  scratch.near.clear();
  if (cull) {
    scene.occluder_bvh.query_box(box, scratch.near);
  } else {
    for (std::uint32_t k = 0; k < scene.occluders.size(); ++k) scratch.near.push_back(k);
  }
  // A sample that sees none of its nodes gets its exact bounce, over the sources culled for
  // the part (found at the first such sample: most tiles have none).
  BounceSourceSubset subset_storage;
  const BounceSourceSubset* subset = nullptr;
  bool culled = false;
  BounceScratch& reference = scratch.reference;
  reference.source_walks = reference.depth_tests = 0;
  auto node_position = [&](std::int64_t gx, std::int64_t gy) {
    return sample_position(scene, static_cast<int>(gx - scene.grid_x), static_cast<int>(gy - scene.grid_y), 0.5, 0.5);
  };
  const double inv_spp = 1.0 / spp;
  for (int j = part.y0; j < part.y1; ++j) {
    for (int i = part.x0; i < part.x1; ++i) {
      Rgb sum{0.0, 0.0, 0.0};
      for (int k = 0; k < spp; ++k) {
        double sx, sy;
        sample_offset(k, spp, sx, sy);
        const Vec2 at = sample_position(scene, i, j, sx, sy);
        const double ax = static_cast<double>(scene.grid_x + i) + sx - 0.5;
        const double ay = static_cast<double>(scene.grid_y + j) + sy - 0.5;
        const std::int64_t nx = node_below(ax, n), ny = node_below(ay, n);
        const double fx = (ax - static_cast<double>(nx)) / n, fy = (ay - static_cast<double>(ny)) / n;
        Rgb e{0.0, 0.0, 0.0};
        double weights = 0.0;
        for (int corner = 0; corner < 4; ++corner) {
          const int dc = corner & 1, dr = corner >> 1;
          const double w = (dc ? fx : 1.0 - fx) * (dr ? fy : 1.0 - fy);
          if (!(w > 0.0)) continue;
          const std::int64_t gx = nx + dc * n, gy = ny + dr * n;
          if (!segment_passes(at, node_position(gx, gy), scene.occluders, scratch.near.data(), scratch.near.size()))
            continue;
          const Rgb& v = nodes.at(gx, gy);
          for (int ch = 0; ch < 3; ++ch) e[ch] += w * v[ch];
          weights += w;
        }
        if (weights > 0.0) {
          for (int ch = 0; ch < 3; ++ch) sum[ch] += e[ch] / weights;
          continue;
        }
        if (!culled) {
          const std::array<Vec2, 4> part_corners = tile_corners(scene, part);
          subset = reachable_sources(scene, bounce, cull, part_corners, bounds_of(part_corners), scratch, counts,
                                     subset_storage);
          culled = true;
        }
        if (subset && subset->count == 0) continue;
        const Vec3 normal = scene.normal_at(i, j);
        const Rgb exact = bounce_irradiance(scene, bounce, at, shade ? &normal : nullptr, reference, subset);
        for (int ch = 0; ch < 3; ++ch) sum[ch] += exact[ch];
      }
      const std::size_t at = static_cast<std::size_t>(j - tile.y0) * kTileSize + static_cast<std::size_t>(i - tile.x0);
      for (int c = 0; c < 3; ++c) out.rgb[c][at] += static_cast<float>(sum[c] * inv_spp);
    }
  }
  counts.bounce_source_walks += reference.source_walks;
  counts.bounce_depth_tests += reference.depth_tests;
}

}  // namespace

int plan_bounce_nodes(const PreparedScene& scene, const TileRect& area, BounceNodes& nodes) {
  const int n = scene.bounce_step;
  nodes.step = n;
  nodes.group = std::max(2, 32 / n);
  // Every sample of the area lies in [x0 - 0.5, x1 - 0.5) x [y0 - 0.5, y1 - 0.5) in grid
  // coordinates (pixel centers on whole numbers), so its nodes in these ranges.
  nodes.gx0 = node_below(static_cast<double>(scene.grid_x + area.x0) - 0.5, n);
  nodes.gy0 = node_below(static_cast<double>(scene.grid_y + area.y0) - 0.5, n);
  nodes.columns = static_cast<int>((node_below(static_cast<double>(scene.grid_x + area.x1) - 0.5, n) - nodes.gx0) / n) + 2;
  nodes.rows = static_cast<int>((node_below(static_cast<double>(scene.grid_y + area.y1) - 0.5, n) - nodes.gy0) / n) + 2;
  nodes.value.resize(static_cast<std::size_t>(nodes.columns) * static_cast<std::size_t>(nodes.rows));
  const int across = (nodes.columns + nodes.group - 1) / nodes.group;
  const int down = (nodes.rows + nodes.group - 1) / nodes.group;
  return across * down;
}

void compute_bounce_nodes(const PreparedScene& scene, const BounceFrame& bounce, bool shaded, bool cull,
                          BounceNodes& nodes, int group, BounceTileScratch& scratch, FrameCounters& counts) {
  const int n = nodes.step;
  const int across = (nodes.columns + nodes.group - 1) / nodes.group;
  const int c0 = group % across * nodes.group, r0 = group / across * nodes.group;
  const int c1 = std::min(nodes.columns, c0 + nodes.group), r1 = std::min(nodes.rows, r0 + nodes.group);
  // The frame pixels of the group's nodes, culled like a tile.
  const int fx0 = static_cast<int>(nodes.gx0 - scene.grid_x) + c0 * n;
  const int fy0 = static_cast<int>(nodes.gy0 - scene.grid_y) + r0 * n;
  const TileRect pixels{fx0, fy0, fx0 + (c1 - 1 - c0) * n + 1, fy0 + (r1 - 1 - r0) * n + 1};
  const std::array<Vec2, 4> corners = tile_corners(scene, pixels);
  BounceSourceSubset subset_storage;
  const BounceSourceSubset* subset =
      reachable_sources(scene, bounce, cull, corners, bounds_of(corners), scratch, counts, subset_storage);
  const bool shade = shading_active(scene, shaded);
  BounceScratch& reference = scratch.reference;
  reference.source_walks = reference.depth_tests = 0;
  for (int r = r0; r < r1; ++r) {
    for (int c = c0; c < c1; ++c) {
      Rgb& value = nodes.value[static_cast<std::size_t>(r) * static_cast<std::size_t>(nodes.columns) +
                               static_cast<std::size_t>(c)];
      if (subset && subset->count == 0) {
        value = Rgb{0.0, 0.0, 0.0};
        continue;
      }
      const int i = fx0 + (c - c0) * n, j = fy0 + (r - r0) * n;
      // A node past the image's edge is shaded with the nearest image pixel's normal.
      const Vec3 normal = scene.normal_at(std::clamp(i, 0, scene.width - 1), std::clamp(j, 0, scene.height - 1));
      value = bounce_irradiance(scene, bounce, sample_position(scene, i, j, 0.5, 0.5), shade ? &normal : nullptr,
                                reference, subset);
    }
  }
  counts.bounce_source_walks += reference.source_walks;
  counts.bounce_depth_tests += reference.depth_tests;
}

void add_bounce_tile(const PreparedScene& scene, const BounceFrame& bounce, const BounceNodes* nodes, int spp,
                     bool shaded, bool cull, const TileRect& tile, const TileRect& part, BounceTileScratch& scratch,
                     TileResult& out, FrameCounters& counts) {
  const bool shade = shading_active(scene, shaded);
  if (nodes) return add_coarse_bounce_tile(scene, bounce, *nodes, spp, shade, cull, tile, part, scratch, out, counts);
  const std::array<Vec2, 4> corners = tile_corners(scene, tile);
  BounceSourceSubset subset_storage;
  const BounceSourceSubset* subset =
      reachable_sources(scene, bounce, cull, corners, bounds_of(corners), scratch, counts, subset_storage);
  if (cull && subset->count == 0) return;
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
                                        reference, subset);
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
