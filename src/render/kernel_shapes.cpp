// Kernel shapes: the tile's frame, shapes clipped near the tile, tangent-pair segments, arc
// windows and the sample grid (see kernel_shapes.hpp).
#include "render/kernel_shapes.hpp"

#include "geometry/box_clip.hpp"

namespace par2d::detail {
namespace {

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

// Half size of the box around the tile that `s` (reaching past kNearHalf) is clipped to.
double clip_half_size(const ConvexShape& s, const TileFrame& frame, Vec2 tile_center) noexcept {
  const double h = distance_to_shape(s, tile_center) * frame.scale;
  const double half = kBoxPerDistance * (h - kTileHalfDiagonal);
  return (half > kNearHalf ? std::min(half, kFarHalf) : kNearHalf) / frame.scale;
}

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
                                KernelShapeScratch::BlockTangentPair* block_pair, const BlockView& block,
                                int& cw, int& ccw) noexcept {
  if (!block_pair || s.kind != ShapeKind::polygon) return tile_tangent_pair(s, corners, cw, ccw);
  if (block_pair->block != block.serial) {
    block_pair->block = block.serial;
    const std::array<Vec2, 4> block_corners{block.corners[0], block.corners[1], block.corners[2],
                                            block.corners[3]};
    if (!tile_tangent_pair(s, block_corners, block_pair->cw, block_pair->ccw)) block_pair->cw = -1;
  }
  if (block_pair->cw < 0) return tile_tangent_pair(s, corners, cw, ccw);
  cw = block_pair->cw;
  ccw = block_pair->ccw;
  return true;
}

}  // namespace

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

TileFrame tile_frame(const PreparedScene& scene, Vec2 origin) noexcept {
  const double pixel = std::max(std::abs(scene.view.x1 - scene.view.x0) / scene.width,
                                std::abs(scene.view.y1 - scene.view.y0) / scene.height);
  int pixel_exponent = 0;
  std::frexp(pixel, &pixel_exponent);
  const double scale = std::ldexp(1.0, -pixel_exponent);
  return {origin, scale, !(2.0 * scene.extent * scale < 0x1p18)};
}

void BlockView::start(const PreparedScene& scene, const TileRect& block,
                      const std::array<Vec2, 4>& block_corners) noexcept {
  ++serial;
  std::copy(block_corners.begin(), block_corners.end(), corners);
  const TileFrame block_frame = tile_frame(scene, block_corners[0]);
  frame_scale = block_frame.scale;
  frame_far = block_frame.far;
  x0 = block.x0;
  y0 = block.y0;
}

KernelShape kernel_shape(const ConvexShape& shape, const TileFrame& frame, const std::array<Vec2, 4>& corners,
                         bool whole, TileWork& work, KernelShapeScratch& scratch, const BlockView& block,
                         KernelShapeScratch::BlockTangentPair* block_pair) {
  KernelShape k;
  k.kind = shape.kind;
  const Vec2 tile_center = 0.5 * (corners[0] + corners[2]);
  ConvexShape& clipped = scratch.clipped;
  std::vector<Vec2>& tmp = scratch.clip_points;
  const ConvexShape& s = near_shape(shape, frame, tile_center, clipped, tmp);
  // A far-reaching shape is clipped per tile: its pair is the clipped shape's.
  if (frame.far) block_pair = nullptr;
  if (int cw, ccw; !whole && tile_tangent_pair_in_block(s, corners, block_pair, block, cw, ccw)) {
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
  // A line's offset is taken at the lesser of its two ends (by x, then y), so that two shapes
  // sharing an edge (a concave light's pieces, and the segment of their shared boundary) get
  // offsets and normals that are exact negations of each other: a point of the edge is then
  // inside both or neither, and on the segment exactly then (vertex_tangents).
  const auto lesser = [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y) ? a : b; };
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 v = s.vertices[i];
    const std::size_t j = k.first + i;
    frame.point(v, work.vx[j], work.vy[j]);
    if (s.kind == ShapeKind::polygon) {
      const Vec2 normal = s.edge_normals[i];
      work.edge_nx[j] = static_cast<float>(normal.x);
      work.edge_ny[j] = static_cast<float>(normal.y);
      work.edge_c[j] = frame.line_offset(normal, lesser(v, s.vertices[(i + 1) % n]));
      // A vertex sharper than 29 degrees (consecutive normals more than 151 degrees apart):
      // beyond it, points within kOnBoundary of both edges' lines lie up to 1 / sin(angle / 2)
      // times that from the polygon, and the kernel's inside test checks such lanes against
      // the edges themselves. At blunter vertices they are within 4 kOnBoundary of it, which
      // section 5's 0.05 pixel widths near a boundary excuse.
      if (k.may_contain && dot(normal, s.edge_normals[(i + n - 1) % n]) < -0.875) k.sharp = true;
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
    work.edge_c[k.first] = frame.line_offset(normal, lesser(s.vertices[0], s.vertices[1]));
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

}  // namespace par2d::detail
