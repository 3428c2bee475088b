// Per-tile work for the SIMD kernels: which lights and occluders matter to a tile, their
// depth order, and their float geometry relative to the tile origin.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "culling/occlusion_proof.hpp"
#include "culling/light_reach.hpp"
#include "world/prepared_scene.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"

namespace par2d::detail {

// Per-thread buffers reused from tile to tile.
struct TileSetupScratch {
  // Per light: occluders that can block some ray from the current block to the light, from
  // one spatial-index query per block and light: in index order, or by direction when there
  // are many (order_by_angle in tile_setup.cpp).
  std::vector<std::vector<std::uint32_t>> block_candidates;
  std::vector<unsigned char> block_shadowed;  // per light: in one occluder's umbra over the whole block
  std::vector<std::int32_t> local_index;  // occluder -> index in TileWork::occluders, or -1
  std::vector<std::uint32_t> used;
  std::vector<unsigned char> used_whole;  // per entry of `used`: in a general pair (kernel shape kept whole)
  std::vector<unsigned char> arc_needed;  // per entry of `used`: some light's packets take its arc
  std::vector<Vec2> hull_points, hull;
  ConvexShape clipped, clipped_light;  // shapes reaching far from the tile, clipped to a box around it
  std::vector<std::uint32_t> pair_occluders;
  std::vector<std::pair<double, std::uint32_t>> ordered_candidates;  // a light's block candidates, angular keys
  std::vector<std::uint32_t> directional;  // a directional light's candidate occluders
  OcclusionProofScratch occlusion;
  // Per shape, its tile tangent pair over the whole current block (see kernel_shape in
  // tile_setup.cpp), found on the shape's first use in the block: a pair that holds over the
  // block holds over each of its tiles, which then skip the test. cw < 0: none over the block.
  struct BlockTangentPair {
    std::uint64_t block = 0;  // block_serial when found; older entries are stale
    std::int32_t cw = -1, ccw = -1;
  };
  std::vector<BlockTangentPair> light_block_pairs, occluder_block_pairs;
  std::uint64_t block_serial = 0;  // counts gather_block_candidates calls
  Vec2 block_corners[4];
  int block_x0 = 0, block_y0 = 0;  // the current block's first pixel column and row
  double frame_scale = 1.0;  // the scene's kernel-unit scale and far flag (TileFrame in tile_setup.cpp)
  bool frame_far = true;
  // A shape's tangent directions seen from the tile corners of the current block (the
  // (kBlockTiles + 1)^2 points of its tile grid, shared by up to four tiles each), for the
  // umbra tests, on first use. Slots are dealt per block to the shapes that need them.
  static constexpr int kGridPoints = (kBlockTiles + 1) * (kBlockTiles + 1);
  struct CornerDirections {
    Vec2 cw, ccw;
    signed char outside = -1;  // -1: not computed yet
  };
  struct GridTangents {
    std::vector<std::uint64_t> block;  // per shape: block_serial when given its slot
    std::vector<std::uint32_t> slot;   // per shape
    std::vector<CornerDirections> directions;  // kGridPoints per slot
    std::uint32_t slots = 0;           // slots dealt in the current block
    // The shape's kGridPoints entries (valid until the next call).
    CornerDirections* of(std::size_t shape, std::uint64_t serial) {
      if (block[shape] != serial) {
        block[shape] = serial;
        slot[shape] = slots++;
        const std::size_t end = static_cast<std::size_t>(slots) * kGridPoints;
        if (directions.size() < end) directions.resize(end);
        std::fill(directions.begin() + static_cast<std::ptrdiff_t>(end - kGridPoints),
                  directions.begin() + static_cast<std::ptrdiff_t>(end), CornerDirections{});
      }
      return directions.data() + static_cast<std::size_t>(slot[shape]) * kGridPoints;
    }
    void start_block(std::size_t shapes) {
      block.resize(shapes, 0);
      slot.resize(shapes, 0);
      slots = 0;
    }
  };
  GridTangents light_grid, occluder_grid;
  // Per light and block candidate: the band outside which no point lies in the occluder's
  // umbra (umbra_possible in tile_setup.cpp), on first use in the block.
  struct UmbraBand {
    signed char state = -1;  // -1: not computed yet, 0: no band (every point may), 1: band below
    Vec2 center, u;
    double big_r = 0, dist = 0, sin_b = 0, cos_b = 0;
  };
  std::vector<std::vector<UmbraBand>> umbra_bands;
  std::vector<std::uint64_t> umbra_band_block;  // per light: block_serial its bands belong to
  // Per light and block candidate: the pair's separating line (PairSeparators), on first use
  // in the block. The scene's table holds lights x occluders lines (32 MB at 256 lights and
  // 4096 occluders), which each tile read at scattered places: on the rubble level a sixth
  // of the frame's time was those reads' cache misses. The block's tiles share these.
  struct BlockSeparator {
    signed char state = -1;  // -1: not looked up yet, 0: none (the shapes touch), 1: `line`
    Line line;
  };
  std::vector<std::vector<BlockSeparator>> block_separators;
  std::vector<std::uint64_t> block_separator_block;  // per light: block_serial its entries belong to
  // Tile proofs tried and succeeded so far in the current block, per light and over all lights
  // (reset per block), for the adaptive rule (tile_setup.cpp). A block's tiles are built by
  // one thread in a fixed order, so the rule decides the same way whatever the scheduling.
  struct TileProofRecord {
    std::uint32_t tried = 0, succeeded = 0;
  };
  std::vector<TileProofRecord> tile_proof_records;
  TileProofRecord block_proof_record;
  // The last tile built: the scene index of each TileWork::lights entry (plain scenes), and
  // whether its lists were culled (cell_lists.hpp refines only culled tiles).
  std::vector<std::uint32_t> tile_lights;
  bool tile_culled = false;
  // Counts for FrameStats, accumulated until the owner resets them.
  std::uint64_t umbra_tests = 0, umbra_hits = 0;
  std::uint64_t tile_proofs_skipped = 0;  // tile proofs the adaptive rule did not try
  std::uint64_t block_proofs_skipped = 0;  // block proofs the adaptive rule did not try
  std::uint64_t hull_pairs_dropped = 0;  // pairs whose occluder misses the tile-light hull
};

// Fills scratch.block_candidates for the pixel rectangle `block`, skipping the lights that
// `reach` or a proof shows hidden from the whole block. Without `reach` (culling off):
// every occluder for every light.
void gather_block_candidates(const PreparedScene& scene, const TileRect& block, const std::vector<LightReach>* reach,
                             TileSetupScratch& scratch);

// Fills `work` for `tile` at `spp` samples per pixel, a tile of the block last given to gather_block_candidates.
// Every tile goes to the kernel: a light that overlaps or touches an occluder is clipped at
// one of the occluder's edges where its cap lies inside it, or else makes a general pair
// (simd/tile_work.hpp). With `culling`, occluders behind a light for the whole
// tile are dropped, and lights in the umbra of one occluder over the whole tile, or
// proven hidden by several (culling/occlusion_proof.hpp), are skipped; the image is the
// same either way.
// Scenes with the game lighting model (PreparedScene::model) get the model's work: range
// culling, pairs only for occluders acting on each light, directional lights as tile lights,
// ambient, and per-pixel normals when `shaded` and the scene has a normal source.
void build_tile_work(const PreparedScene& scene, const TileRect& tile, int spp, bool culling, TileWork& work,
                     TileSetupScratch& scratch, bool shaded = false);

}  // namespace par2d::detail
