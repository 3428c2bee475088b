// One bounce by its definition: piece radiances from the exact direct value, then per reflecting
// occluder the directions to its front-facing pieces, split where other occluders come first.
#include "scalar/bounce_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/aabb.hpp"
#include "lighting/angular_profile.hpp"

namespace par2d::detail {
namespace {

// The direction of v from x in the frame of `arc`, in [0, arc.width]: an end point of the arc
// may round to just before its start, which the frame would wrap to nearly 2 pi.
double frame_angle(const AngularSpan& arc, Vec2 v) noexcept {
  double u = angle_in_light_frame(arc, std::atan2(v.y, v.x));
  if (u > arc.width) u = u > arc.width + 0.5 * (kTwoPi - arc.width) ? 0.0 : arc.width;
  return u;
}

bool acts(const OccluderTerms& terms, bool x_inside, std::uint32_t mask) noexcept {
  return terms.acts_on(mask) && !(x_inside && terms.lit_interior);
}

// The directions (frame of `arc`) along which the walk from x meets `piece` from its front.
// Appends at most three intervals (an arc piece can wrap past the seen half of its circle).
// The last end point whose direction was found: consecutive straight pieces share one.
struct LastEnd {
  Vec2 point{std::numeric_limits<double>::quiet_NaN(), 0.0};
  double angle = 0.0;
};

void piece_directions(const BouncePiece& piece, std::uint32_t index, Vec2 x, const AngularSpan& arc,
                      std::vector<BounceScratch::Emitter>& out, LastEnd& last) {
  const auto push = [&](Vec2 p, Vec2 q) {
    const double u = frame_angle(arc, p - x), v = frame_angle(arc, q - x);
    if (u != v) out.push_back({std::min(u, v), std::max(u, v), index});
  };
  if (!piece.arc) {
    // A straight piece is met from its front exactly from the open half-plane its normal faces.
    if (!(dot(piece.normal, x - piece.mid) > 0.0)) return;
    const double u = piece.a.x == last.point.x && piece.a.y == last.point.y ? last.angle : frame_angle(arc, piece.a - x);
    const double v = frame_angle(arc, piece.b - x);
    last = {piece.b, v};
    if (u != v) out.push_back({std::min(u, v), std::max(u, v), index});
    return;
  }
  // An arc is met from its front where the circle is first entered: the points within
  // acos(r / d) of the direction from the center to x.
  const Vec2 cx = x - piece.center;
  const double d = length(cx);
  if (!(d > piece.radius)) return;
  const double beta = std::atan2(cx.y, cx.x), gamma = std::acos(piece.radius / d);
  const double start = std::remainder(piece.angle0 - beta, kTwoPi), width = piece.angle1 - piece.angle0;
  for (const double shift : {-kTwoPi, 0.0, kTwoPi}) {
    const double lo = std::max(start + shift, -gamma), hi = std::min(start + shift + width, gamma);
    if (!(lo < hi)) continue;
    const auto at = [&](double a) { return piece.center + piece.radius * Vec2{std::cos(beta + a), std::sin(beta + a)}; };
    push(at(lo), at(hi));
  }
}

// scratch.coverage: the parts of [0, width] that no opaque blocked piece covers, each with the
// product of the transmittances of the blocked pieces covering it. Uncovered parts narrower
// than kContactTolerance of the arc are the rounding between pieces that meet end to end (as
// in the direct reference), not light.
void build_coverage(const PreparedScene& scene, double width, BounceScratch& scratch) {
  auto& sweep = scratch.sweep;
  sweep.clear();
  for (std::size_t q = 0; q < scratch.blocked.size(); ++q) {
    const ArcInterval piece = scratch.blocked[q];
    if (!(piece.hi > piece.lo)) continue;
    sweep.push_back({piece.lo, static_cast<int>(q) + 1});
    sweep.push_back({piece.hi, -static_cast<int>(q) - 1});
  }
  std::sort(sweep.begin(), sweep.end(),
            [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
  scratch.active.clear();
  scratch.coverage.clear();
  int opaque = 0;
  double at = 0.0;
  const double residue = kContactTolerance * width;
  const auto advance = [&](double to) {
    if (!(to > at)) return;
    if (opaque == 0 && !(scratch.active.empty() && to - at < residue)) {
      Rgb t{1.0, 1.0, 1.0};
      for (std::uint32_t q : scratch.active) {
        const Rgb& tq = scene.occluder_terms[scratch.blocked_occluder[q]].transmittance;
        for (int c = 0; c < 3; ++c) t[c] *= tq[c];
      }
      scratch.coverage.push_back({at, to, t});
    }
    at = to;
  };
  for (const auto& [position, event] : sweep) {
    advance(std::min(position, width));
    const std::uint32_t q = static_cast<std::uint32_t>(event > 0 ? event - 1 : -event - 1);
    const bool opaque_piece = scene.occluder_terms[scratch.blocked_occluder[q]].opaque();
    if (event > 0) {
      if (opaque_piece) ++opaque;
      else scratch.active.push_back(q);
    } else if (opaque_piece) {
      --opaque;
    } else {
      const auto it = std::find(scratch.active.begin(), scratch.active.end(), q);
      *it = scratch.active.back();
      scratch.active.pop_back();
    }
  }
  advance(width);
}

}  // namespace

void build_bounce_sources(const PreparedScene& scene, BounceFrame& frame) {
  frame.pieces.clear();
  frame.sources.clear();
  frame.radiance.clear();
  if (!scene.bounce) return;
  // Scene files and validate_scene refuse more pieces than the contract allows; a Renderer's
  // updates check one occluder at a time, so its frame refuses them here, before allocating.
  double count = 0.0;
  for (const OccluderTerms& terms : scene.occluder_terms) {
    if (!terms.reflects()) continue;
    count += bounce_piece_count(terms.bounce_shape, scene.bounce_piece, kMaxBouncePieces);
    if (!(count <= kMaxBouncePieces))
      throw std::length_error("bounce.piece: the reflecting occluders make more than 1048576 pieces; use a longer piece");
  }
  std::vector<std::uint32_t> near;
  std::vector<LightOverlap> spares;
  for (std::size_t j = 0; j < scene.occluders.size(); ++j) {
    const OccluderTerms& terms = scene.occluder_terms[j];
    if (!terms.reflects()) continue;
    BounceSource source;
    source.occluder = static_cast<std::uint32_t>(j);
    source.first = static_cast<std::uint32_t>(frame.pieces.size());
    bounce_pieces(terms.bounce_shape, scene.bounce_piece, scene.scale, frame.pieces);
    source.count = static_cast<std::uint32_t>(frame.pieces.size() - source.first);
    if (source.count == 0) continue;
    source.light.shape = scene.occluders[j];
    find_light_overlaps(scene, source.light, near, spares);
    // Its own occluder never shadows a piece (section 7): it is not among those it meets.
    auto& ids = source.light.overlapping_occluders;
    const auto self = std::lower_bound(ids.begin(), ids.end(), static_cast<std::uint32_t>(j));
    if (self != ids.end() && *self == j) {
      source.light.overlaps.erase(source.light.overlaps.begin() + (self - ids.begin()));
      ids.erase(self);
    }
    frame.sources.push_back(std::move(source));
  }
  frame.radiance.assign(frame.pieces.size(), Rgb{0.0, 0.0, 0.0});
}

void bounce_radiances(const PreparedScene& scene, BounceFrame& frame, std::size_t first, std::size_t last,
                      ScalarScratch& scratch, bool cull, const LightHiddenTest* hidden) {
  for (const BounceSource& source : frame.sources) {
    const std::size_t lo = std::max<std::size_t>(first, source.first);
    const std::size_t hi = std::min<std::size_t>(last, source.first + source.count);
    const Rgb& albedo = scene.occluder_terms[source.occluder].albedo;
    for (std::size_t k = lo; k < hi; ++k) {
      const BouncePiece& piece = frame.pieces[k];
      const Vec3 normal{piece.normal.x, piece.normal.y, 0.0};
      const Rgb s = cull ? piece_direct_light(scene, piece.mid, piece.normal, source.occluder, scratch, hidden)
                         : direct_without(scene, piece.mid, normal, source.occluder, scratch);
      for (int c = 0; c < 3; ++c) frame.radiance[k][c] = kPi * albedo[c] * s[c];
    }
  }
}

void finish_bounce_frame(BounceFrame& frame) noexcept {
  for (BounceSource& source : frame.sources) {
    source.lit = false;
    for (std::uint32_t k = source.first; k < source.first + source.count && !source.lit; ++k) {
      const Rgb& l = frame.radiance[k];
      source.lit = std::max({l[0], l[1], l[2]}) > 0.0;
    }
  }
}

void prepare_bounce_frame(const PreparedScene& scene, BounceFrame& frame, ScalarScratch& scratch) {
  build_bounce_sources(scene, frame);
  bounce_radiances(scene, frame, 0, frame.pieces.size(), scratch, false);
  finish_bounce_frame(frame);
}

Rgb bounce_irradiance(const PreparedScene& scene, const BounceFrame& frame, Vec2 x, const Vec3* normal,
                      BounceScratch& scratch, const BounceSourceSubset* subset) {
  Rgb e{0.0, 0.0, 0.0};
  if (frame.sources.empty()) return e;
  const std::size_t occluders = scene.occluders.size();
  auto& spans = scratch.scalar.occluder_spans;
  auto& inside = scratch.scalar.inside;
  if (spans.size() < occluders || scratch.span_stamp.size() < occluders) {
    spans.resize(occluders);
    inside.resize(occluders);
    scratch.span_stamp.assign(occluders, 0);
    scratch.stamp = 0;
  }
  if (++scratch.stamp == 0) {  // wrapped: forget every stamp
    std::fill(scratch.span_stamp.begin(), scratch.span_stamp.end(), 0u);
    scratch.stamp = 1;
  }
  // An occluder's span from x, once per point.
  const auto span_of = [&](std::uint32_t k) -> const AngularSpan& {
    if (scratch.span_stamp[k] != scratch.stamp) {
      scratch.span_stamp[k] = scratch.stamp;
      spans[k] = angular_span(scene.occluders[k], x);
      inside[k] = spans[k].full ? 1 : 0;
    }
    return spans[k];
  };
  // The occluders containing x (their boxes contain it).
  scratch.containing.clear();
  scratch.near.clear();
  scene.occluder_bvh.query_box({x.x, x.y, x.x, x.y}, scratch.near);
  for (const std::uint32_t k : scratch.near)
    if (span_of(k).full) scratch.containing.push_back(k);
  AngularProfile<double> profile;
  const std::size_t walked = subset ? subset->count : frame.sources.size();
  for (std::size_t n = 0; n < walked; ++n) {
    const BounceSource& source = frame.sources[subset ? subset->sources[n] : n];
    if (!source.lit) continue;
    ++scratch.source_walks;
    const std::uint32_t j = source.occluder;
    const AngularSpan& arc = span_of(j);
    // Inside its own occluder x meets no piece from the front; seen edge-on, none at all.
    if (arc.full || !(arc.width > 0.0)) continue;
    const std::uint32_t mask = scene.occluder_terms[j].mask;
    // Acting occluders containing x come first along every direction.
    Rgb factor{1.0, 1.0, 1.0};
    for (const std::uint32_t k : scratch.containing) {
      if (!acts(scene.occluder_terms[k], true, mask)) continue;
      for (int c = 0; c < 3; ++c) factor[c] *= scene.occluder_terms[k].transmittance[c];
    }
    if (!(std::max({factor[0], factor[1], factor[2]}) > 0.0)) continue;
    scratch.emitters.clear();
    LastEnd last;
    for (std::uint32_t k = source.first; k < source.first + source.count; ++k) {
      const Rgb& l = frame.radiance[k];
      if (!(std::max({l[0], l[1], l[2]}) > 0.0)) continue;
      piece_directions(frame.pieces[k], k, x, arc, scratch.emitters, last);
    }
    if (scratch.emitters.empty()) continue;
    // Only an occluder meeting a segment from x to a point of the reflector can come first:
    // its box meets the convex hull of x and the reflector (or the region's list holds it).
    const std::uint32_t* near = nullptr;
    std::size_t near_count = 0;
    if (subset) {
      near = subset->blockers + subset->first[n];
      near_count = subset->first[n + 1] - subset->first[n];
    } else {
      hull_with_shape(&x, 1, scene.occluders[j], scratch.hull_points, scratch.hull);
      scratch.near.clear();
      scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), scratch.near);
      near = scratch.near.data();
      near_count = scratch.near.size();
    }
    scratch.blocked.clear();
    scratch.blocked_occluder.clear();
    for (std::size_t q = 0; q < near_count; ++q) {
      const std::uint32_t k = near[q];
      if (k == j) continue;
      const AngularSpan& span = span_of(k);
      if (inside[k] || !acts(scene.occluder_terms[k], false, mask)) continue;
      ++scratch.depth_tests;
      blocked_pieces(source.light, scene.occluders[k], k, x, arc, span, scratch.scalar, scratch.blocked);
      scratch.blocked_occluder.resize(scratch.blocked.size(), k);
    }
    build_coverage(scene, arc.width, scratch);
    if (scratch.coverage.empty()) continue;
    profile = AngularProfile<double>{};
    if (normal)
      set_profile_shading(profile, arc.start, std::atan2(normal->y, normal->x), std::hypot(normal->x, normal->y),
                          normal->z, 0.0, 1.0);
    std::sort(scratch.emitters.begin(), scratch.emitters.end(),
              [](const BounceScratch::Emitter& a, const BounceScratch::Emitter& b) { return a.lo < b.lo; });
    Rgb sum{0.0, 0.0, 0.0};
    std::size_t first = 0;  // the first covered part that can meet the current emitter
    for (const BounceScratch::Emitter& emitter : scratch.emitters) {
      while (first < scratch.coverage.size() && scratch.coverage[first].hi <= emitter.lo) ++first;
      Rgb seen{0.0, 0.0, 0.0};
      for (std::size_t q = first; q < scratch.coverage.size() && scratch.coverage[q].lo < emitter.hi; ++q) {
        const BounceScratch::Covered& part = scratch.coverage[q];
        const double a = std::max(part.lo, emitter.lo), b = std::min(part.hi, emitter.hi);
        if (!(b > a)) continue;
        const double w = profile_cumulative(profile, b) - profile_cumulative(profile, a);
        for (int c = 0; c < 3; ++c) seen[c] += part.transmittance[c] * w;
      }
      const Rgb& l = frame.radiance[emitter.piece];
      for (int c = 0; c < 3; ++c) sum[c] += l[c] * std::max(0.0, seen[c]);
    }
    for (int c = 0; c < 3; ++c) e[c] += factor[c] * sum[c] / kTwoPi;
  }
  return e;
}

}  // namespace par2d::detail
