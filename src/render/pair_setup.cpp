// A light's pairs over a tile, with the culling that drops pairs and lights: see pair_setup.hpp.
#include "render/pair_setup.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "render/model_terms.hpp"
#include "render/tile_plan.hpp"

namespace par2d::detail {
namespace {

// A line separating the kernel's versions of a light and an occluder when one of them reaches
// far from the tile: the scene's line, made for the whole shapes, is rounded relative to
// their size and may miss the tile's neighbourhood by many pixels, while these shapes are
// tile-sized in precision. Checked like the scene's (strictly separating), else empty (the
// kernel's exact general path).
std::optional<Line> near_separator(const ConvexShape& light, const ConvexShape& occluder, double scale) noexcept {
  // A circle far larger than the box: distances to it cancel in double (its boundary is
  // its center minus its radius), so no line is trusted; the kernel's general path decides
  // depth from the circle's nearest point instead.
  if ((light.kind == ShapeKind::circle && light.radius * scale > kNearHalf) ||
      (occluder.kind == ShapeKind::circle && occluder.radius * scale > kNearHalf))
    return std::nullopt;
  std::optional<Line> line = separating_line(occluder, light);
  if (!line) return line;
  for (Vec2 v : occluder.vertices)
    if (!(line->side(v) - occluder.radius > 0.0)) return std::nullopt;
  for (Vec2 v : light.vertices)
    if (!(line->side(v) + light.radius < 0.0)) return std::nullopt;
  return line;
}

using CornerDirections = PairSetupScratch::CornerDirections;

// Whether the whole rectangle lies in the occluder's umbra for the light, given that it is
// on the occluder's side of their separating line: from each corner, the occluder's arc
// must contain the light's. The umbra of a convex occluder for a convex light is convex,
// so the four corners decide for the whole rectangle. Tangent directions come from the
// block's grid caches (`grid`: each corner's grid point), computed there on first use.
bool rect_in_umbra(const ConvexShape& light, const ConvexShape& occluder, const std::array<Vec2, 4>& corners,
                   const int (&grid)[4], CornerDirections* light_directions,
                   CornerDirections* occluder_directions) noexcept {
  for (int i = 0; i < 4; ++i) {
    CornerDirections& l = light_directions[grid[i]];
    if (l.outside < 0) l.outside = tangent_directions(light, corners[i], l.cw, l.ccw);
    if (l.outside == 0) return false;  // a corner inside the light sees it
    CornerDirections& o = occluder_directions[grid[i]];
    if (o.outside < 0) o.outside = tangent_directions(occluder, corners[i], o.cw, o.ccw);
    if (o.outside != 0 && !arc_contains(o.cw, o.ccw, l.cw, l.ccw)) return false;
  }
  return true;
}

// The two bridge edges of the hull of the tile and the light, as half-planes holding both:
// every segment from a point of the tile to a point of the light stays in each, so an
// occluder wholly outside one blocks nothing anywhere in the tile (exactly: such a pair's
// intervals are empty at every pixel). A bridge runs from a corner along its clockwise
// (resp. counter-clockwise) tangent direction to the light, which has the light on its
// inner side, and is a bridge when the other corners are there too. Tangent directions
// come from the block's grid cache (shared with the umbra tests).
struct HullSide {
  // Inside: dot(normal, y - point) >= -slack. The normal is not unit length (no square root):
  // slack is the tolerance times its L1 norm, which is at least its length.
  Vec2 point, normal;
  double slack;
};

int tile_light_bridges(const ConvexShape& light, const std::array<Vec2, 4>& corners, const int (&grid)[4],
                       CornerDirections* light_directions, double tolerance, HullSide (&out)[2]) noexcept {
  int count = 0;
  for (int side = 0; side < 2; ++side) {
    for (int i = 0; i < 4; ++i) {
      CornerDirections& d = light_directions[grid[i]];
      if (d.outside < 0) d.outside = tangent_directions(light, corners[i], d.cw, d.ccw);
      if (d.outside == 0) return 0;  // a corner in the light: the light may be seen any way
      const Vec2 along = side == 0 ? d.cw : d.ccw;
      // The light is left of the clockwise tangent (cross >= 0) and right of the other.
      const Vec2 normal = side == 0 ? Vec2{-along.y, along.x} : Vec2{along.y, -along.x};
      const double slack = tolerance * (std::abs(normal.x) + std::abs(normal.y));
      if (!(slack > 0.0)) return 0;
      bool holds_tile = true;
      for (int j = 0; j < 4 && holds_tile; ++j) holds_tile = dot(normal, corners[j] - corners[i]) >= -slack;
      if (holds_tile) {
        out[count++] = HullSide{corners[i], normal, slack};
        break;
      }
    }
  }
  return count;
}

// Whether the shape lies wholly outside the half-plane, by more than three times its slack
// (the bridge may hold the tile only to within one slack).
bool outside_hull_side(const ConvexShape& s, const HullSide& side) noexcept {
  double farthest = s.radius > 0.0 ? s.radius * std::sqrt(dot(side.normal, side.normal)) : 0.0;
  // The centroid is a point of the shape, so a centroid inside the half-plane (most pairs)
  // decides without the vertex loop, which would find a vertex at least as far in.
  if (farthest + dot(side.normal, s.centroid - side.point) >= -3.0 * side.slack) return false;
  double vertex = -std::numeric_limits<double>::infinity();
  for (const Vec2 v : s.vertices) vertex = std::max(vertex, dot(side.normal, v - side.point));
  return farthest + vertex < -3.0 * side.slack;
}

// A disc inside a light (center and radius), for umbra_possible; radius < 0: not computed yet.
struct InnerDisc {
  Vec2 center;
  double radius = -1.0;
};

// The part of umbra_possible that depends on the light and the occluder only (the band of
// their discs' outer common tangents), kept per block for each (light, candidate).
using UmbraBand = PairSetupScratch::UmbraBand;
void umbra_band(const ConvexShape& light, const ConvexShape& occluder, InnerDisc& disc, UmbraBand& band) noexcept {
  if (disc.radius < 0.0) {
    disc.center = light.centroid;
    if (light.kind == ShapeKind::circle) {
      disc.radius = light.radius;
    } else if (light.kind == ShapeKind::segment) {
      disc.radius = 0.0;
    } else {
      double r = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < light.vertices.size(); ++i)
        r = std::min(r, dot(light.edge_normals[i], light.centroid - light.vertices[i]));
      disc.radius = std::max(r, 0.0);
    }
  }
  band.center = 0.5 * (occluder.bounds_min + occluder.bounds_max);
  band.big_r = length(0.5 * (occluder.bounds_max - occluder.bounds_min));
  const Vec2 axis = band.center - disc.center;
  band.dist = length(axis);
  // Discs one inside the other have no outer tangents: no shortcut.
  if (!(band.dist > std::abs(band.big_r - disc.radius) * (1.0 + 1e-9) + 1e-300)) {
    band.state = 0;
    return;
  }
  band.u = (1.0 / band.dist) * axis;
  band.sin_b = (band.big_r - disc.radius) / band.dist;
  band.cos_b = std::sqrt(std::max(0.0, 1.0 - band.sin_b * band.sin_b));
  band.state = 1;
}

// Whether the rectangle can lie in the occluder's umbra for the light at all, in O(1): the
// umbra of the occluder for the light lies in that of the occluder's bounding disc (box
// center, half diagonal) for a disc inside the light, which lies between the discs' two
// outer common tangents, |h| cos b <= R + t sin b (t along the axis from the light's disc
// to the occluder's, h across it, sin b = (R - r) / D). A corner outside that band rules
// the rectangle out. Only a shortcut: rect_in_umbra decides when this says maybe (most
// tries fail: lights larger than small occluders have short umbrae narrower than a tile).
bool umbra_possible(const UmbraBand& band, const std::array<Vec2, 4>& corners) noexcept {
  if (band.state == 0) return true;
  for (const Vec2 x : corners) {
    const Vec2 q = x - band.center;
    // A relative margin keeps corners on the band's edge (rounding) as "maybe".
    if (std::abs(cross(band.u, q)) * band.cos_b >
        (band.big_r + dot(band.u, q) * band.sin_b) * (1.0 + 1e-9) + 1e-12 * band.dist)
      return false;
  }
  return true;
}

bool tangent_points(const ConvexShape& light, Vec2 x, Vec2 (&out)[2]) noexcept {
  if (contains(light, x)) return false;
  if (light.kind == ShapeKind::circle) {
    // tangent_directions' vectors have length |d|^2 and the tangent length is t.
    Vec2 cw, ccw;
    tangent_directions(light, x, cw, ccw);
    const Vec2 d = light.vertices[0] - x;
    const double dd = dot(d, d);
    const double t = std::sqrt(std::max(0.0, dd - light.radius * light.radius));
    out[0] = x + (t / dd) * cw;
    out[1] = x + (t / dd) * ccw;
    return true;
  }
  int cw = 0, ccw = 1;
  if (light.kind == ShapeKind::polygon) tangent_vertices(light, x, cw, ccw);
  out[0] = light.vertices[static_cast<std::size_t>(cw)];
  out[1] = light.vertices[static_cast<std::size_t>(ccw)];
  return true;
}

// Whether an occluder that overlaps or touches a light blocks none of the light's directions
// at any point of the rectangle: some line has the occluder on one side (side >= 0) and the
// whole rectangle strictly on the other, and from every rectangle point both of the light's
// tangent points lie strictly on the rectangle's side (side < 0). Then the light's near boundary seen
// from such a point x lies in the triangle of x and the two tangent points, so every ray meets
// the light no later than it crosses the line, before any point of the occluder. The points
// that see no light point beyond the line form a convex set (an intersection of the inner
// half-planes of the light's supporting lines at those points), so the four corners decide.
// Lines tried: a polygon's edge lines, a circle's tangent facing the rectangle, a segment's line.
// Whether the rectangle lies strictly on the negative side of `line` and, from each of its
// points, both of the light's tangent points lie strictly on the negative side (see
// general_pair_behind for why the corners decide).
bool light_before_line(const ConvexShape& light, const Line& line, const std::array<Vec2, 4>& corners,
                       CornerTangentPoints& tangents) noexcept {
  for (const Vec2& c : corners)
    if (!(line.side(c) < 0.0)) return false;
  if (light.kind == ShapeKind::circle) {
    // In closed form (what tangent_points gives, without its calls and stores; lights
    // overlapping walls ask this of every tile that sees them). From x outside the circle
    // (center c, radius r, d = c - x, t the tangent length), the tangent points are
    // x + (t / |d|^2) (t d +- r perp(d)), so their sides are side(x) + (t / |d|^2) (t n.d +- r
    // cross(n, d)), and both are negative when the larger one is.
    const Vec2 center = light.vertices[0];
    const double r = light.radius;
    for (const Vec2& x : corners) {
      const double power = circle_power(center, r, x);
      if (!(power > 0.0)) return false;  // a corner in the closed light (tangent_points: none)
      const Vec2 d = center - x;
      const double t = std::sqrt(power);
      const double along = dot(line.normal, d), across = std::abs(cross(line.normal, d));
      if (!(line.side(x) + (t / dot(d, d)) * (t * along + r * across) < 0.0)) return false;
    }
    return true;
  }
  for (int i = 0; i < 4; ++i) {
    if (tangents.state[i] < 0) tangents.state[i] = tangent_points(light, corners[i], tangents.point[i]) ? 1 : 0;
    if (tangents.state[i] == 0) return false;
    // Strictly: a tangent point on the line may be an occluder point too, where a ray meets
    // both at once and the contract hides the light.
    if (line.side(tangents.point[i][0]) >= 0.0 || line.side(tangents.point[i][1]) >= 0.0) return false;
  }
  return true;
}

bool general_pair_behind(const ConvexShape& light, const ConvexShape& occluder, const std::array<Vec2, 4>& corners,
                         CornerTangentPoints& tangents) noexcept {
  const Vec2 center = 0.5 * (corners[0] + corners[2]);
  auto decides = [&](const Line& line) { return light_before_line(light, line, corners, tangents); };
  if (occluder.kind == ShapeKind::polygon) {
    for (std::size_t i = 0; i < occluder.vertices.size(); ++i)
      if (decides(Line{occluder.edge_normals[i], occluder.vertices[i]})) return true;
    return false;
  }
  if (occluder.kind == ShapeKind::circle) {
    Vec2 u = center - occluder.vertices[0];
    const double len = length(u);
    if (!(len > 0.0)) return false;
    u = (1.0 / len) * u;
    return decides(Line{-1.0 * u, occluder.vertices[0] + occluder.radius * u});
  }
  const Vec2 e = occluder.vertices[1] - occluder.vertices[0];
  const double len = length(e);
  Vec2 n{-e.y / len, e.x / len};
  if (dot(n, center - occluder.vertices[0]) > 0.0) n = -1.0 * n;
  return decides(Line{n, occluder.vertices[0]});
}

// How many corners lie on the occluder's side of the line (n.p >= offset).
int corners_in_front(const Line& line, const std::array<Vec2, 4>& corners) noexcept {
  int front = 0;
  for (Vec2 p : corners) front += line.side(p) >= 0.0;
  return front;
}

// How many corners lie strictly on the occluder's side of the line.
int corners_beyond(const Line& line, const std::array<Vec2, 4>& corners) noexcept {
  int beyond = 0;
  for (Vec2 p : corners) beyond += line.side(p) > 0.0;
  return beyond;
}

// Whether all of `shape` lies on the closed positive side of `line`.
bool on_positive_side(const ConvexShape& shape, const Line& line) noexcept {
  if (shape.kind == ShapeKind::circle) return line.side(shape.vertices[0]) - shape.radius >= 0.0;
  for (const Vec2 v : shape.vertices)
    if (!(line.side(v) >= 0.0)) return false;
  return true;
}

// The separating line of light l and its block candidate `candidate` (occluder k), through
// the block's entries (PairSetupScratch::block_separators; `candidates`: the light's block
// candidate count, `serial`: the block's).
// `clip_line`: a clipped light's clip line (VisibleLights). An occluder wholly on the far
// side of it, like the next box of the wall a torch pokes into, is separated from the kept
// part of the light by the clip line itself: the whole room in front of the wall is then
// on the light's side, where the closest points' bisector would stand across the room.
// (The occluder does not meet the light, so it meets none of the kept part: from a point on
// the light's side no segment to a kept point reaches it, from the other side it comes first.)
// Other occluders take the scene's line for the whole light, which separates the kept part
// too; lines made for the kept part would outlive it in the scene's table when the clipping
// occluder moves (the World forgets only the moved occluder's lines).
std::optional<Line> block_separator(const PreparedScene& scene, std::size_t l, std::size_t candidate, std::uint32_t k,
                                    std::size_t candidates, std::uint64_t serial, const Line* clip_line,
                                    PairSetupScratch& scratch) {
  PairSetupScratch::BlockSeparator* run = scratch.block_separators.run(l, candidates, serial);
  if (!run) scratch.uncached_separator = PairSetupScratch::BlockSeparator{};  // the block's entries are all dealt
  PairSetupScratch::BlockSeparator& entry = run ? run[candidate] : scratch.uncached_separator;
  if (entry.state < 0 && clip_line && on_positive_side(scene.occluders[k], *clip_line)) {
    entry.state = 1;
    entry.line = *clip_line;
  }
  if (entry.state < 0) {
    const std::optional<Line> line = scene.separators.get(l, k, scene.lights[l].shape, scene.occluders[k]);
    entry.state = line ? 1 : 0;
    if (line) entry.line = *line;
  }
  if (entry.state == 0) return std::nullopt;
  return entry.line;
}

}  // namespace

namespace {

// build_light_pairs; `each_tile`: every pair separated on this tile's shapes, as far pairs are.
void build_pairs(const PreparedScene& scene, std::size_t l, const std::vector<std::uint32_t>& candidates,
                 const TileView& tile, const BlockView& block, PairSetupScratch& scratch, KernelShapeScratch& shapes,
                 TileWork& work, LightPairs& out, const VisibleLights::Entry* visible, bool each_tile) {
  const PreparedLight& light = scene.lights[l];
  const bool model = scene.model;
  const bool culling = tile.culling;
  const TileFrame& frame = tile.frame;
  const std::array<Vec2, 4>& corners = tile.corners;
  const Aabb& box = tile.box;
  const int(&grid)[4] = tile.grid;
  LightClip& clip = out.clip;
  CornerTangentPoints& light_tangent_points = out.tangent_points;
  const bool hull_test = culling && !candidates.empty();
  BoxPairHull tile_hull;
  CornerDirections* light_directions = nullptr;  // the light's grid cache, on first umbra test
  InnerDisc inner_disc;
  // Only general pairs and clipped lights use the tangent points: computed on first use.
  light_tangent_points.forget();
  bool clipped = false;
  if (hull_test) tile_hull.assign(box, bounds_of(light.shape));
  const Vec2 tile_center = 0.5 * (corners[0] + corners[2]);
  const bool light_far = !candidates.empty() && (each_tile || reaches_far(light.shape, frame, tile_center));
  const ConvexShape* light_near = nullptr;
  const std::uint32_t first_pair = static_cast<std::uint32_t>(work.pairs.size());
  out.first_pair = first_pair;
  out.first_point = work.point_x.size();
  bool shadowed = false;
  bool general = false;
  for (std::size_t candidate = 0; candidate < candidates.size(); ++candidate) {
    const std::uint32_t k = candidates[candidate];
    const ConvexShape& occluder = scene.occluders[k];
    if (hull_test && !tile_hull.touches(bounds_of(occluder))) continue;
    KernelPair pair;
    pair.occluder = k;
    const auto overlap =
        std::lower_bound(light.overlapping_occluders.begin(), light.overlapping_occluders.end(), k);
    bool overlapping = overlap != light.overlapping_occluders.end() && *overlap == k;
    const LightOverlap* overlap_info =
        overlapping ? &light.overlaps[static_cast<std::size_t>(overlap - light.overlapping_occluders.begin())] : nullptr;
    const bool far_pair = light_far || reaches_far(occluder, frame, tile_center);
    // A light wholly in the closed occluder is hidden everywhere (contacts count as hidden,
    // as in the scalar reference): nothing of it reaches this tile. Not for far-reaching
    // pairs, whose whole shapes double cannot place to within a contact.
    const bool prover = !model || proves_shadow(scene, k, light.terms.mask);
    if (overlapping && !far_pair && prover && overlap_info->contained) {
      shadowed = true;
      break;
    }
    std::optional<Line> line;
    if (far_pair) {
      // Decided on the shapes the kernel gets: the scene's test, in double on the whole
      // shapes, may take a pair 1e-16 of their size apart for overlapping.
      if (!light_near)
        light_near = &kernel_view(light.shape, frame, tile_center, shapes.clipped_light, shapes.clip_points);
      line = near_separator(*light_near,
                            kernel_view(occluder, frame, tile_center, shapes.clipped, shapes.clip_points),
                            frame.scale);
      if (line) overlapping = false;
    } else if (!overlapping) {
      line = block_separator(scene, l, candidate, k, candidates.size(), block.serial,
                             visible ? &visible->line : nullptr, scratch);
    }
    // Clipping drops the cap inside the occluder: only where the occluder hides it. A light
    // with a visible part is clipped by the occluder that part was cut by, the one whose
    // clip its other pairs' lines rely on.
    if (!line && overlapping && !clipped && prover) {
      if (visible ? k == visible->occluder : overlap_info->clips) {
        clip = overlap_info->clip;
        clipped = true;
        line = clip.line;  // separates the light's near part from the occluder
      }
    }
    if (!line) {
      // Overlapping or touching shapes (or disjoint ones too close for a separating
      // line, where the depth test alone is exact): the kernel's general pair, unless
      // the occluder lies wholly behind the light over this tile.
      if (culling && general_pair_behind(light.shape, occluder, corners,
                                         light_tangent_points))
        continue;
      pair.general = true;
      general = true;
      pair.first_point = static_cast<std::uint32_t>(work.point_x.size());
      if (overlapping) {
        for (Vec2 p : overlap_info->points) {
          float x, y;
          frame.point(p, x, y);
          work.point_x.push_back(x);
          work.point_y.push_back(y);
        }
      }
      pair.point_count = static_cast<std::uint32_t>(work.point_x.size()) - pair.first_point;
      work.pairs.push_back(pair);
      continue;
    }
    pair.nx = static_cast<float>(line->normal.x);
    pair.ny = static_cast<float>(line->normal.y);
    pair.c = frame.line_offset(line->normal, line->point);
    if (culling) {
      const int front = corners_in_front(*line, corners);
      // The light comes first everywhere in the tile: every corner on its side, or on the
      // line (the samples lie inside the tile, so on the light's side then; tilemaps put
      // walls' faces, and so a clipped torch's clip line, on tile edges).
      if (front == 0 || corners_beyond(*line, corners) == 0) continue;
      if (front == 4) {
        pair.nx = pair.ny = 0.0f;
        pair.c = -1.0f;
        pair.front = true;
        UmbraBand* band = nullptr;
        if (prover) {
          // The light's bands for this block, one per candidate, found on first use.
          UmbraBand* bands = scratch.umbra_bands.run(l, candidates.size(), block.serial);
          if (bands) {
            band = &bands[candidate];
          } else {  // the block's bands are all dealt: found anew
            scratch.uncached_band = UmbraBand{};
            band = &scratch.uncached_band;
          }
          if (band->state < 0) umbra_band(light.shape, occluder, inner_disc, *band);
        }
        if (band && umbra_possible(*band, corners)) {
          ++scratch.counts.umbra_tests;
          if (!light_directions) light_directions = scratch.light_grid.run(l, PairSetupScratch::kGridPoints, block.serial);
          CornerDirections* occluder_directions =
              scratch.occluder_grid.run(k, PairSetupScratch::kGridPoints, block.serial);
          if (!occluder_directions) {  // the block's runs are all dealt: found anew
            std::fill(scratch.uncached_grid.begin(), scratch.uncached_grid.end(), CornerDirections{});
            occluder_directions = scratch.uncached_grid.data();
          }
          if (rect_in_umbra(light.shape, occluder, corners, grid, light_directions, occluder_directions)) {
            ++scratch.counts.umbra_hits;
            shadowed = true;
            break;
          }
        }
      }
    }
    work.pairs.push_back(pair);
  }
  // Pairs whose occluder lies outside the hull of the tile and the light block nothing
  // here: dropped (the light goes unblocked when none is left, and an occluder no pair
  // keeps gets no arc). Not once the tile has enough pairs for per-cell lists, whose
  // shadow cones already keep such pairs from every cell (there the test costs more than it
  // saves).
  if (!shadowed && culling && work.pairs.size() > first_pair && !tile_gets_cells(culling, work.pairs.size())) {
    if (!light_directions) light_directions = scratch.light_grid.run(l, PairSetupScratch::kGridPoints, block.serial);
    // Rounding in the tangent directions and the dot products is ~1e-16 of these lengths.
    const Vec2 reach = light.shape.centroid - tile_center;
    const double tolerance = 1e-9 * (std::abs(reach.x) + std::abs(reach.y) + (box.max_x - box.min_x) +
                                     (box.max_y - box.min_y) + std::abs(tile_center.x) + std::abs(tile_center.y));
    HullSide sides[2];
    const int side_count = tile_light_bridges(light.shape, corners, grid, light_directions, tolerance, sides);
    if (side_count != 0) {
      std::size_t kept = first_pair;
      for (std::size_t p = first_pair; p < work.pairs.size(); ++p) {
        const KernelPair& pair = work.pairs[p];
        bool outside = false;
        if (!pair.general) {
          const ConvexShape& occluder = scene.occluders[pair.occluder];
          for (int i = 0; i < side_count && !outside; ++i)
            outside = outside_hull_side(occluder, sides[i]);
        }
        if (outside) {
          ++scratch.counts.tile_pairs_outside_hull;
          continue;
        }
        work.pairs[kept++] = pair;
      }
      work.pairs.resize(kept);
    }
  }
  out.shadowed = shadowed;
  out.general = general;
  out.clipped = clipped;
}

}  // namespace

void build_light_pairs(const PreparedScene& scene, std::size_t l, const std::vector<std::uint32_t>& candidates,
                       const TileView& tile, const BlockView& block, PairSetupScratch& scratch,
                       KernelShapeScratch& shapes, TileWork& work, LightPairs& out,
                       const VisibleLights::Entry* visible) {
  if (visible) {
    // The clip line separates the other occluders only where the kernel clips the light at
    // its occluder, which the far pairs' per-tile test may not do: such tiles separate every
    // pair anew.
    const Vec2 tile_center = 0.5 * (tile.corners[0] + tile.corners[2]);
    if (reaches_far(scene.lights[l].shape, tile.frame, tile_center) ||
        reaches_far(scene.occluders[visible->occluder], tile.frame, tile_center)) {
      build_pairs(scene, l, candidates, tile, block, scratch, shapes, work, out, nullptr, true);
      return;
    }
  }
  build_pairs(scene, l, candidates, tile, block, scratch, shapes, work, out, visible, false);
  if (visible && !out.shadowed && !out.clipped) {
    // The clipping occluder was not among the pairs (it always is: it meets the light), so
    // the clip line may not separate the others: the tile separates each pair anew.
    work.pairs.resize(out.first_pair);
    work.point_x.resize(out.first_point);
    work.point_y.resize(out.first_point);
    build_pairs(scene, l, candidates, tile, block, scratch, shapes, work, out, nullptr, true);
  }
}

bool clip_needless(const ConvexShape& light, const TileView& tile, LightPairs& pairs) noexcept {
  return light_before_line(light, pairs.clip.line, tile.corners, pairs.tangent_points);
}

}  // namespace par2d::detail
