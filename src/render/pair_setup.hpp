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

// Entries found on first use in a block and shared by its tiles: per key (a light or an
// occluder) a run of entries, dealt from one flat array of fixed capacity. A block whose keys
// need more entries than it holds leaves the rest uncached (run() returns null and the caller
// computes the same values without keeping them: the image does not change), so the storage
// stays as reserved whatever the lights' motion and the frame allocates nothing.
template <class Entry>
class BlockRuns {
 public:
  // Room for `keys` keys and `capacity` entries (allocates: only when the scene's counts change).
  void reserve_for(std::size_t keys, std::size_t capacity) {
    serial_.resize(keys, 0);
    first_.resize(keys, 0);
    entries_.reserve(capacity);  // sized within this as blocks deal runs: pages untouched till used
    capacity_ = std::max(capacity_, capacity);
  }
  // Forgets the runs of the previous block (their keys' serials are older than the new block's).
  void start_block() noexcept { used_ = 0; }
  // The `count` entries of `key` in the block `serial`, reset to Entry{} on the key's first
  // call in the block; null when the capacity left in the block is less than `count`.
  Entry* run(std::size_t key, std::size_t count, std::uint64_t serial) noexcept {
    if (serial_[key] != serial) {
      if (capacity_ - used_ < count) return nullptr;
      serial_[key] = serial;
      first_[key] = used_;
      used_ += count;
      if (entries_.size() < used_) entries_.resize(used_);  // within the reserved capacity
      std::fill_n(entries_.data() + first_[key], count, Entry{});
    }
    return entries_.data() + first_[key];
  }
  std::size_t reserved_bytes() const noexcept {
    return entries_.capacity() * sizeof(Entry) + serial_.capacity() * sizeof(std::uint64_t) +
           first_.capacity() * sizeof(std::size_t);
  }

 private:
  std::vector<Entry> entries_;
  std::vector<std::uint64_t> serial_;  // per key: BlockView::serial of its run
  std::vector<std::size_t> first_;     // per key: its run's first entry
  std::size_t used_ = 0;               // entries dealt in the current block
  std::size_t capacity_ = 0;           // entries a block may deal (reserved)
};

// Per-thread buffers of the pair setup, most of them per block and found on first use.
struct PairSetupScratch {
  // A shape's tangent directions seen from the tile corners of the current block (the
  // (kBlockTiles + 1)^2 points of its tile grid, shared by up to four tiles each), for the
  // umbra tests, on first use: a run of kGridPoints per light (light_grid) or occluder.
  static constexpr int kGridPoints = (kBlockTiles + 1) * (kBlockTiles + 1);
  struct CornerDirections {
    Vec2 cw, ccw;
    signed char outside = -1;  // -1: not computed yet
  };
  BlockRuns<CornerDirections> light_grid, occluder_grid;
  // Per light and block candidate: the band outside which no point lies in the occluder's
  // umbra (umbra_possible in pair_setup.cpp), on first use in the block.
  struct UmbraBand {
    signed char state = -1;  // -1: not computed yet, 0: no band (every point may), 1: band below
    Vec2 center, u;
    double big_r = 0, dist = 0, sin_b = 0, cos_b = 0;
  };
  BlockRuns<UmbraBand> umbra_bands;  // a run per light: one entry per block candidate
  // Per light and block candidate: the pair's separating line (PairSeparators), on first use
  // in the block. The scene's table holds lights x occluders lines (32 MB at 256 lights and
  // 4096 occluders), which each tile read at scattered places: on the rubble level a sixth
  // of the frame's time was those reads' cache misses. The block's tiles share these.
  struct BlockSeparator {
    signed char state = -1;  // -1: not looked up yet, 0: none (the shapes touch), 1: `line`
    Line line;
  };
  BlockRuns<BlockSeparator> block_separators;  // a run per light: one entry per block candidate
  // Where entries are found anew once a block's runs are all dealt (BlockRuns).
  BlockSeparator uncached_separator;
  UmbraBand uncached_band;
  std::vector<CornerDirections> uncached_grid;  // kGridPoints
  // Its counts (umbra_tests, umbra_hits, tile_pairs_outside_hull: pairs whose occluder
  // misses the tile-light hull), accumulated until the owner clears them.
  FrameCounters counts;

  // Room for a scene of `lights` lights and `occluders` occluders (allocates; called when
  // those counts change, never per frame otherwise). The capacities:
  // - light_grid: every light's run (a light takes one run per block), exact.
  // - umbra_bands, block_separators: a light's run has one entry per block candidate, so a
  //   block needs at most lights x occluders; storage is kept to O(lights + occluders) by
  //   kPairEntriesPerShape entries per light and occluder (at least 4096), or lights x
  //   occluders when that is less. Blocks needing more compute the rest uncached.
  // - occluder_grid: runs for at most kOccluderGridRuns occluders a block (each run is
  //   kGridPoints entries, 1 KB); only occluders with an umbra test in the block take one.
  static constexpr std::size_t kPairEntriesPerShape = 4;
  static constexpr std::size_t kMinPairEntries = 4096;
  static constexpr std::size_t kOccluderGridRuns = 256;
  void reserve_for(std::size_t lights, std::size_t occluders) {
    const std::size_t pair_entries =
        std::min(lights * occluders, std::max(kMinPairEntries, kPairEntriesPerShape * (lights + occluders)));
    light_grid.reserve_for(lights, lights * kGridPoints);
    occluder_grid.reserve_for(occluders, std::min(occluders, kOccluderGridRuns) * kGridPoints);
    umbra_bands.reserve_for(lights, pair_entries);
    block_separators.reserve_for(lights, pair_entries);
    uncached_grid.resize(kGridPoints);
  }
  std::size_t reserved_bytes() const noexcept {
    return light_grid.reserved_bytes() + occluder_grid.reserved_bytes() + umbra_bands.reserved_bytes() +
           block_separators.reserved_bytes() + uncached_grid.capacity() * sizeof(CornerDirections);
  }

  // Entries of earlier blocks carry an older serial: found anew on first use.
  void start_block() noexcept {
    light_grid.start_block();
    occluder_grid.start_block();
    umbra_bands.start_block();
    block_separators.start_block();
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
