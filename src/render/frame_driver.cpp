// The frame driver: blocks dealt to lanes, lanes to threads, each tile set up, computed by
// the ISA's kernel (or the scalar reference) and stored into the host's format.
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

constexpr int kLanesPerWorker = 4;

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
struct FrameEngine::ThreadState final : TileKernelRunner {
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

FrameEngine::FrameEngine() = default;
FrameEngine::~FrameEngine() = default;
FrameEngine::FrameEngine(FrameEngine&&) noexcept = default;
FrameEngine& FrameEngine::operator=(FrameEngine&&) noexcept = default;

bool FrameEngine::render(const PreparedScene& scene, const std::vector<LightReach>* reach,
                         const FrameSettings& settings, const Scheduler& scheduler, const FrameTarget& target,
                         FrameCounters* frame_counts, const std::vector<std::uint8_t>* dirty, LightLayerCache* layers,
                         const FrameControl* control) {
  const KernelSet* kernels = kernels_for(settings.isa);
  const TileRect& region = target.region;
  // Blocks of the whole frame that meet the region.
  const int bx0 = region.x0 / kBlockSize, bx1 = (region.x1 - 1) / kBlockSize + 1;
  const int by0 = region.y0 / kBlockSize, by1 = (region.y1 - 1) / kBlockSize + 1;
  const int columns = bx1 - bx0;
  const int frame_columns = (scene.width + kBlockSize - 1) / kBlockSize;
  int blocks = columns * (by1 - by0);
  if (!kernels) layers = nullptr;  // the scalar reference computes every light itself
  if (dirty) {  // only the flagged blocks, in the same order
    block_list_.clear();
    for (int b = 0; b < blocks; ++b) {
      const int bx = bx0 + b % columns, by = by0 + b / columns;
      if ((*dirty)[static_cast<std::size_t>(by * frame_columns + bx)]) block_list_.push_back(b);
    }
    blocks = static_cast<int>(block_list_.size());
    if (blocks == 0) {
      if (frame_counts) *frame_counts = FrameCounters{};
      if (control && control->progress && *control->progress) (*control->progress)(Progress{0, 0});
      return true;
    }
  }
  // Progress and cancellation: the tiles that meet the region in the blocks computed.
  const ProgressFunction* progress = control && control->progress && *control->progress ? control->progress : nullptr;
  const std::atomic<bool>* cancel = control ? control->cancel : nullptr;
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> tiles_done{0};
  std::uint64_t tiles_total = 0;
  const std::thread::id caller = std::this_thread::get_id();
  const auto stopped = [&] {
    return stop.load(std::memory_order_relaxed) || (cancel && cancel->load(std::memory_order_relaxed));
  };
  if (control) {
    for (int k = 0; k < blocks; ++k) {
      const int b = dirty ? block_list_[static_cast<std::size_t>(k)] : k;
      const int x0 = std::max((bx0 + b % columns) * kBlockSize, region.x0);
      const int y0 = std::max((by0 + b / columns) * kBlockSize, region.y0);
      const int x1 = std::min((bx0 + b % columns + 1) * kBlockSize, region.x1);
      const int y1 = std::min((by0 + b / columns + 1) * kBlockSize, region.y1);
      tiles_total += static_cast<std::uint64_t>((x1 - 1) / kTileSize - x0 / kTileSize + 1) *
                     static_cast<std::uint64_t>((y1 - 1) / kTileSize - y0 / kTileSize + 1);
    }
    if (stopped()) return false;
  }
  // After a tile: counted, and reported from the calling thread (its own counts rise, so the
  // reports do too).
  std::uint64_t reported = 0;  // the calling thread's last report
  const auto tile_finished = [&] {
    const std::uint64_t done = tiles_done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (!progress || std::this_thread::get_id() != caller) return;
    reported = done;
    if (!(*progress)(Progress{done, tiles_total})) stop.store(true, std::memory_order_relaxed);
  };
  const bool cull = settings.culling && reach != nullptr;
  // RenderOptions::bounce: the bounce term where the scene has one and the options want it;
  // the direct light (kernel or reference, with the ambient) unless only the bounce is asked.
  const bool bouncing = scene.bounce && settings.bounce != BounceTerm::excluded;
  const bool direct = settings.bounce != BounceTerm::only;
  if (!direct) layers = nullptr;
  VectorTileStores stores;
  if (kernels) {
    stores = kernels->stores;
    if (pixel_format_info(target.format)->srgb8) {
      if (srgb_.exposure != target.exposure || srgb_.below.empty()) build_srgb_buckets(target.exposure, srgb_);
      stores.srgb = &srgb_;
    }
  }

  auto render_block = [&](int b, ThreadState& state) {
    if (control && stopped()) return;
    if (dirty) b = block_list_[static_cast<std::size_t>(b)];
    const int x0 = (bx0 + b % columns) * kBlockSize, y0 = (by0 + b / columns) * kBlockSize;
    const TileRect block{x0, y0, std::min(x0 + kBlockSize, scene.width), std::min(y0 + kBlockSize, scene.height)};
    FrameCounters& counts = state.counts;
    const std::size_t frame_block = static_cast<std::size_t>((bx0 + b % columns) + (by0 + b / columns) * frame_columns);
    // Calls fn(tile, part, t) for the block's tiles that meet the region (part: the pixels
    // inside it; t: the tile's number in the block, row by row), counting them.
    const auto for_each_tile = [&](auto&& fn) {
      for_each_cell(block, kTileSize, [&](const TileRect& tile) {
        const TileRect part{std::max(tile.x0, region.x0), std::max(tile.y0, region.y0), std::min(tile.x1, region.x1),
                            std::min(tile.y1, region.y1)};
        if (part.x0 >= part.x1 || part.y0 >= part.y1) return;
        if (control && stopped()) return;
        ++counts.tiles;
        counts.pixels += static_cast<std::uint64_t>(part.x1 - part.x0) * static_cast<std::uint64_t>(part.y1 - part.y0);
        fn(tile, part, (tile.y0 - y0) / kTileSize * kBlockTiles + (tile.x0 - x0) / kTileSize);
        if (control) tile_finished();
      });
    };
    if (layers && layers->recombine_only(frame_block)) {  // every light from its layer: no culling, no kernel
      for_each_tile([&](const TileRect& tile, const TileRect& part, int t) {
        recombine_tile(scene, layers->block(frame_block), t, *kernels, state.result, counts);
        store_tile(state.result, tile.x0, tile.y0, part, target, stores);
      });
      return;
    }
    if (layers) start_layered_block(scene.lights.size(), layers->block(frame_block), state.layered);
    if (kernels && direct) {
      const std::uint64_t tried = state.setup.occlusion.proofs_tried;
      const std::uint64_t succeeded = state.setup.occlusion.proofs_succeeded;
      gather_block_candidates(scene, block, cull ? reach : nullptr, state.setup,
                              layers ? state.layered.skip.data() : nullptr);
      std::uint64_t skipped = 0;
      if (layers)
        for (const unsigned char s : state.layered.skip) skipped += s;
      count_block(scene, state.setup, tried, succeeded, skipped, counts);
    }
    for_each_tile([&](const TileRect& tile, const TileRect& part, int t) {
      if (!direct) {
        for (auto& channel : state.result.rgb) std::fill(std::begin(channel), std::end(channel), 0.0f);
      } else if (!kernels) {  // Isa::scalar: the reference, tile by tile
        ++counts.scalar_tiles;
        render_tile_scalar(scene, settings.spp, part, tile.x0, tile.y0, state.scalar, state.result, settings.shaded);
      } else if (layers) {
        build_tile_work(scene, tile, settings.spp, cull, state.work, state.setup, settings.shaded);
        if (settings.sample_needs) sample_needs(scene, part, state.setup, state.scalar, counts);
        render_layered_tile(scene, tile, t, *kernels, layers->may_fill(frame_block), layers->layer_floats(),
                            state.work, state.setup, state.cells, layers->block(frame_block), state.layered, state,
                            state.result, counts);
      } else {
        build_tile_work(scene, tile, settings.spp, cull, state.work, state.setup, settings.shaded);
        build_cell_lists(scene, tile, kernels->lanes, state.setup, state.work, state.cells);
        if (settings.sample_needs) sample_needs(scene, part, state.setup, state.scalar, counts);
        state.run(state.work, state.result);
      }
      if (bouncing)
        add_bounce_tile(scene, *bounce_, settings.spp, settings.shaded, settings.culling && kernels != nullptr, tile,
                        part, state.bounce, state.result, counts);
      store_tile(state.result, tile.x0, tile.y0, part, target, stores);
    });
    if (layers && layers->may_fill(frame_block)) layers->finish_block(frame_block);
  };

  // Blocks are dealt to lanes (lane l takes blocks l, l + lanes, ...), each lane with its own
  // buffers, and lanes to threads: which buffers serve which block does not depend on the
  // scheduler, so once a frame has sized them, the same frame never needs more (per-thread
  // buffers would meet a new, larger block whenever TBB deals blocks differently). Several
  // lanes per worker keep the load balanced.
  const int lanes = std::min(blocks, kLanesPerWorker * scheduler.workers());
  if (states_.size() < static_cast<std::size_t>(lanes)) states_.resize(static_cast<std::size_t>(lanes));
  // Buffers are reserved for the scene's counts, not grown to each frame's need: a frame then
  // allocates nothing wherever the lights move (changed counts, a light or occluder with more
  // vertices than before, or a new size may allocate).
  if (kernels) {
    const SceneBounds bounds = scene_bounds(scene);
    for (int lane = 0; lane < lanes; ++lane) {
      ThreadState& state = states_[static_cast<std::size_t>(lane)];
      if (state.setup.reserved != bounds) state.reserve_for(bounds, kernels->lanes);
      // A tile copies each overlap's points at most once (SceneBounds::overlap_points): room
      // for twice that when it grows past it, so that the overlaps' pool growing a little
      // does not make every lane reallocate.
      if (state.work.point_x.capacity() < bounds.overlap_points) {
        state.work.point_x.reserve(2 * bounds.overlap_points);
        state.work.point_y.reserve(2 * bounds.overlap_points);
      }
    }
  }
  // The pieces' radiances first (they depend on every light and occluder), lane by lane.
  if (bouncing) {
    if (!bounce_) bounce_ = std::make_unique<BounceFrame>();
    build_bounce_sources(scene, *bounce_);
    const std::size_t pieces = bounce_->pieces.size();
    scheduler.for_each_index(lanes, [&](int lane, int) {
      const std::size_t lo = pieces * static_cast<std::size_t>(lane) / static_cast<std::size_t>(lanes);
      const std::size_t hi = pieces * static_cast<std::size_t>(lane + 1) / static_cast<std::size_t>(lanes);
      bounce_radiances(scene, *bounce_, lo, hi, states_[static_cast<std::size_t>(lane)].scalar);
    });
    finish_bounce_frame(*bounce_);
  }
  scheduler.for_each_index(lanes, [&](int lane, int) {
    ThreadState& state = states_[static_cast<std::size_t>(lane)];
    state.kernels = kernels;
    state.counts = FrameCounters{};
    state.setup.clear_counts();
    for (int b = lane; b < blocks; b += lanes) render_block(b, state);
    state.counts += state.setup.counts();
  });
  if (layers) layers->finish_frame();
  if (control) {
    const std::uint64_t done = tiles_done.load();
    if (done < tiles_total) return false;
    if (progress && reported < done) (*progress)(Progress{done, tiles_total});
  }
  if (!frame_counts) return true;
  FrameCounters sum;
  for (int lane = 0; lane < lanes; ++lane) sum += states_[static_cast<std::size_t>(lane)].counts;
  if (bouncing) {
    sum.bounce_pieces = bounce_->pieces.size();
    for (const BounceSource& source : bounce_->sources) sum.bounce_lit_sources += source.lit ? 1u : 0u;
  }
  *frame_counts = sum;
  return true;
}

}  // namespace par2d::detail
