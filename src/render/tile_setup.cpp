// Builds TileWork: culling in double precision, then shapes rounded to float relative to the
// tile. The steps live with their concerns (block_culling, pair_setup, kernel_shapes,
// model_terms); this file runs them in order and interns the tile's occluders.
#include "render/tile_setup.hpp"

#include <algorithm>
#include <array>

namespace par2d::detail {

void TileSetupScratch::reserve_for(const SceneBounds& bounds) {
  reserved = bounds;
  const std::size_t lights = bounds.lights;
  // A light's block candidates name each occluder at most once (the index's query reports a
  // leaf once; without culling every occluder is listed once).
  block_candidates.resize(lights);
  for (std::vector<std::uint32_t>& c : block_candidates) c.reserve(bounds.candidates());
  block_shadowed.reserve(lights);
  culling.reserve_for(bounds);
  occlusion.reserve_for(bounds.candidates(), bounds.max_vertices, std::max(kBlockStripBudget, kTileStripBudget));
  pairs.reserve_for(lights, bounds.occluders);
  shapes.start_block(lights, bounds.occluders);  // per shape, sized here once
  // A tile's occluders are distinct scene occluders; its lights distinct scene lights.
  occluders.reserve_for(bounds.occluders);
  tile_lights.reserve(lights);
  block_enclosers.reserve(bounds.candidates());
  enclosers_query.reserve(bounds.candidates());
}

std::size_t TileSetupScratch::reserved_bytes() const noexcept {
  std::size_t bytes = block_candidates.capacity() * sizeof(std::vector<std::uint32_t>) + block_shadowed.capacity() +
                      tile_lights.capacity() * sizeof(std::uint32_t);
  for (const std::vector<std::uint32_t>& c : block_candidates) bytes += c.capacity() * sizeof(std::uint32_t);
  bytes += culling.reserved_bytes() + occlusion.reserved_bytes() + pairs.reserved_bytes() + occluders.reserved_bytes();
  bytes += (shapes.light_block_pairs.capacity() + shapes.occluder_block_pairs.capacity()) *
           sizeof(KernelShapeScratch::BlockTangentPair);
  return bytes;
}

void gather_block_candidates(const PreparedScene& scene, const TileRect& block, const std::vector<LightReach>* reach,
                             TileSetupScratch& scratch, const unsigned char* skip) {
  // The frame driver reserves for each frame's counts; a caller of its own gets them here.
  if (scratch.reserved.lights != scene.lights.size() || scratch.reserved.occluders != scene.occluders.size())
    scratch.reserve_for(scene_bounds(scene));
  const std::array<Vec2, 4> corners = tile_corners(scene, block);
  // Entries of earlier blocks (or scenes) carry an older serial: found anew on first use.
  scratch.block.start(scene, block, corners);
  scratch.shapes.start_block(scene.lights.size(), scene.occluders.size());
  scratch.pairs.start_block();
  scratch.culling.start_block(scene.lights.size());
  cull_block(scene, corners, reach, scratch.block_candidates, scratch.block_shadowed, scratch.culling,
             scratch.occlusion, skip);
  const Aabb box = bounds_of(corners);
  const double tile_w = (box.max_x - box.min_x) / kBlockTiles, tile_h = (box.max_y - box.min_y) / kBlockTiles;
  scratch.enclosers_query.clear();
  scratch.block_enclosers.clear();
  scene.occluder_bvh.query_box(box, scratch.enclosers_query);
  for (const std::uint32_t k : scratch.enclosers_query) {
    const ConvexShape& o = scene.occluders[k];
    if (o.bounds_max.x - o.bounds_min.x >= tile_w && o.bounds_max.y - o.bounds_min.y >= tile_h)
      scratch.block_enclosers.push_back(k);
  }
}

namespace {

// Whether an occluder holding the whole tile (every corner inside it: a convex shape then
// holds the rectangle, and every sample) shadows light `l` there: opaque, dark inside and
// acting on it, it leaves the light exactly 0 at every sample (docs/contract.md sections 1
// and 6: a point inside an acting opaque occluder receives nothing from the light, even
// inside the light). Tilemap walls hold whole tiles.
bool tile_enclosed_from(const PreparedScene& scene, std::size_t l, const std::vector<std::uint32_t>& enclosing) {
  for (const std::uint32_t k : enclosing)
    if (!scene.model || proves_shadow(scene, k, scene.lights[l].terms.mask)) return true;
  return false;
}

}  // namespace

void build_tile_work(const PreparedScene& scene, const TileRect& tile, int spp, bool culling, TileWork& work,
                     TileSetupScratch& scratch, bool shaded) {
  work.clear();
  const bool model = scene.model;
  work.model = model;
  culling = culling && culling_trusted(scene);
  scratch.tile_lights.clear();
  TileView view;
  view.culling = culling;
  const Vec2 origin = sample_position(scene, tile.x0, tile.y0, 0.0, 0.0);
  // The frame's scale depends on the scene only: found once per block.
  view.frame = TileFrame{origin, scratch.block.frame_scale, scratch.block.frame_far};
  const TileFrame& frame = view.frame;
  work.spp = spp;
  fill_sample_grid(scene, spp, frame, work);
  view.corners = tile_corners(scene, tile);
  const std::array<Vec2, 4>& corners = view.corners;
  view.box = bounds_of(corners);
  const Aabb& box = view.box;
  TileOccluders& occluders = scratch.occluders;
  occluders.start_tile(scene.occluders.size());
  // The tile's corners on the block's tile grid (corner order of tile_corners).
  const int grid_x = (tile.x0 - scratch.block.x0) / kTileSize, grid_y = (tile.y0 - scratch.block.y0) / kTileSize;
  const int grid_row = kBlockTiles + 1;
  const int grid_corner = grid_y * grid_row + grid_x;
  view.grid[0] = grid_corner;
  view.grid[1] = grid_corner + 1;
  view.grid[2] = grid_corner + grid_row + 1;
  view.grid[3] = grid_corner + grid_row;

  // Per light below, plain values with flags rather than std::optional, and the tangent
  // points made once: GCC 12's std::optional zero-fills its whole storage when
  // default-constructed, and so does a Vec2 array: two 144-byte `rep stos` per tile and
  // light, slow to start on lengths this short.
  // The occluders holding the whole tile, among the block's that may.
  std::vector<std::uint32_t>& enclosing = scratch.enclosers_query;
  enclosing.clear();
  if (culling) {
    for (const std::uint32_t k : scratch.block_enclosers) {
      const ConvexShape& o = scene.occluders[k];
      if (box.min_x < o.bounds_min.x || box.max_x > o.bounds_max.x || box.min_y < o.bounds_min.y ||
          box.max_y > o.bounds_max.y)
        continue;
      if (std::all_of(corners.begin(), corners.end(), [&](Vec2 c) { return contains(o, c); })) enclosing.push_back(k);
    }
  }
  LightPairs light_pairs;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (scratch.block_shadowed[l]) continue;
    const PreparedLight& light = scene.lights[l];
    if (model && beyond_range(box, light.shape, light.terms)) continue;
    if (!enclosing.empty() && tile_enclosed_from(scene, l, enclosing)) continue;
    build_light_pairs(scene, l, scratch.block_candidates[l], view, scratch.block, scratch.pairs, scratch.shapes,
                      work, light_pairs, scratch.culling.visible.clipped(l));
    if (!light_pairs.shadowed && culling && work.pairs.size() - light_pairs.first_pair >= kTileProofMinPairs)
      light_pairs.shadowed = tile_proof_hides_light(scene, l, box, work, light_pairs.first_pair, scratch.culling,
                                                    scratch.occlusion);
    if (light_pairs.shadowed) {
      work.pairs.resize(light_pairs.first_pair);
      work.point_x.resize(light_pairs.first_point);
      work.point_y.resize(light_pairs.first_point);
      continue;
    }
    KernelLight kl;
    kl.first_pair = light_pairs.first_pair;
    kl.pair_count = static_cast<std::uint32_t>(work.pairs.size()) - kl.first_pair;
    KernelLightTerms terms;
    for (std::uint32_t p = kl.first_pair; p < work.pairs.size(); ++p) {
      KernelPair& pair = work.pairs[p];
      // The model kernel keeps a separated pair's wrapped part as an interval of its own.
      kl.interval_count += pair.general ? pair.point_count + 1 : (model ? 2 : 1);
      if (model && !scene.occluder_terms[pair.occluder].opaque()) terms.translucent = true;
      work.max_points_per_pair = std::max(work.max_points_per_pair, pair.point_count);
      const std::int32_t local = occluders.intern(pair.occluder);
      if (pair.general) occluders.used_whole[static_cast<std::size_t>(local)] = 1;
      pair.occluder = static_cast<std::uint32_t>(local);
    }
    // A ranged light is kept whole: the window needs the distance to the whole shape.
    const bool ranged = model && light.terms.has_range();
    kl.shape = kernel_shape(light.shape, frame, corners, light_pairs.general || ranged, work, scratch.shapes,
                            scratch.block, &scratch.shapes.light_block_pairs[l]);
    kl.shape.closed = true;
    bool clipped = light_pairs.clipped;
    if (clipped && culling && clip_needless(light.shape, view, light_pairs)) clipped = false;
    if (clipped) {
      const LightClip& clip = light_pairs.clip;
      kl.shape.clipped = true;
      kl.shape.clip_nx = static_cast<float>(clip.line.normal.x);
      kl.shape.clip_ny = static_cast<float>(clip.line.normal.y);
      kl.shape.clip_c = frame.line_offset(clip.line.normal, clip.line.point);
      frame.point(clip.chord[0], kl.shape.chord_x[0], kl.shape.chord_y[0]);
      frame.point(clip.chord[1], kl.shape.chord_x[1], kl.shape.chord_y[1]);
    }
    for (int c = 0; c < 3; ++c) kl.emission[c] = static_cast<float>(light.emission[c] / kTwoPi);
    work.max_intervals_per_light = std::max(work.max_intervals_per_light, kl.interval_count);
    work.lights.push_back(kl);
    scratch.tile_lights.push_back(static_cast<std::uint32_t>(l));
    if (model) {
      finish_light_terms(light.terms, ranged, frame.scale, terms);
      work.light_terms.push_back(terms);
    }
  }
  if (model) {
    add_directional_lights(scene, corners, box, scratch.directional, occluders, work);
    set_tile_shading(scene, tile, shaded, work);
  }
  // Cells or shape-major: decided here once, for the cell lists too.
  scratch.plan = plan_tile(culling, work.pairs.size(), spp);
  // Arc windows (KernelShape::window) for the occluders whose arcs the kernel takes and the
  // lights whose arcs' starts it needs (those with pairs). A shape-major tile computes
  // single-pair lights with no arc for them or for the occluders only they use.
  const bool windows = !model;
  const bool shape_major = scratch.plan.shape_major;
  if (windows) {
    occluders.arc_needed.assign(occluders.used.size(), shape_major ? 0 : 1);
    for (KernelLight& kl : work.lights) {
      const KernelPair* pairs = work.pairs.data() + kl.first_pair;
      if (kl.pair_count == 0 || (shape_major && single_pair_light(pairs, kl.pair_count))) continue;
      if (shape_major)
        for (std::uint32_t p = 0; p < kl.pair_count; ++p) occluders.arc_needed[pairs[p].occluder] = 1;
      if (!kl.shape.clipped) assign_arc_window(kl.shape, work);
    }
  }
  for (std::size_t u = 0; u < occluders.used.size(); ++u) {
    work.occluders.push_back(kernel_shape(scene.occluders[occluders.used[u]], frame, corners,
                                          occluders.used_whole[u] != 0, work, scratch.shapes, scratch.block,
                                          &scratch.shapes.occluder_block_pairs[occluders.used[u]]));
    if (windows && occluders.arc_needed[u]) assign_arc_window(work.occluders.back(), work);
    if (model) work.occluder_terms.push_back(kernel_occluder_terms(scene.occluder_terms[occluders.used[u]]));
  }
}

}  // namespace par2d::detail
