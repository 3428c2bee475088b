// Every count a frame keeps, per lane: filled where the work is done (the frame driver, block
// culling, pair setup, the occlusion proofs), summed with +=, and turned into the public
// FrameStats and FrameDiagnostics in one place (to_frame_report), so a new counter leaves the
// public API alone.
#pragma once

#include <cstdint>

#include "par2d/render.hpp"

namespace par2d::detail {

// Counting costs a few additions per block and tile, so it is always on. The meanings are
// FrameStats' and FrameDiagnostics'; the fields that differ say how they map.
struct FrameCounters {
  // Blocks (frame_driver.cpp).
  std::uint64_t blocks = 0;
  std::uint64_t block_lights = 0;
  std::uint64_t block_lights_out_of_reach = 0;
  std::uint64_t block_candidates = 0;
  std::uint64_t block_proofs_tried = 0;
  std::uint64_t block_proofs_succeeded = 0;
  // The adaptive proof rule (block_culling.cpp).
  std::uint64_t block_proofs_skipped = 0;
  std::uint64_t tile_proofs_skipped = 0;
  // Occlusion proofs over blocks and tiles together (OcclusionProofScratch's own counts);
  // FrameDiagnostics' tile proofs are these less the block proofs.
  std::uint64_t proofs_tried = 0;
  std::uint64_t proofs_succeeded = 0;
  // Pair setup (pair_setup.cpp).
  std::uint64_t umbra_tests = 0;
  std::uint64_t umbra_hits = 0;
  std::uint64_t tile_pairs_outside_hull = 0;
  // Tiles and the kernel's work (frame_driver.cpp).
  std::uint64_t pixels = 0;
  std::uint64_t samples = 0;
  std::uint64_t tiles = 0;
  std::uint64_t tile_lights = 0;
  std::uint64_t tile_pairs = 0;
  std::uint64_t tile_general_pairs = 0;
  std::uint64_t light_samples = 0;
  std::uint64_t pair_samples = 0;
  std::uint64_t scalar_tiles = 0;
  // The light-layer cache (layered_tiles.cpp): (tile, light) shares added from a layer, and
  // those computed alone to be stored.
  std::uint64_t layer_tiles_reused = 0;
  std::uint64_t layer_tiles_filled = 0;
  // One exact pixel per tile (FrameSettings::sample_needs; frame_driver.cpp).
  std::uint64_t sampled_pixels = 0;
  std::uint64_t sampled_visible_lights = 0;
  std::uint64_t sampled_blocking_pairs = 0;
  // One bounce (bounce_tiles.cpp; the frame's pieces and lit sources by frame_driver.cpp).
  std::uint64_t bounce_pieces = 0;
  std::uint64_t bounce_lit_sources = 0;
  std::uint64_t bounce_tile_sources = 0;
  std::uint64_t bounce_tile_sources_hidden = 0;
  std::uint64_t bounce_source_walks = 0;
  std::uint64_t bounce_depth_tests = 0;

  FrameCounters& operator+=(const FrameCounters& o) noexcept {
    blocks += o.blocks;
    block_lights += o.block_lights;
    block_lights_out_of_reach += o.block_lights_out_of_reach;
    block_candidates += o.block_candidates;
    block_proofs_tried += o.block_proofs_tried;
    block_proofs_succeeded += o.block_proofs_succeeded;
    block_proofs_skipped += o.block_proofs_skipped;
    tile_proofs_skipped += o.tile_proofs_skipped;
    proofs_tried += o.proofs_tried;
    proofs_succeeded += o.proofs_succeeded;
    umbra_tests += o.umbra_tests;
    umbra_hits += o.umbra_hits;
    tile_pairs_outside_hull += o.tile_pairs_outside_hull;
    pixels += o.pixels;
    samples += o.samples;
    tiles += o.tiles;
    tile_lights += o.tile_lights;
    tile_pairs += o.tile_pairs;
    tile_general_pairs += o.tile_general_pairs;
    light_samples += o.light_samples;
    pair_samples += o.pair_samples;
    scalar_tiles += o.scalar_tiles;
    layer_tiles_reused += o.layer_tiles_reused;
    layer_tiles_filled += o.layer_tiles_filled;
    sampled_pixels += o.sampled_pixels;
    sampled_visible_lights += o.sampled_visible_lights;
    sampled_blocking_pairs += o.sampled_blocking_pairs;
    bounce_pieces += o.bounce_pieces;
    bounce_lit_sources += o.bounce_lit_sources;
    bounce_tile_sources += o.bounce_tile_sources;
    bounce_tile_sources_hidden += o.bounce_tile_sources_hidden;
    bounce_source_walks += o.bounce_source_walks;
    bounce_depth_tests += o.bounce_depth_tests;
    return *this;
  }
};
// A new field must be added above too.
static_assert(sizeof(FrameCounters) == 33 * sizeof(std::uint64_t), "FrameCounters::operator+= adds every field");

// The public report of a frame's counts: the one place FrameCounters map to FrameStats (what a
// host reads) and FrameDiagnostics (what the algorithm did).
inline void to_frame_report(const FrameCounters& c, FrameStats& s, FrameDiagnostics& d) noexcept {
  s = FrameStats{};
  s.pixels = c.pixels;
  s.tiles = c.tiles;
  s.layer_tiles_reused = c.layer_tiles_reused;
  s.layer_tiles_filled = c.layer_tiles_filled;
  s.bounce_pieces = c.bounce_pieces;
  s.bounce_lit_sources = c.bounce_lit_sources;
  d = FrameDiagnostics{};
  d.samples = c.samples;
  d.blocks = c.blocks;
  d.block_lights = c.block_lights;
  d.block_lights_out_of_reach = c.block_lights_out_of_reach;
  d.block_candidates = c.block_candidates;
  d.block_proofs_tried = c.block_proofs_tried;
  d.block_proofs_succeeded = c.block_proofs_succeeded;
  d.block_proofs_skipped = c.block_proofs_skipped;
  d.tile_lights = c.tile_lights;
  d.tile_pairs = c.tile_pairs;
  d.tile_general_pairs = c.tile_general_pairs;
  d.tile_proofs_tried = c.proofs_tried - c.block_proofs_tried;
  d.tile_proofs_succeeded = c.proofs_succeeded - c.block_proofs_succeeded;
  d.tile_proofs_skipped = c.tile_proofs_skipped;
  d.umbra_tests = c.umbra_tests;
  d.umbra_hits = c.umbra_hits;
  d.tile_pairs_outside_hull = c.tile_pairs_outside_hull;
  d.light_samples = c.light_samples;
  d.pair_samples = c.pair_samples;
  d.scalar_tiles = c.scalar_tiles;
  d.sampled_pixels = c.sampled_pixels;
  d.sampled_visible_lights = c.sampled_visible_lights;
  d.sampled_blocking_pairs = c.sampled_blocking_pairs;
  d.bounce_tile_sources = c.bounce_tile_sources;
  d.bounce_tile_sources_hidden = c.bounce_tile_sources_hidden;
  d.bounce_source_walks = c.bounce_source_walks;
  d.bounce_depth_tests = c.bounce_depth_tests;
}
// Every public count is mapped above: the two reports hold the 33 counts less the two proof
// totals, plus the two tile proof counts derived from them.
static_assert(sizeof(FrameStats) + sizeof(FrameDiagnostics) == sizeof(FrameCounters),
              "to_frame_report maps every count");

}  // namespace par2d::detail
