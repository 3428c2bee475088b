// Shapes as the kernel gets them: the tile's frame (kernel coordinates), shapes clipped near
// the tile, tangent-pair segments, arc windows, and the tile's sample grid.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "par2d/types.hpp"
#include "render/tiling.hpp"
#include "simd/tile_work.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// The tile's pixel rectangle in world coordinates (corners of all its sample positions).
inline std::array<Vec2, 4> tile_corners(const PreparedScene& scene, const TileRect& tile) noexcept {
  const Vec2 a = sample_position(scene, tile.x0, tile.y0, 0.0, 0.0);
  const Vec2 b = sample_position(scene, tile.x1, tile.y1, 0.0, 0.0);
  return {Vec2{a.x, a.y}, Vec2{b.x, a.y}, Vec2{b.x, b.y}, Vec2{a.x, b.y}};
}

inline Aabb bounds_of(const std::array<Vec2, 4>& rect) noexcept {
  return {std::min(rect[0].x, rect[2].x), std::min(rect[0].y, rect[2].y), std::max(rect[0].x, rect[2].x),
          std::max(rect[0].y, rect[2].y)};
}

// Kernel coordinates: world minus the tile origin, times a power of two that makes a pixel
// about one unit. Relative to the origin so float keeps its precision far from the world
// origin; scaled (exactly, by a power of two, the same in x and y so angles do not change)
// so that views of 1e-300 or 1e300 units per pixel neither underflow nor overflow float.
struct TileFrame {
  Vec2 origin;
  double scale = 1.0;
  // Whether some shape may reach 2^18 kernel units from a tile (twice the scene's largest
  // coordinate does): else no shape needs clipping and no pair is decided anew. Much beyond
  // that, float cross products of a pixel with far vertices (~2^36 at 2^18, rounded to 24
  // bits: errors near 2^12) cancel down to the size of what decides the side of an edge for a
  // pixel 0.05 px from it (about 2^14 there): at 5e8 pixels the kernel moved such edges.
  bool far = true;

  // Beyond this, float arithmetic in the kernel could overflow; values are clamped to it
  // (lengths and line offsets keep their sign, points their direction from the tile).
  static constexpr double kLimit = 1e18;

  float length(double v) const noexcept {
    return static_cast<float>(std::clamp(v * scale, -kLimit, kLimit));
  }
  void point(Vec2 p, float& x, float& y) const noexcept { relative(p - origin, x, y); }
  // A vector already relative to the origin (computed by the caller without cancellation).
  void relative(Vec2 v, float& x, float& y) const noexcept {
    double dx = v.x * scale, dy = v.y * scale;
    const double big = std::max(std::abs(dx), std::abs(dy));
    if (big > kLimit) dx *= kLimit / big, dy *= kLimit / big;
    x = static_cast<float>(dx);
    y = static_cast<float>(dy);
  }
  // Offset c of the line through `point` with unit normal n (n.p = c) in kernel
  // coordinates, from the point's position relative to the origin (no cancellation).
  float line_offset(Vec2 normal, Vec2 point) const noexcept { return length(dot(normal, point - origin)); }

};

// A pixel becomes about one unit, whatever the scene's extent: shapes reaching far from
// the tile are first clipped to a box around it (near_shape in kernel_shapes.cpp), so the
// kernel's coordinates stay far inside float's range (it squares them, and the range ends
// near 2^128).
TileFrame tile_frame(const PreparedScene& scene, Vec2 origin) noexcept;

// Half sizes, in kernel units (about pixels), of the boxes around a tile that shapes are
// clipped to. Cutting a shape at distance D turns each direction in which a pixel sees it
// along an edge running out past D by about h / D, h the pixel's distance from that edge's
// line (a half-plane light whose edge passes h from a pixel subtends pi; clipped, pi - 2h/D).
// So the box grows with the shape's distance h from the tile: D = 2^17 (h - tile half
// diagonal), at least 2^18, keeps h / D under 2^-14 (about 1e-5 of the light's emission, a
// tenth of the contract's 1e-4 bound) for the tile's nearest and farthest pixels. A fixed
// 2^18 box put 8 % of a band light's emission at 2^17 pixels out of sight. D can be that
// large because float side tests against vertices at D err by about D^2 2^-24, and the value
// they decide is about h D: the margin h 2^24 / D stays 2^7. The box stops at 2^58 (float
// products of its coordinates, up to 2^116, stay in range); one that misses it lies more than
// 2^58 pixels from the tile.
inline constexpr double kNearHalf = 0x1p18;
inline constexpr double kFarHalf = 0x1p58;
inline constexpr double kBoxPerDistance = 0x1p17;
inline constexpr double kTileHalfDiagonal = 0.7072 * kTileSize;

// A circle of a larger radius (kernel units) is replaced by the circle of this radius with
// the same point nearest the tile and the same normal there: a subset of it that departs from
// it, over the near box, by under 2^40 / 2^60 radians as seen from the tile, and whose
// squared radius float still holds.
inline constexpr double kMaxRadius = 0x1p59;

// Whether the kernel gets `s` changed (near_shape, or a circle's radius capped).
inline bool reaches_far(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  if (!frame.far) return false;
  const double near = kNearHalf / frame.scale;
  if (s.kind == ShapeKind::circle && s.radius * frame.scale > kMaxRadius) return true;
  return !(s.bounds_min.x >= tile_center.x - near && s.bounds_max.x <= tile_center.x + near &&
           s.bounds_min.y >= tile_center.y - near && s.bounds_max.y <= tile_center.y + near);
}

// The shape as the kernel sees it, in double, for a far-reaching shape (reaches_far): its
// part near the tile, or a circle of capped radius with the same point nearest the tile.
const ConvexShape& kernel_view(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center, ConvexShape& out,
                               std::vector<Vec2>& tmp);

// The current block as each of its tiles sees it, set by gather_block_candidates.
struct BlockView {
  // Counts gather_block_candidates calls: per-block cache entries (tangent pairs, grid
  // tangents, umbra bands, separators) carry the serial they were found under, so entries of
  // earlier blocks (or scenes) are found anew on first use.
  std::uint64_t serial = 0;
  Vec2 corners[4];
  int x0 = 0, y0 = 0;  // the block's first pixel column and row
  double frame_scale = 1.0;  // the scene's kernel-unit scale and far flag (TileFrame)
  bool frame_far = true;

  void start(const PreparedScene& scene, const TileRect& block, const std::array<Vec2, 4>& block_corners) noexcept;
};

// Per-thread buffers of the kernel shapes.
struct KernelShapeScratch {
  // Per shape, its tile tangent pair over the whole current block (see kernel_shape in
  // kernel_shapes.cpp), found on the shape's first use in the block: a pair that holds over
  // the block holds over each of its tiles, which then skip the test. cw < 0: none over the
  // block.
  struct BlockTangentPair {
    std::uint64_t block = 0;  // BlockView::serial when found; older entries are stale
    std::int32_t cw = -1, ccw = -1;
  };
  std::vector<BlockTangentPair> light_block_pairs, occluder_block_pairs;
  ConvexShape clipped, clipped_light;  // shapes reaching far from the tile, clipped to a box around it
  std::vector<Vec2> clip_points;       // clip_to_box's buffer

  void start_block(std::size_t lights, std::size_t occluders) {
    light_block_pairs.resize(lights);
    occluder_block_pairs.resize(occluders);
  }
};

// The tile's occluders: each scene occluder a pair uses gets one TileWork::occluders entry,
// in order of first use.
struct TileOccluders {
  std::vector<std::int32_t> local_index;  // occluder -> index in TileWork::occluders, or -1
  std::vector<std::uint32_t> used;        // index in TileWork::occluders -> occluder
  std::vector<unsigned char> used_whole;  // per entry of `used`: in a general pair (kernel shape kept whole)
  std::vector<unsigned char> arc_needed;  // per entry of `used`: some light's packets take its arc

  // Each entry of `used` is a distinct scene occluder: `occluders` entries at most.
  void reserve_for(std::size_t occluders) {
    local_index.assign(occluders, -1);
    used.reserve(occluders);
    used_whole.reserve(occluders);
    arc_needed.reserve(occluders);
  }
  std::size_t reserved_bytes() const noexcept {
    return local_index.capacity() * sizeof(std::int32_t) + used.capacity() * sizeof(std::uint32_t) +
           used_whole.capacity() + arc_needed.capacity();
  }

  // Only the previous tile's entries are reset: a full reset would write 16 KB per tile at
  // 4096 occluders.
  void start_tile(std::size_t occluders) {
    if (local_index.size() != occluders) {
      local_index.assign(occluders, -1);
    } else {
      for (std::uint32_t k : used) local_index[k] = -1;
    }
    used.clear();
    used_whole.clear();
  }
  // Occluder k's index in TileWork::occluders, given one on first use.
  std::int32_t intern(std::uint32_t k) {
    std::int32_t& local = local_index[k];
    if (local < 0) {
      local = static_cast<std::int32_t>(used.size());
      used.push_back(k);
      used_whole.push_back(0);
    }
    return local;
  }
};

// The tile's sample offsets from its origin (TileWork::sample_grid). Inline: its test runs
// once per tile.
inline void fill_sample_grid(const PreparedScene& scene, int spp, const TileFrame& frame, TileWork& work) {
  // A sample's offset from the origin: (c + s) pixel sizes, the same in every tile. Made
  // again only when the sampling, the pixel size or the frame's scale changes (NaN never
  // compares equal, so it would be remade): computing two positions per sample and their
  // difference here, per tile, would be a large part of build_tile_work's time.
  const double pixel_w = (scene.view.x1 - scene.view.x0) / scene.width;
  const double pixel_h = (scene.view.y1 - scene.view.y0) / scene.height;
  TileWork::SampleGrid& samples = work.sample_grid;
  if (samples.spp != spp || samples.pixel_w != pixel_w || samples.pixel_h != pixel_h || samples.scale != frame.scale) {
    samples = {spp, pixel_w, pixel_h, frame.scale};
    work.sample_x.resize(static_cast<std::size_t>(spp) * kTileSize);
    work.sample_y.resize(static_cast<std::size_t>(spp) * kTileSize);
    for (int k = 0; k < spp; ++k) {
      double sx, sy;
      sample_offset(k, spp, sx, sy);
      // Columns and rows past the image edge (padding) get positions too; they are dropped.
      for (int c = 0; c < kTileSize; ++c) {
        work.sample_x[static_cast<std::size_t>(k * kTileSize + c)] = frame.length((c + sx) * pixel_w);
        work.sample_y[static_cast<std::size_t>(k * kTileSize + c)] = frame.length((c + sy) * pixel_h);
      }
    }
    const auto [min_x, max_x] = std::minmax_element(work.sample_x.begin(), work.sample_x.end());
    const auto [min_y, max_y] = std::minmax_element(work.sample_y.begin(), work.sample_y.end());
    work.sample_min_x = *min_x, work.sample_max_x = *max_x;
    work.sample_min_y = *min_y, work.sample_max_y = *max_y;
  }
}

// The kernel shape of `shape` for the tile with these corners, its vertices appended to work.
// `whole`: keep every vertex and edge (a general pair's depth test needs the shape itself).
// `block_pair`: the shape's entry in the scratch's block tangent pairs (null: none).
KernelShape kernel_shape(const ConvexShape& shape, const TileFrame& frame, const std::array<Vec2, 4>& corners,
                         bool whole, TileWork& work, KernelShapeScratch& scratch, const BlockView& block,
                         KernelShapeScratch::BlockTangentPair* block_pair);

// Gives a kernel shape its arc window (KernelShape::window) where one fixed direction holds
// every direction from the tile's samples to it (see kernel_shapes.cpp).
void assign_arc_window(KernelShape& k, const TileWork& work) noexcept;

}  // namespace par2d::detail
