// The frame driver: a frame plan's blocks dealt to lanes, lanes to threads, each block's tiles
// computed by its strategy, the bounce term added and stored into the host's format.
#include "render/frame_driver.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <iterator>
#include <memory>
#include <thread>
#include <vector>

#include "render/bounce_tiles.hpp"
#include "render/cell_lists.hpp"
#include "render/frame_counters.hpp"
#include "render/kernel_table.hpp"
#include "render/layered_tiles.hpp"
#include "render/light_layers.hpp"
#include "render/scalar_tiles.hpp"
#include "render/scene_bounds.hpp"
#include "render/tile_setup.hpp"
#include "render/tiling.hpp"
#include "scalar/bounce_reference.hpp"
#include "scalar/scalar_renderer.hpp"

namespace par2d::detail {
namespace {

// Pieces of the bounce stage per lane, taken one at a time (deal_indices): small enough that
// no lane is left with a long piece of the stage when the others are done.
constexpr int kBouncePartsPerLane = 16;

// fn(lane, index) for every index in [0, count) on `lanes` lanes (lane in [0, lanes), one lane
// never on two threads at once): each lane takes the next index not yet taken until none is
// left, so a lane whose thread is slower (a costlier part of the frame, or a core another
// process holds) takes fewer, and the threads finish within one index of each other. What an
// index computes must not depend on the lane that computes it.
template <class Fn>
void deal_indices(const Scheduler& scheduler, int lanes, std::size_t count, Fn&& fn) {
  std::atomic<std::size_t> next{0};
  scheduler.for_each_index(lanes, [&](int lane, int) {
    for (std::size_t i = next.fetch_add(1, std::memory_order_relaxed); i < count;
         i = next.fetch_add(1, std::memory_order_relaxed))
      fn(lane, i);
  });
}

// A block's counts, after gather_block_candidates: `tried` and `succeeded` are the proof
// counts before it, so the differences are the block proofs. `skipped`: lights left out
// because the light-layer cache holds them (not out of reach).
void count_block(const PreparedScene& scene, const TileSetupScratch& setup, std::uint64_t tried,
                 std::uint64_t succeeded, std::uint64_t skipped, FrameCounters& counts) noexcept {
  const std::uint64_t proven = setup.occlusion.proofs_succeeded - succeeded;
  std::uint64_t shadowed = 0;
  for (const unsigned char s : setup.block_shadowed) shadowed += s;
  shadowed -= skipped;
  for (const std::vector<std::uint32_t>& c : setup.block_candidates) counts.block_candidates += c.size();
  ++counts.blocks;
  counts.block_lights += scene.lights.size();
  counts.block_lights_out_of_reach += shadowed - proven;
  counts.block_proofs_tried += setup.occlusion.proofs_tried - tried;
  counts.block_proofs_succeeded += proven;
}

// The kernel's work on a tile: its lights, pairs and the samples they are evaluated at (per
// cell when the tile has cell lists).
void count_tile_work(const TileWork& work, FrameCounters& counts) noexcept {
  const std::uint64_t samples = static_cast<std::uint64_t>(work.spp) * kTilePixels;
  counts.samples += samples;
  counts.tile_lights += work.lights.size();
  counts.tile_pairs += work.pairs.size();
  for (const KernelPair& pair : work.pairs) counts.tile_general_pairs += pair.general ? 1u : 0u;
  if (work.cells.empty()) {
    counts.light_samples += work.lights.size() * samples;
    counts.pair_samples += work.pairs.size() * samples;
  } else {  // each packet evaluates its cell's lists
    const std::uint64_t cell_samples = samples / work.cells.size();
    for (const KernelCell& cell : work.cells) {
      counts.light_samples += cell.light_count * cell_samples;
      for (std::uint32_t i = cell.first_light; i < cell.first_light + cell.light_count; ++i)
        counts.pair_samples += work.cell_lights[i].pair_count * cell_samples;
    }
  }
}

// FrameStats' sampled needs at the middle pixel of `part`, a part of a tile of the block last
// given to gather_block_candidates: that block's candidates hold every occluder that can stand
// between its pixels and each light it may see.
void sample_needs(const PreparedScene& scene, const TileRect& part, const TileSetupScratch& setup, ScalarScratch& scalar,
                  FrameCounters& counts) {
  const Vec2 x = sample_position(scene, (part.x0 + part.x1) / 2, (part.y0 + part.y1) / 2, 0.5, 0.5);
  ++counts.sampled_pixels;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (setup.block_shadowed[l]) continue;
    const LightNeeds needs = light_needs(scene, l, x, setup.block_candidates[l], scalar);
    counts.sampled_visible_lights += needs.visible ? 1u : 0u;
    counts.sampled_blocking_pairs += needs.blocking;
  }
}

}  // namespace

// Everything one lane of blocks reuses from tile to tile and frame to frame.
struct FrameLane final : TileKernelRunner {
  TileWork work;
  TileSetupScratch setup;
  CellListScratch cells;
  ScalarScratch scalar;
  BounceTileScratch bounce;
  std::unique_ptr<float[]> scratch;  // 64-byte aligned view into it via `aligned`
  std::size_t scratch_floats = 0;
  float* aligned = nullptr;
  TileResult result;
  LayeredTileScratch layered;
  FrameCounters counts;  // this lane's counts in this frame (its setup's added when the lane ends)
  const KernelSet* kernels = nullptr;  // this frame's

  // Counts the work and runs the kernel on it.
  void run(const TileWork& tile_work, TileResult& out) override {
    count_tile_work(tile_work, counts);
    kernels->render_tile(tile_work, kernel_scratch(kernel_scratch_floats(tile_work, kernels->lanes)), out);
  }

  // The kernel's scratch for any tile of a scene with these counts, by kernel_scratch_floats
  // (simd/tile_work.hpp) at its largest: arc planes (plain scenes) for every occluder up to
  // kMaxArcPlaneOccluders, or the model's per-packet keys (game-model scenes), a light's
  // intervals one or two per pair (a general pair: its meeting points plus one, at most two
  // per edge of the pair's shapes, 2 max(V, 2)), at most one pair per occluder and light.
  // Capped at kReservedKernelFloats (2 MiB): a tile past that (hundreds of occluders in one
  // tile) grows the scratch.
  static constexpr std::size_t kReservedKernelFloats = std::size_t{1} << 19;
  // Kernel shape vertices reserved per tile at most (5 floats each).
  static constexpr std::size_t kReservedTileVertices = 16384;
  static std::size_t kernel_floats_bound(const SceneBounds& bounds, int lanes) noexcept {
    const std::size_t occluders = bounds.occluders, lights = bounds.lights + bounds.directionals;
    const std::size_t points = 2 * std::max<std::size_t>(bounds.max_vertices, 2);
    const std::size_t intervals = std::min(occluders, bounds.tile_pairs()) * std::max<std::size_t>(points + 1, 2);
    std::size_t sort_slots = 1, event_slots = 1, key_slots = 1;
    while (sort_slots < intervals) sort_slots *= 2;
    while (event_slots < points) event_slots *= 2;
    while (key_slots < 2 * intervals + 2) key_slots *= 2;
    const std::size_t model_floats = occluders + 2 * key_slots + sort_slots + 1;
    const std::size_t packet = static_cast<std::size_t>(lanes) * (2 * occluders + 2 * sort_slots + event_slots + 2);
    const std::size_t arcs = (2 * std::min(occluders, kMaxArcPlaneOccluders) + 1) * kTilePixels + lights + (occluders + 3) / 4;
    const std::size_t most = std::max(arcs, static_cast<std::size_t>(lanes) * model_floats) + packet;
    return std::min(most, kReservedKernelFloats);
  }

  // Reserves this lane's buffers for any frame of a scene with these counts (allocates; when
  // they change): the setup's parts (TileSetupScratch::reserve_for), the tile's work (its
  // lights are the scene's and directional lights, its occluders distinct scene occluders, at
  // most SceneBounds::tile_pairs() pairs, kMaxTileCells cells each listing some of these),
  // the cell lists' buffers and the kernel's scratch.
  void reserve_for(const SceneBounds& bounds, int lanes) {
    setup.reserve_for(bounds);
    const std::size_t lights = bounds.lights + bounds.directionals, occluders = bounds.occluders;
    const std::size_t pairs = bounds.tile_pairs();
    work.lights.reserve(lights);
    work.light_terms.reserve(lights);
    work.pairs.reserve(pairs);
    work.occluders.reserve(occluders);
    work.occluder_terms.reserve(occluders);
    work.cells.reserve(kMaxTileCells);
    work.cell_lights.reserve(kMaxTileCells * lights);
    work.cell_pairs.reserve(kMaxTileCells * pairs);
    work.cell_occluders.reserve(kMaxTileCells * occluders);
    cells.cell_boxes.reserve(kMaxTileCells);
    cells.cell_centers.reserve(kMaxTileCells);
    cells.occluder_discs.reserve(occluders);
    cells.occluder_cells.reserve(occluders);
    cells.pair_cells.reserve(std::min(occluders, pairs));  // one light's pairs
    // A tile's kernel shapes: each light and occluder once, a polygon clipped to the near box
    // (clip_to_box: 4 more points at most) or a light's visible part (one more).
    const std::size_t vertices = std::min((lights + occluders) * (bounds.max_vertices + 8), kReservedTileVertices);
    if (work.vx.size() < vertices)
      for (std::vector<float>* v : {&work.vx, &work.vy, &work.edge_nx, &work.edge_ny, &work.edge_c}) v->resize(vertices);
    cells.pair_buffer.reserve(kMaxTileCells * pairs);  // sized within this as tiles need (untouched till then)
    const std::size_t kernel_floats = kernel_floats_bound(bounds, lanes);
    if (kernel_floats > scratch_floats) allocate_kernel_scratch(kernel_floats);
  }

  // Bytes this lane's buffers reserve (FrameEngine::reserved_bytes).
  std::size_t reserved_bytes() const noexcept {
    return setup.reserved_bytes() + (work.lights.capacity() * sizeof(KernelLight)) +
           work.light_terms.capacity() * sizeof(KernelLightTerms) +
           (work.pairs.capacity() + work.cell_pairs.capacity() + cells.pair_buffer.capacity()) * sizeof(KernelPair) +
           work.occluders.capacity() * sizeof(KernelShape) + work.occluder_terms.capacity() * sizeof(KernelOccluderTerms) +
           (work.point_x.capacity() + work.point_y.capacity()) * sizeof(float) +
           work.cells.capacity() * sizeof(KernelCell) + work.cell_lights.capacity() * sizeof(KernelCellLight) +
           work.cell_occluders.capacity() * sizeof(std::uint32_t) +
           cells.occluder_discs.capacity() * sizeof(CellListScratch::Disc) +
           (cells.occluder_cells.capacity() + cells.pair_cells.capacity()) * sizeof(unsigned) +
           (scratch_floats + 16) * sizeof(float);
  }

  // A tile past the reserved bound grows the scratch by half again.
  float* kernel_scratch(std::size_t floats) {
    if (floats > scratch_floats) allocate_kernel_scratch(floats + floats / 2);
    return aligned;
  }
  void allocate_kernel_scratch(std::size_t floats) {
    scratch_floats = floats;
    // Not zeroed (the kernel writes before it reads): pages of a reservation no tile needs
    // are never touched.
    scratch.reset(new float[scratch_floats + 16]);
    const auto address = reinterpret_cast<std::uintptr_t>(scratch.get());
    aligned = scratch.get() + ((64 - address % 64) % 64) / sizeof(float);
  }
};

namespace {

// Progress and cancellation of one frame (FrameControl). Unwatched (no control), the engine
// asks nothing of it per tile.
class FrameProgress {
 public:
  FrameProgress(const FrameControl* control, std::uint64_t tiles) noexcept
      : watched_(control != nullptr), tiles_(tiles), caller_(std::this_thread::get_id()) {
    if (!control) return;
    cancel_ = control->cancel;
    if (control->progress && *control->progress) progress_ = control->progress;
  }
  bool watched() const noexcept { return watched_; }
  // Whether tiles not yet begun are to be skipped.
  bool stopped() const noexcept {
    return stop_.load(std::memory_order_relaxed) || (cancel_ && cancel_->load(std::memory_order_relaxed));
  }
  // After a tile: counted, and reported from the calling thread (its own counts rise, so the
  // reports do too).
  void tile_finished() {
    const std::uint64_t done = tiles_done_.fetch_add(1, std::memory_order_relaxed) + 1;
    if (!progress_ || std::this_thread::get_id() != caller_) return;
    reported_ = done;
    if (!(*progress_)(Progress{done, tiles_})) stop_.store(true, std::memory_order_relaxed);
  }
  // A frame with no block to compute: one report of nothing.
  void report_empty() const {
    if (progress_) (*progress_)(Progress{0, 0});
  }
  // After the frame: false when tiles were skipped; else the last report, if the calling
  // thread's own was not.
  bool finish() const {
    if (!watched_) return true;
    const std::uint64_t done = tiles_done_.load();
    if (done < tiles_) return false;
    if (progress_ && reported_ < done) (*progress_)(Progress{done, tiles_});
    return true;
  }

 private:
  bool watched_;
  std::uint64_t tiles_;
  std::thread::id caller_;
  const ProgressFunction* progress_ = nullptr;
  const std::atomic<bool>* cancel_ = nullptr;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> tiles_done_{0};
  std::uint64_t reported_ = 0;  // the calling thread's last report
};

}  // namespace

// What every lane reads while it runs a plan's blocks.
struct FrameRun {
  const FramePlan& plan;
  const PreparedScene& scene;
  const FrameTarget& target;
  VectorTileStores stores;    // the plan's ISA's, for the target's format
  const BounceFrame* bounce;  // the bounce stage's pieces (plan.bounce.run)
  const BounceNodes* nodes;   // the coarse bounce's nodes (a step above 1), else null
  FrameProgress& progress;
};

namespace {

// Calls direct(tile, part, t) for the tiles of `block` that meet its part and the region (part:
// the tile's pixels inside the region; t: the tile's number in the block, row by row), counting
// them; `direct` leaves the tile's direct light in the lane's result. Then the frame's stages
// after it: the bounce term, the store into the target, progress.
template <class Direct>
void for_each_tile(const FrameRun& run, const PlannedBlock& block, FrameLane& lane, Direct&& direct) {
  const FramePlan& plan = run.plan;
  const TileRect& region = plan.region;
  FrameCounters& counts = lane.counts;
  const TileRect wanted{std::max(block.part.x0, region.x0), std::max(block.part.y0, region.y0),
                        std::min(block.part.x1, region.x1), std::min(block.part.y1, region.y1)};
  for_each_cell(block.rect, kTileSize, [&](const TileRect& tile) {
    if (tile.x1 <= wanted.x0 || wanted.x1 <= tile.x0 || tile.y1 <= wanted.y0 || wanted.y1 <= tile.y0) return;
    const TileRect part{std::max(tile.x0, region.x0), std::max(tile.y0, region.y0), std::min(tile.x1, region.x1),
                        std::min(tile.y1, region.y1)};
    if (run.progress.watched() && run.progress.stopped()) return;
    ++counts.tiles;
    counts.pixels += static_cast<std::uint64_t>(part.x1 - part.x0) * static_cast<std::uint64_t>(part.y1 - part.y0);
    direct(tile, part, (tile.y0 - block.rect.y0) / kTileSize * kBlockTiles + (tile.x0 - block.rect.x0) / kTileSize);
    if (plan.bounce.run)
      add_bounce_tile(run.scene, *run.bounce, run.nodes, plan.spp, plan.shaded, plan.bounce.cull, tile, part,
                      lane.bounce, lane.result, counts);
    store_tile(lane.result, tile.x0, tile.y0, part, run.target, run.stores);
    if (run.progress.watched()) run.progress.tile_finished();
  });
}

// The block's culling (gather_block_candidates with the plan's reach), counted. `skip`: per
// scene light, 1 where the light-layer cache holds it (`skipped` of them), or null.
void cull_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane, const unsigned char* skip,
                std::uint64_t skipped) {
  const std::uint64_t tried = lane.setup.occlusion.proofs_tried;
  const std::uint64_t succeeded = lane.setup.occlusion.proofs_succeeded;
  gather_block_candidates(run.scene, block.rect, run.plan.cull_reach, lane.setup, skip);
  count_block(run.scene, lane.setup, tried, succeeded, skipped, lane.counts);
}

// The block strategies (BlockStrategy), one function each.

void kernel_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  const FramePlan& plan = run.plan;
  const bool cull = plan.cull_reach != nullptr;
  cull_block(run, block, lane, nullptr, 0);
  for_each_tile(run, block, lane, [&](const TileRect& tile, const TileRect& part, int) {
    build_tile_work(run.scene, tile, plan.spp, cull, lane.work, lane.setup, plan.shaded);
    build_cell_lists(run.scene, tile, plan.kernels->lanes, lane.setup, lane.work, lane.cells);
    if (plan.sample_needs) sample_needs(run.scene, part, lane.setup, lane.scalar, lane.counts);
    lane.run(lane.work, lane.result);
  });
}

void layered_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  const FramePlan& plan = run.plan;
  const bool cull = plan.cull_reach != nullptr;
  std::vector<LightLayer>& layers = plan.layers->block(block.index);
  start_layered_block(run.scene.lights.size(), layers, lane.layered);
  std::uint64_t skipped = 0;
  for (const unsigned char s : lane.layered.skip) skipped += s;
  cull_block(run, block, lane, lane.layered.skip.data(), skipped);
  for_each_tile(run, block, lane, [&](const TileRect& tile, const TileRect& part, int t) {
    build_tile_work(run.scene, tile, plan.spp, cull, lane.work, lane.setup, plan.shaded);
    if (plan.sample_needs) sample_needs(run.scene, part, lane.setup, lane.scalar, lane.counts);
    render_layered_tile(run.scene, tile, t, *plan.kernels, block.fill_layers, plan.layers->layer_floats(), lane.work,
                        lane.setup, lane.cells, layers, lane.layered, lane, lane.result, lane.counts);
  });
  if (block.fill_layers) plan.layers->finish_block(block.index);
}

void recombine_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  const std::vector<LightLayer>& layers = run.plan.layers->block(block.index);
  for_each_tile(run, block, lane, [&](const TileRect&, const TileRect&, int t) {
    recombine_tile(run.scene, layers, t, *run.plan.kernels, lane.result, lane.counts);
  });
}

void scalar_reference_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  for_each_tile(run, block, lane, [&](const TileRect& tile, const TileRect& part, int) {
    ++lane.counts.scalar_tiles;
    render_tile_scalar(run.scene, run.plan.spp, part, tile.x0, tile.y0, lane.scalar, lane.result, run.plan.shaded);
  });
}

void no_direct_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  for_each_tile(run, block, lane, [&](const TileRect&, const TileRect&, int) {
    for (auto& channel : lane.result.rgb) std::fill(std::begin(channel), std::end(channel), 0.0f);
  });
}

// The one place a block's strategy is dispatched.
void run_block(const FrameRun& run, const PlannedBlock& block, FrameLane& lane) {
  switch (block.strategy) {
    case BlockStrategy::kernel: return kernel_block(run, block, lane);
    case BlockStrategy::layered: return layered_block(run, block, lane);
    case BlockStrategy::recombine: return recombine_block(run, block, lane);
    case BlockStrategy::scalar_reference: return scalar_reference_block(run, block, lane);
    case BlockStrategy::no_direct: return no_direct_block(run, block, lane);
  }
}

}  // namespace

FrameEngine::FrameEngine() = default;
FrameEngine::~FrameEngine() = default;
FrameEngine::FrameEngine(FrameEngine&&) noexcept = default;
FrameEngine& FrameEngine::operator=(FrameEngine&&) noexcept = default;

bool FrameEngine::run(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler,
                      const FrameTarget& target, FrameCounters* counts, const FrameControl* control) {
  FrameProgress progress(control, plan.tiles);
  if (plan.blocks.empty()) {  // an incremental frame in which nothing changed
    if (counts) *counts = FrameCounters{};
    progress.report_empty();
    return true;
  }
  if (progress.watched() && progress.stopped()) return false;
  const int lanes = reserve_lanes(plan, scene, scheduler);
  const bool coarse = plan.bounce.run && scene.bounce_step > 1;
  node_counts_ = FrameCounters{};
  if (plan.bounce.run)
    run_bounce_stage(scene, scheduler, lanes, plan.bounce.cull,
                     plan.bounce.cull && plan.cull_reach ? plan.cull_reach->data() : nullptr);
  if (coarse) run_bounce_nodes(plan, scene, scheduler, lanes);
  const FrameRun run{plan, scene, target, stores_for(plan, target), bounce_.get(), coarse ? bounce_nodes_.get() : nullptr,
                     progress};
  run_lanes(run, scheduler, lanes);
  if (plan.layers) plan.layers->finish_frame();
  if (!progress.finish()) return false;
  if (counts) {
    *counts = sum_counters(plan, lanes);
    *counts += node_counts_;
  }
  return true;
}

// One lane per worker, each with its own buffers; the lanes take the plan's blocks one at a
// time as they finish the last (deal_indices), so the frame ends within one block of perfect
// balance (lanes given fixed shares of the blocks left one thread idle for up to a share at
// the end of a frame).
// Buffers are reserved for the scene's counts, not grown to each block's need: whichever lane
// a block falls to, a frame then allocates nothing wherever the lights move (changed counts, a
// light or occluder with more vertices than before, or a new size may allocate, and a tile
// past the kernel scratch's cap grows it in the lane it falls to).
int FrameEngine::reserve_lanes(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler) {
  const int lanes = std::min(static_cast<int>(plan.blocks.size()), scheduler.workers());
  if (lanes_.size() < static_cast<std::size_t>(lanes)) lanes_.resize(static_cast<std::size_t>(lanes));
  if (!plan.kernels) return lanes;
  const SceneBounds bounds = scene_bounds(scene);
  for (int l = 0; l < lanes; ++l) {
    FrameLane& lane = lanes_[static_cast<std::size_t>(l)];
    if (lane.setup.reserved != bounds) lane.reserve_for(bounds, plan.kernels->lanes);
    // A tile copies each overlap's points at most once (SceneBounds::overlap_points): room
    // for twice that when it grows past it, so that the overlaps' pool growing a little
    // does not make every lane reallocate.
    if (lane.work.point_x.capacity() < bounds.overlap_points) {
      lane.work.point_x.reserve(2 * bounds.overlap_points);
      lane.work.point_y.reserve(2 * bounds.overlap_points);
    }
  }
  return lanes;
}

// The pieces' radiances first (they depend on every light and occluder), lane by lane.
void FrameEngine::run_bounce_stage(const PreparedScene& scene, const Scheduler& scheduler, int lanes, bool cull,
                                   const LightReach* reach) {
  const ReachHidesLights reach_test(reach);
  const LightHiddenTest* hidden = reach ? &reach_test : nullptr;
  if (!bounce_) bounce_ = std::make_unique<BounceFrame>();
  build_bounce_sources(scene, *bounce_);
  // Each piece's radiance depends on that piece alone: the stage in parts taken by the lanes.
  const std::size_t pieces = bounce_->pieces.size();
  const std::size_t parts = std::min(pieces, static_cast<std::size_t>(kBouncePartsPerLane) * static_cast<std::size_t>(lanes));
  deal_indices(scheduler, lanes, parts, [&](int lane, std::size_t part) {
    const std::size_t lo = pieces * part / parts, hi = pieces * (part + 1) / parts;
    bounce_radiances(scene, *bounce_, lo, hi, lanes_[static_cast<std::size_t>(lane)].scalar, cull, hidden);
  });
  finish_bounce_frame(*bounce_);
}

// The coarse bounce's nodes for every pixel the plan's blocks store, in groups dealt to lanes
// like blocks; their counts kept apart (run_lanes starts the lanes' counts afresh).
void FrameEngine::run_bounce_nodes(const FramePlan& plan, const PreparedScene& scene, const Scheduler& scheduler,
                                   int lanes) {
  if (!bounce_nodes_) bounce_nodes_ = std::make_unique<BounceNodes>();
  TileRect area{plan.region.x1, plan.region.y1, plan.region.x0, plan.region.y0};
  for (const PlannedBlock& block : plan.blocks) {
    area.x0 = std::min(area.x0, std::max(block.part.x0, plan.region.x0));
    area.y0 = std::min(area.y0, std::max(block.part.y0, plan.region.y0));
    area.x1 = std::max(area.x1, std::min(block.part.x1, plan.region.x1));
    area.y1 = std::max(area.y1, std::min(block.part.y1, plan.region.y1));
  }
  if (area.x1 <= area.x0 || area.y1 <= area.y0) return;
  const int groups = plan_bounce_nodes(scene, area, *bounce_nodes_);
  std::vector<FrameCounters> counts(static_cast<std::size_t>(lanes));
  deal_indices(scheduler, lanes, static_cast<std::size_t>(std::max(groups, 0)), [&](int l, std::size_t g) {
    compute_bounce_nodes(scene, *bounce_, plan.shaded, plan.bounce.cull, *bounce_nodes_, static_cast<int>(g),
                         lanes_[static_cast<std::size_t>(l)].bounce, counts[static_cast<std::size_t>(l)]);
  });
  for (const FrameCounters& c : counts) node_counts_ += c;
}

// The plan's ISA's vector stores (none for the scalar reference), with the sRGB buckets of the
// target's exposure.
VectorTileStores FrameEngine::stores_for(const FramePlan& plan, const FrameTarget& target) {
  if (!plan.kernels) return {};
  VectorTileStores stores = plan.kernels->stores;
  if (pixel_format_info(target.format)->srgb8) {
    if (srgb_.exposure != target.exposure || srgb_.below.empty()) build_srgb_buckets(target.exposure, srgb_);
    stores.srgb = &srgb_;
  }
  return stores;
}

void FrameEngine::run_lanes(const FrameRun& run, const Scheduler& scheduler, int lanes) {
  for (int l = 0; l < lanes; ++l) {  // before any lane starts: a lane may take no block at all
    FrameLane& lane = lanes_[static_cast<std::size_t>(l)];
    lane.kernels = run.plan.kernels;
    lane.counts = FrameCounters{};
    lane.setup.clear_counts();
  }
  deal_indices(scheduler, lanes, run.plan.blocks.size(), [&](int l, std::size_t b) {
    if (run.progress.watched() && run.progress.stopped()) return;
    run_block(run, run.plan.blocks[b], lanes_[static_cast<std::size_t>(l)]);
  });
  for (int l = 0; l < lanes; ++l) {
    FrameLane& lane = lanes_[static_cast<std::size_t>(l)];
    lane.counts += lane.setup.counts();
  }
}

FrameCounters FrameEngine::sum_counters(const FramePlan& plan, int lanes) const {
  FrameCounters sum;
  for (int l = 0; l < lanes; ++l) sum += lanes_[static_cast<std::size_t>(l)].counts;
  if (plan.bounce.run) {
    sum.bounce_pieces = bounce_->pieces.size();
    for (const BounceSource& source : bounce_->sources) sum.bounce_lit_sources += source.lit ? 1u : 0u;
  }
  return sum;
}

}  // namespace par2d::detail
