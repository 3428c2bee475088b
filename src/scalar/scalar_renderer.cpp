// Reference PAR: each shape becomes an arc of directions from x; occluders in front of a
// light are cut out of its arc (union, not sum); the rest, over 2*pi, weights its emission.
// With the game lighting model's terms, each elementary piece of the arc (between blocked
// pieces' end points) is weighted by the product of the transmittances covering it and by the
// closed-form cone x clamped-cosine integral over it (lighting/angular_profile.hpp).
#include "scalar/scalar_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lighting/angular_profile.hpp"
#include "world/occluder_bvh.hpp"

namespace par2d::detail {
namespace {

Vec2 direction(double angle) noexcept { return {std::cos(angle), std::sin(angle)}; }

// Whether the occluder comes first along the direction, contacts counting as first
// (docs/contract.md: the light is visible only when t_L < t_occ).
bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, double angle,
                    EntryHints& hints) noexcept {
  return detail::occluder_first(occluder, light, x, direction(angle), hints);
}

// Calls emit(lo, hi) for each piece of the light's arc (light frame) that occluder k is in
// front of, x in neither shape: the part of the occluder's span inside the arc, split where
// the nearer of the two shapes can change.
template <class Emit>
void for_each_blocked_piece(const PreparedLight& light, const ConvexShape& occluder, std::size_t k, Vec2 x,
                            const AngularSpan& arc, const AngularSpan& span, ScalarScratch& scratch, Emit&& emit) {
  scratch.pieces.clear();
  clip_to_light_arc(arc, span, scratch.pieces);
  if (scratch.pieces.empty()) return;
  const auto overlap = std::lower_bound(light.overlapping_occluders.begin(), light.overlapping_occluders.end(), k);
  if (overlap == light.overlapping_occluders.end() || *overlap != k) {
    // Disjoint convex shapes: along every direction that meets both, the same one comes
    // first (the paper's depth test), so one key ray per piece decides the whole piece.
    EntryHints hints;
    for (const ArcInterval& piece : scratch.pieces) {
      if (occluder_first(occluder, light.shape, x, arc.start + 0.5 * (piece.lo + piece.hi), hints))
        emit(piece.lo, piece.hi);
    }
    return;
  }
  // Overlapping shapes: which one comes first can only change at a direction through a
  // point where their boundaries meet, so test one key ray between consecutive such
  // directions.
  const auto& points = light.overlaps[static_cast<std::size_t>(overlap - light.overlapping_occluders.begin())].points;
  // Key rays in angular order: each ray's entry edges are found from the previous ones'.
  EntryHints hints;
  for (const ArcInterval& piece : scratch.pieces) {
    scratch.events.assign({piece.lo, piece.hi});
    for (Vec2 p : points) {
      const Vec2 d = p - x;
      if (d.x == 0.0 && d.y == 0.0) continue;
      const double a = angle_in_light_frame(arc, std::atan2(d.y, d.x));
      if (a > piece.lo && a < piece.hi) scratch.events.push_back(a);
    }
    std::sort(scratch.events.begin(), scratch.events.end());
    for (std::size_t e = 0; e + 1 < scratch.events.size(); ++e) {
      const double lo = scratch.events[e], hi = scratch.events[e + 1];
      if (hi > lo && occluder_first(occluder, light.shape, x, arc.start + 0.5 * (lo + hi), hints)) emit(lo, hi);
    }
  }
}

}  // namespace

double visible_measure(const PreparedScene& scene, std::size_t light_index, Vec2 x,
                       const std::vector<AngularSpan>& occluder_spans, ScalarScratch& scratch) {
  const PreparedLight& light = scene.lights[light_index];
  const AngularSpan arc = angular_span(light.shape, x);
  if (arc.width <= 0.0) return 0.0;
  // Inside the light t_L = 0: nothing can come first (x is in no occluder).
  if (arc.full) return arc.width;

  scratch.blocked.clear();
  for (std::size_t k = 0; k < scene.occluders.size(); ++k) {
    for_each_blocked_piece(light, scene.occluders[k], k, x, arc, occluder_spans[k], scratch,
                           [&](double lo, double hi) { scratch.blocked.push_back({lo, hi}); });
  }
  // Blocked pieces that meet end to end come from different atan2 calls: a cover of the whole
  // arc can leave a residue of a few ulps of it, which is rounding, not a visible sliver.
  const double visible = arc.width - union_measure(scratch.blocked);
  return visible > kContactTolerance * arc.width ? visible : 0.0;
}

LightNeeds light_needs(const PreparedScene& scene, std::size_t light_index, Vec2 x, const std::vector<std::uint32_t>& ids,
                       ScalarScratch& scratch) {
  const PreparedLight& light = scene.lights[light_index];
  const AngularSpan arc = angular_span(light.shape, x);
  if (arc.width <= 0.0) return {};
  LightNeeds needs;
  scratch.blocked.clear();
  for (const std::uint32_t k : ids) {
    const AngularSpan span = angular_span(scene.occluders[k], x);
    if (span.full) return {};  // inside an occluder: every direction is blocked at t = 0
    if (arc.full) continue;    // inside the light: nothing comes first
    const std::size_t before = scratch.blocked.size();
    for_each_blocked_piece(light, scene.occluders[k], k, x, arc, span, scratch,
                           [&](double lo, double hi) { scratch.blocked.push_back({lo, hi}); });
    if (scratch.blocked.size() > before) ++needs.blocking;
  }
  const double visible = arc.full ? arc.width : arc.width - union_measure(scratch.blocked);
  needs.visible = visible > kContactTolerance * arc.width;
  if (!needs.visible) needs.blocking = 0;
  return needs;
}

namespace {

// docs/contract.md section 1 (every occluder opaque and acting on every light, no other term).
Rgb plain_irradiance(const PreparedScene& scene, Vec2 x, ScalarScratch& scratch) {
  Rgb e{0.0, 0.0, 0.0};
  if (scene.lights.empty()) return e;
  scratch.occluder_spans.resize(scene.occluders.size());
  for (std::size_t k = 0; k < scene.occluders.size(); ++k) {
    const AngularSpan span = angular_span(scene.occluders[k], x);
    if (span.full) return e;  // inside an occluder: every direction is blocked at t = 0
    scratch.occluder_spans[k] = span;
  }
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const double weight = visible_measure(scene, l, x, scratch.occluder_spans, scratch) / kTwoPi;
    for (int c = 0; c < 3; ++c) e[c] += scene.lights[l].emission[c] * weight;
  }
  return e;
}

// Whether occluder k acts on a light with mask `mask` at x (docs/contract.md section 6: masks
// share a bit, and x is not inside it when its interior is lit).
bool acts(const OccluderTerms& terms, bool x_inside, std::uint32_t mask) noexcept {
  return terms.acts_on(mask) && !(x_inside && terms.lit_interior);
}

void set_shading(AngularProfile<double>& p, double origin, const Vec3& n, double sin_el, double cos_el) noexcept {
  set_profile_shading(p, origin, std::atan2(n.y, n.x), std::hypot(n.x, n.y), n.z, sin_el, cos_el);
}

// Integral over the arc u in [0, width] of V(u) * profile(u), per channel, where V(u) is the
// product of the transmittances of the blocked pieces (scratch.piece_lo_hi, blocked by
// scratch.piece_occluder) covering u: the pieces' end points cut the arc into elementary
// pieces, each covered by a fixed set. Uncovered pieces narrower than kContactTolerance of the
// arc are the rounding between pieces that meet end to end (see visible_measure), not light.
Rgb covered_integral(const PreparedScene& scene, const AngularProfile<double>& p, double width,
                     ScalarScratch& scratch) {
  const auto cumulative = [&p](double u) { return profile_cumulative(p, u); };
  auto& sweep = scratch.sweep;
  sweep.clear();
  for (std::size_t q = 0; q < scratch.piece_lo_hi.size(); ++q) {
    const ArcInterval piece = scratch.piece_lo_hi[q];
    if (!(piece.hi > piece.lo)) continue;
    sweep.push_back({piece.lo, static_cast<int>(q) + 1});
    sweep.push_back({piece.hi, -static_cast<int>(q) - 1});
  }
  std::sort(sweep.begin(), sweep.end(),
            [](const std::pair<double, int>& a, const std::pair<double, int>& b) { return a.first < b.first; });
  scratch.active.clear();
  int opaque = 0;
  Rgb sum{0.0, 0.0, 0.0};
  double at = 0.0, f_at = cumulative(0.0);
  const double residue = kContactTolerance * width;
  // Adds the elementary piece [at, to] with the current cover, and moves `at` to `to`.
  const auto advance = [&](double to) {
    if (!(to > at)) return;
    const double f_to = cumulative(to);
    if (opaque == 0 && !(scratch.active.empty() && to - at < residue)) {
      Rgb t{1.0, 1.0, 1.0};
      for (std::uint32_t q : scratch.active) {
        const Rgb& tq = scene.occluder_terms[scratch.piece_occluder[q]].transmittance;
        for (int c = 0; c < 3; ++c) t[c] *= tq[c];
      }
      for (int c = 0; c < 3; ++c) sum[c] += t[c] * (f_to - f_at);
    }
    at = to;
    f_at = f_to;
  };
  for (const auto& [position, event] : sweep) {
    advance(std::min(position, width));
    if (event > 0) {
      const std::uint32_t q = static_cast<std::uint32_t>(event - 1);
      if (scene.occluder_terms[scratch.piece_occluder[q]].opaque())
        ++opaque;
      else
        scratch.active.push_back(q);
    } else {
      const std::uint32_t q = static_cast<std::uint32_t>(-event - 1);
      if (scene.occluder_terms[scratch.piece_occluder[q]].opaque()) {
        --opaque;
      } else {
        const auto it = std::find(scratch.active.begin(), scratch.active.end(), q);
        *it = scratch.active.back();
        scratch.active.pop_back();
      }
    }
  }
  advance(width);
  return sum;
}

// docs/contract.md section 6 at x, shaded by `normal` when not null. Occluder `skip` (when a
// valid index) is left out, as if absent, and the ambient term only added with `ambient`: a
// bounce piece's direct light (section 7) is taken so on its own occluder's boundary.
// `choose(l)` gives the occluders light l is evaluated against (ascending), or null to leave
// the light out: the reference takes every occluder and every light; a caller that knows the
// others add nothing passes fewer. Directional
// lights always look at every occluder. Angular spans are computed for the occluders looked at.
template <class Choose>
Rgb model_irradiance_over(const PreparedScene& scene, Vec2 x, const Vec3* normal, ScalarScratch& scratch,
                          std::size_t skip, bool ambient, Choose&& choose) {
  Rgb e = ambient ? scene.ambient : Rgb{0.0, 0.0, 0.0};
  const std::size_t occluders = scene.occluders.size();
  scratch.occluder_spans.resize(occluders);
  scratch.inside.resize(occluders);
  scratch.span_stamp.resize(occluders, 0);
  if (++scratch.stamp == 0) {  // wrapped: forget every span
    std::fill(scratch.span_stamp.begin(), scratch.span_stamp.end(), 0u);
    scratch.stamp = 1;
  }
  // Left out: contains nothing, and acts on no light (its mask bits are ignored below).
  const bool skipping = skip < occluders;
  auto span_of = [&](std::size_t k) -> const AngularSpan& {
    if (scratch.span_stamp[k] != scratch.stamp) {
      scratch.span_stamp[k] = scratch.stamp;
      scratch.occluder_spans[k] = angular_span(scene.occluders[k], x);
      scratch.inside[k] = scratch.occluder_spans[k].full && !(skipping && k == skip) ? 1 : 0;
    }
    return scratch.occluder_spans[k];
  };
  AngularProfile<double> profile;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const PreparedLight& light = scene.lights[l];
    const LightTerms& terms = light.terms;
    double window = 1.0;
    if (terms.has_range()) {
      window = range_window(point_distance(light.shape, x), terms.range, terms.falloff,
                            [&](double base) { return std::pow(base, terms.falloff); });
      if (!(window > 0.0)) continue;
    }
    const std::vector<std::uint32_t>* chosen = choose(l);
    if (!chosen) continue;
    // Acting occluders containing x: t_B = 0 <= t_L along every direction.
    Rgb factor{window, window, window};
    for (const std::uint32_t k : *chosen) {
      span_of(k);
      if (!scratch.inside[k] || !acts(scene.occluder_terms[k], true, terms.mask)) continue;
      for (int c = 0; c < 3; ++c) factor[c] *= scene.occluder_terms[k].transmittance[c];
    }
    if (!(std::max({factor[0], factor[1], factor[2]}) > 0.0)) continue;
    const AngularSpan arc = angular_span(light.shape, x);
    if (arc.width <= 0.0) continue;
    scratch.piece_lo_hi.clear();
    scratch.piece_occluder.clear();
    // Inside the light (t_L = 0) only occluders containing x come first.
    if (!arc.full) {
      for (const std::uint32_t k : *chosen) {
        const AngularSpan& span = span_of(k);
        if (scratch.inside[k] || k == skip || !acts(scene.occluder_terms[k], false, terms.mask)) continue;
        for_each_blocked_piece(light, scene.occluders[k], k, x, arc, span, scratch, [&](double lo, double hi) {
          scratch.piece_lo_hi.push_back({lo, hi});
          scratch.piece_occluder.push_back(k);
        });
      }
    }
    profile = AngularProfile<double>{};
    if (terms.has_cone) set_profile_cone(profile, arc.start, terms.cone_center, terms.cone_half, terms.cone_fade);
    if (terms.cookie.count > 0) set_profile_cookie(profile, arc.start, &terms.cookie);
    if (normal) set_shading(profile, arc.start, *normal, terms.sin_elevation, terms.cos_elevation);
    // The integrand is >= 0; differences of its antiderivative over a tiny arc may round below.
    const Rgb seen = covered_integral(scene, profile, arc.width, scratch);
    for (int c = 0; c < 3; ++c) e[c] += light.emission[c] * factor[c] * std::max(0.0, seen[c]) / kTwoPi;
  }
  for (const PreparedDirectional& sun : scene.directionals) {
    // Every acting occluder the ray meets is in front of a light at infinity; one containing
    // x meets every ray (its span is the full circle).
    const AngularSpan arc{sun.start, sun.width, false};
    scratch.piece_lo_hi.clear();
    scratch.piece_occluder.clear();
    for (std::size_t k = 0; k < occluders; ++k) {
      const AngularSpan& span = span_of(k);
      if (k == skip || !acts(scene.occluder_terms[k], scratch.inside[k] != 0, sun.mask)) continue;
      scratch.pieces.clear();
      clip_to_light_arc(arc, span, scratch.pieces);
      for (const ArcInterval& piece : scratch.pieces) {
        scratch.piece_lo_hi.push_back(piece);
        scratch.piece_occluder.push_back(static_cast<std::uint32_t>(k));
      }
    }
    profile = AngularProfile<double>{};
    if (normal) set_shading(profile, arc.start, *normal, sun.sin_elevation, sun.cos_elevation);
    const Rgb seen = covered_integral(scene, profile, arc.width, scratch);
    for (int c = 0; c < 3; ++c) e[c] += sun.emission[c] * std::max(0.0, seen[c]) / kTwoPi;
  }
  return e;
}

// The reference's choice: every light against every occluder.
Rgb model_irradiance(const PreparedScene& scene, Vec2 x, const Vec3* normal, ScalarScratch& scratch,
                     std::size_t skip = static_cast<std::size_t>(-1), bool ambient = true) {
  // Every occluder's index, kept from point to point while the count stays.
  std::vector<std::uint32_t>& every = scratch.every_occluder;
  if (every.size() != scene.occluders.size()) {
    every.resize(scene.occluders.size());
    for (std::size_t k = 0; k < every.size(); ++k) every[k] = static_cast<std::uint32_t>(k);
  }
  return model_irradiance_over(scene, x, normal, scratch, skip, ambient, [&](std::size_t) { return &every; });
}

}  // namespace

Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, ScalarScratch& scratch) {
  if (!scene.model) return plain_irradiance(scene, x, scratch);
  return model_irradiance(scene, x, nullptr, scratch);
}

Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, const Vec3* normal, ScalarScratch& scratch) {
  if (!scene.model) return plain_irradiance(scene, x, scratch);
  return model_irradiance(scene, x, normal, scratch);
}

Rgb direct_without(const PreparedScene& scene, Vec2 x, const Vec3& normal, std::size_t skip, ScalarScratch& scratch) {
  return model_irradiance(scene, x, &normal, scratch, skip, false);
}

Rgb piece_direct_light(const PreparedScene& scene, Vec2 x, Vec2 n, std::size_t skip, ScalarScratch& scratch,
                       const LightHiddenTest* hidden) {
  const Vec3 normal{n.x, n.y, 0.0};
  // The points just off the piece, which S_k is the limit at (a box around x: its own occluder
  // only blocks directions of zero shading from there, so a reach that hides the box from a
  // light, proven with that occluder among the others, hides the light from the piece too).
  const double margin = 1e-7 * (1.0 + std::fabs(x.x) + std::fabs(x.y));
  const Aabb near{x.x - margin, x.y - margin, x.x + margin, x.y + margin};
  return model_irradiance_over(
      scene, x, &normal, scratch, skip, false, [&](std::size_t l) -> const std::vector<std::uint32_t>* {
        const ConvexShape& shape = scene.lights[l].shape;
        // A light wholly on the closed back side of the piece's line gets shading 0 at every
        // direction toward it (s = max(0, cos a * n . dir)), and one with elevation 90 degrees
        // everywhere: it adds nothing.
        if (!(scene.lights[l].terms.cos_elevation > 0.0)) return nullptr;
        if (hidden && hidden->hides(l, near)) return nullptr;
        double front = -std::numeric_limits<double>::infinity();  // the largest n . p over the light's points p
        if (shape.kind == ShapeKind::circle) {
          front = dot(n, shape.vertices[0]) + shape.radius * std::hypot(n.x, n.y);
        } else {
          for (const Vec2 v : shape.vertices) front = std::max(front, dot(n, v));
        }
        if (!(front > dot(n, x))) return nullptr;
        // Every segment from x to the light lies in their hull: an occluder whose box misses it
        // blocks no direction toward the light, nor contains x.
        hull_with_shape(&x, 1, shape, scratch.hull_points, scratch.hull);
        std::vector<std::uint32_t>& list = scratch.chosen;
        list.clear();
        scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), list);
        std::sort(list.begin(), list.end());
        return &list;
      });
}

void blocked_pieces(const PreparedLight& light, const ConvexShape& occluder, std::size_t k, Vec2 x, const AngularSpan& arc,
                    const AngularSpan& span, ScalarScratch& scratch, std::vector<ArcInterval>& out) {
  for_each_blocked_piece(light, occluder, k, x, arc, span, scratch,
                         [&](double lo, double hi) { out.push_back({lo, hi}); });
}

}  // namespace par2d::detail
