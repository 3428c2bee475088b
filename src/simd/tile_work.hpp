// What a SIMD tile kernel reads: the tile's shapes in float, relative to the tile origin.
//
// Layout. Every coordinate is world minus the tile origin (the world position of the
// tile's top-left pixel corner), computed in double and only then rounded to float, so
// precision depends on distances inside the tile's neighbourhood, never on how far the
// view is from the world origin (docs/contract.md section 5).
// Shapes are plain arrays of structs: the kernel broadcasts one shape's numbers to all
// lanes and evaluates it for a packet of pixels (the lanes) at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "lighting/cookie_segments.hpp"

namespace par2d::detail {

// Tiles are kTileSize x kTileSize pixels: a multiple of every SIMD width; large enough to
// amortize the per-tile culling, small enough that culling stays tight and every thread
// gets many tiles (16 px cost fewer instructions than 32 px on the example scenes:
// docs/performance.md).
inline constexpr int kTileSize = 16;
inline constexpr std::size_t kTilePixels = static_cast<std::size_t>(kTileSize) * kTileSize;

// One shape for the kernel. Polygons and segments use vertices [first, first + count)
// of TileWork::vx/vy; polygons also edge lines [first, first + count) of
// TileWork::edge_* (edge i runs from vertex i to i+1; inside is edge_nx*x + edge_ny*y >=
// edge_c for every edge, with unit normals so the value is a signed distance).
// Circles: center (cx, cy) and radius r; (px, py) is the circle point nearest the tile
// and (ux, uy) the outward unit normal there, for a cancellation-free inside test:
// |x - c|^2 - r^2 = |q|^2 - 2 r (u . q) with q = p - x small near the tile.
struct KernelShape {
  ShapeKind kind = ShapeKind::polygon;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  bool may_contain = true;  // polygons: whether the tile meets the bounding box (else skip the inside test)
  bool ordered = false;     // segments: vertex first is the clockwise tangent over the whole tile (a tile tangent pair)
  // Segment lights: a sample on the segment (within kOnBoundary, simd/tile_kernel.hpp) is in it,
  // as a polygon edge's is; an occluder segment has no interior for the kernel.
  bool closed = false;
  // Polygons: a vertex so sharp that the inside test must look at the edges, not only at
  // their lines (render/kernel_shapes.cpp, vertex_tangents in simd/tile_kernel.hpp).
  bool sharp = false;
  // Occluders whose arcs the kernel takes and lights with pairs, in plain (not game-model)
  // tiles (assign_arc_window in render/kernel_shapes.cpp): every direction from a tile sample to a
  // point whose angle the kernel takes (a polygon's or segment's vertices, a circle's
  // center) lies within atan(0.875), 41 degrees, of direction `window` * 45 degrees
  // (kWindowX/Y below; -1: none). The kernel then takes each arc end's angle from that
  // direction by one division and the atan polynomial, without atan2's octant selects; a
  // polygon or segment so placed holds no sample (its vertices' box misses them). One byte,
  // in what was padding: a bigger shape measured slower with AVX-512.
  std::int8_t window = -1;
  // Ordered segments: their two ends again (as in vx/vy), read by the kernel from here: a
  // shape-major loop then keeps them in registers, where it must reload vx/vy after each
  // vector store (a vector store may alias any float).
  float end_x[2] = {0, 0}, end_y[2] = {0, 0};
  float cx = 0, cy = 0, r = 0;
  float px = 0, py = 0, ux = 0, uy = 0;
  // Lights only: the part with clip_nx*x + clip_ny*y <= clip_c (an occluder overlapping the
  // light holds the rest, see clip_light_by_occluder in world/prepared_scene.cpp). The arc's
  // ends are the light's tangent points where they lie on that side, else the chord's ends,
  // where the line crosses the light's boundary.
  bool clipped = false;
  float clip_nx = 0, clip_ny = 0, clip_c = 0;
  float chord_x[2] = {0, 0}, chord_y[2] = {0, 0};
};

// The arc windows' directions k * 45 degrees (KernelShape::window), unnormalized, and their angles.
inline constexpr float kWindowX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
inline constexpr float kWindowY[8] = {0, 1, 1, 1, 0, -1, -1, -1};
inline constexpr float kWindowAngle[8] = {0.0f,        0.785398163f, 1.57079633f, 2.35619449f,
                                          3.14159265f, 3.92699082f,  4.71238898f, 5.49778714f};

// An occluder in front of a light for some pixels of the tile: in front where
// nx*x + ny*y >= c (the occluder's side of a line separating the two shapes).
// A pair in front for the whole tile has `front` set (and nx = ny = 0, c = -1).
// A `general` pair has no separating line (the shapes overlap or touch): which of the two
// a ray meets first can change only at the directions of the points where their
// boundaries meet, points [first_point, first_point + point_count) of
// TileWork::point_x/point_y, so the kernel cuts the occluder's arc there and decides each
// piece by a depth test along its middle direction. Both shapes of a general pair are
// given whole (never reduced to a tile tangent pair), since the depth test needs them.
struct KernelPair {
  std::uint32_t occluder = 0;  // index into TileWork::occluders
  float nx = 0, ny = 0, c = 0;
  std::uint32_t first_point = 0;
  std::uint32_t point_count = 0;
  bool general = false;
  bool front = false;
};

struct KernelLight {
  KernelShape shape;
  float emission[3] = {0, 0, 0};  // already divided by 2*pi
  std::uint32_t first_pair = 0;   // pairs [first_pair, first_pair + pair_count)
  std::uint32_t pair_count = 0;
  // Blocked intervals the pairs can add to the light's union: 1 per separated pair,
  // point_count + 1 per general pair.
  std::uint32_t interval_count = 0;
};

// A light (clipped or whole) whose only pair in the tile is a disjoint occluder: a plain one-sample tile
// without cells computes its share shape-major (tile_single_pair_lights in the kernel), and
// the occluder's arc is not needed for it.
inline bool single_pair_light(const KernelPair* pairs, std::size_t pair_count) noexcept {
  return pair_count == 1 && !pairs[0].general;
}

// A light's game-model terms (docs/contract.md section 6) for the model kernel, parallel to
// TileWork::lights. Angles are ray directions in radians.
struct KernelLightTerms {
  // A directional light: the fixed arc [dir_start, dir_start + dir_width] at infinity (the
  // light's shape is unused; every pair is in front wherever its occluder is seen).
  bool directional = false;
  float dir_start = 0, dir_width = 0;
  bool ranged = false;
  float range = 0;  // in tile frame units when ranged (may round to 0: range_window copes)
  float falloff = 2;  // the window's exponent
  bool cone = false;
  double cone_center = 0, cone_half = 0, cone_fade = 0;
  // The light's cookie (the prepared scene's; it outlives the tile work), or null.
  const detail::CookieSegments* cookie = nullptr;
  // Some direction weighs less than another (a cone or a cookie): the shortcuts for a flat
  // profile do not apply.
  bool weighted() const noexcept { return cone || cookie != nullptr; }
  double sin_elevation = 0, cos_elevation = 1;
  bool translucent = false;  // some pair's occluder lets light through (per-piece products needed)
};

// An occluder's game-model terms, parallel to TileWork::occluders.
struct KernelOccluderTerms {
  float transmittance[3] = {0, 0, 0};
  bool opaque = true;
  bool lit_interior = false;
};

// A cell: a rectangle of the tile's packets (TileWork::cell_width x cell_height pixels) with
// its own light list, where a tile sees far more than each of its pixels (rubble: a tile's
// pairs cast shadows on parts of it). Cell lights index TileWork::lights and keep only the
// pairs whose occluder can stand between the cell and the light (cell_lists.cpp); a light
// no occluder can block over the cell keeps no pairs.
struct KernelCellLight {
  std::uint32_t light = 0;       // index into TileWork::lights
  std::uint32_t first_pair = 0;  // pairs [first_pair, first_pair + pair_count) of TileWork::cell_pairs
  std::uint32_t pair_count = 0;
};

// Every cell holds this many pixels (a quarter of a tile), whatever its shape.
inline constexpr int kCellPixels = 64;

// A cell's width for packets of `lanes` lanes: whole packets, at least 8 pixels (8 x 8 cells
// for 4 and 8 lanes, 16 x 4 for 16). One definition for the setup that makes the cells
// (cell_lists.cpp) and the kernel that walks them with compile-time sizes: cells of another
// width would still render right, through the kernel's slower general loop.
constexpr int cell_width_for(int lanes) noexcept { return lanes < 8 ? 8 : (lanes > kTileSize ? kTileSize : lanes); }

struct KernelCell {
  std::uint32_t first_light = 0, light_count = 0;        // TileWork::cell_lights
  std::uint32_t first_occluder = 0, occluder_count = 0;  // TileWork::cell_occluders: the arcs the cell needs
};

struct TileWork {
  int spp = 1;
  // The game lighting model: `model` selects the model kernel (plain scenes never set it).
  bool model = false;
  bool shaded = false;  // per-pixel normals below are in use
  float ambient[3] = {0, 0, 0};
  std::vector<KernelLightTerms> light_terms;
  std::vector<KernelOccluderTerms> occluder_terms;
  // Shading only: the unit normal in world axes (z toward the viewer) of tile pixel (row r,
  // column c), component k, is normal_plane[k][r * normal_stride + c]. A normal map's planes
  // are read in place (padded past the image, see world_normals.hpp); a constant normal is
  // one row of constant_normal with stride 0.
  const float* normal_plane[3] = {nullptr, nullptr, nullptr};
  std::size_t normal_stride = 0;
  alignas(64) float constant_normal[3][kTileSize];
  // Sample positions relative to the tile origin: sample s of the pixel in tile column c
  // is at x = sample_x[s * kTileSize + c], and in tile row r at y = sample_y[s * kTileSize + r].
  // Each is the exact offset of the scalar path's sample (docs/contract.md section 2) from the
  // origin, (c + s) pixel sizes, rounded once to float; the scalar path rounds the same point
  // to double. The offsets are the same for every tile of a frame: build_tile_work makes them
  // again only when what they are made from (sample_grid) changes.
  std::vector<float> sample_x, sample_y;
  struct SampleGrid {
    int spp = 0;
    double pixel_w = 0, pixel_h = 0, scale = 0;
  } sample_grid;
  // The box of the samples above (relative to the tile origin, like them).
  float sample_min_x = 0, sample_max_x = 0, sample_min_y = 0, sample_max_y = 0;
  std::vector<KernelShape> occluders;
  std::vector<KernelLight> lights;
  std::vector<KernelPair> pairs;
  std::vector<float> vx, vy;
  std::vector<float> edge_nx, edge_ny, edge_c;
  std::uint32_t vertex_count = 0;  // entries in use of vx, vy, edge_* (which only grow)
  std::vector<float> point_x, point_y;  // boundary meeting points of general pairs
  std::uint32_t max_intervals_per_light = 0;
  std::uint32_t max_points_per_pair = 0;
  // Cells, row-major over the tile (none: every packet of a plain tile uses the tile's lists;
  // game-model tiles always have cells, see cell_lists.hpp).
  int cell_width = 0, cell_height = 0;
  std::vector<KernelCell> cells;
  std::vector<KernelCellLight> cell_lights;
  std::vector<KernelPair> cell_pairs;
  std::vector<std::uint32_t> cell_occluders;  // indices into occluders

  void clear() noexcept {
    occluders.clear();
    lights.clear();
    light_terms.clear();
    occluder_terms.clear();
    model = false;
    shaded = false;
    pairs.clear();
    vertex_count = 0;
    point_x.clear();
    point_y.clear();
    max_intervals_per_light = 0;
    max_points_per_pair = 0;
    cell_width = cell_height = 0;
    cells.clear();
    cell_lights.clear();
    cell_pairs.clear();
    cell_occluders.clear();
  }
};

// Output of a tile kernel: mean irradiance over the samples for each of the tile's
// pixels (row-major), one plane per channel. Pixels past the image edge are
// computed too (padding instead of scalar tails) and dropped by the caller.
struct TileResult {
  alignas(64) float rgb[3][kTilePixels];
};

// The 8-bit sRGB code of exposure * v for one exposure, looked up on the kernel's float v:
// code(v) = number of k with v >= threshold[k], where threshold[k] is the least float whose
// product with the exposure (in double, as the scalar encoder computes it) reaches the
// linear value at which code k begins. Buckets of width 1 / scale (a power of two, no wider
// than the closest two thresholds, so each holds at most one) answer in two look-ups:
// code = below[b] + (v >= inside[b]) with b = min(floor(v * scale), last). Built per
// exposure by frame_output.cpp (build_srgb_buckets); the codes are stored as floats so
// that both look-ups are float gathers.
struct SrgbBuckets {
  double exposure = 0.0;
  bool valid = false;  // false: exposure outside [2^-20, 2^20], the scalar encoder is used
  float scale = 0.0f;
  int last = 0;
  std::vector<float> below;
  std::vector<float> inside;
};

// Floats of per-packet scratch a kernel of `lanes` lanes needs for this work.
inline std::size_t kernel_packet_scratch_floats(const TileWork& work, int lanes) noexcept {
  std::size_t sort_slots = 1;
  while (sort_slots < work.max_intervals_per_light) sort_slots *= 2;
  std::size_t event_slots = 1;
  while (event_slots < work.max_points_per_pair) event_slots *= 2;
  std::size_t model_floats = 0;
  if (work.model) {
    // Inside flags per occluder, interval owners, and the sorted piece ends with their
    // cumulative profile values (2 per interval plus the arc's ends).
    std::size_t key_slots = 1;
    while (key_slots < 2 * static_cast<std::size_t>(work.max_intervals_per_light) + 2) key_slots *= 2;
    model_floats = work.occluders.size() + 2 * key_slots + sort_slots / 1 + 1;
  }
  return static_cast<std::size_t>(lanes) * (2 * work.occluders.size() + 2 * sort_slots + event_slots + 2 + model_floats);
}

// The plain kernel at one sample per pixel keeps every occluder's arc over the whole tile
// (start and width planes, 2 KiB an occluder; with cells, a cell's pixels at a time) up to
// this many occluders in the tile (8 MiB). A tile with more (a dense level with culling off,
// or thousands of occluders around one tile) computes each packet's arcs in the packet: the
// same arcs, in scratch that does not grow with the tile's pixels.
inline constexpr std::size_t kMaxArcPlaneOccluders = 4096;

inline bool uses_arc_planes(const TileWork& work) noexcept {
  return !work.model && work.spp == 1 && work.occluders.size() <= kMaxArcPlaneOccluders;
}

// Floats of scratch a kernel of `lanes` lanes needs for this work (caller-provided, 64-byte
// aligned, so the kernel never allocates).
inline std::size_t kernel_scratch_floats(const TileWork& work, int lanes) noexcept {
  // With arc planes (uses_arc_planes), those planes and an inside plane ahead of the
  // per-packet scratch, and after it a light index per light and a byte per occluder (the
  // lights its packets compute, and which lights use each occluder, see
  // render_plain_tile_shape_major).
  const std::size_t tile_arcs = !uses_arc_planes(work)
                                    ? 0
                                    : (2 * work.occluders.size() + 1) * kTilePixels + work.lights.size() +
                                          (work.occluders.size() + 3) / 4;
  return tile_arcs + kernel_packet_scratch_floats(work, lanes);
}

}  // namespace par2d::detail
