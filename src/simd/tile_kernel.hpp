// The PAR tile kernel, written once over the xsimd architecture and instantiated per ISA
// in tile_kernel_<isa>.cpp (and nowhere else).
//
// SoA layout: a packet is W consecutive pixels of a tile row (tiles are kTileSize square,
// row-major; W divides kTileSize), one lane each; every shape parameter is broadcast to all lanes.
// Lane semantics: each lane computes E at its own sample position; control flow depends
// only on the tile's shape lists, never on lane data, so there are no lane branches:
// per-lane decisions (inside, in front, overlap, wrap) are masks and selects.
// Edge cases: a pixel inside any occluder gets 0; inside a light gets the light's full
// arc; a zero direction (pixel exactly on a vertex) gives angle 0, never NaN.
// Reference: detail::scalar_irradiance (scalar/scalar_renderer.cpp), which this must
// match within docs/contract.md section 5 away from shape boundaries.
#pragma once

#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <utility>

#include "lighting/angular_profile.hpp"
#include "simd/fast_atan2.hpp"
#include "simd/tile_work.hpp"

namespace par2d::simd {

using detail::KernelLight;
using detail::KernelLightTerms;
using detail::KernelOccluderTerms;
using detail::KernelPair;
using detail::KernelShape;
using detail::ShapeKind;
using detail::TileResult;
using detail::TileWork;

inline constexpr float kTwoPiF = 6.28318530717958647692f;
inline constexpr float kInvTwoPiF = 0.15915494309189533577f;

template <class A>
struct Arc {
  xsimd::batch<float, A> start;  // absolute angle of the arc's clockwise-most direction
  xsimd::batch<float, A> width;  // in [0, 2*pi]
  xsimd::batch_bool<float, A> inside;
};

// Shape arcs are inlined into the packet loop (three call sites), so that nothing passes
// through memory and tile-constant branches fold into straight code. Sanitizer builds
// (PAR2D_KERNEL_INLINE_HINTS, set by PAR2D_SANITIZE) leave inlining to the compiler: forced
// into one body, the instrumented kernels made functions whose compile time grows faster
// than their size (GCC's alias analysis under ASan took minutes per kernel file).
#if defined(__GNUC__) && !defined(PAR2D_KERNEL_INLINE_HINTS)
#define PAR2D_KERNEL_INLINE inline __attribute__((always_inline))
#define PAR2D_KERNEL_NOINLINE __attribute__((noinline))
#define PAR2D_KERNEL_LAMBDA_INLINE __attribute__((always_inline))
#else
#define PAR2D_KERNEL_INLINE inline
#define PAR2D_KERNEL_NOINLINE
#define PAR2D_KERNEL_LAMBDA_INLINE
#endif

// The arc between the clockwise tangent direction lo and the counter-clockwise one hi.
// kWithStart = false computes only the width (one atan2 instead of two). kWhole: lo and hi
// are a whole shape's tangents (so the arc is never wider than pi), not a clipped light's.
template <class A, bool kWithStart, bool kWhole = true>
PAR2D_KERNEL_INLINE void arc_from_tangents(const xsimd::batch<float, A>& lox, const xsimd::batch<float, A>& loy,
                                           const xsimd::batch<float, A>& hix, const xsimd::batch<float, A>& hiy,
                                           Arc<A>& arc) noexcept {
  using B = xsimd::batch<float, A>;
  // With the start, the width is the second absolute angle's difference from it, not the
  // angle between the tangents (fast_atan2_upper of their cross and dot products): that
  // takes fewer instructions but more time with AVX-512.
  if constexpr (kWithStart) {
    arc.start = fast_atan2(loy, lox);
    B width = fast_atan2(hiy, hix) - arc.start;
    width = xsimd::select(width < B(0.0f), width + B(kTwoPiF), width);
    // An outside arc is narrower than pi; a width near 2*pi is -0 rounded up (collinear view).
    arc.width = xsimd::select(width > B(4.71238898f), B(0.0f), width);
  } else {
    // The angle from the clockwise to the counter-clockwise tangent, in [0, pi]. For a whole
    // shape a negative cross product is rounding, near 0 or (a far-reaching shape close by)
    // near pi; for a clipped light it may be a real reversal, an empty arc.
    if constexpr (kWhole) {
      arc.width = fast_atan2_upper(xsimd::abs(lox * hiy - loy * hix), xsimd::fma(lox, hix, loy * hiy));
    } else {
      arc.width = xsimd::max(fast_atan2(lox * hiy - loy * hix, xsimd::fma(lox, hix, loy * hiy)), B(0.0f));
    }
  }
}

// Tangent directions of a circle from (px, py): the center direction d turned by -+asin(r/|d|),
// scaled by |d| (`tangent` is the tangent length).
template <class A>
PAR2D_KERNEL_INLINE void circle_tangents(const KernelShape& s, const xsimd::batch<float, A>& px,
                                         const xsimd::batch<float, A>& py, const xsimd::batch<float, A>& tangent,
                                         xsimd::batch<float, A>& lox, xsimd::batch<float, A>& loy,
                                         xsimd::batch<float, A>& hix, xsimd::batch<float, A>& hiy) noexcept {
  using B = xsimd::batch<float, A>;
  const B dx = B(s.cx) - px, dy = B(s.cy) - py, r(s.r);
  lox = xsimd::fma(dx, tangent, dy * r);
  loy = xsimd::fms(dy, tangent, dx * r);
  hix = xsimd::fms(dx, tangent, dy * r);
  hiy = xsimd::fma(dy, tangent, dx * r);
}

// |x - c|^2 - r^2 of a circle without cancellation (see KernelShape).
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> circle_excess(const KernelShape& s, const xsimd::batch<float, A>& px,
                                                         const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  const B qx = B(s.px) - px, qy = B(s.py) - py;
  return xsimd::fma(qx, qx, qy * qy) - B(2.0f * s.r) * xsimd::fma(B(s.ux), qx, B(s.uy) * qy);
}

// How far outside a polygon's edge line (kernel units, about a pixel each) a point still
// counts as inside, and how near a segment's line as on it: far below the 0.05 pixel widths
// near boundaries where docs/contract.md section 5 lets float decide either way.
inline constexpr float kOnBoundary = 0x1p-12f;

// Squared distance from (px, py) to the nearest of the shape's first `edges` edge segments
// (vertex i to vertex i + 1, the last closing to vertex 0), each projection clamped to its
// segment's ends.
template <class A>
inline xsimd::batch<float, A> edge_distance2(const TileWork& work, const KernelShape& s, std::uint32_t edges,
                                             const xsimd::batch<float, A>& px,
                                             const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  const float* vx = work.vx.data() + s.first;
  const float* vy = work.vy.data() + s.first;
  B best(std::numeric_limits<float>::infinity());
  for (std::uint32_t i = 0; i < edges; ++i) {
    const std::uint32_t j = i + 1 == s.count ? 0 : i + 1;
    const B ax = px - B(vx[i]), ay = py - B(vy[i]);
    const float ex = vx[j] - vx[i], ey = vy[j] - vy[i];
    const float len2 = ex * ex + ey * ey;
    const B t = len2 > 0.0f ? xsimd::min(xsimd::max(xsimd::fma(ax, B(ex), ay * B(ey)) * B(1.0f / len2), B(0.0f)),
                                         B(1.0f))
                            : B(0.0f);
    const B qx = xsimd::fnma(t, B(ex), ax), qy = xsimd::fnma(t, B(ey), ay);
    best = xsimd::min(best, xsimd::fma(qx, qx, qy * qy));
  }
  return best;
}

// The inside test of a polygon with a sharp vertex (KernelShape::sharp), given the lanes'
// largest offset outside its edge lines and the lanes those lines call inside: where a lane
// is not clearly inside (by more than kOnBoundary), it is inside only where an edge segment,
// not just its line, passes within kOnBoundary. The directions to a sliver seen end-on are
// all close together, which the running min and max of vertex_tangents order.
template <class A>
PAR2D_KERNEL_NOINLINE xsimd::batch_bool<float, A> sharp_polygon_inside(const TileWork& work, const KernelShape& s,
                                                                       const xsimd::batch<float, A>& px,
                                                                       const xsimd::batch<float, A>& py,
                                                                       const xsimd::batch<float, A>& outside_by,
                                                                       const xsimd::batch_bool<float, A>& inside) noexcept {
  using B = xsimd::batch<float, A>;
  const auto unclear = inside & (outside_by > B(-kOnBoundary));
  if (!xsimd::any(unclear)) return inside;
  return (inside & ~unclear) | (unclear & (edge_distance2<A>(work, s, s.count, px, py) <= B(kOnBoundary * kOnBoundary)));
}

// Tangent directions (lo clockwise, hi counter-clockwise) of a polygon or segment from
// (px, py), and whether the point is inside. Outside a convex polygon all vertices lie in an
// open half-plane of directions, where the pseudo-cross sign is a total order: running min
// and max find the tangents. A tile tangent pair (`ordered`) is already in order.
template <class A>
PAR2D_KERNEL_INLINE void vertex_tangents(const TileWork& work, const KernelShape& s, const xsimd::batch<float, A>& px,
                                         const xsimd::batch<float, A>& py, xsimd::batch<float, A>& lox,
                                         xsimd::batch<float, A>& loy, xsimd::batch<float, A>& hix,
                                         xsimd::batch<float, A>& hiy, xsimd::batch_bool<float, A>& inside) noexcept {
  using B = xsimd::batch<float, A>;
  if (s.ordered) {  // from the shape's own copy of its ends (KernelShape::end_x)
    inside = B(0.0f) > B(0.0f);  // a segment has no interior
    lox = B(s.end_x[0]) - px, loy = B(s.end_y[0]) - py;
    hix = B(s.end_x[1]) - px, hiy = B(s.end_y[1]) - py;
    return;
  }
  const float* vx = work.vx.data() + s.first;
  const float* vy = work.vy.data() + s.first;
  lox = B(vx[0]) - px, loy = B(vy[0]) - py;
  if (s.kind == ShapeKind::segment) {
    hix = B(vx[1]) - px, hiy = B(vy[1]) - py;
    // The side of the segment's line (edge slot 0, see kernel_shape in render/kernel_shapes.cpp)
    // orders the ends: cross(a - x, b - x) = |b - a| (n.x - c). From the line's offset, not the
    // ends' cross product, which loses its sign for a point near a segment whose ends are far.
    const B side = xsimd::fma(B(work.edge_nx[s.first]), px, B(work.edge_ny[s.first]) * py) - B(work.edge_c[s.first]);
    const auto swap = side < B(0.0f);
    // A point on the segment is in it, as the reference has it (closed shapes), within the
    // tolerance the polygon test below allows, and by the same offset: a polygon edge on this
    // line has the negated normal and offset (kernel_shape), so where a concave light's two
    // pieces both hold a point of their shared boundary, the boundary's segment holds it too,
    // and where one piece does not, the segment does not either (World::push_light's sum).
    inside = s.closed ? (xsimd::abs(side) <= B(kOnBoundary)) & (xsimd::fma(lox, hix, loy * hiy) <= B(0.0f))
                      : B(0.0f) > B(0.0f);
    const B bx = hix, by = hiy;
    hix = xsimd::select(swap, lox, bx);
    hiy = xsimd::select(swap, loy, by);
    lox = xsimd::select(swap, bx, lox);
    loy = xsimd::select(swap, by, loy);
    return;
  }
  hix = lox, hiy = loy;
  for (std::uint32_t i = 1; i < s.count; ++i) {
    const B dx = B(vx[i]) - px, dy = B(vy[i]) - py;
    const auto more_cw = (lox * dy - loy * dx) < B(0.0f);
    lox = xsimd::select(more_cw, dx, lox);
    loy = xsimd::select(more_cw, dy, loy);
    const auto more_ccw = (hix * dy - hiy * dx) > B(0.0f);
    hix = xsimd::select(more_ccw, dx, hix);
    hiy = xsimd::select(more_ccw, dy, hiy);
  }
  if (!s.may_contain) {  // the tile misses the polygon's box
    inside = B(0.0f) > B(0.0f);
    return;
  }
  // Distance outside the polygon (<= 0 inside).
  const float* nx = work.edge_nx.data() + s.first;
  const float* ny = work.edge_ny.data() + s.first;
  const float* nc = work.edge_c.data() + s.first;
  B outside_by = B(nc[0]) - xsimd::fma(B(nx[0]), px, B(ny[0]) * py);
  for (std::uint32_t i = 1; i < s.count; ++i)
    outside_by = xsimd::max(outside_by, B(nc[i]) - xsimd::fma(B(nx[i]), px, B(ny[i]) * py));
  // Within kOnBoundary of an edge's line counts as inside: nearer, the directions to that
  // edge's ends are too close to opposite for the running min and max to order them.
  inside = outside_by <= B(kOnBoundary);
  // The edge lines only bound the polygon from outside: beyond a sharp vertex (a sliver's
  // tip pointing at the point), a point well away from the polygon can lie within kOnBoundary
  // of the two edge lines that cross there (sharp_polygon_inside). Blunt polygons need no
  // more (KernelShape::sharp); the rare sharp one takes a call out of line.
  if (__builtin_expect(s.sharp, false)) inside = sharp_polygon_inside<A>(work, s, px, py, outside_by, inside);
}

// Tangent directions (lo clockwise, hi counter-clockwise) of a whole, unclipped shape from
// (px, py), and whether the point is inside: a circle's from its tangent length.
template <class A>
PAR2D_KERNEL_INLINE void shape_tangents(const TileWork& work, const KernelShape& s, const xsimd::batch<float, A>& px,
                                        const xsimd::batch<float, A>& py, xsimd::batch<float, A>& lox,
                                        xsimd::batch<float, A>& loy, xsimd::batch<float, A>& hix,
                                        xsimd::batch<float, A>& hiy, xsimd::batch_bool<float, A>& inside) noexcept {
  using B = xsimd::batch<float, A>;
  if (s.kind == ShapeKind::circle) {
    const B excess = circle_excess<A>(s, px, py);
    inside = excess <= B(0.0f);
    circle_tangents<A>(s, px, py, xsimd::sqrt(xsimd::max(excess, B(0.0f))), lox, loy, hix, hiy);
    return;
  }
  vertex_tangents<A>(work, s, px, py, lox, loy, hix, hiy, inside);
}

// Tangent directions of a light clipped to one side of a line (KernelShape::clipped), and
// whether the point is inside the whole light: the kept part's arc ends are the light's
// tangent points where they lie on that side, else the chord ends (the kept part is the hull
// of the light's near boundary and the chord).
template <class A>
PAR2D_KERNEL_INLINE void clipped_tangents(const TileWork& work, const KernelShape& s, const xsimd::batch<float, A>& px,
                                          const xsimd::batch<float, A>& py, xsimd::batch<float, A>& lox,
                                          xsimd::batch<float, A>& loy, xsimd::batch<float, A>& hix,
                                          xsimd::batch<float, A>& hiy, xsimd::batch_bool<float, A>& inside) noexcept {
  using B = xsimd::batch<float, A>;
  B scale_v(1.0f), scale_room(1.0f);  // tangent point = x + (scale_v / scale_room) * direction
  if (s.kind == ShapeKind::circle) {
    const B excess = circle_excess<A>(s, px, py);
    inside = excess <= B(0.0f);
    scale_v = xsimd::sqrt(xsimd::max(excess, B(0.0f)));
    circle_tangents<A>(s, px, py, scale_v, lox, loy, hix, hiy);
    const B dx = B(s.cx) - px, dy = B(s.cy) - py;
    scale_room = xsimd::fma(dx, dx, dy * dy);  // |d|^2, the length of the circle's tangent vectors times |d|
  } else {
    vertex_tangents<A>(work, s, px, py, lox, loy, hix, hiy, inside);
  }
  const B cnx(s.clip_nx), cny(s.clip_ny);
  const B room = B(s.clip_c) - xsimd::fma(cnx, px, cny * py);  // > 0 on the kept side
  const B ax = B(s.chord_x[0]) - px, ay = B(s.chord_y[0]) - py;
  const B bx = B(s.chord_x[1]) - px, by = B(s.chord_y[1]) - py;
  const auto a_first = xsimd::fms(ax, by, ay * bx) >= B(0.0f);  // chord end a is the clockwise one
  // A tangent point beyond the line: k (n.v) > room with k = scale_v / scale_room.
  const auto lo_beyond = xsimd::fma(cnx, lox, cny * loy) * scale_v > room * scale_room;
  const auto hi_beyond = xsimd::fma(cnx, hix, cny * hiy) * scale_v > room * scale_room;
  lox = xsimd::select(lo_beyond, xsimd::select(a_first, ax, bx), lox);
  loy = xsimd::select(lo_beyond, xsimd::select(a_first, ay, by), loy);
  hix = xsimd::select(hi_beyond, xsimd::select(a_first, bx, ax), hix);
  hiy = xsimd::select(hi_beyond, xsimd::select(a_first, by, ay), hiy);
}

// Arc of a light clipped to one side of a line (clipped_tangents). Kept out of line: only
// lights overlapping a wall take it (their unblocked sweeps inline it, tile_unblocked_lights).
template <class A, bool kWithStart>
PAR2D_KERNEL_NOINLINE Arc<A> clipped_shape_arc(const TileWork& work, const KernelShape& s,
                                                   const xsimd::batch<float, A>& px,
                                                   const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  Arc<A> arc;
  B lox, loy, hix, hiy;
  clipped_tangents<A>(work, s, px, py, lox, loy, hix, hiy, arc.inside);
  arc_from_tangents<A, kWithStart, false>(lox, loy, hix, hiy, arc);
  return arc;
}

// A circle's inside flag and width (twice the half-width, asin(r / distance) as an atan2 of
// the radius and the tangent length), per lane; returns the half-width.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> circle_half_width(const KernelShape& s, const xsimd::batch<float, A>& px,
                                                             const xsimd::batch<float, A>& py, Arc<A>& arc) noexcept {
  using B = xsimd::batch<float, A>;
  const B excess = circle_excess<A>(s, px, py);
  arc.inside = excess <= B(0.0f);
  const B half = fast_atan2_first_quadrant(B(s.r), xsimd::sqrt(xsimd::max(excess, B(0.0f))));
  arc.width = half + half;
  return half;
}

// The angle of direction (dx, dy) from the shape's arc window direction (KernelShape::
// window), which lies within 45 degrees of it: the ratio of the direction's components
// across and along the window is in [-1, 1], where the atan polynomial holds as it is.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> angle_in_window(const KernelShape& s, const xsimd::batch<float, A>& dx,
                                                           const xsimd::batch<float, A>& dy) noexcept {
  using B = xsimd::batch<float, A>;
  const B wx(detail::kWindowX[s.window]), wy(detail::kWindowY[s.window]);
  return atan_unit(xsimd::fms(wx, dy, wy * dx) / xsimd::fma(wx, dx, wy * dy));
}

// shape_arc for a windowed shape: each end's angle is the window's plus one
// angle_in_window; the width is the difference of the ends' (no wrap: both lie in the
// window). A circle's start comes from its center's direction, its half-width as in shape_arc.
template <class A>
PAR2D_KERNEL_INLINE Arc<A> windowed_shape_arc(const TileWork& work, const KernelShape& s,
                                              const xsimd::batch<float, A>& px,
                                              const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  Arc<A> arc;
  if (s.kind == ShapeKind::circle) {
    const B half = circle_half_width<A>(s, px, py, arc);
    arc.start = (B(detail::kWindowAngle[s.window]) - half) + angle_in_window<A>(s, B(s.cx) - px, B(s.cy) - py);
    return arc;
  }
  B lox, loy, hix, hiy;
  vertex_tangents<A>(work, s, px, py, lox, loy, hix, hiy, arc.inside);
  const B lo = angle_in_window<A>(s, lox, loy);
  arc.start = B(detail::kWindowAngle[s.window]) + lo;
  arc.width = xsimd::max(angle_in_window<A>(s, hix, hiy) - lo, B(0.0f));
  return arc;
}

// Arc of directions in which `shape` is seen from (px, py), per lane. Tangent
// directions come from pseudo-cross products (compare + select per vertex); only the
// two tangents go through atan2 (a circle's through one, its center direction, and asin as
// an atan2 of the radius and the tangent length).
// kWithStart = false computes only `width` and `inside` (a light no occluder can block
// in this tile needs no start angle), with one atan2 instead of two.
template <class A, bool kWithStart = true>
PAR2D_KERNEL_INLINE Arc<A> shape_arc(const TileWork& work, const KernelShape& s, const xsimd::batch<float, A>& px,
                                     const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  if (s.clipped) return clipped_shape_arc<A, kWithStart>(work, s, px, py);
  if constexpr (kWithStart) {
    if (s.window >= 0) return windowed_shape_arc<A>(work, s, px, py);
  }
  Arc<A> arc;
  if (s.kind == ShapeKind::circle) {
    const B half = circle_half_width<A>(s, px, py, arc);
    if constexpr (kWithStart) {
      const B dx = B(s.cx) - px, dy = B(s.cy) - py;
      arc.start = fast_atan2(dy, dx) - half;
    }
    return arc;
  }
  B lox, loy, hix, hiy;
  vertex_tangents<A>(work, s, px, py, lox, loy, hix, hiy, arc.inside);
  arc_from_tangents<A, kWithStart>(lox, loy, hix, hiy, arc);
  return arc;
}

// Batcher's odd-even merge sort network for n = 2^k inputs: the list of compare-exchange
// pairs (i, j), i < j, each putting the smaller key at i. Built at compile time, so the
// kernel walks a flat table: no index arithmetic or skipped iterations per comparator.
template <std::size_t N>
constexpr std::size_t odd_even_merge_size() noexcept {
  std::size_t count = 0;
  for (std::size_t p = 1; p < N; p <<= 1)
    for (std::size_t k = p; k >= 1; k >>= 1)
      for (std::size_t j = k % p; j + k <= N - 1; j += 2 * k)
        for (std::size_t i = 0; i <= k - 1 && i + j + k <= N - 1; ++i)
          if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) ++count;
  return count;
}

template <std::size_t N>
struct SortingNetwork {
  static constexpr std::size_t kSize = odd_even_merge_size<N>();
  std::uint8_t first[kSize > 0 ? kSize : 1] = {};
  std::uint8_t second[kSize > 0 ? kSize : 1] = {};
  constexpr SortingNetwork() noexcept {
    std::size_t c = 0;
    for (std::size_t p = 1; p < N; p <<= 1)
      for (std::size_t k = p; k >= 1; k >>= 1)
        for (std::size_t j = k % p; j + k <= N - 1; j += 2 * k)
          for (std::size_t i = 0; i <= k - 1 && i + j + k <= N - 1; ++i)
            if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) {
              first[c] = static_cast<std::uint8_t>(i + j);
              second[c] = static_cast<std::uint8_t>(i + j + k);
              ++c;
            }
  }
};

template <class A, std::size_t N>
inline void sort_by_lo_network(float* lo, float* hi) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  static constexpr SortingNetwork<N> kNetwork{};
  for (std::size_t c = 0; c < SortingNetwork<N>::kSize; ++c) {
    float* lo_i = lo + kNetwork.first[c] * W;
    float* lo_j = lo + kNetwork.second[c] * W;
    float* hi_i = hi + kNetwork.first[c] * W;
    float* hi_j = hi + kNetwork.second[c] * W;
    const B a = B::load_aligned(lo_i), b = B::load_aligned(lo_j);
    const B ha = B::load_aligned(hi_i), hb = B::load_aligned(hi_j);
    const auto swap = a > b;
    xsimd::min(a, b).store_aligned(lo_i);
    xsimd::max(a, b).store_aligned(lo_j);
    xsimd::select(swap, hb, ha).store_aligned(hi_i);
    xsimd::select(swap, ha, hb).store_aligned(hi_j);
  }
}

// Sorts the pair (lo, hi) arrays by lo, ascending, over `slots` (a power of two) entries.
// A sorting network: its compare-exchange sequence depends only on `slots`, so every
// lane runs the same instructions (no lane branches, unlike insertion sort). Batcher's
// odd-even merge sort needs 1, 5, 19, 63 comparators for 2, 4, 8, 16 slots (bitonic: 1,
// 6, 24, 80), and a tile-light pair keeps 1-4 occluders after culling in the examples.
// Beyond 64 slots a bitonic network is generated on the fly.
template <class A>
inline void sort_by_lo(float* lo, float* hi, std::size_t slots) noexcept {
  switch (slots) {
    case 1: return;
    case 2: return sort_by_lo_network<A, 2>(lo, hi);
    case 4: return sort_by_lo_network<A, 4>(lo, hi);
    case 8: return sort_by_lo_network<A, 8>(lo, hi);
    case 16: return sort_by_lo_network<A, 16>(lo, hi);
    case 32: return sort_by_lo_network<A, 32>(lo, hi);
    case 64: return sort_by_lo_network<A, 64>(lo, hi);
    default: break;
  }
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  for (std::size_t k = 2; k <= slots; k <<= 1) {
    for (std::size_t j = k >> 1; j > 0; j >>= 1) {
      for (std::size_t i = 0; i < slots; ++i) {
        const std::size_t l = i ^ j;
        if (l <= i) continue;
        const B a = B::load_aligned(lo + i * W), b = B::load_aligned(lo + l * W);
        const B ha = B::load_aligned(hi + i * W), hb = B::load_aligned(hi + l * W);
        const bool ascending = (i & k) == 0;
        const auto swap = ascending ? (a > b) : (a < b);
        xsimd::select(swap, b, a).store_aligned(lo + i * W);
        xsimd::select(swap, a, b).store_aligned(lo + l * W);
        xsimd::select(swap, hb, ha).store_aligned(hi + i * W);
        xsimd::select(swap, ha, hb).store_aligned(hi + l * W);
      }
    }
  }
}

// The same network on N intervals held in registers (N = 2 or 4, the common case: a light
// with one to four occluders in front somewhere in the tile), then the union sweep: no
// loads and stores per comparator.
template <class A>
PAR2D_KERNEL_INLINE void compare_exchange(xsimd::batch<float, A>& lo_i, xsimd::batch<float, A>& lo_j,
                                          xsimd::batch<float, A>& hi_i, xsimd::batch<float, A>& hi_j) noexcept {
  using B = xsimd::batch<float, A>;
  const auto swap = lo_i > lo_j;
  const B a = lo_i, ha = hi_i;
  lo_i = xsimd::min(a, lo_j);
  lo_j = xsimd::max(a, lo_j);
  hi_i = xsimd::select(swap, hi_j, ha);
  hi_j = xsimd::select(swap, ha, hi_j);
}

template <class A, std::size_t N, std::size_t... C>
PAR2D_KERNEL_INLINE void sort_in_registers(xsimd::batch<float, A> (&lo)[N], xsimd::batch<float, A> (&hi)[N],
                                           std::index_sequence<C...>) noexcept {
  static constexpr SortingNetwork<N> kNetwork{};
  (compare_exchange<A>(lo[kNetwork.first[C]], lo[kNetwork.second[C]], hi[kNetwork.first[C]], hi[kNetwork.second[C]]),
   ...);
}

// Measure of the union of `count` <= N intervals lo/hi (lane-minor in memory, N slots with
// padding `pad` past count) and [0, reach0].
template <class A, std::size_t N>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> union_measure_in_registers(const float* lo_mem, const float* hi_mem,
                                                                      std::size_t count,
                                                                      const xsimd::batch<float, A>& pad,
                                                                      xsimd::batch<float, A> reach0) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  B lo[N], hi[N];
  for (std::size_t i = 0; i < N; ++i) {
    lo[i] = i < count ? B::load_aligned(lo_mem + i * W) : pad;
    hi[i] = i < count ? B::load_aligned(hi_mem + i * W) : pad;
  }
  sort_in_registers<A, N>(lo, hi, std::make_index_sequence<SortingNetwork<N>::kSize>{});
  B covered = reach0, reach = reach0;
  for (std::size_t i = 0; i < N; ++i) {
    covered += xsimd::max(hi[i] - xsimd::max(lo[i], reach), B(0.0f));
    reach = xsimd::max(reach, hi[i]);
  }
  return covered;
}

// Measure of the union of intervals [lo[i], hi[i]] (i < count, sorted by lo) and [0, reach0]:
// a running-max sweep; each interval adds only the part beyond everything before it.
template <class A>
inline xsimd::batch<float, A> sorted_union_measure(const float* lo, const float* hi, std::size_t count,
                                                   xsimd::batch<float, A> reach0) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  B covered = reach0, reach = reach0;
  for (std::size_t i = 0; i < count; ++i) {
    const B l = B::load_aligned(lo + i * W), h = B::load_aligned(hi + i * W);
    covered += xsimd::max(h - xsimd::max(l, reach), B(0.0f));
    reach = xsimd::max(reach, h);
  }
  return covered;
}

template <class A>
inline std::size_t sort_slots(std::size_t count) noexcept {
  std::size_t slots = 1;
  while (slots < count) slots *= 2;
  return slots;
}

// The distance t_S to the shape's first point along the unit direction (dx, dy) from
// (px, py), for a ray that meets the shape from outside it (reference: ray_entry in
// geometry/convex_shape.cpp).
// `s` must be a whole shape, not a tile tangent pair.
template <class A>
inline xsimd::batch<float, A> shape_ray_entry(const TileWork& work, const KernelShape& s,
                                              const xsimd::batch<float, A>& px, const xsimd::batch<float, A>& py,
                                              const xsimd::batch<float, A>& dx,
                                              const xsimd::batch<float, A>& dy) noexcept {
  using B = xsimd::batch<float, A>;
  if (s.kind == ShapeKind::circle) {
    // From the nearest point p = c + r u (KernelShape): with q = p - x, the entry solves
    // t^2 - 2 b t + excess = 0, b = d.q - r u.d; its smaller root excess / (b + sqrt(b^2 -
    // excess)) does not cancel, so a circle far larger than the tile keeps its precision here.
    const B qx = B(s.px) - px, qy = B(s.py) - py;
    const B b = xsimd::fma(dx, qx, dy * qy) - B(s.r) * xsimd::fma(B(s.ux), dx, B(s.uy) * dy);
    const B excess = circle_excess<A>(s, px, py);
    const B den = b + xsimd::sqrt(xsimd::max(xsimd::fms(b, b, excess), B(0.0f)));
    return xsimd::select(den > B(0.0f), excess / xsimd::select(den > B(0.0f), den, B(1.0f)), b);
  }
  const float* vx = work.vx.data() + s.first;
  const float* vy = work.vy.data() + s.first;
  if (s.kind == ShapeKind::segment) {
    const B ax = B(vx[0]) - px, ay = B(vy[0]) - py;
    const B bx = B(vx[1]) - px, by = B(vy[1]) - py;
    // x + t d on the segment's line n.p = c (edge slot 0, see kernel_shape): t n.d = c - n.x,
    // exact near the tile even where the end points are far.
    const B lnx(work.edge_nx[s.first]), lny(work.edge_ny[s.first]);
    const B den = xsimd::fma(lnx, dx, lny * dy);
    const B num = B(work.edge_c[s.first]) - xsimd::fma(lnx, px, lny * py);
    // Along the segment's own line: the nearer end point.
    const B along = xsimd::max(xsimd::min(xsimd::fma(ax, dx, ay * dy), xsimd::fma(bx, dx, by * dy)), B(0.0f));
    return xsimd::select(den == B(0.0f), along, num / xsimd::select(den == B(0.0f), B(1.0f), den));
  }
  const float* nx = work.edge_nx.data() + s.first;
  const float* ny = work.edge_ny.data() + s.first;
  const float* nc = work.edge_c.data() + s.first;
  // The ray enters the inside half-plane of every edge it moves into (n.d > 0); it is in
  // the polygon from the last of those entries on.
  B t(0.0f);
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const B den = xsimd::fma(B(nx[i]), dx, B(ny[i]) * dy);
    const B num = B(nc[i]) - xsimd::fma(B(nx[i]), px, B(ny[i]) * py);
    const auto entering = den > B(0.0f);
    t = xsimd::select(entering, xsimd::max(t, num / xsimd::select(entering, den, B(1.0f))), t);
  }
  return t;
}

// Sorts `slots` (a power of two) batches of keys ascending, per lane.
template <class A>
inline void sort_keys(float* keys, std::size_t slots) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  if (slots == 2) {
    const B a = B::load_aligned(keys), b = B::load_aligned(keys + W);
    xsimd::min(a, b).store_aligned(keys);
    xsimd::max(a, b).store_aligned(keys + W);
    return;
  }
  for (std::size_t k = 2; k <= slots; k <<= 1) {  // bitonic
    for (std::size_t j = k >> 1; j > 0; j >>= 1) {
      for (std::size_t i = 0; i < slots; ++i) {
        const std::size_t l = i ^ j;
        if (l <= i) continue;
        const B a = B::load_aligned(keys + i * W), b = B::load_aligned(keys + l * W);
        const bool ascending = (i & k) == 0;
        (ascending ? xsimd::min(a, b) : xsimd::max(a, b)).store_aligned(keys + i * W);
        (ascending ? xsimd::max(a, b) : xsimd::min(a, b)).store_aligned(keys + l * W);
      }
    }
  }
}

// Steps of a light's share in packet_irradiance (below), for plain scenes and the model alike.

// A packet's scratch (sized by kernel_packet_scratch_floats): the occluders' arc starts and
// widths, W floats per tile occluder at its tile index (when the packet computes them), then
// a light's interval ends lo and hi (sort slots of the most intervals a light has, each),
// then a general pair's events; `rest` is past the events.
struct PacketScratch {
  float* occ_start = nullptr;
  float* occ_width = nullptr;
  float* lo = nullptr;
  float* hi = nullptr;
  float* events = nullptr;
  float* rest = nullptr;
};
// The intervals' part from `at` on (occ_start and occ_width left null).
template <class A>
PAR2D_KERNEL_INLINE PacketScratch interval_scratch(const TileWork& work, float* at) noexcept {
  constexpr std::size_t W = xsimd::batch<float, A>::size;
  const std::size_t slots = sort_slots<A>(work.max_intervals_per_light);
  PacketScratch out;
  out.lo = at;
  out.hi = at + slots * W;
  out.events = out.hi + slots * W;
  out.rest = out.events + sort_slots<A>(work.max_points_per_pair) * W;
  return out;
}
template <class A>
PAR2D_KERNEL_INLINE PacketScratch packet_scratch_layout(const TileWork& work, float* scratch) noexcept {
  constexpr std::size_t W = xsimd::batch<float, A>::size;
  const std::size_t occluder_count = work.occluders.size();
  PacketScratch out = interval_scratch<A>(work, scratch + 2 * occluder_count * W);
  out.occ_start = scratch;
  out.occ_width = scratch + occluder_count * W;
  return out;
}

// The occluder's arc start measured from the light's, into [0, 2*pi).
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> arc_offset(const xsimd::batch<float, A>& occ_start,
                                                      const xsimd::batch<float, A>& light_start) noexcept {
  using B = xsimd::batch<float, A>;
  B o = occ_start - light_start;
  o -= B(kTwoPiF) * xsimd::floor(o * B(kInvTwoPiF));
  return o;
}

// A light's width seen from the lanes: the whole turn inside it.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> seen_width(const Arc<A>& arc) noexcept {
  using B = xsimd::batch<float, A>;
  return xsimd::select(arc.inside, B(kTwoPiF), arc.width);
}

// The visible width of a light with nothing in front of it anywhere in the tile or cell.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> unblocked_width(const TileWork& work, const KernelShape& light,
                                                           const xsimd::batch<float, A>& px,
                                                           const xsimd::batch<float, A>& py) noexcept {
  return seen_width<A>(shape_arc<A, false>(work, light, px, py));
}

// Each occluder's arc in `count` occluders, the i-th at tile index index(i), stored at that
// index (W floats each) in start_out and width_out; inside(k, lanes) hears which lanes lie
// inside occluder k.
template <class A, class Index, class Inside>
PAR2D_KERNEL_INLINE void packet_occluder_arcs(const TileWork& work, std::size_t count, const Index& index,
                                              const xsimd::batch<float, A>& px, const xsimd::batch<float, A>& py,
                                              float* start_out, float* width_out, Inside&& inside) noexcept {
  constexpr std::size_t W = xsimd::batch<float, A>::size;
  const KernelShape* occluders = work.occluders.data();
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t k = index(i);
    const Arc<A> arc = shape_arc<A>(work, occluders[k], px, py);
    inside(k, arc.inside);
    arc.start.store_aligned(start_out + k * W);
    arc.width.store_aligned(width_out + k * W);
  }
}

// Disjoint convex shapes: the occluder is in front along every shared direction exactly when
// the pixel is on its side of the pair's separating line (everywhere for a `front` pair).
// Lanes in `excluded` are blocked by nothing.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch_bool<float, A> separated_blocks(const KernelPair& pair,
                                                                 const xsimd::batch<float, A>& px,
                                                                 const xsimd::batch<float, A>& py,
                                                                 const xsimd::batch_bool<float, A>& excluded) noexcept {
  using B = xsimd::batch<float, A>;
  return pair.front ? ~excluded : (xsimd::fma(B(pair.nx), px, B(pair.ny) * py) >= B(pair.c)) & ~excluded;
}

// An interval [o, end] of the light's arc [0, width] (o in [0, 2*pi)) where `blocks`, empty
// (width, width) elsewhere: its part before 2*pi, clipped to the arc.
template <class A>
struct BlockedInterval {
  xsimd::batch<float, A> lo, hi;
};
template <class A>
PAR2D_KERNEL_INLINE BlockedInterval<A> first_turn_interval(const xsimd::batch_bool<float, A>& blocks,
                                                           const xsimd::batch<float, A>& o,
                                                           const xsimd::batch<float, A>& end,
                                                           const xsimd::batch<float, A>& width) noexcept {
  return {xsimd::select(blocks, xsimd::min(o, width), width), xsimd::select(blocks, xsimd::min(end, width), width)};
}
// Its part that wraps past the light's start, [0, end - 2*pi] clipped to the arc.
template <class A>
PAR2D_KERNEL_INLINE BlockedInterval<A> wrapped_interval(const xsimd::batch_bool<float, A>& blocks,
                                                        const xsimd::batch<float, A>& end,
                                                        const xsimd::batch<float, A>& width) noexcept {
  using B = xsimd::batch<float, A>;
  return {xsimd::select(blocks, B(0.0f), width),
          xsimd::select(blocks, xsimd::max(xsimd::min(end - B(kTwoPiF), width), B(0.0f)), width)};
}
// The wrapped parts of opaque intervals all start at 0: their union is [0, reach0], a
// running max of their ends.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> wrapped_reach(const xsimd::batch<float, A>& reach0,
                                                         const xsimd::batch_bool<float, A>& blocks,
                                                         const xsimd::batch<float, A>& end,
                                                         const xsimd::batch<float, A>& width) noexcept {
  using B = xsimd::batch<float, A>;
  return xsimd::select(blocks, xsimd::max(reach0, xsimd::min(end - B(kTwoPiF), width)), reach0);
}

// What the n intervals in the lo/hi slots and [0, reach] leave of the arc [0, width] (at
// least 0): in registers up to 8 intervals, else sorted in place (slots past n are padded).
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> uncovered_width(float* lo, float* hi, std::size_t n,
                                                           const xsimd::batch<float, A>& width,
                                                           const xsimd::batch<float, A>& reach) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  if (n == 0) return xsimd::max(width - reach, B(0.0f));
  if (n == 1) return xsimd::max(width - union_measure_in_registers<A, 1>(lo, hi, 1, width, reach), B(0.0f));
  if (n == 2) return xsimd::max(width - union_measure_in_registers<A, 2>(lo, hi, 2, width, reach), B(0.0f));
  if (n <= 4) return xsimd::max(width - union_measure_in_registers<A, 4>(lo, hi, n, width, reach), B(0.0f));
  if (n <= 8) return xsimd::max(width - union_measure_in_registers<A, 8>(lo, hi, n, width, reach), B(0.0f));
  const std::size_t used = sort_slots<A>(n);
  for (std::size_t p = n; p < used; ++p) {  // empty padding sorts last
    width.store_aligned(lo + p * W);
    width.store_aligned(hi + p * W);
  }
  sort_by_lo<A>(lo, hi, used);
  return xsimd::max(width - sorted_union_measure<A>(lo, hi, n, reach), B(0.0f));
}

// e += the light's emission (times `scale`) times `weight`.
template <class A>
PAR2D_KERNEL_INLINE void add_emission(xsimd::batch<float, A> (&e)[3], const KernelLight& light,
                                      const xsimd::batch<float, A>& weight) noexcept {
  using B = xsimd::batch<float, A>;
  for (int c = 0; c < 3; ++c) e[c] = xsimd::fma(B(light.emission[c]), weight, e[c]);
}
template <class A>
PAR2D_KERNEL_INLINE void add_emission(xsimd::batch<float, A> (&e)[3], const KernelLight& light,
                                      const xsimd::batch<float, A>& scale,
                                      const xsimd::batch<float, A>& weight) noexcept {
  using B = xsimd::batch<float, A>;
  for (int c = 0; c < 3; ++c) e[c] = xsimd::fma(B(light.emission[c]) * scale, weight, e[c]);
}

// Blocked intervals of a general pair (shapes that overlap or touch), written to
// lo/hi slots [0, pair.point_count]: the occluder's arc clipped to the light's, cut at the
// directions of the pair's boundary meeting points. For a pixel outside both shapes the
// nearer of the two can change only at those directions (and at the arcs' ends), so a
// depth test along each piece's middle direction decides the whole piece; a piece
// narrower than float can split costs at most its width. Reference: the overlap branch of
// visible_measure in scalar/scalar_renderer.cpp.
template <class A>
inline void general_pair_intervals(const TileWork& work, const KernelLight& light, const KernelPair& pair,
                                   const Arc<A>& arc, const xsimd::batch<float, A>& width,
                                   const xsimd::batch<float, A>& occ_start, const xsimd::batch<float, A>& occ_width,
                                   const xsimd::batch<float, A>& px, const xsimd::batch<float, A>& py, float* events,
                                   float* lo, float* hi) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  // The occluder's arc in the light's frame: [o, o + occ_width], o in [0, 2*pi). Both arcs
  // are narrower than pi outside the shapes, so they share at most one interval: the
  // part before 2*pi, or else the part that wraps past the light's start.
  const B o = arc_offset<A>(occ_start, arc.start);
  const B end = o + occ_width;
  const auto first_turn = o < width;
  const B from = xsimd::select(first_turn, o, B(0.0f));
  const B to = xsimd::max(xsimd::select(first_turn, xsimd::min(end, width), xsimd::min(end - B(kTwoPiF), width)), from);
  const std::uint32_t m = pair.point_count;
  const float* qx = work.point_x.data() + pair.first_point;
  const float* qy = work.point_y.data() + pair.first_point;
  for (std::uint32_t j = 0; j < m; ++j) {
    B a = fast_atan2(B(qy[j]) - py, B(qx[j]) - px) - arc.start;
    a -= B(kTwoPiF) * xsimd::floor(a * B(kInvTwoPiF));
    // Directions outside the interval cut nothing: clamped, they make empty pieces.
    xsimd::min(xsimd::max(a, from), to).store_aligned(events + j * W);
  }
  const std::size_t slots = sort_slots<A>(m);
  if (m > 1) {
    for (std::size_t j = m; j < slots; ++j) to.store_aligned(events + j * W);
    sort_keys<A>(events, slots);
  }
  const KernelShape& occluder = work.occluders[pair.occluder];
  // Inside the light nothing comes first (t_L = 0).
  const auto outside_light = ~arc.inside;
  B prev = from;
  for (std::uint32_t j = 0; j <= m; ++j) {
    const B next = j < m ? B::load_aligned(events + j * W) : to;
    const auto sc = xsimd::sincos(arc.start + B(0.5f) * (prev + next));
    const B t_light = shape_ray_entry<A>(work, light.shape, px, py, sc.second, sc.first);
    const B t_occluder = shape_ray_entry<A>(work, occluder, px, py, sc.second, sc.first);
    // The light is visible only where t_L < t_occ; float ties (shared edges, contact
    // along a line) go to the occluder, as exact ties do.
    const auto blocks = (t_occluder <= t_light * B(1.0f + 1e-5f)) & outside_light;
    xsimd::select(blocks, prev, width).store_aligned(lo + j * W);
    xsimd::select(blocks, next, width).store_aligned(hi + j * W);
    prev = next;
  }
}

using detail::single_pair_light;

// ---- The game lighting model (docs/contract.md section 6): scenes with PreparedScene::model.

// Distance from (px, py) to the closed shape `s` (0 inside), `s` a whole shape. Circles
// from the cancellation-free excess |x - c|^2 - r^2 = (d)(d + 2r).
template <class A>
inline xsimd::batch<float, A> shape_distance(const TileWork& work, const KernelShape& s,
                                             const xsimd::batch<float, A>& px,
                                             const xsimd::batch<float, A>& py) noexcept {
  using B = xsimd::batch<float, A>;
  if (s.kind == ShapeKind::circle) {
    const B excess = xsimd::max(circle_excess<A>(s, px, py), B(0.0f));
    const B r(s.r);
    return excess / (xsimd::sqrt(xsimd::fma(r, r, excess)) + r);
  }
  const std::uint32_t edges = s.kind == ShapeKind::segment ? 1 : s.count;
  B d = xsimd::sqrt(edge_distance2<A>(work, s, edges, px, py));
  if (s.kind == ShapeKind::polygon) {
    const float* nx = work.edge_nx.data() + s.first;
    const float* ny = work.edge_ny.data() + s.first;
    const float* nc = work.edge_c.data() + s.first;
    B outside_by = B(nc[0]) - xsimd::fma(B(nx[0]), px, B(ny[0]) * py);
    for (std::uint32_t i = 1; i < s.count; ++i)
      outside_by = xsimd::max(outside_by, B(nc[i]) - xsimd::fma(B(nx[i]), px, B(ny[i]) * py));
    d = xsimd::select(outside_by <= B(0.0f), B(0.0f), d);
  }
  return d;
}

// sin t for |t| <= pi: folded into [-pi/2, pi/2] (sin t = sin(+-pi - t)), then the Taylor
// polynomial to t^11 (error below 6e-8 there); the lobe integral needs no cosine.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> lobe_sin(const xsimd::batch<float, A>& t) noexcept {
  using B = xsimd::batch<float, A>;
  const B pi(3.14159265358979f), half_pi(1.57079632679490f);
  const B x = xsimd::select(t > half_pi, pi - t, xsimd::select(t < -half_pi, -pi - t, t));
  const B x2 = x * x;
  B p = xsimd::fma(x2, B(-2.50521083854417e-8f), B(2.75573192239859e-6f));
  p = xsimd::fma(x2, p, B(-1.98412698412698e-4f));
  p = xsimd::fma(x2, p, B(8.33333333333333e-3f));
  p = xsimd::fma(x2, p, B(-1.66666666666667e-1f));
  return xsimd::fma(x * x2, p, x);
}

// A light's direction profile in the kernel: the closed forms of lighting/angular_profile.hpp,
// with one copy of a lone cone or lobe instead of three (u - center wrapped into [-pi, pi),
// where the whole support lies, plus whole turns times the profile's total), so a shaded
// evaluation costs one sincos. Cone and shading together take the general form.
// kProfileLobe: a caller that knows the profile is a lone lobe (shading, no cone) compiles
// the sweep without the per-evaluation tests of the profile's kind.
inline constexpr int kProfileAny = 0;
inline constexpr int kProfileLobe = 1;

template <class A>
struct KernelProfile {
  using B = xsimd::batch<float, A>;
  detail::AngularProfile<B> p;
  B total{};  // integral over a whole turn of the lone cone or lobe

  template <int kKind = kProfileAny>
  PAR2D_KERNEL_INLINE B cumulative(const B& u) const noexcept {
    if constexpr (kKind == kProfileLobe) {
      const B v = u - p.lobe_center;
      const B turns = xsimd::floor((v + B(3.14159265358979f)) * B(kInvTwoPiF));
      const B v0 = xsimd::fnma(turns, B(kTwoPiF), v);
      const B t = xsimd::min(xsimd::max(v0, -p.lobe_half), p.lobe_half);
      return xsimd::fma(turns, total, xsimd::fma(p.amplitude, lobe_sin<A>(t), p.offset * t));
    }
    if (p.cookie || (p.cone && p.shading)) return detail::profile_cumulative(p, u);
    if (!p.cone && !p.shading) return u;
    const B v = u - (p.shading ? p.lobe_center : p.cone_center);
    const B turns = xsimd::floor((v + B(3.14159265358979f)) * B(kInvTwoPiF));
    const B v0 = xsimd::fnma(turns, B(kTwoPiF), v);
    if (p.shading) {  // lobe_cumulative of lighting/angular_profile.hpp
      const B t = xsimd::min(xsimd::max(v0, -p.lobe_half), p.lobe_half);
      return xsimd::fma(turns, total, xsimd::fma(p.amplitude, lobe_sin<A>(t), p.offset * t));
    }
    return xsimd::fma(turns, total, detail::profile_detail::trapezoid_cumulative(p, v0));
  }
  bool flat() const noexcept { return !p.cone && !p.shading && !p.cookie; }
};

// One step of the gap sweep over intervals sorted by lo: the gap [reach, max(lo, reach)]
// adds its weight, then reach moves to max(reach, hi). reach_value is always
// profile.cumulative(reach), so a step where no lane's interval starts beyond reach (no gap)
// or ends beyond it (reach stays) skips that evaluation: the same values, bit for bit.
// Intervals of nearby occluders overlap in most lanes of a packet, so many steps skip one.
template <class A, int kKind>
PAR2D_KERNEL_INLINE void profiled_gap_step(const KernelProfile<A>& profile, const xsimd::batch<float, A>& lo,
                                           const xsimd::batch<float, A>& hi, xsimd::batch<float, A>& reach,
                                           xsimd::batch<float, A>& reach_value,
                                           xsimd::batch<float, A>& sum) noexcept {
  using B = xsimd::batch<float, A>;
  B gap_end_value = reach_value;
  if (xsimd::any(lo > reach)) {
    const B gap_end = xsimd::max(lo, reach);
    gap_end_value = profile.template cumulative<kKind>(gap_end);
    sum += gap_end_value - reach_value;
  }
  const auto moves = hi > reach;
  if (xsimd::any(moves)) {
    const B next = xsimd::max(reach, hi);
    reach_value = xsimd::select(moves, profile.template cumulative<kKind>(next), gap_end_value);
    reach = next;
  } else {
    reach_value = gap_end_value;
  }
}

// Weight of the arc [0, width] minus the union of opaque intervals lo/hi (`count`, padded
// to `slots` with `width`), under the profile: the gaps of the sorted intervals.
// The gap sweep over N <= 8 intervals sorted in registers (lo/hi as in union_measure_in_registers).
template <class A, int kKind, std::size_t N>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> profiled_gaps_in_registers(const KernelProfile<A>& profile,
                                                                      const float* lo_mem, const float* hi_mem,
                                                                      std::size_t count,
                                                                      const xsimd::batch<float, A>& width,
                                                                      const xsimd::batch<float, A>& reach0) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  B lo[N], hi[N];
  for (std::size_t i = 0; i < N; ++i) {
    lo[i] = i < count ? B::load_aligned(lo_mem + i * W) : width;
    hi[i] = i < count ? B::load_aligned(hi_mem + i * W) : width;
  }
  sort_in_registers<A, N>(lo, hi, std::make_index_sequence<SortingNetwork<N>::kSize>{});
  B reach = reach0, reach_value = profile.template cumulative<kKind>(reach), sum(0.0f);
  for (std::size_t i = 0; i < count; ++i) {  // padding sorts last and adds nothing
    profiled_gap_step<A, kKind>(profile, lo[i], hi[i], reach, reach_value, sum);
  }
  sum += profile.template cumulative<kKind>(xsimd::max(width, reach)) - reach_value;
  return xsimd::max(sum, B(0.0f));
}

template <class A, int kKind>
inline xsimd::batch<float, A> profiled_gaps_of_kind(const KernelProfile<A>& profile, float* lo, float* hi,
                                                    std::size_t count, const xsimd::batch<float, A>& width,
                                                    const xsimd::batch<float, A>& reach0) noexcept {
  if (count == 1) return profiled_gaps_in_registers<A, kKind, 1>(profile, lo, hi, count, width, reach0);
  if (count == 2) return profiled_gaps_in_registers<A, kKind, 2>(profile, lo, hi, count, width, reach0);
  if (count <= 4) return profiled_gaps_in_registers<A, kKind, 4>(profile, lo, hi, count, width, reach0);
  if (count <= 8) return profiled_gaps_in_registers<A, kKind, 8>(profile, lo, hi, count, width, reach0);
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  const std::size_t used = sort_slots<A>(count);
  for (std::size_t p = count; p < used; ++p) {
    width.store_aligned(lo + p * W);
    width.store_aligned(hi + p * W);
  }
  sort_by_lo<A>(lo, hi, used);
  // The gaps between the covered parts, from the part [0, reach0] that wraps past 0.
  B reach = reach0, reach_value = profile.template cumulative<kKind>(reach), sum(0.0f);
  for (std::size_t i = 0; i < count; ++i)
    profiled_gap_step<A, kKind>(profile, B::load_aligned(lo + i * W), B::load_aligned(hi + i * W), reach, reach_value,
                                sum);
  sum += profile.template cumulative<kKind>(xsimd::max(width, reach)) - reach_value;
  return xsimd::max(sum, B(0.0f));
}

template <class A>
inline xsimd::batch<float, A> profiled_gaps(const KernelProfile<A>& profile, float* lo, float* hi, std::size_t count,
                                            const xsimd::batch<float, A>& width,
                                            const xsimd::batch<float, A>& reach0) noexcept {
  if (profile.p.shading && !profile.p.cone && !profile.p.cookie)
    return profiled_gaps_of_kind<A, kProfileLobe>(profile, lo, hi, count, width, reach0);
  return profiled_gaps_of_kind<A, kProfileAny>(profile, lo, hi, count, width, reach0);
}

// Per channel, the integral over [0, width] of the product of the transmittances of the
// intervals covering each direction, under the profile: the interval ends sorted into
// elementary pieces, each piece's product taken at its middle (an end lies on no piece's inside).
template <class A>
inline void translucent_pieces(const TileWork& work, const KernelProfile<A>& profile, const float* lo, const float* hi,
                               const float* owner, std::size_t count, const xsimd::batch<float, A>& width,
                               float* keys, xsimd::batch<float, A> (&visible)[3]) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  const std::size_t key_count = 2 * count + 2;
  const std::size_t slots = sort_slots<A>(key_count);
  B(0.0f).store_aligned(keys);
  for (std::size_t i = 0; i < count; ++i) {
    B::load_aligned(lo + i * W).store_aligned(keys + (2 * i + 1) * W);
    B::load_aligned(hi + i * W).store_aligned(keys + (2 * i + 2) * W);
  }
  for (std::size_t k = 2 * count + 1; k < slots; ++k) width.store_aligned(keys + k * W);
  sort_keys<A>(keys, slots);
  for (int c = 0; c < 3; ++c) visible[c] = B(0.0f);
  B prev = B::load_aligned(keys);
  B prev_value = profile.cumulative(prev);
  for (std::size_t k = 1; k < key_count; ++k) {
    const B next = B::load_aligned(keys + k * W);
    const B next_value = profile.cumulative(next);
    const B mid = B(0.5f) * (prev + next);
    B t[3] = {B(1.0f), B(1.0f), B(1.0f)};
    for (std::size_t i = 0; i < count; ++i) {
      const auto covers = (B::load_aligned(lo + i * W) < mid) & (mid < B::load_aligned(hi + i * W));
      const KernelOccluderTerms& terms = work.occluder_terms[static_cast<std::size_t>(owner[i])];
      if (terms.opaque) {
        for (int c = 0; c < 3; ++c) t[c] = xsimd::select(covers, B(0.0f), t[c]);
      } else {
        for (int c = 0; c < 3; ++c) t[c] = xsimd::select(covers, t[c] * B(terms.transmittance[c]), t[c]);
      }
    }
    const B piece = xsimd::max(next_value - prev_value, B(0.0f));
    for (int c = 0; c < 3; ++c) visible[c] = xsimd::fma(t[c], piece, visible[c]);
    prev = next;
    prev_value = next_value;
  }
}

// A shaded light with nothing in front anywhere in the tile (no pairs, no cone, not clipped)
// whose lobe covers every direction in every lane (C >= A: s = A cos(theta - beta) + C > 0 on
// the whole turn): the integral over the arc [th1, th2] is A [sin(th2 - beta) - sin(th1 - beta)]
// + C width, and A sin(th - beta) = cos(el) cross(v, n_xy) / |v| for a tangent vector v, so
// neither the arc's start angle nor beta nor a polynomial sine is needed. Inside: 2 pi C.
constexpr float kTinyF = 1e-30f;

template <class A>
PAR2D_KERNEL_INLINE void shaded_unblocked_light(const TileWork& work, const KernelLight& light,
                                                const xsimd::batch<float, A>& px, const xsimd::batch<float, A>& py,
                                                const xsimd::batch<float, A>& nx, const xsimd::batch<float, A>& ny,
                                                const xsimd::batch<float, A>& c_term,
                                                const xsimd::batch<float, A>& cos_el,
                                                const xsimd::batch<float, A>& window,
                                                xsimd::batch<float, A> (&e)[3]) noexcept {
  using B = xsimd::batch<float, A>;
  const KernelShape& s = light.shape;
  B lobe, width;
  xsimd::batch_bool<float, A> inside;
  if (s.kind == ShapeKind::circle) {
    // Tangent vectors (d t +- perp(d) r) of length |d|^2 = excess + r^2: their difference is
    // 2 r perp(d), so the sine difference is 2 r (d . n_xy) / |d|^2.
    const B excess = circle_excess<A>(s, px, py);
    inside = excess <= B(0.0f);
    const B room = xsimd::max(excess, B(0.0f));
    const B r(s.r);
    const B half = fast_atan2_first_quadrant(r, xsimd::sqrt(room));
    width = half + half;
    const B dx = B(s.cx) - px, dy = B(s.cy) - py;
    lobe = cos_el * B(2.0f * s.r) * xsimd::fma(dx, nx, dy * ny) / xsimd::max(xsimd::fma(r, r, room), B(kTinyF));
  } else {
    B lox, loy, hix, hiy;
    vertex_tangents<A>(work, s, px, py, lox, loy, hix, hiy, inside);
    Arc<A> arc;
    arc_from_tangents<A, false>(lox, loy, hix, hiy, arc);
    width = arc.width;
    // A lane on an end (|v| = 0, cross 0) takes 0 rather than 0/0.
    const B sin_hi = xsimd::fms(hiy, nx, hix * ny) / xsimd::max(xsimd::sqrt(xsimd::fma(hix, hix, hiy * hiy)), B(kTinyF));
    const B sin_lo = xsimd::fms(loy, nx, lox * ny) / xsimd::max(xsimd::sqrt(xsimd::fma(lox, lox, loy * loy)), B(kTinyF));
    lobe = cos_el * (sin_hi - sin_lo);
  }
  const B visible = xsimd::select(inside, B(kTwoPiF) * c_term, xsimd::fma(c_term, width, lobe));
  add_emission<A>(e, light, xsimd::max(visible, B(0.0f)) * window);
}

// ---- The packet kernel: one body for plain scenes and the game lighting model.

// Which packet kernel packet_irradiance compiles. PlainPacket, for plain scenes: kCells takes
// the lights and pairs of the packet's cell (`cell`, see KernelCell), else the tile's;
// kTileArcs reads occluder arcs computed beforehand (TileArcs), else the packet computes
// them. ModelPacket, for the game lighting model (docs/contract.md section 6): every
// game-model tile has cells, one over the whole tile where it keeps the tile's lists
// (cell_lists.cpp); kShaded weighs directions by the pixel's normal.
template <bool kCellLists, bool kArcPlanes>
struct PlainPacket {
  static constexpr bool kModel = false, kCells = kCellLists, kTileArcs = kArcPlanes, kShaded = false;
};
template <bool kNormals>
struct ModelPacket {
  static constexpr bool kModel = true, kCells = true, kTileArcs = false, kShaded = kNormals;
};

// What a plain scene's lights and occluders are in the model's terms (read only under kModel).
inline constexpr KernelLightTerms kPlainLightTerms{};
inline constexpr KernelOccluderTerms kPlainOccluderTerms{};

// The occluder arcs of a plain tile computed beforehand, for the whole tile (see
// render_plain_tile_shape_major) or with kCells for the packet's cell (render_plain_cell_tile):
// the packet's view of them.
template <class A>
struct TileArcs {
  const float* start = nullptr;  // occluder k's start angles at start[k * kTilePixels]
  const float* width = nullptr;
  const float* inside = nullptr;  // 1 where a lane is inside some occluder, else 0
  // Without cells: the irradiance of the lights without pairs and of the single-pair lights
  // (summed beforehand); the packet computes only the lights listed in `lights` (work.lights
  // indices). With cells, unused: the packet computes its cell's lights.
  const float* unblocked[3] = {nullptr, nullptr, nullptr};
  const std::uint32_t* lights = nullptr;
  std::size_t light_count = 0;
};

// Lanes where the occluder's interval [o, end] of a light's arc [0, width] is kept: it blocks
// there and has a first-turn part or a part that wraps past the light's start.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch_bool<float, A> meets_arc(const xsimd::batch_bool<float, A>& blocks,
                                                          const xsimd::batch<float, A>& o,
                                                          const xsimd::batch<float, A>& end,
                                                          const xsimd::batch<float, A>& width) noexcept {
  using B = xsimd::batch<float, A>;
  return blocks & ((o < width) | (end > B(kTwoPiF)));
}

// Irradiance (times 1/(2*pi), folded into the emissions) of one packet at (px, py), whose
// first pixel is tile pixel `pixel`, written to e. Per light: its arc, the blocked intervals
// of the occluders in front of it, then what they leave of the arc, times the emission.
// Under the model (reference: the scalar renderer's model path) a directional light has a
// fixed arc, a range window scales the light, lit-interior occluders are dropped where the
// lane is inside them and a dark one containing the lane covers the whole arc, and the
// visible set weighs by the union measure when every occluder is opaque and the profile is
// flat, else by the profile's integral over the gaps, or over every elementary piece times
// its transmittances. `tile_arcs`: with Terms::kTileArcs, the arcs computed beforehand.
template <class A, class Terms>
PAR2D_KERNEL_INLINE void packet_irradiance(const TileWork& work, const detail::KernelCell* cell,
                                           const xsimd::batch<float, A>& px, const xsimd::batch<float, A>& py,
                                           std::size_t pixel, float* scratch, xsimd::batch<float, A> (&e)[3],
                                           const TileArcs<A>& tile_arcs = {}) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  constexpr bool kModel = Terms::kModel, kCells = Terms::kCells, kTileArcs = Terms::kTileArcs;
  constexpr bool kShaded = Terms::kShaded;
  const PacketScratch room = kTileArcs ? interval_scratch<A>(work, scratch) : packet_scratch_layout<A>(work, scratch);
  const float* occ_start_all;
  const float* occ_width;
  // Between occluders' arcs: a constant, so that a pair's arc address is a shift and an add.
  constexpr std::size_t occ_stride = kTileArcs ? detail::kTilePixels : W;
  float* const lo = room.lo;
  float* const hi = room.hi;
  float* const events = room.events;
  // The model's, past the shared part: inside flags per occluder, the pieces' keys, the
  // intervals' owners (one float per interval, tile-constant).
  float* const occ_inside = room.rest;
  float* keys = nullptr;
  float* owner = nullptr;
  if constexpr (kModel) {
    std::size_t key_slots = 1;
    while (key_slots < 2 * static_cast<std::size_t>(work.max_intervals_per_light) + 2) key_slots *= 2;
    keys = occ_inside + work.occluders.size() * W;
    owner = keys + 2 * key_slots * W;
  }
  // The model reads the work's arrays through local pointers: a vector store may alias
  // anything (the intrinsics' types do), so `work.pairs[i]` would reload the vector's start
  // after each. The plain kernel reads them through `work`: held across its loops, the
  // pointers cost it more than the reloads (docs/performance.md).
  const KernelLight* lights = work.lights.data();
  const KernelLightTerms* light_terms = work.light_terms.data();
  const KernelOccluderTerms* occluder_terms = work.occluder_terms.data();
  const KernelPair* cell_pairs = work.cell_pairs.data();

  auto in_occluder = B(0.0f) > B(0.0f);  // plain: the lanes inside some occluder
  std::size_t arcs = work.occluders.size();
  if constexpr (kTileArcs) {
    occ_start_all = tile_arcs.start;
    occ_width = tile_arcs.width;
    in_occluder = B::load_aligned(tile_arcs.inside) != B(0.0f);
  } else {
    occ_start_all = room.occ_start;
    occ_width = room.occ_width;
    // Arcs are stored at the occluder's tile index; a cell computes only those its pairs read
    // (and those whose inside test it needs, see cell_lists.cpp).
    if constexpr (kCells) arcs = cell->occluder_count;
    const std::uint32_t* cell_occluders = kCells ? work.cell_occluders.data() + cell->first_occluder : nullptr;
    packet_occluder_arcs<A>(
        work, arcs, [&](std::size_t i) { return kCells ? std::size_t{cell_occluders[i]} : i; }, px, py,
        room.occ_start, room.occ_width, [&](std::size_t k, const xsimd::batch_bool<float, A>& inside) {
          // The model's interiors act per light; the plain kernel needs their union only.
          if constexpr (kModel) {
            xsimd::select(inside, B(1.0f), B(0.0f)).store_aligned(occ_inside + k * W);
          } else {
            in_occluder = in_occluder | inside;
          }
        });
  }
  if constexpr (kModel) {
    for (int c = 0; c < 3; ++c) e[c] = B(work.ambient[c]);
  } else {
    for (int c = 0; c < 3; ++c) e[c] = B(0.0f);
    // Every lane inside an occluder: 0 whatever the lights (the select at the end).
    if (arcs != 0 && xsimd::all(in_occluder)) return;
    if constexpr (kTileArcs && !kCells)
      for (int c = 0; c < 3; ++c) e[c] = B::load_aligned(tile_arcs.unblocked[c]);
  }
  B beta, normal_xy, normal_z, nx_raw, ny_raw;
  if constexpr (kShaded) {
    const std::size_t at = pixel / detail::kTileSize * work.normal_stride + pixel % detail::kTileSize;
    const B nx = B::load_unaligned(work.normal_plane[0] + at), ny = B::load_unaligned(work.normal_plane[1] + at);
    nx_raw = nx;
    ny_raw = ny;
    beta = fast_atan2(ny, nx);
    normal_xy = xsimd::sqrt(xsimd::fma(nx, nx, ny * ny));
    normal_z = B::load_unaligned(work.normal_plane[2] + at);
  }
  const auto none = B(0.0f) > B(0.0f);
  // The lobe of the pixel's normal for the last elevation seen (lights mostly share one):
  // its half width needs an acos, its total a square root.
  detail::AngularProfile<B> lobe;
  KernelProfile<A> profile;  // set per light (constructing one per light costs as much as using it)
  B lobe_total;
  double lobe_sin = 2.0, lobe_cos = 2.0;
  // One light's share, inlined into the loops over the lights below.
  auto add_light = [&](std::size_t l, const KernelPair* pairs, std::size_t pair_count) PAR2D_KERNEL_LAMBDA_INLINE {
    const KernelLight& light = kModel ? lights[l] : work.lights[l];
    const KernelLightTerms& terms = kModel ? light_terms[l] : kPlainLightTerms;
    B window(1.0f);
    if (kModel && terms.ranged) {
      window = detail::range_window(shape_distance<A>(work, light.shape, px, py), B(terms.range), terms.falloff,
                                    [&](const B& base) { return xsimd::pow(base, B(terms.falloff)); });
      if (!xsimd::any(window > B(0.0f))) return;
    }
    // Nothing in front of this light anywhere in the tile (or cell) and a flat profile: the
    // width alone (the plain kernel's lights in tile_arcs have pairs).
    if (kModel ? !kShaded && !terms.weighted() && pair_count == 0 && !terms.directional
               : (kCells || !kTileArcs) && pair_count == 0) {
      if constexpr (kModel) {
        add_emission<A>(e, light, window, unblocked_width<A>(work, light.shape, px, py));
      } else {
        add_emission<A>(e, light, unblocked_width<A>(work, light.shape, px, py));
      }
      return;
    }
    if constexpr (kShaded) {
      if (!terms.weighted() && pair_count == 0 && !terms.directional && !light.shape.clipped) {
        const B c_term = B(static_cast<float>(terms.sin_elevation)) * normal_z;
        const B cos_el(static_cast<float>(terms.cos_elevation));
        if (xsimd::all(c_term >= cos_el * normal_xy)) {
          shaded_unblocked_light<A>(work, light, px, py, nx_raw, ny_raw, c_term, cos_el, window, e);
          return;
        }
      }
    }
    // A directional light's arc is fixed (and never holds the lane). Initialized, not assigned:
    // an assigned arc went through memory in the plain kernel.
    const bool directional = kModel && terms.directional;
    const Arc<A> arc = directional ? Arc<A>{B(terms.dir_start), B(terms.dir_width), none}
                                   : shape_arc<A>(work, light.shape, px, py);
    const B width = directional ? arc.width : seen_width<A>(arc);
    // Translucent pieces need each wrapped part as an interval of its own; opaque ones all
    // start at 0 and merge into [0, reach0].
    const bool split_wraps = kModel && terms.translucent;
    B reach0(0.0f);
    auto dark_inside = none;  // model: in an opaque dark occluder acting on the light, it contributes 0
    std::size_t n = 0;  // intervals written
    for (std::size_t p = 0; p < pair_count; ++p) {
      const KernelPair& pair = pairs[p];
      const KernelOccluderTerms& occ_terms = kModel ? occluder_terms[pair.occluder] : kPlainOccluderTerms;
      const B occ_start = B::load_aligned(occ_start_all + pair.occluder * occ_stride);
      const B occ_w = B::load_aligned(occ_width + pair.occluder * occ_stride);
      const auto in_occ = kModel ? B::load_aligned(occ_inside + pair.occluder * W) > B(0.0f) : none;
      if (pair.general) {
        general_pair_intervals<A>(work, light, pair, arc, width, occ_start, occ_w, px, py, events, lo + n * W,
                                  hi + n * W);
        if constexpr (kModel) {
          // Inside the occluder: a lit interior is absent, a dark one covers every direction
          // once (the first piece becomes [0, width], the others empty).
          for (std::uint32_t j = 0; j <= pair.point_count; ++j) {
            float* l_slot = lo + (n + j) * W;
            float* h_slot = hi + (n + j) * W;
            const B inside_lo = occ_terms.lit_interior || j > 0 ? width : B(0.0f);
            xsimd::select(in_occ, inside_lo, B::load_aligned(l_slot)).store_aligned(l_slot);
            xsimd::select(in_occ, width, B::load_aligned(h_slot)).store_aligned(h_slot);
            owner[n + j] = static_cast<float>(pair.occluder);
          }
        }
        n += pair.point_count + 1;
        continue;
      }
      // Inside the light nothing is in front (t_L = 0); a directional light's occluders are in
      // front wherever they are seen. Lanes inside an occluder get 0 at the end (the plain
      // kernel's select, the model's dark_inside), so what their intervals say does not matter.
      auto blocks = directional
                        ? ~none
                        : separated_blocks<A>(pair, px, py, kModel ? arc.inside : arc.inside | in_occluder);
      const B o = arc_offset<A>(occ_start, arc.start);
      const B end = o + occ_w;
      const bool opaque_dark = !kModel || (occ_terms.opaque && !occ_terms.lit_interior);
      if (opaque_dark) {
        if constexpr (kModel) dark_inside = dark_inside | in_occ;
        if (!split_wraps) {
          reach0 = wrapped_reach<A>(reach0, blocks, end, width);
          // With cells (plain tiles with many pairs): an interval starting inside the blocked
          // prefix [0, reach0] extends it, so several occluders that together span the light's
          // arc end its work too when they arrive in order of their starts (their candidates
          // are ordered by angle per block, see order_by_angle in render/block_culling.cpp).
          // Elsewhere lights have a pair or two and this costs more than it saves.
          if constexpr (kCells && !kModel)
            reach0 = xsimd::select(blocks & (o <= reach0), xsimd::max(reach0, xsimd::min(end, width)), reach0);
          // A blocked prefix spanning the light's arc in every lane (one opaque occluder that
          // starts before the light's arc and ends past it, or with plain cells such a chain;
          // or the lane inside an occluder) hides the light there: the union is the whole arc
          // whatever the other intervals, and the light adds exactly 0 under any profile and
          // window, so the rest of its work is skipped.
          if (xsimd::all((reach0 >= width) | (kModel ? dark_inside : in_occluder))) return;
          // An interval empty in every lane (not in front, or seen outside the light's arc)
          // adds nothing: not kept, so the sort and sweep run over the intervals this packet
          // really sees. Stored in any case and counted only when kept: whether a pair is
          // kept varies from packet to packet without pattern, and a branch on it is
          // mispredicted often enough to cost a fifth of the kernel's time where pairs are
          // many (docs/performance.md). The plain kernel keeps intervals with a first-turn
          // part (the wrap is in reach0), the model also those whose only part is the wrap.
          const BlockedInterval<A> interval = first_turn_interval<A>(blocks, o, end, width);
          interval.lo.store_aligned(lo + n * W);
          interval.hi.store_aligned(hi + n * W);
          if constexpr (kModel) {
            n += xsimd::any(meets_arc<A>(blocks, o, end, width)) ? 1 : 0;
          } else {
            n += xsimd::any(interval.hi > interval.lo) ? 1 : 0;
          }
          continue;
        }
      }
      if constexpr (kModel) {
        // Each part with its owner. A translucent dark occluder around the lane covers every
        // direction once; a lit one is absent there (an opaque dark one is 0 there already:
        // dark_inside).
        const auto whole = occ_terms.lit_interior || opaque_dark ? none : in_occ;
        if (!opaque_dark) blocks = blocks & ~in_occ;
        if (!xsimd::any(whole | meets_arc<A>(blocks, o, end, width))) continue;
        const BlockedInterval<A> interval = first_turn_interval<A>(blocks, o, end, width);
        xsimd::select(whole, B(0.0f), interval.lo).store_aligned(lo + n * W);
        xsimd::select(whole, width, interval.hi).store_aligned(hi + n * W);
        owner[n] = static_cast<float>(pair.occluder);
        ++n;
        // The part that wraps past the arc's start.
        if (!split_wraps) {
          reach0 = wrapped_reach<A>(reach0, blocks, end, width);
          continue;
        }
        const BlockedInterval<A> wrapped = wrapped_interval<A>(blocks, end, width);
        wrapped.lo.store_aligned(lo + n * W);
        wrapped.hi.store_aligned(hi + n * W);
        owner[n] = static_cast<float>(pair.occluder);
        ++n;
      }
    }
    if constexpr (!kModel) {
      add_emission<A>(e, light, uncovered_width<A>(lo, hi, n, width, xsimd::max(reach0, B(0.0f))));
    } else {
      profile.p.cone = terms.cone;
      profile.p.cookie = nullptr;
      if (terms.cookie) {
        detail::set_profile_cookie(profile.p, arc.start, terms.cookie);
      } else if (terms.cone) {
        detail::set_profile_cone(profile.p, arc.start, terms.cone_center, terms.cone_half, terms.cone_fade);
        profile.total = profile.p.half + profile.p.plateau;
      }
      if constexpr (kShaded) {
        if (terms.sin_elevation != lobe_sin || terms.cos_elevation != lobe_cos) {
          detail::set_profile_shading(lobe, B(0.0f), beta, normal_xy, normal_z, terms.sin_elevation,
                                      terms.cos_elevation);
          // Over a whole turn: 2 (A sin h + C h), with A sin h = sqrt(A^2 - C^2) where the lobe is partial.
          const B a = lobe.amplitude, c = lobe.offset;
          const B a_sin = xsimd::select(xsimd::abs(c) < a, xsimd::sqrt(xsimd::max(xsimd::fms(a, a, c * c), B(0.0f))),
                                        B(0.0f));
          lobe_total = B(2.0f) * xsimd::fma(c, lobe.lobe_half, a_sin);
          lobe_sin = terms.sin_elevation;
          lobe_cos = terms.cos_elevation;
        }
        profile.p.shading = true;
        profile.p.amplitude = lobe.amplitude;
        profile.p.offset = lobe.offset;
        profile.p.lobe_half = lobe.lobe_half;
        profile.p.lobe_center = detail::profile_wrap(beta - arc.start);
        profile.total = lobe_total;
      }
      if (terms.translucent) {
        B visible[3];
        translucent_pieces<A>(work, profile, lo, hi, owner, n, width, keys, visible);
        // Clamped as below.
        for (int c = 0; c < 3; ++c)
          e[c] = xsimd::fma(B(light.emission[c]) * window,
                            xsimd::select(dark_inside, B(0.0f), xsimd::max(visible[c], B(0.0f))), e[c]);
        return;
      }
      B visible;
      const B reach = xsimd::max(reach0, B(0.0f));
      if (!profile.flat()) {
        if (kShaded && !terms.weighted() && n == 1) {
          // The commonest shaded cases inline: a call spills every live register of the kernel.
          visible = profiled_gaps_in_registers<A, kProfileLobe, 1>(profile, lo, hi, n, width, reach);
        } else if (kShaded && !terms.weighted() && n == 2) {
          visible = profiled_gaps_in_registers<A, kProfileLobe, 2>(profile, lo, hi, n, width, reach);
        } else if (n > 0) {
          visible = profiled_gaps<A>(profile, lo, hi, n, width, reach);
        } else if (kShaded && !terms.weighted()) {
          visible =
              profile.template cumulative<kProfileLobe>(width) - profile.template cumulative<kProfileLobe>(B(0.0f));
        } else {
          visible = profile.cumulative(width) - profile.cumulative(B(0.0f));
        }
        // Differences of the antiderivative over an arc narrower than float's angle steps (a
        // tiny light far away, ~1e-6 rad) can round below 0; the integrand is not.
        visible = xsimd::max(visible, B(0.0f));
      } else if (n == 0) {
        visible = width;  // reach0 grows only with a kept interval
      } else {
        visible = uncovered_width<A>(lo, hi, n, width, reach);
      }
      visible = xsimd::select(dark_inside, B(0.0f), visible);
      add_emission<A>(e, light, window, visible);
    }
  };
  if constexpr (kCells) {
    const detail::KernelCellLight* cell_lights = work.cell_lights.data() + cell->first_light;
    for (std::size_t i = 0; i < cell->light_count; ++i)
      add_light(cell_lights[i].light, (kModel ? cell_pairs : work.cell_pairs.data()) + cell_lights[i].first_pair,
                cell_lights[i].pair_count);
  } else if constexpr (kTileArcs) {
    for (std::size_t i = 0; i < tile_arcs.light_count; ++i) {
      const std::size_t l = tile_arcs.lights[i];
      add_light(l, work.pairs.data() + work.lights[l].first_pair, work.lights[l].pair_count);
    }
  } else {
    for (std::size_t l = 0; l < work.lights.size(); ++l)
      add_light(l, work.pairs.data() + work.lights[l].first_pair, work.lights[l].pair_count);
  }
  if constexpr (!kModel)
    for (int c = 0; c < 3; ++c) e[c] = xsimd::select(in_occluder, B(0.0f), e[c]);
}

// The cell of the packet whose first pixel is tile pixel `first` (a cell is whole packets wide).
inline const detail::KernelCell* packet_cell(const TileWork& work, std::size_t first) noexcept {
  const std::size_t row = first / detail::kTileSize, column = first % detail::kTileSize;
  const std::size_t width = static_cast<std::size_t>(work.cell_width);
  const std::size_t height = static_cast<std::size_t>(work.cell_height);
  return &work.cells[row / height * (detail::kTileSize / width) + column / width];
}

// The tile's packets one at a time, each the mean over the work's samples of
// packet_irradiance (with cells, from the packet's cell's lists): the model kernel, and the
// plain one where it keeps no arc planes.
template <class A, class Terms>
void render_packets(const TileWork& work, float* scratch, TileResult& out) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  const B inv_spp(1.0f / static_cast<float>(work.spp));
  for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
    const detail::KernelCell* cell = Terms::kCells ? packet_cell(work, first) : nullptr;
    B sum[3] = {B(0.0f), B(0.0f), B(0.0f)};
    for (int s = 0; s < work.spp; ++s) {
      const B px = B::load_unaligned(work.sample_x.data() + s * detail::kTileSize + first % detail::kTileSize);
      const B py(work.sample_y[s * detail::kTileSize + first / detail::kTileSize]);
      B e[3];
      packet_irradiance<A, Terms>(work, cell, px, py, first, scratch, e);
      for (int c = 0; c < 3; ++c) sum[c] += e[c];
    }
    for (int c = 0; c < 3; ++c) {
      const B mean = work.spp == 1 ? sum[c] : sum[c] * inv_spp;  // the same bits: inv_spp is 1 then
      mean.store_aligned(out.rgb[c] + first);
    }
  }
}

// Calls f(known), `known` a copy of `s` whose kind and flags are set from constants in each
// branch, so that a shape loop inlined into f folds shape_arc's tests on them away.
template <class F>
PAR2D_KERNEL_INLINE void with_known_kind(const KernelShape& s, F&& f) {
  auto as = [&](ShapeKind kind, bool ordered, bool may_contain) PAR2D_KERNEL_LAMBDA_INLINE {
    KernelShape known = s;
    known.kind = kind;
    known.ordered = ordered;
    known.may_contain = may_contain;
    known.clipped = false;
    f(known);
  };
  if (s.clipped) {  // a light overlapping a wall: out of line anyway
    f(s);
  } else if (s.kind == ShapeKind::circle) {
    as(ShapeKind::circle, false, true);
  } else if (s.kind == ShapeKind::segment) {
    if (s.ordered) as(ShapeKind::segment, true, false);
    else as(ShapeKind::segment, false, false);
  } else if (s.may_contain) {
    as(ShapeKind::polygon, false, true);
  } else {
    as(ShapeKind::polygon, false, false);
  }
}

// Whether a kernel shape may hold some of the tile's pixels (segments and polygons whose box
// misses the tile hold none): known per instantiation inside with_known_kind.
PAR2D_KERNEL_INLINE bool may_hold_pixels(const KernelShape& s) noexcept {
  return s.kind == ShapeKind::circle || (s.kind == ShapeKind::polygon && s.may_contain);
}

// Every occluder's arc over every pixel center of the tile, one occluder at a time: the
// shape's kind, vertex range and flags are read and branched on once per tile instead of
// once per packet, and its loop over the packets is straight code. Arcs go to
// scratch[k * kTilePixels + pixel] (start, then width), inside flags to one plane after them.
// Occluders whose only pairs belong to single-pair lights (arc_users[k] == kSinglePairUse)
// are skipped: tile_single_pair_lights needs no arc and sets their inside flags itself.
inline constexpr unsigned char kSinglePairUse = 1, kPacketUse = 2;

// Calls sweep(arc_of, may_hold_pixels) with arc_of(px, py) the occluder's arc with its
// tile-constant branches taken here (its window, kind and flags: shape_arc's own tests then
// fold away in each instantiation, and so does the inside flag of a shape that holds no pixel).
template <class A, class Sweep>
PAR2D_KERNEL_INLINE void with_known_arc(const TileWork& work, const KernelShape& s, Sweep&& sweep) {
  using B = xsimd::batch<float, A>;
  if (s.window >= 0) {
    with_known_kind(s, [&](const KernelShape& known) PAR2D_KERNEL_LAMBDA_INLINE {
      sweep([&](const B& px, const B& py)
                PAR2D_KERNEL_LAMBDA_INLINE { return windowed_shape_arc<A>(work, known, px, py); },
            may_hold_pixels(known));
    });
    return;
  }
  with_known_kind(s, [&](const KernelShape& known) PAR2D_KERNEL_LAMBDA_INLINE {
    sweep([&](const B& px, const B& py) PAR2D_KERNEL_LAMBDA_INLINE { return shape_arc<A>(work, known, px, py); },
          may_hold_pixels(known));
  });
}

template <class A>
PAR2D_KERNEL_NOINLINE void tile_occluder_arcs(const TileWork& work, const unsigned char* arc_users, float* start,
                                              float* width, float* inside) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data();
  const float* sample_y = work.sample_y.data();
  for (std::size_t first = 0; first < detail::kTilePixels; first += W) B(0.0f).store_aligned(inside + first);
  const std::size_t count = work.occluders.size();
  for (std::size_t k = 0; k < count; ++k) {
    if (arc_users[k] == kSinglePairUse) continue;
    const KernelShape& s = work.occluders[k];
    float* start_k = start + k * detail::kTilePixels;
    float* width_k = width + k * detail::kTilePixels;
    auto sweep = [&](auto arc_of, bool may_hold_pixels) PAR2D_KERNEL_LAMBDA_INLINE {
      for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
        const B px = B::load_unaligned(sample_x + first % detail::kTileSize);
        const B py(sample_y[first / detail::kTileSize]);
        const Arc<A> arc = arc_of(px, py);
        arc.start.store_aligned(start_k + first);
        arc.width.store_aligned(width_k + first);
        if (may_hold_pixels) {
          const B was = B::load_aligned(inside + first);
          xsimd::select(arc.inside, B(1.0f), was).store_aligned(inside + first);
        }
      }
    };
    with_known_arc<A>(work, s, sweep);
  }
}

// A cell's width and height for packets of W lanes (detail::cell_width_for, which the setup
// uses to make the cells).
template <std::size_t W>
inline constexpr std::size_t kCellWidth = static_cast<std::size_t>(detail::cell_width_for(static_cast<int>(W)));
template <std::size_t W>
inline constexpr std::size_t kCellHeight = detail::kCellPixels / kCellWidth<W>;

// The arcs of one cell's occluders over the cell's pixels, occluder-major like
// tile_occluder_arcs: each occluder's kind and flags are branched on once per cell instead of
// once per packet (where occluders are small, that dispatch is over a quarter of an arc's
// instructions).
// The cell's arcs go to scratch[k * kTilePixels + cell_offset + i] for its pixel i in
// row-major order within the cell (start, then width), its inside flags to
// inside[cell_offset + i]: each cell's pixels lie together, kCellPixels from cell_offset.
template <class A>
PAR2D_KERNEL_NOINLINE void cell_occluder_arcs(const TileWork& work, const detail::KernelCell& cell,
                                              std::size_t x0, std::size_t y0, std::size_t cell_offset,
                                              float* start, float* width, float* inside) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  constexpr std::size_t cell_width = kCellWidth<W>, cell_height = kCellHeight<W>;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data() + x0;
  const float* sample_y = work.sample_y.data() + y0;
  float* cell_inside = inside + cell_offset;
  for (std::size_t first = 0; first < detail::kCellPixels; first += W) B(0.0f).store_aligned(cell_inside + first);
  const std::uint32_t* occluders = work.cell_occluders.data() + cell.first_occluder;
  for (std::uint32_t i = 0; i < cell.occluder_count; ++i) {
    const std::size_t k = occluders[i];
    float* start_k = start + k * detail::kTilePixels + cell_offset;
    float* width_k = width + k * detail::kTilePixels + cell_offset;
    auto sweep = [&](auto arc_of, bool may_hold_pixels) PAR2D_KERNEL_LAMBDA_INLINE {
      std::size_t at = 0;
      for (std::size_t row = 0; row < cell_height; ++row) {
        const B py(sample_y[row]);
        for (std::size_t column = 0; column < cell_width; column += W, at += W) {
          const Arc<A> arc = arc_of(B::load_unaligned(sample_x + column), py);
          arc.start.store_aligned(start_k + at);
          arc.width.store_aligned(width_k + at);
          if (may_hold_pixels) {
            const B was = B::load_aligned(cell_inside + at);
            xsimd::select(arc.inside, B(1.0f), was).store_aligned(cell_inside + at);
          }
        }
      }
    };
    with_known_arc<A>(work, work.occluders[k], sweep);
  }
}

// The tile's lights without pairs (nothing can stand in front of them anywhere in the tile),
// summed shape-major into `sum`.
template <class A>
PAR2D_KERNEL_NOINLINE void tile_unblocked_lights(const TileWork& work, TileResult& sum) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data();
  const float* sample_y = work.sample_y.data();
  for (int c = 0; c < 3; ++c)
    for (std::size_t first = 0; first < detail::kTilePixels; first += W) B(0.0f).store_aligned(sum.rgb[c] + first);
  for (const KernelLight& light : work.lights) {
    if (light.pair_count != 0) continue;
    const B emission[3] = {B(light.emission[0]), B(light.emission[1]), B(light.emission[2])};
    if (light.shape.clipped && light.shape.kind == ShapeKind::circle) {
      // A round light overlapping a wall (torches): the clipped arc inlined with the kind
      // known, instead of a call per packet.
      KernelShape known = light.shape;
      known.kind = ShapeKind::circle;
      for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
        const B px = B::load_unaligned(sample_x + first % detail::kTileSize);
        const B py(sample_y[first / detail::kTileSize]);
        Arc<A> arc;
        B lox, loy, hix, hiy;
        clipped_tangents<A>(work, known, px, py, lox, loy, hix, hiy, arc.inside);
        arc_from_tangents<A, false, false>(lox, loy, hix, hiy, arc);
        const B visible = xsimd::select(arc.inside, B(kTwoPiF), arc.width);
        for (int c = 0; c < 3; ++c)
          xsimd::fma(emission[c], visible, B::load_aligned(sum.rgb[c] + first)).store_aligned(sum.rgb[c] + first);
      }
      continue;
    }
    with_known_kind(light.shape, [&](const KernelShape& known) PAR2D_KERNEL_LAMBDA_INLINE {
      for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
        const B px = B::load_unaligned(sample_x + first % detail::kTileSize);
        const B py(sample_y[first / detail::kTileSize]);
        const Arc<A> arc = shape_arc<A, false>(work, known, px, py);
        const B visible = xsimd::select(arc.inside, B(kTwoPiF), arc.width);
        for (int c = 0; c < 3; ++c)
          xsimd::fma(emission[c], visible, B::load_aligned(sum.rgb[c] + first)).store_aligned(sum.rgb[c] + first);
      }
    });
  }
}

// The visible measure of a light's arc (clockwise tangent direction l, counter-clockwise h)
// past one occluder's (o, p), per lane, where `blocks` says the occluder is in front. Outside
// both shapes both arcs are narrower than pi, so a direction d lies in an arc [a, b] exactly
// when cross(a, d) >= 0 and cross(d, b) >= 0, and what stays visible is one arc between two of
// the four directions: [l, h] (no cut), [l, o] (the occluder covers the light's
// counter-clockwise end), [p, h] (its clockwise end), nothing (all of it), or both [l, o] and
// [p, h] (the occluder's arc inside the light's; the second atan2 only then). Each arc's
// measure is the angle between its ends, atan2 of their cross and dot products: no absolute
// angles, no intervals to sort. At the cases' borders the formulas meet (o = h, p = l, ...),
// so a sign flipped by rounding there moves the result by the rounding only.
template <class A>
PAR2D_KERNEL_INLINE xsimd::batch<float, A> visible_past_one_occluder(
    const xsimd::batch<float, A>& lx, const xsimd::batch<float, A>& ly, const xsimd::batch<float, A>& hx,
    const xsimd::batch<float, A>& hy, const xsimd::batch<float, A>& ox, const xsimd::batch<float, A>& oy,
    const xsimd::batch<float, A>& qx, const xsimd::batch<float, A>& qy,
    const xsimd::batch_bool<float, A>& blocks) noexcept {
  using B = xsimd::batch<float, A>;
  const B z(0.0f);
  // An occluder narrower than float resolves from this lane (a 1e-4 circle 3500 units away:
  // 3e-8 rad) can come out with its ends equal or swapped, and next to one of the light's ends
  // the cases below would then read it as covering the light. Its true arc is
  // within rounding of nothing: it blocks nothing there. (Ends nearly opposite, cross(o, q)
  // near 0 with a negative dot, are an arc near pi wide: those still block.)
  const auto collapsed = ((ox * qy - oy * qx) <= z) & (xsimd::fma(ox, qx, oy * qy) > z);
  const auto blocking = blocks & ~collapsed;
  const B l_o = lx * oy - ly * ox;  // cross(l, o)
  const B o_h = ox * hy - oy * hx;
  const B l_q = lx * qy - ly * qx;  // q: the occluder's counter-clockwise direction
  const B q_h = qx * hy - qy * hx;
  const auto o_in = (l_o >= z) & (o_h > z);  // the occluder's clockwise end inside the light's arc
  const auto q_in = (l_q > z) & (q_h >= z);
  const auto cut_ccw_end = blocking & o_in;                    // visible from l to o
  const auto cut_cw_end = blocking & q_in & ~o_in;             // visible from q to h
  const auto covered = blocking & ~(o_in | q_in) & (l_o <= z) & (l_q > z);  // l inside the occluder's arc
  const B ax = xsimd::select(cut_cw_end, qx, lx), ay = xsimd::select(cut_cw_end, qy, ly);
  const B bx = xsimd::select(cut_ccw_end, ox, hx), by = xsimd::select(cut_ccw_end, oy, hy);
  B visible = xsimd::select(covered, z, fast_atan2_upper(xsimd::abs(ax * by - ay * bx), xsimd::fma(ax, bx, ay * by)));
  const auto inner = cut_ccw_end & q_in;  // the occluder's arc inside the light's: [q, h] as well
  if (xsimd::any(inner))
    visible += xsimd::select(inner, fast_atan2_upper(xsimd::abs(q_h), xsimd::fma(qx, hx, qy * hy)), z);
  return visible;
}

// One single-pair light (single_pair_light) summed shape-major into `sum` like the unblocked
// ones: each packet gets both shapes' tangent directions (no atan2) and one
// visible_past_one_occluder. The occluder's inside flags are added to `inside`. The shapes'
// kinds and flags fold away where the caller set them from constants.
template <class A>
PAR2D_KERNEL_INLINE void single_pair_sweep(const TileWork& work, const KernelLight& light, const KernelPair& pair,
                                           const KernelShape& light_shape, const KernelShape& occluder,
                                           TileResult& sum, float* inside) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data();
  const float* sample_y = work.sample_y.data();
  const B emission[3] = {B(light.emission[0]), B(light.emission[1]), B(light.emission[2])};
  // In front in a lane: everywhere (front), or on the occluder's side of the separating line.
  const B nx(pair.front ? 0.0f : pair.nx), ny(pair.front ? 0.0f : pair.ny);
  const B line_c(pair.front ? -std::numeric_limits<float>::infinity() : pair.c);
  const bool occluder_may_hold_pixels = may_hold_pixels(occluder);
  for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
    const B px = B::load_unaligned(sample_x + first % detail::kTileSize);
    const B py(sample_y[first / detail::kTileSize]);
    B lx, ly, hx, hy, ox, oy, qx, qy;
    xsimd::batch_bool<float, A> in_light, in_occluder;
    if (light_shape.clipped)
      clipped_tangents<A>(work, light_shape, px, py, lx, ly, hx, hy, in_light);
    else
      shape_tangents<A>(work, light_shape, px, py, lx, ly, hx, hy, in_light);
    shape_tangents<A>(work, occluder, px, py, ox, oy, qx, qy, in_occluder);
    const auto blocks = (xsimd::fma(nx, px, ny * py) >= line_c) & ~in_light;
    B visible = visible_past_one_occluder<A>(lx, ly, hx, hy, ox, oy, qx, qy, blocks);
    // A clipped light's ends may be reversed: from behind its chord's line the kept part
    // can be out of sight, an empty arc (clipped_shape_arc's width is 0 there too).
    if (light_shape.clipped) visible = xsimd::select(lx * hy - ly * hx < B(0.0f), B(0.0f), visible);
    visible = xsimd::select(in_light, B(kTwoPiF), visible);
    for (int c = 0; c < 3; ++c)
      xsimd::fma(emission[c], visible, B::load_aligned(sum.rgb[c] + first)).store_aligned(sum.rgb[c] + first);
    if (occluder_may_hold_pixels) {
      const B was = B::load_aligned(inside + first);
      xsimd::select(in_occluder, B(1.0f), was).store_aligned(inside + first);
    }
  }
}

// A round single-pair light (most torches and lamps) with the occluder's kind known. Out of
// line: inlined into tile_single_pair_lights, its five loops change the registers GCC gives
// that function's other loops, which then cost more on scenes of polygon lights.
template <class A>
PAR2D_KERNEL_NOINLINE void round_light_single_pair(const TileWork& work, const KernelLight& light,
                                                   const KernelPair& pair, TileResult& sum, float* inside) noexcept {
  KernelShape known_light = light.shape;
  known_light.kind = ShapeKind::circle;
  known_light.ordered = false;
  known_light.may_contain = true;
  known_light.clipped = false;
  with_known_kind(work.occluders[pair.occluder], [&](const KernelShape& known_occluder) PAR2D_KERNEL_LAMBDA_INLINE {
    single_pair_sweep<A>(work, light, pair, known_light, known_occluder, sum, inside);
  });
}

// A single-pair light overlapping a wall (KernelShape::clipped: torches), its tangents those of
// the kept part (clipped_tangents), a round one with its kind known. Out of line like
// round_light_single_pair.
template <class A>
PAR2D_KERNEL_NOINLINE void clipped_light_single_pair(const TileWork& work, const KernelLight& light,
                                                     const KernelPair& pair, TileResult& sum, float* inside) noexcept {
  const KernelShape& occluder = work.occluders[pair.occluder];
  if (light.shape.kind == ShapeKind::circle) {
    KernelShape known_light = light.shape;
    known_light.kind = ShapeKind::circle;
    known_light.ordered = false;
    known_light.may_contain = true;
    known_light.clipped = true;
    single_pair_sweep<A>(work, light, pair, known_light, occluder, sum, inside);
  } else {
    single_pair_sweep<A>(work, light, pair, light.shape, occluder, sum, inside);
  }
}

// The tile's single-pair lights (single_pair_sweep). Instantiations: both shapes tile tangent
// pairs with their kinds known, a round light with each kind of occluder, and any other kinds
// branched on per packet. Every pair of known kinds (25 inlined loops) took the
// AddressSanitizer build of a kernel file past 20 minutes (then at -O3).
template <class A>
PAR2D_KERNEL_NOINLINE void tile_single_pair_lights(const TileWork& work, TileResult& sum, float* inside) noexcept {
  for (const KernelLight& light : work.lights) {
    const KernelPair* pair = work.pairs.data() + light.first_pair;
    if (!single_pair_light(pair, light.pair_count)) continue;
    const KernelShape& occluder = work.occluders[pair->occluder];
    if (light.shape.clipped) {
      clipped_light_single_pair<A>(work, light, *pair, sum, inside);
    } else if (light.shape.ordered && occluder.ordered) {
      // Copies whose flags the compiler sees: shape_tangents' kind tests fold away.
      KernelShape known_light = light.shape, known_occluder = occluder;
      for (KernelShape* known : {&known_light, &known_occluder}) {
        known->kind = ShapeKind::segment;
        known->ordered = true;
        known->may_contain = false;
        known->clipped = false;
      }
      single_pair_sweep<A>(work, light, *pair, known_light, known_occluder, sum, inside);
    } else if (light.shape.kind == ShapeKind::circle) {
      round_light_single_pair<A>(work, light, *pair, sum, inside);
    } else {
      single_pair_sweep<A>(work, light, *pair, light.shape, occluder, sum, inside);
    }
  }
}

// The arc planes in the kernel's scratch (uses_arc_planes; sized by kernel_scratch_floats):
// every occluder's start angles over the tile's pixels, then their widths, then one plane
// of inside flags, then the packets' own scratch.
struct ArcPlanes {
  float* start;
  float* width;
  float* inside;
  float* packet_scratch;
};

inline ArcPlanes arc_planes(const TileWork& work, float* scratch) noexcept {
  const std::size_t plane = work.occluders.size() * detail::kTilePixels;
  return {scratch, scratch + plane, scratch + 2 * plane, scratch + 2 * plane + detail::kTilePixels};
}

// The plain kernel at one sample per pixel without cells: occluder arcs shape-major for the
// whole tile (tile_occluder_arcs), the lights without pairs and with a single pair too,
// then the other lights packet by packet.
template <class A>
PAR2D_KERNEL_NOINLINE void render_plain_tile_shape_major(const TileWork& work, float* scratch,
                                                         TileResult& out) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  const ArcPlanes planes = arc_planes(work, scratch);
  float* start = planes.start;
  float* width = planes.width;
  float* inside = planes.inside;
  float* packet_scratch = planes.packet_scratch;
  // Past the packets' scratch (kernel_scratch_floats keeps room): the lights the packets
  // compute, and which lights use each occluder (a byte each; an occluder in no pair keeps
  // its arc, for its inside flags).
  std::uint32_t* packet_lights = reinterpret_cast<std::uint32_t*>(
      packet_scratch + detail::kernel_packet_scratch_floats(work, static_cast<int>(W)));
  unsigned char* arc_users = reinterpret_cast<unsigned char*>(packet_lights + work.lights.size());
  std::fill(arc_users, arc_users + work.occluders.size(), static_cast<unsigned char>(0));
  std::size_t packet_light_count = 0;
  for (std::size_t l = 0; l < work.lights.size(); ++l) {
    const KernelLight& light = work.lights[l];
    const KernelPair* pairs = work.pairs.data() + light.first_pair;
    if (light.pair_count == 0) continue;  // tile_unblocked_lights
    const bool single = single_pair_light(pairs, light.pair_count);
    // Placement new: the scratch holds floats, and its storage is reused for indices.
    if (!single) ::new (static_cast<void*>(packet_lights + packet_light_count++)) std::uint32_t(static_cast<std::uint32_t>(l));
    const unsigned char use = single ? kSinglePairUse : kPacketUse;
    for (std::uint32_t p = 0; p < light.pair_count; ++p) arc_users[pairs[p].occluder] |= use;
  }
  tile_occluder_arcs<A>(work, arc_users, start, width, inside);
  // The unblocked and single-pair lights' sums go straight into the result's planes; each
  // packet reads its part before it overwrites it.
  tile_unblocked_lights<A>(work, out);
  tile_single_pair_lights<A>(work, out, inside);
  if (packet_light_count == 0) {
    // Only the lanes inside an occluder are left to set (to 0), and only shapes that may
    // hold pixels set inside flags.
    bool any_inside = false;
    for (const KernelShape& occluder : work.occluders) any_inside = any_inside || may_hold_pixels(occluder);
    if (!any_inside) return;
    for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
      const auto in_occluder = B::load_aligned(inside + first) != B(0.0f);
      for (int c = 0; c < 3; ++c)
        xsimd::select(in_occluder, B(0.0f), B::load_aligned(out.rgb[c] + first)).store_aligned(out.rgb[c] + first);
    }
    return;
  }
  TileArcs<A> arcs;
  arcs.lights = packet_lights;
  arcs.light_count = packet_light_count;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data();
  const float* sample_y = work.sample_y.data();
  for (std::size_t first = 0; first < detail::kTilePixels; first += W) {
    const B px = B::load_unaligned(sample_x + first % detail::kTileSize);
    const B py(sample_y[first / detail::kTileSize]);
    arcs.start = start + first;
    arcs.width = width + first;
    arcs.inside = inside + first;
    for (int c = 0; c < 3; ++c) arcs.unblocked[c] = out.rgb[c] + first;
    B e[3];
    packet_irradiance<A, PlainPacket<false, true>>(work, nullptr, px, py, first, packet_scratch, e, arcs);
    for (int c = 0; c < 3; ++c) e[c].store_aligned(out.rgb[c] + first);
  }
}

// The plain kernel at one sample per pixel with cells: cell by cell, the cell's occluder arcs
// occluder-major (cell_occluder_arcs), then its packets from those arcs and its lists.
template <class A>
PAR2D_KERNEL_NOINLINE void render_plain_cell_tile(const TileWork& work, float* scratch, TileResult& out) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  const ArcPlanes planes = arc_planes(work, scratch);
  float* start = planes.start;
  float* width = planes.width;
  float* inside = planes.inside;
  float* packet_scratch = planes.packet_scratch;
  constexpr std::size_t cell_width = kCellWidth<W>, cell_height = kCellHeight<W>;
  constexpr std::size_t columns = detail::kTileSize / cell_width;
  // Read once: a vector store may alias any float, so members read in the loop are reloaded.
  const float* sample_x = work.sample_x.data();
  const float* sample_y = work.sample_y.data();
  TileArcs<A> arcs;
  for (std::size_t c = 0; c < work.cells.size(); ++c) {
    const detail::KernelCell& cell = work.cells[c];
    const std::size_t x0 = c % columns * cell_width, y0 = c / columns * cell_height;
    if (cell.light_count == 0) {  // no light here (or wholly in the tile's padding): dark
      for (std::size_t row = y0; row < y0 + cell_height; ++row)
        for (std::size_t column = x0; column < x0 + cell_width; column += W)
          for (int ch = 0; ch < 3; ++ch) B(0.0f).store_aligned(out.rgb[ch] + row * detail::kTileSize + column);
      continue;
    }
    const std::size_t cell_offset = c * detail::kCellPixels;
    cell_occluder_arcs<A>(work, cell, x0, y0, cell_offset, start, width, inside);
    std::size_t at = cell_offset;
    for (std::size_t row = y0; row < y0 + cell_height; ++row) {
      const B py(sample_y[row]);
      for (std::size_t column = x0; column < x0 + cell_width; column += W, at += W) {
        const B px = B::load_unaligned(sample_x + column);
        arcs.start = start + at;
        arcs.width = width + at;
        arcs.inside = inside + at;
        B e[3];
        packet_irradiance<A, PlainPacket<true, true>>(work, &cell, px, py, row * detail::kTileSize + column,
                                                     packet_scratch, e, arcs);
        for (int ch = 0; ch < 3; ++ch) e[ch].store_aligned(out.rgb[ch] + row * detail::kTileSize + column);
      }
    }
  }
}

// The plain kernel over the tile's packets, each from its cell's lists with kCells.
template <class A, bool kCells>
PAR2D_KERNEL_INLINE void render_plain_tile(const TileWork& work, float* scratch, TileResult& out) noexcept {
  constexpr std::size_t W = xsimd::batch<float, A>::size;
  // One sample per pixel with arc planes (tile_work.hpp): the arcs shape-major over the tile
  // or cell by cell. Otherwise, and for cells made for another packet width (not by this
  // library's setup), each packet computes its own arcs.
  if (detail::uses_arc_planes(work)) {
    if constexpr (!kCells) return render_plain_tile_shape_major<A>(work, scratch, out);
    if (work.cell_width == static_cast<int>(kCellWidth<W>)) return render_plain_cell_tile<A>(work, scratch, out);
  }
  render_packets<A, PlainPacket<kCells, false>>(work, scratch, out);
}

// Fills `out` with the mean irradiance over the work's samples for all the tile's pixels.
template <class A>
void render_tile(const TileWork& work, float* scratch, TileResult& out) noexcept {
  using B = xsimd::batch<float, A>;
  constexpr std::size_t W = B::size;
  static_assert(detail::kTileSize % W == 0, "a packet must not straddle a tile row");
  if (work.model) {
    if (work.shaded) return render_packets<A, ModelPacket<true>>(work, scratch, out);
    return render_packets<A, ModelPacket<false>>(work, scratch, out);
  }
  if (work.cells.empty()) return render_plain_tile<A, false>(work, scratch, out);
  return render_plain_tile<A, true>(work, scratch, out);
}

}  // namespace par2d::simd
