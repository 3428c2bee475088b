// Builds TileWork: culling in double precision, then shapes rounded to float relative to the tile.
#include "render/tile_setup.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "geometry/box_clip.hpp"
#include "render/cell_lists.hpp"
#include "par2d/render.hpp"


namespace par2d::detail {
namespace {

// The tile's pixel rectangle in world coordinates (corners of all its sample positions).
std::array<Vec2, 4> tile_corners(const PreparedScene& scene, const TileRect& tile) noexcept {
  const Vec2 a = sample_position(scene, tile.x0, tile.y0, 0.0, 0.0);
  const Vec2 b = sample_position(scene, tile.x1, tile.y1, 0.0, 0.0);
  return {Vec2{a.x, a.y}, Vec2{b.x, a.y}, Vec2{b.x, b.y}, Vec2{a.x, b.y}};
}

Aabb bounds_of(const std::array<Vec2, 4>& rect) noexcept {
  return {std::min(rect[0].x, rect[2].x), std::min(rect[0].y, rect[2].y), std::max(rect[0].x, rect[2].x),
          std::max(rect[0].y, rect[2].y)};
}

// For a polygon wholly outside the tile: when the same two vertices are the tangent
// vertices at all four tile corners, they are for every point of the tile (the points
// with a given tangent vertex form a wedge, which is convex), so the kernel need only
// look at those two, as a segment: no inside test, no search over vertices.
bool tile_tangent_pair(const ConvexShape& s, const std::array<Vec2, 4>& corners, int& cw, int& ccw) noexcept {
  if (s.kind != ShapeKind::polygon || boxes_meet(bounds_of(s), bounds_of(corners))) return false;
  tangent_vertices(s, corners[0], cw, ccw);
  // At the other corners only a check: seen from outside a convex polygon, a vertex both of
  // whose neighbours lie strictly counter-clockwise of it (clockwise, for the other tangent)
  // is the clockwise (counter-clockwise) tangent vertex.
  const std::size_t n = s.vertices.size();
  const Vec2 cw_prev = s.vertices[(static_cast<std::size_t>(cw) + n - 1) % n], cw_v = s.vertices[static_cast<std::size_t>(cw)],
             cw_next = s.vertices[(static_cast<std::size_t>(cw) + 1) % n];
  const Vec2 ccw_prev = s.vertices[(static_cast<std::size_t>(ccw) + n - 1) % n],
             ccw_v = s.vertices[static_cast<std::size_t>(ccw)], ccw_next = s.vertices[(static_cast<std::size_t>(ccw) + 1) % n];
  for (int i = 1; i < 4; ++i) {
    const Vec2 x = corners[static_cast<std::size_t>(i)];
    const Vec2 a = cw_v - x, b = ccw_v - x;
    if (!(cross(a, cw_prev - x) > 0.0 && cross(a, cw_next - x) > 0.0)) return false;
    if (!(cross(b, ccw_prev - x) < 0.0 && cross(b, ccw_next - x) < 0.0)) return false;
  }
  return true;
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
// the tile are first clipped to a box around it (near_shape), so the kernel's coordinates stay
// far inside float's range (it squares them, and the range ends near 2^128).
TileFrame tile_frame(const PreparedScene& scene, Vec2 origin) noexcept {
  const double pixel = std::max(std::abs(scene.view.x1 - scene.view.x0) / scene.width,
                                std::abs(scene.view.y1 - scene.view.y0) / scene.height);
  int pixel_exponent = 0;
  std::frexp(pixel, &pixel_exponent);
  const double scale = std::ldexp(1.0, -pixel_exponent);
  return {origin, scale, !(2.0 * scene.extent * scale < 0x1p18)};
}

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
constexpr double kNearHalf = 0x1p18;
constexpr double kFarHalf = 0x1p58;
constexpr double kBoxPerDistance = 0x1p17;
constexpr double kTileHalfDiagonal = 0.7072 * kTileSize;

// Half size of the box around the tile that `s` (reaching past kNearHalf) is clipped to.
double clip_half_size(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  const double h = distance_to_shape(s, tile_center) * frame.scale;
  const double half = kBoxPerDistance * (h - kTileHalfDiagonal);
  return (half > kNearHalf ? std::min(half, kFarHalf) : kNearHalf) / frame.scale;
}

// A circle of a larger radius (kernel units) is replaced by the circle of this radius with
// the same point nearest the tile and the same normal there: a subset of it that departs from
// it, over the near box, by under 2^40 / 2^60 radians as seen from the tile, and whose
// squared radius float still holds.
constexpr double kMaxRadius = 0x1p59;

// The shape the kernel gets for `s`: `s` itself when it lies within the near box around the
// tile center, else its part within the near (or far) box, in `clipped`. A subset of `s`, so
// separating lines and culling decisions made for `s` hold for it; the same as `s` wherever
// the tile's rays meet it within the box.
const ConvexShape& near_shape(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center, ConvexShape& clipped,
                              std::vector<Vec2>& tmp) {
  if (!frame.far || s.kind == ShapeKind::circle) return s;
  const double near = kNearHalf / frame.scale;
  if (s.bounds_min.x >= tile_center.x - near && s.bounds_max.x <= tile_center.x + near &&
      s.bounds_min.y >= tile_center.y - near && s.bounds_max.y <= tile_center.y + near)
    return s;
  // The box reaches past the shape's nearest point unless capped at kFarHalf.
  if (clip_to_box(s, tile_center, clip_half_size(s, frame, tile_center), clipped, tmp)) return clipped;
  return s;
}

// Takes `count` vertex slots (edge lines only meaningful for polygons) and returns the first
// index. The arrays only grow, so that a tile's setup writes in place without bookkeeping.
inline std::uint32_t grow_vertices(TileWork& work, std::size_t count) {
  const std::size_t first = work.vertex_count, size = first + count;
  if (size > work.vx.size()) {
    const std::size_t grown = std::max<std::size_t>(2 * size, 64);
    for (std::vector<float>* v : {&work.vx, &work.vy, &work.edge_nx, &work.edge_ny, &work.edge_c}) v->resize(grown);
  }
  work.vertex_count = static_cast<std::uint32_t>(size);
  return static_cast<std::uint32_t>(first);
}

// A circle whose nearest point lies more than 2^50 kernel units from the tile origin is seen
// scaled about the origin by a power of two (this exponent) that brings it to 2^50 (2^28 if
// its radius is then still capped): its directions from the origin do not change, from
// elsewhere in the tile by under 2^-24 rad,
// and float holds its coordinates (a light 1e300 pixels off in a view 1e-300 wide).
int far_circle_shift(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  if (!frame.far || s.kind != ShapeKind::circle) return 0;
  const Vec2 c = s.vertices[0];
  const double d = length((tile_center - frame.origin) + to_circle_boundary(c, s.radius, tile_center));
  if (!(d > 0.0) || !std::isfinite(d)) return 0;
  const int e = std::ilogb(d) + std::ilogb(frame.scale);
  // A circle whose radius stays above kMaxRadius is replaced by one of that radius tangent at
  // the nearest point; seen from distance h that subtends 2 sqrt(2 h / kMaxRadius) rad less
  // than a half-plane (an eighth of a radian at 2^50: 2 % of a light 1e106 pixels off with a
  // radius of 1e122). Brought to 2^28, under 2^-14 rad.
  const int radius_e = std::ilogb(s.radius) + std::ilogb(frame.scale);
  const int target = radius_e - std::max(0, e - 50) >= std::ilogb(kMaxRadius) ? 28 : 50;
  return e > target ? target - e : 0;
}

// Whether the kernel gets `s` changed (near_shape, or a circle's radius capped).
bool reaches_far(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  if (!frame.far) return false;
  const double near = kNearHalf / frame.scale;
  if (s.kind == ShapeKind::circle && s.radius * frame.scale > kMaxRadius) return true;
  return !(s.bounds_min.x >= tile_center.x - near && s.bounds_max.x <= tile_center.x + near &&
           s.bounds_min.y >= tile_center.y - near && s.bounds_max.y <= tile_center.y + near);
}

// The shape as the kernel sees it, in double, for a far-reaching shape (reaches_far): its
// part near the tile, or a circle of capped radius with the same point nearest the tile.
const ConvexShape& kernel_view(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center, ConvexShape& out,
                               std::vector<Vec2>& tmp) {
  if (s.kind != ShapeKind::circle) return near_shape(s, frame, tile_center, out, tmp);
  const int shift = far_circle_shift(s, frame, tile_center);
  if (shift == 0 && !(s.radius * frame.scale > kMaxRadius)) return s;
  Vec2 c = s.vertices[0];
  double r = s.radius;
  if (shift != 0) {
    const Vec2 rel = c - frame.origin;
    c = frame.origin + Vec2{std::ldexp(rel.x, shift), std::ldexp(rel.y, shift)};
    r = std::ldexp(r, shift);
  }
  if (r * frame.scale > kMaxRadius) {
    Vec2 u = tile_center - c;
    const double len = length(u);
    u = len > 0.0 ? (1.0 / len) * u : Vec2{1.0, 0.0};
    const double capped = kMaxRadius / frame.scale;
    c = (tile_center + to_circle_boundary(c, r, tile_center)) - capped * u;
    r = capped;
  }
  out.kind = ShapeKind::circle;
  out.edge_normals.clear();
  out.vertices.assign(1, c);
  out.radius = r;
  out.centroid = out.vertices[0];
  out.bounds_min = {out.vertices[0].x - r, out.vertices[0].y - r};
  out.bounds_max = {out.vertices[0].x + r, out.vertices[0].y + r};
  return out;
}

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

// A circle's kernel shape in `frame`.
KernelShape circle_kernel_shape(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  KernelShape k;
  k.kind = ShapeKind::circle;
  const Vec2 c = s.vertices[0];
  Vec2 u = tile_center - c;
  const double len = length(u);
  u = len > 0.0 ? (1.0 / len) * u : Vec2{1.0, 0.0};
  // The circle point nearest the tile, relative to the origin: formed from small
  // relative terms, because the inside test needs it on the circle to float precision
  // (its absolute coordinates would be rounded to the scene's magnitude).
  // to_circle_boundary(c, s.radius, tile_center) written out, with its length of c - tile_center
  // taken from `len` (the same value: negation is exact).
  const Vec2 to_boundary =
      len > 0.0 ? (circle_power(c, s.radius, tile_center) / (len + s.radius)) * ((1.0 / len) * (c - tile_center))
                : Vec2{s.radius, 0.0};
  const Vec2 nearest = (tile_center - frame.origin) + to_boundary;
  if (s.radius * frame.scale > kMaxRadius) {
    // A far larger circle: the one of radius kMaxRadius tangent to it inside at `nearest`.
    const double r = kMaxRadius / frame.scale;
    frame.relative(nearest - r * u, k.cx, k.cy);
    k.r = static_cast<float>(kMaxRadius);
  } else {
    frame.point(c, k.cx, k.cy);
    k.r = frame.length(s.radius);
  }
  frame.relative(nearest, k.px, k.py);
  k.ux = static_cast<float>(u.x);
  k.uy = static_cast<float>(u.y);
  return k;
}

// The shape's tile tangent pair for these tile corners, taken from its pair over the whole
// block where it has one (the wedges of points with a given tangent vertex are convex, so
// the pair at the block's corners is the pair at every point of the block); `block_pair` is
// the shape's cache entry, or null.
bool tile_tangent_pair_in_block(const ConvexShape& s, const std::array<Vec2, 4>& corners,
                                TileSetupScratch::BlockTangentPair* block_pair, const TileSetupScratch& scratch,
                                int& cw, int& ccw) noexcept {
  if (!block_pair || s.kind != ShapeKind::polygon) return tile_tangent_pair(s, corners, cw, ccw);
  if (block_pair->block != scratch.block_serial) {
    block_pair->block = scratch.block_serial;
    const std::array<Vec2, 4> block_corners{scratch.block_corners[0], scratch.block_corners[1],
                                            scratch.block_corners[2], scratch.block_corners[3]};
    if (!tile_tangent_pair(s, block_corners, block_pair->cw, block_pair->ccw)) block_pair->cw = -1;
  }
  if (block_pair->cw < 0) return tile_tangent_pair(s, corners, cw, ccw);
  cw = block_pair->cw;
  ccw = block_pair->ccw;
  return true;
}

// `whole`: keep every vertex and edge (a general pair's depth test needs the shape itself).
// `block_pair`: the shape's entry in the scratch's block tangent pairs (null: none).
KernelShape kernel_shape(const ConvexShape& shape, const TileFrame& frame, const std::array<Vec2, 4>& corners,
                         bool whole, TileWork& work, TileSetupScratch& scratch,
                         TileSetupScratch::BlockTangentPair* block_pair) {
  KernelShape k;
  k.kind = shape.kind;
  const Vec2 tile_center = 0.5 * (corners[0] + corners[2]);
  ConvexShape& clipped = scratch.clipped;
  std::vector<Vec2>& tmp = scratch.hull_points;
  const ConvexShape& s = near_shape(shape, frame, tile_center, clipped, tmp);
  // A far-reaching shape is clipped per tile: its pair is the clipped shape's.
  if (frame.far) block_pair = nullptr;
  if (int cw, ccw; !whole && tile_tangent_pair_in_block(s, corners, block_pair, scratch, cw, ccw)) {
    k.kind = ShapeKind::segment;
    k.ordered = true;
    k.count = 2;
    k.first = grow_vertices(work, 2);
    frame.point(s.vertices[static_cast<std::size_t>(cw)], work.vx[k.first], work.vy[k.first]);
    frame.point(s.vertices[static_cast<std::size_t>(ccw)], work.vx[k.first + 1], work.vy[k.first + 1]);
    for (int e = 0; e < 2; ++e) {
      k.end_x[e] = work.vx[k.first + static_cast<std::uint32_t>(e)];
      k.end_y[e] = work.vy[k.first + static_cast<std::uint32_t>(e)];
    }
    return k;
  }
  if (s.kind == ShapeKind::circle) {
    const int shift = far_circle_shift(s, frame, tile_center);
    if (shift != 0) {
      // Seen scaled about the origin (far_circle_shift): the same circle in a frame whose
      // unit is 2^-shift times larger.
      const TileFrame scaled{frame.origin, std::ldexp(frame.scale, shift), frame.far};
      return circle_kernel_shape(s, scaled, tile_center);
    }
    return circle_kernel_shape(s, frame, tile_center);
  }
  const std::size_t n = s.vertices.size();
  k.count = static_cast<std::uint32_t>(n);
  k.may_contain = boxes_meet(bounds_of(s), bounds_of(corners));
  k.first = grow_vertices(work, n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 v = s.vertices[i];
    const std::size_t j = k.first + i;
    frame.point(v, work.vx[j], work.vy[j]);
    if (s.kind == ShapeKind::polygon) {
      const Vec2 normal = s.edge_normals[i];
      work.edge_nx[j] = static_cast<float>(normal.x);
      work.edge_ny[j] = static_cast<float>(normal.y);
      work.edge_c[j] = frame.line_offset(normal, v);
    }
  }
  if (s.kind == ShapeKind::segment) {
    // The segment's line, for the kernel's depth test: its offset is formed near the tile,
    // so it stays exact where the end points are far (cross products of them would cancel).
    const Vec2 e = s.vertices[1] - s.vertices[0];
    const double len = length(e);
    const Vec2 normal{-e.y / len, e.x / len};
    work.edge_nx[k.first] = static_cast<float>(normal.x);
    work.edge_ny[k.first] = static_cast<float>(normal.y);
    work.edge_c[k.first] = frame.line_offset(normal, s.vertices[0]);
  }
  return k;
}

// Gives a kernel shape its arc window (KernelShape::window) where one of the
// eight directions k * 45 degrees holds, with margin, every direction from the tile's samples
// to the points whose angles the kernel takes: the box of those points minus the samples' box
// is a box of directions, and a cone (convex) holds a box when it holds its four corners. The
// margin (0.875 instead of 1) keeps the kernel's float ratios inside the polynomial's range.
void assign_arc_window(KernelShape& k, const TileWork& work) noexcept {
  float x0, x1, y0, y1;
  if (k.kind == ShapeKind::circle) {
    x0 = x1 = k.cx, y0 = y1 = k.cy;
  } else if (k.ordered) {
    x0 = std::min(k.end_x[0], k.end_x[1]), x1 = std::max(k.end_x[0], k.end_x[1]);
    y0 = std::min(k.end_y[0], k.end_y[1]), y1 = std::max(k.end_y[0], k.end_y[1]);
  } else {
    x0 = x1 = work.vx[k.first], y0 = y1 = work.vy[k.first];
    for (std::uint32_t i = 1; i < k.count; ++i) {
      x0 = std::min(x0, work.vx[k.first + i]), x1 = std::max(x1, work.vx[k.first + i]);
      y0 = std::min(y0, work.vy[k.first + i]), y1 = std::max(y1, work.vy[k.first + i]);
    }
  }
  // In float: a rounding here moves a corner by an ulp, far inside the margin.
  const float dx0 = x0 - work.sample_max_x, dx1 = x1 - work.sample_min_x;
  const float dy0 = y0 - work.sample_max_y, dy1 = y1 - work.sample_min_y;
  // The nearest of the eight directions to the box's middle (tan(22.5 degrees) = 0.41421).
  const float mx = dx0 + dx1, my = dy0 + dy1;
  int ux = mx < 0.0f ? -1 : 1, uy = my < 0.0f ? -1 : 1;
  if (std::abs(my) <= 0.41421356f * std::abs(mx)) uy = 0;
  else if (std::abs(mx) <= 0.41421356f * std::abs(my)) ux = 0;
  const float fx = static_cast<float>(ux), fy = static_cast<float>(uy);
  auto holds = [&](float x, float y) { return std::abs(fx * y - fy * x) <= 0.875f * (fx * x + fy * y); };
  // `holds` is false for NaN too.
  if (!(holds(dx0, dy0) && holds(dx0, dy1) && holds(dx1, dy0) && holds(dx1, dy1))) return;
  // The window index k of direction (ux, uy) (kWindowX/Y), at (uy + 1) * 3 + ux + 1.
  static constexpr std::int8_t kWindowOf[9] = {5, 6, 7, 4, -1, 0, 3, 2, 1};
  k.window = kWindowOf[(uy + 1) * 3 + ux + 1];
  k.may_contain = false;  // the vertices' box misses every sample
}

using CornerDirections = TileSetupScratch::CornerDirections;

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
  // decides without the vertex loop, which would find a vertex at least as far in (the
  // dungeon: 1.3 M fewer instructions a frame).
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
using UmbraBand = TileSetupScratch::UmbraBand;
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

// A light's tangent points (where its arc's two bounding rays touch it) seen from the four
// corners of a rectangle, on first use.
struct CornerTangentPoints {
  Vec2 point[4][2];
  signed char state[4] = {-1, -1, -1, -1};  // -1: not computed yet, 0: corner inside the light, 1: known
  void forget() noexcept { std::fill(state, state + 4, static_cast<signed char>(-1)); }
};

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

// Whether the culling's double-precision tests (light reach, occlusion proofs, umbra and
// behind tests on the whole shapes) can be trusted: not when some coordinate lies 2^40 pixels
// or more from the origin, where their rounding reaches pixels (a slanted wall 1e25 long
// let a proof hide a light in front of it). Such scenes render without culling (the same
// image, slower).
bool culling_trusted(const PreparedScene& scene) noexcept {
  const double pixel = std::max(std::abs(scene.view.x1 - scene.view.x0) / scene.width,
                                std::abs(scene.view.y1 - scene.view.y0) / scene.height);
  return scene.extent < 0x1p40 * pixel;
}

// How many corners lie on the occluder's side of the line (n.p >= offset).
int corners_in_front(const Line& line, const std::array<Vec2, 4>& corners) noexcept {
  int front = 0;
  for (Vec2 p : corners) front += line.side(p) >= 0.0;
  return front;
}

// Occlusion proofs: the most strips one may use per block and light, and per tile and light.
// A tile tries one only for a light with at least kTileProofMinPairs occluders in front:
// with fewer, the kernel's merge costs less than a failed proof. Measured with
// bench/par2d_bench on the scaling targets and the dungeon: block budgets 16/32/64 and tile
// budgets 8/16 moved frame times by under 10%; tile proofs saved ~15% on the 256-light
// scene and cost nothing measurable on the others.
constexpr int kBlockStripBudget = 64;
constexpr int kTileStripBudget = 16;
constexpr std::size_t kTileProofMinPairs = 8;

// Adaptive tile proofs. A failed proof costs about what a success saves the kernel (~30-40 k
// instructions against a light's pairs over 256 samples), so proofs pay only where they
// mostly succeed. Where occluders are much smaller than the gaps between them (the rubble
// level: 1.5-4 px occluders, 3-5 px lights), ~87 % of tile proofs fail, and a light whose
// proofs failed on one tile of a block mostly fails on the rest. So a light stops trying tile
// proofs in a block once all it tried there failed, while the block's tile proofs (all
// lights) succeed less than 1 in kBlockProofSuccessRatio times: on the benchmark's level
// (4-12 px occluders) ~58 % succeed and the rule skips ~0.3 % of them. A skipped proof only
// hands the kernel a light that may be hidden: the same image. Measured with callgrind,
// AVX2, 1 thread (par2d render, 960x540, 64 lights, 1024 occluders): rubble 8615 M -> 7089 M
// instructions; the rule without the block's gate also skipped ~25 % of the benchmark
// level's proofs, which then succeeded 47 % of the time. Counting the block's own proofs in
// the gate saved 1 % more on rubble but cost the dungeon 0.5 % and skipped 7 % of a smaller
// default level's proofs.
// Since then the kernel got cheaper (cell lists, arc windows) and a proof's break-even rose:
// the gate now asks 1 in 2, and past the block's first kTileProofWarmup tries a light's
// first try in the block passes the gate too (it used to be free: with 60-150 lights per
// tile on rubble, first tries alone were most of the proofs). Callgrind, same cuts: rubble
// 6,327.6 M -> 5,997.1 M, the default level 2,973.6 M -> 2,970.7 M (1 in 2 alone: 6,216.1 M
// and 2,969.2 M; no tile proofs at all: 5,870.6 M and 2,989.2 M).
constexpr int kBlockProofSuccessRatio = 2;
constexpr std::uint32_t kTileProofWarmup = 16;

bool tile_proof_worth_trying(const TileSetupScratch::TileProofRecord& light,
                             const TileSetupScratch::TileProofRecord& block) noexcept {
  if (light.succeeded > 0) return true;
  const bool block_pays = block.succeeded * kBlockProofSuccessRatio >= block.tried;
  if (light.tried == 0) return block.tried < kTileProofWarmup || block_pays;
  return block_pays;
}

// Adaptive block proofs. A block tries a proof per light (in scene order): on rubble ~39 k
// instructions each, and 1.4 % succeed (a light is hidden from a whole 64 px block only
// inside a closed pocket of small occluders). A success spares up to 16 tiles the light's
// setup and tile proofs (~40 k instructions each), so block proofs pay down to about 1 success
// in 16 tries. Once a block has tried kBlockProofWarmup proofs and fewer than 1 in
// kBlockProofPayRatio succeeded, it tries no more: its tiles meet those lights with their own
// adaptive tile proofs. A skipped proof only hands the tiles a light that may be hidden: the
// same image. Decided per block from its own tries, so the same whatever the threads.
// 960x540, 64 lights, 1024 occluders: rubble skips 60 % of its block proofs (56 of 124
// successes lost), the benchmark's level (4-12 px) none, the dungeon none (57 % succeed),
// paper none (4 lights per block). A warm-up of 8 skipped 81 % on rubble but also 143 of the
// benchmark level's proofs, which then succeeded 31 % of the time: +0.4 % instructions there.
constexpr std::uint32_t kBlockProofWarmup = 24;
constexpr std::uint32_t kBlockProofPayRatio = 16;

bool block_proof_worth_trying(const TileSetupScratch::TileProofRecord& block) noexcept {
  return block.tried < kBlockProofWarmup || block.succeeded * kBlockProofPayRatio >= block.tried;
}

// Game lighting model (docs/contract.md section 6).
// Whether occluder k may prove a shadow of a light with this mask: only opaque, dark-interior
// occluders acting on it hide what lies behind them.
bool proves_shadow(const PreparedScene& scene, std::uint32_t k, std::uint32_t light_mask) noexcept {
  const OccluderTerms& t = scene.occluder_terms[k];
  return t.opaque() && !t.lit_interior && t.acts_on(light_mask);
}

// Whether every point of `box` lies at least `range` from the light's shape (its box is
// nearer than the shape): the range window is 0 there.
bool beyond_range(const Aabb& box, const ConvexShape& light, const LightTerms& terms) noexcept {
  if (!terms.has_range()) return false;
  const double dx = std::max({light.bounds_min.x - box.max_x, 0.0, box.min_x - light.bounds_max.x});
  const double dy = std::max({light.bounds_min.y - box.max_y, 0.0, box.min_y - light.bounds_max.y});
  return std::hypot(dx, dy) >= terms.range;
}

// Occluders a ray from the box in a direction within [start, start + width] may meet: the
// box swept along those directions, as convex hulls of sub-arcs at most pi/2 wide reaching
// past every shape (`reach`), queried in the index and merged.
void directional_candidates(const PreparedScene& scene, const std::array<Vec2, 4>& corners, double start,
                            double width, double reach, TileSetupScratch& scratch, std::vector<std::uint32_t>& out) {
  out.clear();
  const int parts = std::max(1, static_cast<int>(std::ceil(width / (0.5 * kPi))));
  const double step = width / parts;
  for (int part = 0; part < parts; ++part) {
    const double a0 = start + part * step, a1 = a0 + step, mid = 0.5 * (a0 + a1);
    // The sector of radius `reach` lies in the hull of its ends and the tangents' meeting point.
    const Vec2 far[3] = {reach * Vec2{std::cos(a0), std::sin(a0)}, reach * Vec2{std::cos(a1), std::sin(a1)},
                         (reach / std::cos(0.5 * step)) * Vec2{std::cos(mid), std::sin(mid)}};
    Vec2 points[16];
    int count = 0;
    for (Vec2 c : corners) {
      points[count++] = c;
      for (Vec2 f : far) points[count++] = c + f;
    }
    scratch.hull.resize(2 * 16 + 1);
    const int hull_count = convex_hull(points, count, scratch.hull.data());
    scratch.pair_occluders.clear();
    scene.occluder_bvh.query_convex(scratch.hull.data(), hull_count, scratch.pair_occluders);
    out.insert(out.end(), scratch.pair_occluders.begin(), scratch.pair_occluders.end());
  }
  if (parts > 1) {
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
}

KernelOccluderTerms kernel_occluder_terms(const OccluderTerms& t) noexcept {
  KernelOccluderTerms k;
  for (int c = 0; c < 3; ++c) k.transmittance[c] = static_cast<float>(t.transmittance[static_cast<std::size_t>(c)]);
  k.opaque = t.opaque();
  k.lit_interior = t.lit_interior;
  return k;
}

// The separating line of light l and its block candidate `candidate` (occluder k), through
// the block's entries (TileSetupScratch::block_separators).
std::optional<Line> block_separator(const PreparedScene& scene, std::size_t l, std::size_t candidate, std::uint32_t k,
                                    TileSetupScratch& scratch) {
  if (scratch.block_separator_block[l] != scratch.block_serial) {
    scratch.block_separator_block[l] = scratch.block_serial;
    scratch.block_separators[l].assign(scratch.block_candidates[l].size(), TileSetupScratch::BlockSeparator{});
  }
  TileSetupScratch::BlockSeparator& entry = scratch.block_separators[l][candidate];
  if (entry.state < 0) {
    const std::optional<Line> line = scene.separators.get(l, k, scene.lights[l].shape, scene.occluders[k]);
    entry.state = line ? 1 : 0;
    if (line) entry.line = *line;
  }
  if (entry.state == 0) return std::nullopt;
  return entry.line;
}

// A monotone stand-in for the angle of (x, y) in [0, 4), 0 along +x, increasing with the
// angle: |x| + |y| in place of the length, no atan2.
double diamond_angle(double x, double y) noexcept {
  const double sum = std::abs(x) + std::abs(y);
  if (!(sum > 0.0)) return 0.0;
  if (y >= 0.0) return x >= 0.0 ? y / sum : 1.0 - x / sum;
  return x < 0.0 ? 2.0 - y / sum : 3.0 + x / sum;
}

// A light's candidates in a block ordered by their direction from the block's center,
// measured from the light's. Pairs follow the candidates' order in every tile, and the
// kernel extends the blocked prefix of a light's arc with each interval that starts inside
// it, stopping on the light once the prefix spans the arc: intervals that arrive in
// angular order close a cover made of several occluders early.
// Fewer candidates leave the lights of the block's tiles a pair or two, where the order
// cannot pay for the sort (ordering every block's cost the dungeon 0.9 % more instructions).
constexpr std::size_t kOrderMinCandidates = 16;

void order_by_angle(const PreparedScene& scene, Vec2 light_center, Vec2 block_center, std::vector<std::uint32_t>& ids,
                    std::vector<std::pair<double, std::uint32_t>>& keyed) {
  const Vec2 to_light = light_center - block_center;
  keyed.clear();
  for (const std::uint32_t k : ids) {
    const Vec2 to_occluder = scene.occluders[k].centroid - block_center;
    double key = diamond_angle(dot(to_light, to_occluder), cross(to_light, to_occluder));
    if (key >= 2.0) key -= 4.0;  // into (-2, 2]: the light's direction in the middle, not at the seam
    keyed.emplace_back(key, k);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = keyed[i].second;
}

}  // namespace

void gather_block_candidates(const PreparedScene& scene, const TileRect& block, const std::vector<LightReach>* reach,
                             TileSetupScratch& scratch) {
  scratch.block_candidates.resize(scene.lights.size());
  scratch.block_shadowed.assign(scene.lights.size(), 0);
  const std::array<Vec2, 4> corners = tile_corners(scene, block);
  // Entries of earlier blocks (or scenes) carry an older serial: found anew on first use.
  ++scratch.block_serial;
  std::copy(corners.begin(), corners.end(), scratch.block_corners);
  scratch.light_block_pairs.resize(scene.lights.size());
  scratch.occluder_block_pairs.resize(scene.occluders.size());
  const TileFrame block_frame = tile_frame(scene, corners[0]);
  scratch.frame_scale = block_frame.scale;
  scratch.frame_far = block_frame.far;
  scratch.block_x0 = block.x0;
  scratch.block_y0 = block.y0;
  scratch.light_grid.start_block(scene.lights.size());
  scratch.umbra_bands.resize(scene.lights.size());
  scratch.umbra_band_block.resize(scene.lights.size(), 0);
  scratch.block_separators.resize(scene.lights.size());
  scratch.block_separator_block.resize(scene.lights.size(), 0);
  scratch.tile_proof_records.assign(scene.lights.size(), TileSetupScratch::TileProofRecord{});
  scratch.block_proof_record = TileSetupScratch::TileProofRecord{};
  scratch.occluder_grid.start_block(scene.occluders.size());
  const Aabb box = bounds_of(corners);
  if (reach && !culling_trusted(scene)) reach = nullptr;
  TileSetupScratch::TileProofRecord block_proofs;  // this block's block proofs so far
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    std::vector<std::uint32_t>& candidates = scratch.block_candidates[l];
    candidates.clear();
    if (!reach) {
      for (std::uint32_t k = 0; k < scene.occluders.size(); ++k)
        if (!scene.model || scene.occluder_terms[k].acts_on(scene.lights[l].terms.mask)) candidates.push_back(k);
      continue;
    }
    if ((*reach)[l].hides(box) || (scene.model && beyond_range(box, scene.lights[l].shape, scene.lights[l].terms))) {
      scratch.block_shadowed[l] = 1;
      continue;
    }
    const ConvexShape& light = scene.lights[l].shape;
    hull_with_shape(corners.data(), 4, light, scratch.hull_points, scratch.hull);
    scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), candidates);
    const std::uint32_t* provers = candidates.data();
    std::size_t prover_count = candidates.size();
    if (scene.model) {
      // Occluders that do not act on the light are not its candidates; of the rest, only
      // opaque dark ones may prove it hidden.
      const std::uint32_t mask = scene.lights[l].terms.mask;
      candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                      [&](std::uint32_t k) { return !scene.occluder_terms[k].acts_on(mask); }),
                       candidates.end());
      scratch.pair_occluders.clear();
      for (std::uint32_t k : candidates)
        if (proves_shadow(scene, k, mask)) scratch.pair_occluders.push_back(k);
      provers = scratch.pair_occluders.data();
      prover_count = scratch.pair_occluders.size();
    }
    // Hidden from the whole block by one occluder or several together (rooms behind a
    // wall, a field of rubble): the proof's cost is shared by the block's tiles.
    if (prover_count != 0 && !block_proof_worth_trying(block_proofs)) {
      ++scratch.block_proofs_skipped;
    } else if (prover_count != 0) {
      ++block_proofs.tried;
      if (rect_hidden_from_light({box.min_x, box.min_y}, {box.max_x, box.max_y}, light, scene.occluders, provers,
                                 prover_count, kBlockStripBudget, scratch.occlusion)) {
        candidates.clear();
        scratch.block_shadowed[l] = 1;
        ++block_proofs.succeeded;
      }
    }
    if (!scene.model && candidates.size() >= kOrderMinCandidates)
      order_by_angle(scene, light.centroid, 0.5 * (corners[0] + corners[2]), candidates, scratch.ordered_candidates);
  }
}

void build_tile_work(const PreparedScene& scene, const TileRect& tile, int spp, bool culling, TileWork& work,
                     TileSetupScratch& scratch, bool shaded) {
  work.clear();
  const bool model = scene.model;
  work.model = model;
  culling = culling && culling_trusted(scene);
  scratch.tile_culled = culling;
  scratch.tile_lights.clear();
  const Vec2 origin = sample_position(scene, tile.x0, tile.y0, 0.0, 0.0);
  // The frame's scale depends on the scene only: found once per block.
  const TileFrame frame{origin, scratch.frame_scale, scratch.frame_far};
  work.spp = spp;
  // A sample's offset from the origin: (c + s) pixel sizes, the same in every tile. Made
  // again only when the sampling, the pixel size or the frame's scale changes (NaN never
  // compares equal, so it would be remade): computing two positions per sample and their
  // difference here, per tile, was a fifth of this function's time (perf, AVX-512, paper).
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
  const std::array<Vec2, 4> corners = tile_corners(scene, tile);
  const Aabb box = bounds_of(corners);
  // Only the previous tile's entries are reset: a full reset would write 16 KB per tile at
  // 4096 occluders.
  if (scratch.local_index.size() != scene.occluders.size()) {
    scratch.local_index.assign(scene.occluders.size(), -1);
  } else {
    for (std::uint32_t k : scratch.used) scratch.local_index[k] = -1;
  }
  scratch.used.clear();
  scratch.used_whole.clear();
  // The tile's corners on the block's tile grid (corner order of tile_corners).
  const int grid_x = (tile.x0 - scratch.block_x0) / kTileSize, grid_y = (tile.y0 - scratch.block_y0) / kTileSize;
  const int grid_row = kBlockTiles + 1;
  const int grid_corner = grid_y * grid_row + grid_x;
  const int grid[4] = {grid_corner, grid_corner + 1, grid_corner + grid_row + 1, grid_corner + grid_row};

  // Per light below, plain values with flags rather than std::optional, and the tangent
  // points made once: GCC 12's std::optional zero-fills its whole storage when
  // default-constructed, and so does a Vec2 array. That was two 144-byte `rep stos` per tile
  // and light, slow to start on lengths this short: about a tenth of this function's time
  // with AVX-512 on paper (perf).
  CornerTangentPoints light_tangent_points;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (scratch.block_shadowed[l]) continue;
    const PreparedLight& light = scene.lights[l];
    if (model && beyond_range(box, light.shape, light.terms)) continue;
    const std::vector<std::uint32_t>& candidates = scratch.block_candidates[l];
    const bool hull_test = culling && !candidates.empty();
    BoxPairHull tile_hull;
    CornerDirections* light_directions = nullptr;  // the light's grid cache, on first umbra test
    InnerDisc inner_disc;
    // Only general pairs and clipped lights use the tangent points: computed on first use.
    light_tangent_points.forget();
    LightClip clip;
    bool clipped = false;
    if (hull_test) tile_hull.assign(box, bounds_of(light.shape));
    const Vec2 tile_center = 0.5 * (corners[0] + corners[2]);
    const bool light_far = !candidates.empty() && reaches_far(light.shape, frame, tile_center);
    const ConvexShape* light_near = nullptr;
    KernelLight kl;
    kl.first_pair = static_cast<std::uint32_t>(work.pairs.size());
    const std::size_t first_point = work.point_x.size();
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
          light_near = &kernel_view(light.shape, frame, tile_center, scratch.clipped_light, scratch.hull_points);
        line = near_separator(*light_near,
                              kernel_view(occluder, frame, tile_center, scratch.clipped, scratch.hull_points),
                              frame.scale);
        if (line) overlapping = false;
      } else if (!overlapping) {
        line = block_separator(scene, l, candidate, k, scratch);
      }
      // Clipping drops the cap inside the occluder: only where the occluder hides it.
      if (!line && overlapping && !clipped && prover) {
        if (overlap_info->clips) {
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
        if (front == 0) continue;  // the light comes first everywhere in the tile
        if (front == 4) {
          pair.nx = pair.ny = 0.0f;
          pair.c = -1.0f;
          pair.front = true;
          UmbraBand* band = nullptr;
          if (prover) {
            // The light's bands for this block, one per candidate, found on first use.
            if (scratch.umbra_band_block[l] != scratch.block_serial) {
              scratch.umbra_band_block[l] = scratch.block_serial;
              scratch.umbra_bands[l].assign(candidates.size(), UmbraBand{});
            }
            band = &scratch.umbra_bands[l][candidate];
            if (band->state < 0) umbra_band(light.shape, occluder, inner_disc, *band);
          }
          if (band && umbra_possible(*band, corners)) {
            ++scratch.umbra_tests;
            if (!light_directions) light_directions = scratch.light_grid.of(l, scratch.block_serial);
            if (rect_in_umbra(light.shape, occluder, corners, grid, light_directions,
                              scratch.occluder_grid.of(k, scratch.block_serial))) {
              ++scratch.umbra_hits;
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
    // shadow cones already keep such pairs from every cell: on rubble (hundreds of pairs a
    // tile) the test there cost 3 % more instructions than it saved.
    if (!shadowed && culling && work.pairs.size() > kl.first_pair && work.pairs.size() < kCellMinPairs) {
      if (!light_directions) light_directions = scratch.light_grid.of(l, scratch.block_serial);
      // Rounding in the tangent directions and the dot products is ~1e-16 of these lengths.
      const Vec2 reach = light.shape.centroid - tile_center;
      const double tolerance = 1e-9 * (std::abs(reach.x) + std::abs(reach.y) + (box.max_x - box.min_x) +
                                       (box.max_y - box.min_y) + std::abs(tile_center.x) + std::abs(tile_center.y));
      HullSide sides[2];
      const int side_count = tile_light_bridges(light.shape, corners, grid, light_directions, tolerance, sides);
      if (side_count != 0) {
        std::size_t kept = kl.first_pair;
        for (std::size_t p = kl.first_pair; p < work.pairs.size(); ++p) {
          const KernelPair& pair = work.pairs[p];
          bool outside = false;
          if (!pair.general) {
            const ConvexShape& occluder = scene.occluders[pair.occluder];
            for (int i = 0; i < side_count && !outside; ++i)
              outside = outside_hull_side(occluder, sides[i]);
          }
          if (outside) {
            ++scratch.hull_pairs_dropped;
            continue;
          }
          work.pairs[kept++] = pair;
        }
        work.pairs.resize(kept);
      }
    }
    // The proof holds whatever the pairs' overlaps: every segment from the tile to a light
    // point meets an occluder before it, so every ray meets one before its first light point.
    if (!shadowed && culling && work.pairs.size() - kl.first_pair >= kTileProofMinPairs) {
      TileSetupScratch::TileProofRecord& light_proofs = scratch.tile_proof_records[l];
      TileSetupScratch::TileProofRecord& block_proofs = scratch.block_proof_record;
      if (!tile_proof_worth_trying(light_proofs, block_proofs)) {
        ++scratch.tile_proofs_skipped;
      } else {
        scratch.pair_occluders.clear();
        for (std::uint32_t p = kl.first_pair; p < work.pairs.size(); ++p)
          if (!model || proves_shadow(scene, work.pairs[p].occluder, light.terms.mask))
            scratch.pair_occluders.push_back(work.pairs[p].occluder);
        shadowed = rect_hidden_from_light({box.min_x, box.min_y}, {box.max_x, box.max_y}, light.shape,
                                          scene.occluders, scratch.pair_occluders.data(), scratch.pair_occluders.size(),
                                          kTileStripBudget, scratch.occlusion);
        ++light_proofs.tried;
        ++block_proofs.tried;
        if (shadowed) {
          ++light_proofs.succeeded;
          ++block_proofs.succeeded;
        }
      }
    }
    if (shadowed) {
      work.pairs.resize(kl.first_pair);
      work.point_x.resize(first_point);
      work.point_y.resize(first_point);
      continue;
    }
    kl.pair_count = static_cast<std::uint32_t>(work.pairs.size()) - kl.first_pair;
    KernelLightTerms terms;
    for (std::uint32_t p = kl.first_pair; p < work.pairs.size(); ++p) {
      KernelPair& pair = work.pairs[p];
      // The model kernel keeps a separated pair's wrapped part as an interval of its own.
      kl.interval_count += pair.general ? pair.point_count + 1 : (model ? 2 : 1);
      if (model && !scene.occluder_terms[pair.occluder].opaque()) terms.translucent = true;
      work.max_points_per_pair = std::max(work.max_points_per_pair, pair.point_count);
      std::int32_t& local = scratch.local_index[pair.occluder];
      if (local < 0) {
        local = static_cast<std::int32_t>(scratch.used.size());
        scratch.used.push_back(pair.occluder);
        scratch.used_whole.push_back(0);
      }
      if (pair.general) scratch.used_whole[static_cast<std::size_t>(local)] = 1;
      pair.occluder = static_cast<std::uint32_t>(local);
    }
    // A ranged light is kept whole: the window needs the distance to the whole shape.
    const bool ranged = model && light.terms.has_range();
    kl.shape =
        kernel_shape(light.shape, frame, corners, general || ranged, work, scratch, &scratch.light_block_pairs[l]);
    // Over a tile wholly before the clip line that sees no light point past it, the clipped
    // light's arc is the whole light's (and the pair was dropped as behind): skip the clip.
    if (clipped && culling && light_before_line(light.shape, clip.line, corners, light_tangent_points))
      clipped = false;
    if (clipped) {
      kl.shape.clipped = true;
      kl.shape.clip_nx = static_cast<float>(clip.line.normal.x);
      kl.shape.clip_ny = static_cast<float>(clip.line.normal.y);
      kl.shape.clip_c = frame.line_offset(clip.line.normal, clip.line.point);
      frame.point(clip.chord[0], kl.shape.chord_x[0], kl.shape.chord_y[0]);
      frame.point(clip.chord[1], kl.shape.chord_x[1], kl.shape.chord_y[1]);
    }
    for (int c = 0; c < 3; ++c) kl.emission[c] = static_cast<float>(light.emission[c] / kTwoPi);
    work.max_intervals_per_light = std::max(work.max_intervals_per_light, kl.interval_count);
    work.lights.push_back(kl);
    scratch.tile_lights.push_back(static_cast<std::uint32_t>(l));
    if (model) {
      if (ranged) {
        terms.ranged = true;
        terms.range = static_cast<float>(light.terms.range * frame.scale);
      }
      terms.cone = light.terms.has_cone;
      terms.cone_center = light.terms.cone_center;
      terms.cone_half = light.terms.cone_half;
      terms.cone_fade = light.terms.cone_fade;
      terms.sin_elevation = light.terms.sin_elevation;
      terms.cos_elevation = light.terms.cos_elevation;
      work.light_terms.push_back(terms);
    }
  }
  if (model) {
    // Directional lights: tile lights whose pairs are every acting occluder a ray of their
    // arc may meet from the tile (all are in front: the light is at infinity).
    const double sweep = 2.0 * scene.extent + 4.0 * std::max(std::abs(box.max_x - box.min_x), std::abs(box.max_y - box.min_y));
    for (const PreparedDirectional& d : scene.directionals) {
      KernelLight kl;
      KernelLightTerms terms;
      terms.directional = true;
      terms.dir_start = static_cast<float>(d.start);
      terms.dir_width = static_cast<float>(d.width);
      terms.sin_elevation = d.sin_elevation;
      terms.cos_elevation = d.cos_elevation;
      kl.first_pair = static_cast<std::uint32_t>(work.pairs.size());
      directional_candidates(scene, corners, d.start, d.width, sweep, scratch, scratch.directional);
      for (std::uint32_t k : scratch.directional) {
        const OccluderTerms& ot = scene.occluder_terms[k];
        if (!ot.acts_on(d.mask)) continue;
        if (!ot.opaque()) terms.translucent = true;
        KernelPair pair;
        pair.front = true;
        pair.c = -1.0f;
        std::int32_t& local = scratch.local_index[k];
        if (local < 0) {
          local = static_cast<std::int32_t>(scratch.used.size());
          scratch.used.push_back(k);
          scratch.used_whole.push_back(0);
        }
        pair.occluder = static_cast<std::uint32_t>(local);
        work.pairs.push_back(pair);
      }
      kl.pair_count = static_cast<std::uint32_t>(work.pairs.size()) - kl.first_pair;
      kl.interval_count = 2 * kl.pair_count;
      for (int c = 0; c < 3; ++c) kl.emission[c] = static_cast<float>(d.emission[static_cast<std::size_t>(c)] / kTwoPi);
      work.max_intervals_per_light = std::max(work.max_intervals_per_light, kl.interval_count);
      work.lights.push_back(kl);
      work.light_terms.push_back(terms);
    }
    for (int c = 0; c < 3; ++c) work.ambient[c] = static_cast<float>(scene.ambient[static_cast<std::size_t>(c)]);
    work.shaded = shading_active(scene, shaded);
    if (work.shaded) {
      if (scene.normal_source == NormalSource::map) {
        // In place: the map's planes are padded with (0, 0, 1) to whole 64-pixel blocks.
        static_assert(kNormalPadding % kTileSize == 0, "a tile must not straddle the normal map's padding");
        const WorldNormals& map = *scene.normal_map;
        for (int c = 0; c < 3; ++c) work.normal_plane[c] = map.row(c, tile.y0) + tile.x0;
        work.normal_stride = map.stride();
      } else {
        // Every pixel the same (pixels past the image too: their values are dropped).
        const float constant[3] = {static_cast<float>(scene.normal.x), static_cast<float>(scene.normal.y),
                                   static_cast<float>(scene.normal.z)};
        for (int c = 0; c < 3; ++c) {
          std::fill_n(work.constant_normal[c], kTileSize, constant[c]);
          work.normal_plane[c] = work.constant_normal[c];
        }
        work.normal_stride = 0;
      }
    }
  }
  // Arc windows (KernelShape::window) for the occluders whose arcs the kernel takes and the
  // lights whose arcs' starts it needs (those with pairs). A plain one-sample tile without
  // cells (build_cell_lists gives a culled tile cells from kCellMinPairs pairs on) computes
  // single-pair lights shape-major, with no arc for them or for the occluders only they use.
  const bool windows = !model;
  const bool shape_major = spp == 1 && (!culling || work.pairs.size() < kCellMinPairs);
  if (windows) {
    scratch.arc_needed.assign(scratch.used.size(), shape_major ? 0 : 1);
    for (KernelLight& kl : work.lights) {
      const KernelPair* pairs = work.pairs.data() + kl.first_pair;
      if (kl.pair_count == 0 || (shape_major && single_pair_light(kl, pairs, kl.pair_count))) continue;
      if (shape_major)
        for (std::uint32_t p = 0; p < kl.pair_count; ++p) scratch.arc_needed[pairs[p].occluder] = 1;
      if (!kl.shape.clipped) assign_arc_window(kl.shape, work);
    }
  }
  for (std::size_t u = 0; u < scratch.used.size(); ++u) {
    work.occluders.push_back(kernel_shape(scene.occluders[scratch.used[u]], frame, corners, scratch.used_whole[u] != 0,
                                          work, scratch, &scratch.occluder_block_pairs[scratch.used[u]]));
    if (windows && scratch.arc_needed[u]) assign_arc_window(work.occluders.back(), work);
    if (model) work.occluder_terms.push_back(kernel_occluder_terms(scene.occluder_terms[scratch.used[u]]));
  }
}

}  // namespace par2d::detail
