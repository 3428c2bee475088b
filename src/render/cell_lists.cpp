// Light lists per cell of a tile: see cell_lists.hpp.
#include "render/cell_lists.hpp"

#include <algorithm>
#include <cmath>

#include "render/tile_setup.hpp"

namespace par2d::detail {
namespace {

CellListScratch::Disc bounding_disc(const ConvexShape& s) noexcept { return {s.centroid, centroid_radius(s)}; }

// Where an occluder can block a light: a ray from x meets the occluder at o before it reaches
// the light at l only if o lies on the segment [x, l], so x = o + t (o - l), t >= 0. With both
// shapes in discs that are apart, every such x lies in the cone from the discs' inner
// homothetic center p (on the segment between their centers, where the inner common
// tangents cross) opening through the occluder's disc: o - p and p - l both lie in that cone
// (it is convex and closed under sums), and so does x - p = (1 + t)(o - p) + t (p - l).
// The cone is the two half-planes inside the inner tangents; a cell wholly outside one of
// them gets no blocked direction from the pair.
struct ShadowCone {
  bool bounded = false;  // false: the discs meet, the pair may block anywhere
  Vec2 apex;
  Vec2 normal[2];  // inward normals of the two tangents
  double margin = 0.0;
};

ShadowCone shadow_cone(const CellListScratch::Disc& light, const CellListScratch::Disc& occluder) noexcept {
  ShadowCone cone;
  const Vec2 axis = occluder.center - light.center;
  const double distance = std::sqrt(dot(axis, axis));
  const double radii = light.radius + occluder.radius;
  if (!(distance > radii * (1.0 + 1e-9))) return cone;
  const Vec2 u = (1.0 / distance) * axis;
  const double s = radii / distance;  // sine of the cone's half angle
  const double c = std::sqrt(std::max(0.0, 1.0 - s * s));
  cone.bounded = true;
  cone.apex = light.center + (light.radius / radii) * axis;
  // The tangents' directions are u turned by +-asin(s); their normals turned toward u.
  cone.normal[0] = Vec2{s * u.x + c * u.y, s * u.y - c * u.x};
  cone.normal[1] = Vec2{s * u.x - c * u.y, c * u.x + s * u.y};
  // Rounding in the cone's few operations stays far below this (coordinates are near the
  // view: culling_trusted).
  cone.margin = 1e-9 * (std::abs(cone.apex.x) + std::abs(cone.apex.y) + distance + radii);
  return cone;
}

// The cells wholly outside the cone (bit c: cell c, of `columns` x `rows` in row order). A
// cell's box, centre x and half extents `half` (the same for every cell), lies outside the
// half-plane of inward normal n when n.(x - apex) + |n.x| half.x + |n.y| half.y < -margin.
// The centres are the first cell's plus whole steps (a few pixels) along x and y, so the
// test is one dot product per normal and an addition per cell: the steps' rounding stays
// far below the margin, as does that of x - apex itself.
struct CellGrid {
  Vec2 first_center, step, half;  // step: from a cell's centre to the next column's (x), row's (y)
  int columns = 1, rows = 1;
};

unsigned cells_outside_cone(const ShadowCone& cone, const CellGrid& grid) noexcept {
  unsigned outside = 0;
  for (const Vec2 n : cone.normal) {
    const double first = dot(n, grid.first_center - cone.apex) + std::abs(n.x) * grid.half.x +
                         std::abs(n.y) * grid.half.y + cone.margin;
    const double along_x = n.x * grid.step.x, along_y = n.y * grid.step.y;
    if (grid.columns == 2 && grid.rows == 2) {  // 4 and 8 lanes
      outside |= static_cast<unsigned>(first < 0.0) | static_cast<unsigned>(first + along_x < 0.0) << 1 |
                 static_cast<unsigned>(first + along_y < 0.0) << 2 |
                 static_cast<unsigned>(first + along_x + along_y < 0.0) << 3;
      continue;
    }
    int c = 0;
    for (int y = 0; y < grid.rows; ++y) {
      const double row = first + y * along_y;
      for (int x = 0; x < grid.columns; ++x, ++c) outside |= static_cast<unsigned>(row + x * along_x < 0.0) << c;
    }
  }
  return outside;
}

// The tile's own lists as one cell over the whole tile: the model kernel always reads cells
// (one copy of it per ISA and shading, where a second one for tiles without cells would add
// minutes to every build; choosing at run time costs more per normal-mapped frame).
void whole_tile_cell(TileWork& work) {
  const std::size_t light_count = work.lights.size();
  work.cell_width = work.cell_height = kTileSize;
  work.cell_lights.resize(light_count);
  for (std::size_t i = 0; i < light_count; ++i)
    work.cell_lights[i] = KernelCellLight{static_cast<std::uint32_t>(i), work.lights[i].first_pair,
                                          work.lights[i].pair_count};
  work.cell_pairs.assign(work.pairs.begin(), work.pairs.end());
  work.cell_occluders.resize(work.occluders.size());
  for (std::size_t k = 0; k < work.occluders.size(); ++k) work.cell_occluders[k] = static_cast<std::uint32_t>(k);
  work.cells.assign(1, KernelCell{0, static_cast<std::uint32_t>(light_count), 0,
                                  static_cast<std::uint32_t>(work.occluders.size())});
}

}  // namespace

void build_cell_lists(const PreparedScene& scene, const TileRect& tile, int lanes, const TileSetupScratch& setup,
                      TileWork& work, CellListScratch& scratch, const std::uint32_t* tile_lights) {
  if (tile_lights == nullptr) tile_lights = setup.tile_lights.data();
  if (!setup.plan.cells) {
    if (work.model) whole_tile_cell(work);
    return;
  }
  work.cell_width = cell_width_for(lanes);
  work.cell_height = kCellPixels / work.cell_width;
  const int columns = kTileSize / work.cell_width, rows = kTileSize / work.cell_height;
  const std::size_t cell_count = static_cast<std::size_t>(columns * rows);
  const std::size_t light_count = work.lights.size();
  const std::size_t tile_occluders = work.occluders.size();

  // Every sample position of a cell's pixels lies in its box. Cells wholly in the tile's
  // padding (past the image edge) are left out of `live`: their pixels are dropped.
  scratch.cell_boxes.clear();
  unsigned live = 0;
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < columns; ++x) {
      const TileRect rect{tile.x0 + x * work.cell_width, tile.y0 + y * work.cell_height,
                          std::min(tile.x0 + (x + 1) * work.cell_width, tile.x1),
                          std::min(tile.y0 + (y + 1) * work.cell_height, tile.y1)};
      const Vec2 a = sample_position(scene, rect.x0, rect.y0, 0.0, 0.0);
      const Vec2 b = sample_position(scene, rect.x1, rect.y1, 0.0, 0.0);
      if (rect.x0 < rect.x1 && rect.y0 < rect.y1) live |= 1u << scratch.cell_boxes.size();
      scratch.cell_boxes.push_back({std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)});
    }
  }
  // Every cell has the same extents.
  const Aabb& first_box = scratch.cell_boxes[0];
  const Vec2 half{0.5 * (first_box.max_x - first_box.min_x), 0.5 * (first_box.max_y - first_box.min_y)};
  scratch.cell_centers.clear();
  for (const Aabb& box : scratch.cell_boxes)
    scratch.cell_centers.push_back(Vec2{0.5 * (box.min_x + box.max_x), 0.5 * (box.min_y + box.max_y)});
  CellGrid grid;
  grid.first_center = scratch.cell_centers[0];
  grid.half = half;
  grid.columns = columns;
  grid.rows = rows;
  if (columns > 1) grid.step.x = scratch.cell_centers[1].x - grid.first_center.x;
  if (rows > 1) grid.step.y = scratch.cell_centers[static_cast<std::size_t>(columns)].y - grid.first_center.y;

  // Per tile occluder: its disc, and the cells that need its arc: those where one of its
  // pairs stays (below) and, for the plain kernel, those whose box it meets (it may hold a
  // pixel there: the plain kernel's inside test covers every arc it computes; the model
  // kernel reads an occluder's arc and inside flag only through the light's pairs, and a
  // pixel inside an occluder lies in each of its pairs' cones).
  scratch.occluder_discs.clear();
  scratch.occluder_cells.assign(tile_occluders, 0u);
  for (std::uint32_t k = 0; k < tile_occluders; ++k) {
    const ConvexShape& shape = scene.occluders[setup.occluders.used[k]];
    scratch.occluder_discs.push_back(bounding_disc(shape));
    if (work.model) continue;
    const Aabb bounds = bounds_of(shape);
    for (std::size_t c = 0; c < cell_count; ++c)
      if (boxes_meet(scratch.cell_boxes[c], bounds)) scratch.occluder_cells[k] |= 1u << c;
  }

  // Per light, each pair's cells (one shadow cone per pair), then the light's pairs cell by
  // cell. Every pair is written and counted only when its cell keeps it: which cells keep a
  // pair varies without pattern, and the mispredicted branch on it took a third of the cell
  // lists' time on rubble (perf, docs/performance.md). The buffer only grows, so it is not refilled.
  if (scratch.pair_buffer.size() < cell_count * work.pairs.size()) scratch.pair_buffer.resize(cell_count * work.pairs.size());
  KernelPair* pairs_out = scratch.pair_buffer.data();
  std::size_t kept_pairs = 0;
  work.cell_lights.resize(cell_count * light_count);
  for (std::size_t i = 0; i < light_count; ++i) {
    const KernelLight& light = work.lights[i];
    scratch.pair_cells.resize(light.pair_count);
    if (light.pair_count != 0) {
      // A directional light is at infinity (its shape unused): its pairs keep every cell.
      const bool directional = work.model && work.light_terms[i].directional;
      const CellListScratch::Disc light_disc =
          directional ? CellListScratch::Disc{} : bounding_disc(scene.lights[tile_lights[i]].shape);
      for (std::uint32_t p = 0; p < light.pair_count; ++p) {
        const KernelPair& pair = work.pairs[light.first_pair + p];
        unsigned cells = live;
        const ShadowCone cone = pair.general || directional
                                    ? ShadowCone{}
                                    : shadow_cone(light_disc, scratch.occluder_discs[pair.occluder]);
        if (cone.bounded) cells &= ~cells_outside_cone(cone, grid);
        scratch.pair_cells[p] = cells;
        scratch.occluder_cells[pair.occluder] |= cells;
      }
    }
    for (std::size_t c = 0; c < cell_count; ++c) {
      KernelCellLight& cell_light = work.cell_lights[c * light_count + i];
      cell_light.light = static_cast<std::uint32_t>(i);
      cell_light.first_pair = static_cast<std::uint32_t>(kept_pairs);
      for (std::uint32_t p = 0; p < light.pair_count; ++p) {
        pairs_out[kept_pairs] = work.pairs[light.first_pair + p];
        kept_pairs += (scratch.pair_cells[p] >> c) & 1u;
      }
      cell_light.pair_count = static_cast<std::uint32_t>(kept_pairs) - cell_light.first_pair;
    }
  }
  work.cell_pairs.assign(pairs_out, pairs_out + kept_pairs);

  // The cells' arcs, written and counted the same way as the pairs.
  work.cells.assign(cell_count, KernelCell{});
  work.cell_occluders.resize(cell_count * tile_occluders);
  std::uint32_t* occluders_out = work.cell_occluders.data();
  std::size_t kept_occluders = 0;
  for (std::size_t c = 0; c < cell_count; ++c) {
    KernelCell& cell = work.cells[c];
    cell.first_light = static_cast<std::uint32_t>(c * light_count);
    cell.light_count = (live & (1u << c)) ? static_cast<std::uint32_t>(light_count) : 0u;
    cell.first_occluder = static_cast<std::uint32_t>(kept_occluders);
    for (std::uint32_t k = 0; k < tile_occluders; ++k) {
      occluders_out[kept_occluders] = k;
      kept_occluders += (scratch.occluder_cells[k] >> c) & 1u;
    }
    cell.occluder_count = static_cast<std::uint32_t>(kept_occluders) - cell.first_occluder;
  }
  work.cell_occluders.resize(kept_occluders);
}

}  // namespace par2d::detail
