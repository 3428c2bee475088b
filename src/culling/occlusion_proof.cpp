// From-region occlusion by a union of occluders: interval cover of the lines across a slab.
#include "culling/occlusion_proof.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace par2d::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Occluders are cut off this fraction of the slab short of the light side, so that a point's
// projection gain stays finite (<= 1024) and rounding stays bounded.
constexpr double kLightSideCut = 1.0 / 1024.0;

// Polygon stand-ins for circles: occluders shrink to an inscribed 12-gon (blocks less), lights
// grow to a circumscribed octagon (meets more lines), so every proof stays valid.
constexpr int kOccluderCircleSides = 12;
constexpr int kLightCircleSides = 8;

// u along the axis, v across it, relative to `origin`.
struct Frame {
  Vec2 axis, origin;
  double u(Vec2 p) const noexcept { return dot(p - origin, axis); }
  double v(Vec2 p) const noexcept { return cross(axis, p - origin); }
};

// Sutherland-Hodgman: keeps the part of polygon (u, v)[0..n) where sign * (u - at) >= 0,
// appended to (out_u, out_v). Crossing points are put exactly on the cut.
void clip(const double* u, const double* v, std::size_t n, double at, double sign, std::vector<double>& out_u,
          std::vector<double>& out_v) {
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = i + 1 == n ? 0 : i + 1;
    const double fi = sign * (u[i] - at), fj = sign * (u[j] - at);
    if (fi >= 0.0) {
      out_u.push_back(u[i]);
      out_v.push_back(v[i]);
    }
    if ((fi >= 0.0) != (fj >= 0.0)) {
      const double t = fi / (fi - fj);
      out_u.push_back(at);
      out_v.push_back(v[i] + t * (v[j] - v[i]));
    }
  }
}

// Unit vectors at angles phase + 2 pi k / n, k < n: the vertices of the circles' stand-in
// polygons (computed once; proofs run thousands of times per frame).
template <int kSides>
struct UnitPolygon {
  double x[kSides], y[kSides];
  explicit UnitPolygon(double phase) {
    for (int k = 0; k < kSides; ++k) {
      x[k] = std::cos(phase + kTwoPi * k / kSides);
      y[k] = std::sin(phase + kTwoPi * k / kSides);
    }
  }
};

enum class Cover { proven, gap };

// Whether the blockers' shadows cover every line of the strip [q0, q1] (q0 == q1: one pencil
// of lines, whose shadows are then exact, closed intervals) that meets the viewer and the light.
Cover cover_strip(const OcclusionProofScratch& s, double q0, double q1, double eps,
                  std::vector<std::pair<double, double>>& intervals) {
  // Lines from a light-side height q that meet the viewer (the light) have p between its
  // points' projections from q; both grow with q, so the strip needs at most [lo(q0), hi(q1)].
  double viewer_lo = kInf, viewer_hi = -kInf;
  for (std::size_t i = 0; i < s.viewer_gain.size(); ++i) {
    viewer_lo = std::min(viewer_lo, s.viewer_gain[i] * q0 + s.viewer_offset[i]);
    viewer_hi = std::max(viewer_hi, s.viewer_gain[i] * q1 + s.viewer_offset[i]);
  }
  double light_lo = kInf, light_hi = -kInf;
  for (std::size_t i = 0; i < s.light_gain.size(); ++i) {
    light_lo = std::min(light_lo, s.light_gain[i] * q0 - s.light_offset[i]);
    light_hi = std::max(light_hi, s.light_gain[i] * q1 - s.light_offset[i]);
  }
  // A light point on the slab side itself is met by lines of every steepness from below or above it.
  for (const double h : s.light_on_side) {
    if (q0 <= h) light_lo = -kInf;
    if (q1 >= h) light_hi = kInf;
  }
  const double need_lo = std::max(viewer_lo, light_lo), need_hi = std::min(viewer_hi, light_hi);
  if (!(need_lo <= need_hi)) return Cover::proven;  // no line meets both

  intervals.clear();
  const std::size_t blockers = s.blocker_first.size() - 1;
  for (std::size_t k = 0; k < blockers; ++k) {
    double lo = kInf, hi = -kInf;
    for (std::uint32_t i = s.blocker_first[k]; i < s.blocker_first[k + 1]; ++i) {
      lo = std::min(lo, s.blocker_a[i] - s.blocker_c[i] * q0);
      hi = std::max(hi, s.blocker_a[i] - s.blocker_c[i] * q1);
    }
    if (hi > lo && hi > need_lo && lo < need_hi) intervals.emplace_back(lo, hi);
  }
  // By start alone: among intervals with one start the sweep's answer does not depend on
  // their order (each passes or fails the gap test alike, reach only grows), and one
  // comparison per step instead of a pair's two.
  std::sort(intervals.begin(), intervals.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double reach = need_lo;
  for (const auto& [lo, hi] : intervals) {
    if (lo >= reach - eps) return Cover::gap;  // lines between reach and lo pass every occluder
    reach = std::max(reach, hi);
    if (reach > need_hi + eps) return Cover::proven;
  }
  return Cover::gap;
}

// Whether the segment [a, b] certainly misses the closed convex shape: a separating axis
// (the segment's normal, or an edge's normal of the shape) with both strictly apart.
bool segment_misses(Vec2 a, Vec2 b, const ConvexShape& s) noexcept {
  if (std::max(a.x, b.x) < s.bounds_min.x || std::min(a.x, b.x) > s.bounds_max.x ||
      std::max(a.y, b.y) < s.bounds_min.y || std::min(a.y, b.y) > s.bounds_max.y)
    return true;
  const Vec2 d = b - a;
  // The box's extent across the segment's line (n = d turned a quarter).
  const Vec2 center = 0.5 * (s.bounds_min + s.bounds_max), half = 0.5 * (s.bounds_max - s.bounds_min);
  const double across = cross(d, center - a), spread = std::abs(d.y) * half.x + std::abs(d.x) * half.y;
  if (across - spread > 0.0 || across + spread < 0.0) return true;
  if (s.kind == ShapeKind::circle) {
    const Vec2 c = s.vertices[0];
    const double dd = dot(d, d);
    const double t = dd > 0.0 ? std::clamp(dot(c - a, d) / dd, 0.0, 1.0) : 0.0;
    const Vec2 q = c - (a + t * d);
    return dot(q, q) > s.radius * s.radius;
  }
  double side_lo = kInf, side_hi = -kInf;
  for (const Vec2 v : s.vertices) {
    const double w = cross(d, v - a);
    side_lo = std::min(side_lo, w);
    side_hi = std::max(side_hi, w);
  }
  if (side_lo > 0.0 || side_hi < 0.0) return true;
  if (s.kind == ShapeKind::segment) {
    const Vec2 e = s.vertices[1] - s.vertices[0];
    const double wa = cross(e, a - s.vertices[0]), wb = cross(e, b - s.vertices[0]);
    return (wa > 0.0 && wb > 0.0) || (wa < 0.0 && wb < 0.0);
  }
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {  // inward normals: outside is < 0
    const Vec2 n = s.edge_normals[i], v = s.vertices[i];
    if (dot(n, a - v) < 0.0 && dot(n, b - v) < 0.0) return true;
  }
  return false;
}

// Whether the segment [a, b] passes every occluder, trying first the one that blocked the
// previous probe (`hint`, an index into ids, updated to this probe's blocker; count: none):
// neighbouring probes are mostly blocked by the same occluder, so a proof that goes on to
// succeed pays less for its probes.
bool probe_passes(Vec2 a, Vec2 b, const std::vector<ConvexShape>& occluders, const std::uint32_t* ids,
                  std::size_t count, std::size_t& hint) noexcept {
  if (hint < count && !segment_misses(a, b, occluders[ids[hint]])) return false;
  for (std::size_t k = 0; k < count; ++k)
    if (k != hint && !segment_misses(a, b, occluders[ids[k]])) {
      hint = k;
      return false;
    }
  return true;
}

// Whether the shape is an axis-aligned box: a polygon whose four vertices are the four
// corners of its bounds (a tilemap's cells and merged runs).
bool is_axis_box(const ConvexShape& s) noexcept {
  if (s.kind != ShapeKind::polygon || s.vertices.size() != 4) return false;
  unsigned corners = 0;
  for (const Vec2 v : s.vertices) {
    const bool right = v.x == s.bounds_max.x, top = v.y == s.bounds_max.y;
    if ((!right && v.x != s.bounds_min.x) || (!top && v.y != s.bounds_min.y)) return false;
    corners |= 1u << (unsigned(right) | unsigned(top) << 1);
  }
  return corners == 0xFu;
}

std::uint32_t group_root(std::vector<std::uint32_t>& parent, std::uint32_t k) noexcept {
  while (parent[k] != k) k = parent[k] = parent[parent[k]];
  return k;
}

// Joins the blockers of axis-aligned boxes that touch or overlap inside the slab into one
// blocker each (one run of points), as segments_blocked describes.
//
// Why this is exact: the closed boxes' intersection, itself a box, is found from their bounds
// by comparisons alone, so a shared edge or corner is never lost to rounding. The boxes are
// joined only when that intersection reaches into the slab by more than `tol` along the
// axis, which bounds the rounding of the frame's u (a few ulp of the coordinates against
// tol = 1e-12 of their magnitude), so the clipped boxes, the parts the shadows come from,
// share a point. A union of convex sets sharing points is connected, and the lines through
// a pencil's point that meet a connected set form one interval, whose ends are the extreme
// projections of the union's vertices: the joined run's interval is that union's shadow,
// exact per pencil and conservative per strip as for a single occluder. Its ends carry the
// rounding of its points' projections, the same as the separate blockers' ends, which the
// cover sweep's eps already allows for.
bool join_touching_boxes(OcclusionProofScratch& s, const std::vector<ConvexShape>& occluders, const Frame& frame,
                         double cut, double tol) {
  const auto blockers = static_cast<std::uint32_t>(s.blocker_first.size() - 1);
  s.box_order.clear();
  for (std::uint32_t k = 0; k < blockers; ++k)
    if (is_axis_box(occluders[s.blocker_occluder[k]])) s.box_order.push_back(k);
  if (s.box_order.size() < 2) return false;
  const auto shape = [&](std::uint32_t k) -> const ConvexShape& { return occluders[s.blocker_occluder[k]]; };
  std::sort(s.box_order.begin(), s.box_order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return shape(a).bounds_min.x < shape(b).bounds_min.x; });
  s.group_parent.resize(blockers);
  for (std::uint32_t k = 0; k < blockers; ++k) s.group_parent[k] = k;
  bool joined = false;
  for (std::size_t i = 0; i < s.box_order.size(); ++i) {
    const ConvexShape& a = shape(s.box_order[i]);
    for (std::size_t j = i + 1; j < s.box_order.size(); ++j) {
      const ConvexShape& b = shape(s.box_order[j]);
      if (b.bounds_min.x > a.bounds_max.x) break;  // sorted by left edge: none further touches a
      const double x0 = b.bounds_min.x, x1 = std::min(a.bounds_max.x, b.bounds_max.x);
      const double y0 = std::max(a.bounds_min.y, b.bounds_min.y), y1 = std::min(a.bounds_max.y, b.bounds_max.y);
      if (y0 > y1) continue;
      double u_lo = kInf, u_hi = -kInf;
      for (const Vec2 corner : {Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x0, y1}, Vec2{x1, y1}}) {
        const double u = frame.u(corner);
        u_lo = std::min(u_lo, u);
        u_hi = std::max(u_hi, u);
      }
      if (u_hi < tol || u_lo > cut - tol) continue;  // they touch outside the slab
      const std::uint32_t ra = group_root(s.group_parent, s.box_order[i]);
      const std::uint32_t rb = group_root(s.group_parent, s.box_order[j]);
      if (ra == rb) continue;
      s.group_parent[std::max(ra, rb)] = std::min(ra, rb);
      joined = true;
    }
  }
  if (!joined) return false;
  // Each blocker's points appended under its group's root, groups in order of their roots.
  for (std::uint32_t k = 0; k < blockers; ++k) s.group_parent[k] = group_root(s.group_parent, k);
  s.box_order.resize(blockers);
  for (std::uint32_t k = 0; k < blockers; ++k) s.box_order[k] = k;
  // std::sort, not std::stable_sort, which takes a buffer from the heap: a frame allocates nothing.
  std::sort(s.box_order.begin(), s.box_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return s.group_parent[a] != s.group_parent[b] ? s.group_parent[a] < s.group_parent[b] : a < b;
  });
  s.grouped_a.clear();
  s.grouped_c.clear();
  s.group_first.assign(1, 0);
  for (std::size_t i = 0; i < s.box_order.size(); ++i) {
    const std::uint32_t k = s.box_order[i];
    for (std::uint32_t p = s.blocker_first[k]; p < s.blocker_first[k + 1]; ++p) {
      s.grouped_a.push_back(s.blocker_a[p]);
      s.grouped_c.push_back(s.blocker_c[p]);
    }
    if (i + 1 == s.box_order.size() || s.group_parent[s.box_order[i + 1]] != s.group_parent[k])
      s.group_first.push_back(static_cast<std::uint32_t>(s.grouped_a.size()));
  }
  s.blocker_a.swap(s.grouped_a);
  s.blocker_c.swap(s.grouped_c);
  s.blocker_first.swap(s.group_first);
  return true;
}

}  // namespace

bool segment_passes(Vec2 a, Vec2 b, const std::vector<ConvexShape>& occluders, const std::uint32_t* ids,
                    std::size_t count) noexcept {
  std::size_t no_hint = count;
  return probe_passes(a, b, occluders, ids, count, no_hint);
}

bool segments_blocked(const Vec2* viewer, int viewer_count, Vec2 axis, const ConvexShape& light,
                      const std::vector<ConvexShape>& occluders, const std::uint32_t* ids, std::size_t count,
                      int strip_budget, OcclusionProofScratch& scratch) {
  if (viewer_count <= 0 || count == 0) return false;
  // Most proofs that fail do so because the light is plainly visible: one segment, from the
  // viewer points' mean or from one of them to the light's interior point, that passes
  // every occluder settles it for a fraction of the proof's cost. (Further segments to the
  // light's sides, where these are blocked, cost more than they save: the proofs that get
  // here mostly succeed.)
  Vec2 viewer_mean{0.0, 0.0};
  for (int i = 0; i < viewer_count; ++i) viewer_mean = viewer_mean + viewer[i];
  viewer_mean = (1.0 / viewer_count) * viewer_mean;
  std::size_t hint = count;
  bool seen = probe_passes(viewer_mean, light.centroid, occluders, ids, count, hint);
  for (int i = 0; i < viewer_count && !seen; ++i) seen = probe_passes(viewer[i], light.centroid, occluders, ids, count, hint);
  if (seen) {
    ++scratch.proofs_probed_out;
    return false;
  }
  Frame frame{axis, viewer[0]};
  double magnitude = 0.0;
  for (const Vec2 p : {light.bounds_min, light.bounds_max}) magnitude = std::max({magnitude, std::abs(p.x), std::abs(p.y)});
  double viewer_end = -kInf;
  for (int i = 0; i < viewer_count; ++i) {
    viewer_end = std::max(viewer_end, frame.u(viewer[i]));
    magnitude = std::max({magnitude, std::abs(viewer[i].x), std::abs(viewer[i].y)});
  }
  // Shift u so that the viewer ends at u = 0 and the light starts at u = gap.
  frame.origin = frame.origin + viewer_end * axis;
  // Light points in the frame (circles as circumscribed octagons with two sides across the axis).
  std::vector<double>&light_u = scratch.light_u, &light_v = scratch.light_v;
  light_u.clear();
  light_v.clear();
  if (light.kind == ShapeKind::circle) {
    const Vec2 c = light.vertices[0];
    const double side_radius = light.radius / std::cos(kPi / kLightCircleSides);
    static const UnitPolygon<kLightCircleSides> kUnit(kPi / kLightCircleSides);
    const double cu = frame.u(c), cv = frame.v(c);
    for (int k = 0; k < kLightCircleSides; ++k) {
      light_u.push_back(cu + side_radius * kUnit.x[k]);
      light_v.push_back(cv + side_radius * kUnit.y[k]);
    }
  } else {
    for (const Vec2 p : light.vertices) light_u.push_back(frame.u(p)), light_v.push_back(frame.v(p));
  }
  double gap = kInf, light_far = -kInf;
  for (const double u : light_u) gap = std::min(gap, u), light_far = std::max(light_far, u);
  // The proof compares projections that rounding moves by up to ~1e3 ulp of the coordinates
  // (differences from the frame origin, times gains up to 1024); it only counts overlaps
  // beyond ~4500 ulp, and needs a slab wider than 1e-9 of the coordinates.
  const double eps = 1e-12 * magnitude;
  if (!(gap > 1e3 * eps)) return false;

  scratch.viewer_gain.clear();
  scratch.viewer_offset.clear();
  double viewer_v_lo = kInf, viewer_v_hi = -kInf;
  for (int i = 0; i < viewer_count; ++i) {
    const double u = std::min(frame.u(viewer[i]), 0.0), v = frame.v(viewer[i]);
    // The line from (gap, q) through (u, v) meets u = 0 at q + (v - q) * gap / (gap - u).
    const double t = gap / (gap - u);
    scratch.viewer_gain.push_back(1.0 - t);
    scratch.viewer_offset.push_back(v * t);
    viewer_v_lo = std::min(viewer_v_lo, v);
    viewer_v_hi = std::max(viewer_v_hi, v);
  }
  scratch.light_gain.clear();
  scratch.light_offset.clear();
  scratch.light_on_side.clear();
  double light_v_lo = kInf, light_v_hi = -kInf;
  for (std::size_t i = 0; i < light_u.size(); ++i) {
    const double d = light_u[i] - gap, v = light_v[i];
    light_v_lo = std::min(light_v_lo, v);
    light_v_hi = std::max(light_v_hi, v);
    if (d <= 1e-9 * gap) {
      scratch.light_on_side.push_back(v);
      continue;
    }
    // The line from (gap, q) through (gap + d, v) meets u = 0 at q - (v - q) * gap / d.
    scratch.light_gain.push_back(1.0 + gap / d);
    scratch.light_offset.push_back(v * gap / d);
  }

  // Occluders clipped to the slab, as point projections.
  const double cut = gap * (1.0 - kLightSideCut);
  scratch.blocker_a.clear();
  scratch.blocker_c.clear();
  scratch.blocker_first.assign(1, 0);
  scratch.blocker_occluder.clear();
  for (std::size_t k = 0; k < count; ++k) {
    const ConvexShape& s = occluders[ids[k]];
    double u_lo = kInf, u_hi = -kInf;
    for (const Vec2 corner : {s.bounds_min, Vec2{s.bounds_max.x, s.bounds_min.y}, s.bounds_max,
                              Vec2{s.bounds_min.x, s.bounds_max.y}}) {
      const double u = frame.u(corner);
      u_lo = std::min(u_lo, u);
      u_hi = std::max(u_hi, u);
    }
    if (u_hi <= 0.0 || u_lo >= cut) continue;
    scratch.clip_u.clear();
    scratch.clip_v.clear();
    auto add = [&](double u, double v) {
      scratch.clip_u.push_back(u);
      scratch.clip_v.push_back(v);
    };
    if (s.kind == ShapeKind::circle) {
      const Vec2 c = s.vertices[0];
      static const UnitPolygon<kOccluderCircleSides> kUnit(0.0);
      const double cu = frame.u(c), cv = frame.v(c);
      for (int i = 0; i < kOccluderCircleSides; ++i) add(cu + s.radius * kUnit.x[i], cv + s.radius * kUnit.y[i]);
    } else {
      for (const Vec2 p : s.vertices) add(frame.u(p), frame.v(p));
    }
    // Most occluders lie wholly inside the slab: both clips would return their points as
    // they are (every point kept, no crossing), so they are skipped.
    bool inside = !scratch.clip_u.empty();
    for (const double u : scratch.clip_u) inside &= u >= 0.0 && u <= cut;
    if (!inside) {
      scratch.half_u.clear();
      scratch.half_v.clear();
      clip(scratch.clip_u.data(), scratch.clip_v.data(), scratch.clip_u.size(), 0.0, 1.0, scratch.half_u,
           scratch.half_v);
      scratch.clip_u.clear();
      scratch.clip_v.clear();
      clip(scratch.half_u.data(), scratch.half_v.data(), scratch.half_u.size(), cut, -1.0, scratch.clip_u,
           scratch.clip_v);
      if (scratch.clip_u.empty()) continue;
    }
    for (std::size_t i = 0; i < scratch.clip_u.size(); ++i) {
      // The line from (gap, q) through (u, v) meets u = 0 at (gap * v - q * u) / (gap - u).
      const double u = scratch.clip_u[i], inv = 1.0 / (gap - u);
      scratch.blocker_a.push_back(gap * scratch.clip_v[i] * inv);
      scratch.blocker_c.push_back(u * inv);
    }
    scratch.blocker_first.push_back(static_cast<std::uint32_t>(scratch.blocker_a.size()));
    scratch.blocker_occluder.push_back(ids[k]);
  }
  if (scratch.blocker_first.size() == 1) return false;

  // A line meeting the viewer at (uT, vT) and the light at (uL, vL) crosses u = gap at
  // (1 - l) vT + l vL with l = (gap - uT) / (uL - uT) in [gap / light_far, 1].
  const double l_min = gap / light_far;
  const double q_lo = std::min(light_v_lo, light_v_lo + (1.0 - l_min) * (viewer_v_lo - light_v_lo));
  const double q_hi = std::max(light_v_hi, light_v_hi + (1.0 - l_min) * (viewer_v_hi - light_v_hi));
  // Strips are taken coarsest first (a queue): a proof succeeds only when every strip of the
  // whole split tree is proven within the budget, whatever the order, but a failing one meets
  // a gap at a coarse middle pencil sooner than by proving one half to the end first.
  scratch.strips.assign(1, {q_lo, q_hi});
  int strips = 0;
  bool joined = false;
  for (std::size_t next = 0; next < scratch.strips.size(); ++next) {
    const auto [q0, q1] = scratch.strips[next];
    if (++strips > strip_budget) return false;
    if (cover_strip(scratch, q0, q1, eps, scratch.intervals) == Cover::proven) continue;
    // Touching boxes are joined only once a strip needs it: most proofs close on their first
    // strips with the occluders as they are, and strips proven before stay proven (the
    // joined shadows hold the separate ones).
    if (!joined) {
      joined = true;
      if (join_touching_boxes(scratch, occluders, frame, cut, eps) &&
          cover_strip(scratch, q0, q1, eps, scratch.intervals) == Cover::proven)
        continue;
    }
    const double mid = 0.5 * (q0 + q1);
    if (!(mid > q0 && mid < q1)) return false;  // cannot split further
    // The middle pencil's shadows are exact: a gap there is a line that passes every occluder.
    if (cover_strip(scratch, mid, mid, -eps, scratch.intervals) == Cover::gap) return false;
    scratch.strips.push_back({q0, mid});
    scratch.strips.push_back({mid, q1});
  }
  return true;
}

void OcclusionProofScratch::reserve_for(std::size_t occluders, std::size_t max_vertices, int strip_budget) {
  // Light points: a polygon's vertices (a visible part has one more than its light) or the
  // 8-gon standing in for a circle (a clipped one: 9).
  const std::size_t light = std::max<std::size_t>(max_vertices, kLightCircleSides) + 1;
  light_u.reserve(light);
  light_v.reserve(light);
  light_gain.reserve(light);
  light_offset.reserve(light);
  light_on_side.reserve(light);
  viewer_gain.reserve(4);  // a rectangle's corners or a chord's two ends
  viewer_offset.reserve(4);
  // An occluder's points (a 12-gon for a circle) clipped by two lines: a convex polygon
  // gains at most one point per clip.
  const std::size_t points = std::max<std::size_t>(max_vertices, kOccluderCircleSides);
  clip_u.reserve(points + 2);
  clip_v.reserve(points + 2);
  half_u.reserve(points + 1);
  half_v.reserve(points + 1);
  // The ids name distinct occluders: one run of points and one interval per occluder.
  blocker_a.reserve(occluders * (points + 2));
  blocker_c.reserve(occluders * (points + 2));
  blocker_first.reserve(occluders + 1);
  blocker_occluder.reserve(occluders);
  box_order.reserve(occluders);
  group_parent.reserve(occluders);
  group_first.reserve(occluders + 1);
  grouped_a.reserve(occluders * (points + 2));
  grouped_c.reserve(occluders * (points + 2));
  intervals.reserve(occluders);
  // Each strip taken (at most strip_budget) queues two halves after the first.
  strips.reserve(1 + 2 * static_cast<std::size_t>(std::max(strip_budget, 0)));
}

std::size_t OcclusionProofScratch::reserved_bytes() const noexcept {
  const std::size_t doubles = light_u.capacity() + light_v.capacity() + viewer_gain.capacity() +
                              viewer_offset.capacity() + light_gain.capacity() + light_offset.capacity() +
                              light_on_side.capacity() + blocker_a.capacity() + blocker_c.capacity() +
                              clip_u.capacity() + clip_v.capacity() + half_u.capacity() + half_v.capacity() +
                              grouped_a.capacity() + grouped_c.capacity();
  const std::size_t indices = blocker_first.capacity() + blocker_occluder.capacity() + box_order.capacity() +
                              group_parent.capacity() + group_first.capacity();
  return doubles * sizeof(double) + indices * sizeof(std::uint32_t) +
         (intervals.capacity() + strips.capacity()) * sizeof(std::pair<double, double>);
}

bool rect_hidden_from_light(Vec2 lo, Vec2 hi, const ConvexShape& light, const std::vector<ConvexShape>& occluders,
                            const std::uint32_t* ids, std::size_t count, int strip_budget,
                            OcclusionProofScratch& scratch) {
  const double gaps[4] = {light.bounds_min.x - hi.x, lo.x - light.bounds_max.x, light.bounds_min.y - hi.y,
                          lo.y - light.bounds_max.y};
  const Vec2 axes[4] = {{1.0, 0.0}, {-1.0, 0.0}, {0.0, 1.0}, {0.0, -1.0}};
  const int side = static_cast<int>(std::max_element(gaps, gaps + 4) - gaps);
  ++scratch.proofs_tried;
  if (!(gaps[side] > 0.0)) return false;
  const Vec2 corners[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  const bool hidden = segments_blocked(corners, 4, axes[side], light, occluders, ids, count, strip_budget, scratch);
  scratch.proofs_succeeded += hidden ? 1u : 0u;
  return hidden;
}

}  // namespace par2d::detail
