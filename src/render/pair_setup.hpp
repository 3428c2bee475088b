// A light's pairs over a tile: which of its block candidates can block it there, with their
// separating lines (or as general pairs), and the culling that drops pairs and lights before
// the kernel: occluders behind the light, umbra tests, the tile-light hull.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "culling/visible_light.hpp"
#include "render/frame_counters.hpp"
#include "render/kernel_shapes.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Per-thread buffers of the pair setup, most of them per block and found on first use.
struct PairSetupScratch {
  // A shape's tangent directions seen from the tile corners of the current block (the
  // (kBlockTiles + 1)^2 points of its tile grid, shared by up to four tiles each), for the
  // umbra tests, on first use. Slots are dealt per block to the shapes that need them.
  static constexpr int kGridPoints = (kBlockTiles + 1) * (kBlockTiles + 1);
  struct CornerDirections {
    Vec2 cw, ccw;
    signed char outside = -1;  // -1: not computed yet
  };
  struct GridTangents {
    std::vector<std::uint64_t> block;  // per shape: BlockView::serial when given its slot
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
  // umbra (umbra_possible in pair_setup.cpp), on first use in the block.
  struct UmbraBand {
    signed char state = -1;  // -1: not computed yet, 0: no band (every point may), 1: band below
    Vec2 center, u;
    double big_r = 0, dist = 0, sin_b = 0, cos_b = 0;
  };
  std::vector<std::vector<UmbraBand>> umbra_bands;
  std::vector<std::uint64_t> umbra_band_block;  // per light: BlockView::serial its bands belong to
  // Per light and block candidate: the pair's separating line (PairSeparators), on first use
  // in the block. The scene's table holds lights x occluders lines (32 MB at 256 lights and
  // 4096 occluders), which each tile read at scattered places: on the rubble level a sixth
  // of the frame's time was those reads' cache misses. The block's tiles share these.
  struct BlockSeparator {
    signed char state = -1;  // -1: not looked up yet, 0: none (the shapes touch), 1: `line`
    Line line;
  };
  std::vector<std::vector<BlockSeparator>> block_separators;
  std::vector<std::uint64_t> block_separator_block;  // per light: BlockView::serial its entries belong to
  // Its counts (umbra_tests, umbra_hits, tile_pairs_outside_hull: pairs whose occluder
  // misses the tile-light hull), accumulated until the owner clears them.
  FrameCounters counts;

  // Entries of earlier blocks carry an older serial: found anew on first use.
  void start_block(std::size_t lights, std::size_t occluders) {
    light_grid.start_block(lights);
    umbra_bands.resize(lights);
    umbra_band_block.resize(lights, 0);
    block_separators.resize(lights);
    block_separator_block.resize(lights, 0);
    occluder_grid.start_block(occluders);
  }
};

// The tile as its lights' pair setup sees it, made once per tile.
struct TileView {
  std::array<Vec2, 4> corners;  // tile_corners
  Aabb box;
  int grid[4];  // the corners on the block's tile grid (corner order of tile_corners)
  TileFrame frame;
  bool culling = false;  // culling on and trusted (culling_trusted)
};

// A light's tangent points (where its arc's two bounding rays touch it) seen from the four
// corners of a rectangle, on first use.
struct CornerTangentPoints {
  Vec2 point[4][2];
  signed char state[4] = {-1, -1, -1, -1};  // -1: not computed yet, 0: corner inside the light, 1: known
  // Four stores: through a reference, std::fill here became a call to memset per light.
  void forget() noexcept { state[0] = state[1] = state[2] = state[3] = -1; }
};

// A light's pairs over the tile (appended to TileWork::pairs, general pairs' points to
// TileWork::point_x and point_y) and what the rest of the light's setup needs of them.
struct LightPairs {
  std::uint32_t first_pair = 0;  // the light's pairs: TileWork::pairs from here on
  std::size_t first_point = 0;   // its general pairs' points: TileWork::point_x from here on
  bool shadowed = false;  // hidden over the whole tile: its pairs and points are to be dropped
  bool general = false;   // some pair is general (the light's kernel shape is kept whole)
  bool clipped = false;   // the light is clipped at one of an overlapping occluder's edges
  LightClip clip;
  // Only general pairs and clipped lights use the tangent points: computed on first use.
  CornerTangentPoints tangent_points;
};

// Appends light l's pairs over the tile to `work`: its block candidates that can block it
// there. A light that overlaps or touches an occluder is clipped at one of the occluder's
// edges where its cap lies inside it, or else makes a general pair (simd/tile_work.hpp).
// With tile.culling, occluders behind the light for the whole tile and occluders outside
// the hull of the tile and the light are dropped, and a light in the umbra of one occluder
// over the whole tile comes back shadowed.
// `visible` (VisibleLights, or nullptr): a light clipped by its designated occluder, whose
// clip line then also separates every other occluder lying wholly beyond it (the kernel
// clips the light there; where the tile cannot, each pair is separated per tile).
void build_light_pairs(const PreparedScene& scene, std::size_t l, const std::vector<std::uint32_t>& candidates,
                       const TileView& tile, const BlockView& block, PairSetupScratch& scratch,
                       KernelShapeScratch& shapes, TileWork& work, LightPairs& out,
                       const VisibleLights::Entry* visible = nullptr);

// Whether a clipped light's clip changes nothing over the tile: over a tile wholly before the
// clip line that sees no light point past it, the clipped light's arc is the whole light's
// (and the pair was dropped as behind).
bool clip_needless(const ConvexShape& light, const TileView& tile, LightPairs& pairs) noexcept;

}  // namespace par2d::detail
