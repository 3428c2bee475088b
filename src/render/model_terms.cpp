// The game lighting model's share of a tile's work: see model_terms.hpp.
#include "render/model_terms.hpp"

namespace par2d::detail {
namespace {

// Occluders a ray from the box in a direction within [start, start + width] may meet: the
// box swept along those directions, as convex hulls of sub-arcs at most pi/2 wide reaching
// past every shape (`reach`), queried in the index and merged.
void directional_candidates(const PreparedScene& scene, const std::array<Vec2, 4>& corners, double start,
                            double width, double reach, DirectionalScratch& scratch, std::vector<std::uint32_t>& out) {
  out.clear();
  const int parts = std::max(1, static_cast<int>(std::ceil(width / (0.5 * kPi))));
  const double step = width / parts;
  for (int part = 0; part < parts; ++part) {
    const double a0 = start + part * step, a1 = a0 + step, mid = 0.5 * (a0 + a1);
    // The sector of radius `reach` lies in the hull of its ends and the tangents' meeting point.
    const Vec2 far[3] = {reach * Vec2{std::cos(a0), std::sin(a0)}, reach * Vec2{std::cos(a1), std::sin(a1)},
                         (reach / std::cos(0.5 * step)) * Vec2{std::cos(mid), std::sin(mid)}};
    Vec2 points[16];
    int count = 0;
    for (Vec2 c : corners) {
      points[count++] = c;
      for (Vec2 f : far) points[count++] = c + f;
    }
    scratch.hull.resize(2 * 16 + 1);
    const int hull_count = convex_hull(points, count, scratch.hull.data());
    scratch.found.clear();
    scene.occluder_bvh.query_convex(scratch.hull.data(), hull_count, scratch.found);
    out.insert(out.end(), scratch.found.begin(), scratch.found.end());
  }
  if (parts > 1) {
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
}

}  // namespace

void finish_light_terms(const LightTerms& light, bool ranged, double scale, KernelLightTerms& terms) noexcept {
  if (ranged) {
    terms.ranged = true;
    terms.range = static_cast<float>(light.range * scale);
    terms.falloff = static_cast<float>(light.falloff);
  }
  terms.cone = light.has_cone;
  terms.cone_center = light.cone_center;
  terms.cone_half = light.cone_half;
  terms.cone_fade = light.cone_fade;
  terms.cookie = light.cookie.count > 0 ? &light.cookie : nullptr;
  terms.sin_elevation = light.sin_elevation;
  terms.cos_elevation = light.cos_elevation;
}

void add_directional_lights(const PreparedScene& scene, const std::array<Vec2, 4>& corners, const Aabb& box,
                            DirectionalScratch& scratch, TileOccluders& occluders, TileWork& work) {
  const double sweep = 2.0 * scene.extent + 4.0 * std::max(std::abs(box.max_x - box.min_x), std::abs(box.max_y - box.min_y));
  for (const PreparedDirectional& d : scene.directionals) {
    KernelLight kl;
    KernelLightTerms terms;
    terms.directional = true;
    terms.dir_start = static_cast<float>(d.start);
    terms.dir_width = static_cast<float>(d.width);
    terms.sin_elevation = d.sin_elevation;
    terms.cos_elevation = d.cos_elevation;
    kl.first_pair = static_cast<std::uint32_t>(work.pairs.size());
    directional_candidates(scene, corners, d.start, d.width, sweep, scratch, scratch.occluders);
    for (std::uint32_t k : scratch.occluders) {
      const OccluderTerms& ot = scene.occluder_terms[k];
      if (!ot.acts_on(d.mask)) continue;
      if (!ot.opaque()) terms.translucent = true;
      KernelPair pair;
      pair.front = true;
      pair.c = -1.0f;
      pair.occluder = static_cast<std::uint32_t>(occluders.intern(k));
      work.pairs.push_back(pair);
    }
    kl.pair_count = static_cast<std::uint32_t>(work.pairs.size()) - kl.first_pair;
    kl.interval_count = 2 * kl.pair_count;
    for (int c = 0; c < 3; ++c) kl.emission[c] = static_cast<float>(d.emission[static_cast<std::size_t>(c)] / kTwoPi);
    work.max_intervals_per_light = std::max(work.max_intervals_per_light, kl.interval_count);
    work.lights.push_back(kl);
    work.light_terms.push_back(terms);
  }
}

void set_tile_shading(const PreparedScene& scene, const TileRect& tile, bool shaded, TileWork& work) {
  for (int c = 0; c < 3; ++c) work.ambient[c] = static_cast<float>(scene.ambient[static_cast<std::size_t>(c)]);
  work.shaded = shading_active(scene, shaded);
  if (work.shaded) {
    if (scene.normal_source == NormalSource::map) {
      // In place: the map's planes are padded with (0, 0, 1) to whole 64-pixel blocks.
      static_assert(kNormalPadding % kTileSize == 0, "a tile must not straddle the normal map's padding");
      const WorldNormals& map = *scene.normal_map;
      for (int c = 0; c < 3; ++c) work.normal_plane[c] = map.row(c, tile.y0) + tile.x0;
      work.normal_stride = map.stride();
    } else {
      // Every pixel the same (pixels past the image too: their values are dropped).
      const float constant[3] = {static_cast<float>(scene.normal.x), static_cast<float>(scene.normal.y),
                                 static_cast<float>(scene.normal.z)};
      for (int c = 0; c < 3; ++c) {
        std::fill_n(work.constant_normal[c], kTileSize, constant[c]);
        work.normal_plane[c] = work.constant_normal[c];
      }
      work.normal_stride = 0;
    }
  }
}

}  // namespace par2d::detail
