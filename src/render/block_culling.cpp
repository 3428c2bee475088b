// Block culling and the adaptive proof rule: see block_culling.hpp.
#include "render/block_culling.hpp"

#include <algorithm>
#include <cmath>

#include "render/kernel_shapes.hpp"
#include "render/model_terms.hpp"
#include "world/occluder_bvh.hpp"

namespace par2d::detail {
namespace {

// Adaptive tile proofs. A failed proof costs about what a success saves the kernel (a
// light's pairs over the tile's samples), so proofs pay only where they mostly succeed. Where
// occluders are much smaller than the gaps between them (1-4 px rubble around small lights)
// most tile proofs fail, and a light whose proofs failed on one tile of a block mostly fails
// on the rest. So a light stops trying tile proofs in a block once all it tried there
// failed, while the block's tile proofs (all lights) succeed less than 1 in
// kBlockProofSuccessRatio times; past the block's first kTileProofWarmup tries, a light's
// first try in the block must pass that gate too (with many lights per tile, first tries
// alone would be most of the proofs). The block's own proofs are not counted in the gate:
// that helps rubble a little but skips useful proofs on levels of larger occluders. A
// skipped proof only hands the kernel a light that may be hidden: the same image.
// Measured in docs/performance.md ("Adaptive tile proofs", "Tile proofs' gate, again").
constexpr int kBlockProofSuccessRatio = 2;
constexpr std::uint32_t kTileProofWarmup = 16;

bool tile_proof_worth_trying(const BlockCullingScratch::TileProofRecord& light,
                             const BlockCullingScratch::TileProofRecord& block) noexcept {
  if (light.succeeded > 0) return true;
  const bool block_pays = block.succeeded * kBlockProofSuccessRatio >= block.tried;
  if (light.tried == 0) return block.tried < kTileProofWarmup || block_pays;
  return block_pays;
}

// Adaptive block proofs. A block tries a proof per light (in scene order); one costs about
// as much as a tile proof and few succeed (a light is hidden from a whole 64 px block only
// inside a closed pocket of small occluders), but a success spares up to 16 tiles the
// light's setup and tile proofs, so block proofs pay down to about 1 success in 16 tries.
// Once a block has tried kBlockProofWarmup proofs and fewer than 1 in kBlockProofPayRatio
// succeeded, it tries no more: its tiles meet those lights with their own adaptive tile
// proofs. A skipped proof only hands the tiles a light that may be hidden: the same image.
// Decided per block from its own tries, so the same whatever the threads. The warm-up is
// long enough that levels whose proofs pay skip none (docs/performance.md).
constexpr std::uint32_t kBlockProofWarmup = 24;
constexpr std::uint32_t kBlockProofPayRatio = 16;

bool block_proof_worth_trying(const BlockCullingScratch::TileProofRecord& block) noexcept {
  return block.tried < kBlockProofWarmup || block.succeeded * kBlockProofPayRatio >= block.tried;
}

// A monotone stand-in for the angle of (x, y) in [0, 4), 0 along +x, increasing with the
// angle: |x| + |y| in place of the length, no atan2.
double diamond_angle(double x, double y) noexcept {
  const double sum = std::abs(x) + std::abs(y);
  if (!(sum > 0.0)) return 0.0;
  if (y >= 0.0) return x >= 0.0 ? y / sum : 1.0 - x / sum;
  return x < 0.0 ? 2.0 - y / sum : 3.0 + x / sum;
}

// A light's candidates in a block ordered by their direction from the block's center,
// measured from the light's. Pairs follow the candidates' order in every tile, and the
// kernel extends the blocked prefix of a light's arc with each interval that starts inside
// it, stopping on the light once the prefix spans the arc: intervals that arrive in
// angular order close a cover made of several occluders early.
// Fewer candidates leave the lights of the block's tiles a pair or two, where the order
// cannot pay for the sort.
constexpr std::size_t kOrderMinCandidates = 16;

void order_by_angle(const PreparedScene& scene, Vec2 light_center, Vec2 block_center, std::vector<std::uint32_t>& ids,
                    std::vector<std::pair<double, std::uint32_t>>& keyed) {
  const Vec2 to_light = light_center - block_center;
  keyed.clear();
  for (const std::uint32_t k : ids) {
    const Vec2 to_occluder = scene.occluders[k].centroid - block_center;
    double key = diamond_angle(dot(to_light, to_occluder), cross(to_light, to_occluder));
    if (key >= 2.0) key -= 4.0;  // into (-2, 2]: the light's direction in the middle, not at the seam
    keyed.emplace_back(key, k);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = keyed[i].second;
}

}  // namespace

void cull_block(const PreparedScene& scene, const std::array<Vec2, 4>& corners, const std::vector<LightReach>* reach,
                std::vector<std::vector<std::uint32_t>>& block_candidates, std::vector<unsigned char>& block_shadowed,
                BlockCullingScratch& scratch, OcclusionProofScratch& occlusion, const unsigned char* skip) {
  block_candidates.resize(scene.lights.size());
  block_shadowed.assign(scene.lights.size(), 0);
  const Aabb box = bounds_of(corners);
  if (reach && !culling_trusted(scene)) reach = nullptr;
  scratch.visible.update(scene);
  BlockCullingScratch::TileProofRecord block_proofs;  // this block's block proofs so far
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    std::vector<std::uint32_t>& candidates = block_candidates[l];
    candidates.clear();
    if (skip && skip[l]) {
      block_shadowed[l] = 1;
      continue;
    }
    if (!reach) {
      for (std::uint32_t k = 0; k < scene.occluders.size(); ++k)
        if (!scene.model || scene.occluder_terms[k].acts_on(scene.lights[l].terms.mask)) candidates.push_back(k);
      continue;
    }
    if ((*reach)[l].hides(box) || (scene.model && beyond_range(box, scene.lights[l].shape, scene.lights[l].terms))) {
      block_shadowed[l] = 1;
      continue;
    }
    const ConvexShape& light = scene.lights[l].shape;
    hull_with_shape(corners.data(), 4, light, scratch.hull_points, scratch.hull);
    scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), candidates);
    const std::uint32_t* provers = candidates.data();
    std::size_t prover_count = candidates.size();
    if (scene.model) {
      // Occluders that do not act on the light are not its candidates; of the rest, only
      // opaque dark ones may prove it hidden.
      const std::uint32_t mask = scene.lights[l].terms.mask;
      candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                      [&](std::uint32_t k) { return !scene.occluder_terms[k].acts_on(mask); }),
                       candidates.end());
      scratch.provers.clear();
      for (std::uint32_t k : candidates)
        if (proves_shadow(scene, k, mask)) scratch.provers.push_back(k);
      provers = scratch.provers.data();
      prover_count = scratch.provers.size();
    }
    // Hidden from the whole block by one occluder or several together (rooms behind a
    // wall, a field of rubble): the proof's cost is shared by the block's tiles.
    if (prover_count != 0 && !block_proof_worth_trying(block_proofs)) {
      ++scratch.counts.block_proofs_skipped;
    } else if (prover_count != 0) {
      ++block_proofs.tried;
      // A light poking into a wall: only its part outside needs hiding (the cap reaches no
      // point outside the wall, and a point inside sees nothing).
      if (rect_hidden_from_light({box.min_x, box.min_y}, {box.max_x, box.max_y}, scratch.visible.shape(scene, l),
                                 scene.occluders, provers, prover_count, kBlockStripBudget, occlusion)) {
        candidates.clear();
        block_shadowed[l] = 1;
        ++block_proofs.succeeded;
      }
    }
    if (!scene.model && candidates.size() >= kOrderMinCandidates)
      order_by_angle(scene, light.centroid, 0.5 * (corners[0] + corners[2]), candidates, scratch.ordered_candidates);
  }
}

bool tile_proof_hides_light(const PreparedScene& scene, std::size_t l, const Aabb& box, const TileWork& work,
                            std::uint32_t first_pair, BlockCullingScratch& scratch, OcclusionProofScratch& occlusion) {
  // The proof holds whatever the pairs' overlaps: every segment from the tile to a light
  // point meets an occluder before it, so every ray meets one before its first light point.
  const PreparedLight& light = scene.lights[l];
  BlockCullingScratch::TileProofRecord& light_proofs = scratch.tile_proof_records[l];
  BlockCullingScratch::TileProofRecord& block_proofs = scratch.block_proof_record;
  if (!tile_proof_worth_trying(light_proofs, block_proofs)) {
    ++scratch.counts.tile_proofs_skipped;
    return false;
  }
  scratch.provers.clear();
  for (std::uint32_t p = first_pair; p < work.pairs.size(); ++p)
    if (!scene.model || proves_shadow(scene, work.pairs[p].occluder, light.terms.mask))
      scratch.provers.push_back(work.pairs[p].occluder);
  const bool shadowed = rect_hidden_from_light({box.min_x, box.min_y}, {box.max_x, box.max_y},
                                               scratch.visible.shape(scene, l), scene.occluders, scratch.provers.data(), scratch.provers.size(),
                                               kTileStripBudget, occlusion);
  ++light_proofs.tried;
  ++block_proofs.tried;
  if (shadowed) {
    ++light_proofs.succeeded;
    ++block_proofs.succeeded;
  }
  return shadowed;
}

}  // namespace par2d::detail
