// Reference PAR: each shape becomes an arc of directions from x; occluders in front of a
// light are cut out of its arc (union, not sum); the rest, over 2*pi, weights its emission.
#include "scalar/scalar_renderer.hpp"

#include <algorithm>
#include <cmath>

namespace par2d::detail {
namespace {

Vec2 direction(double angle) noexcept { return {std::cos(angle), std::sin(angle)}; }

// Whether the occluder comes first along the direction, contacts counting as first
// (docs/contract.md: the light is visible only when t_L < t_occ).
bool occluder_first(const ConvexShape& occluder, const ConvexShape& light, Vec2 x, double angle,
                    EntryHints& hints) noexcept {
  return detail::occluder_first(occluder, light, x, direction(angle), hints);
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
    scratch.pieces.clear();
    clip_to_light_arc(arc, occluder_spans[k], scratch.pieces);
    if (scratch.pieces.empty()) continue;
    const ConvexShape& occluder = scene.occluders[k];
    const auto overlap = std::lower_bound(light.overlapping_occluders.begin(),
                                          light.overlapping_occluders.end(), k);
    if (overlap == light.overlapping_occluders.end() || *overlap != k) {
      // Disjoint convex shapes: along every direction that meets both, the same one comes
      // first (the paper's depth test), so one key ray per piece decides the whole piece.
      EntryHints hints;
      for (const ArcInterval& piece : scratch.pieces) {
        if (occluder_first(occluder, light.shape, x, arc.start + 0.5 * (piece.lo + piece.hi), hints))
          scratch.blocked.push_back(piece);
      }
      continue;
    }
    // Overlapping shapes: which one comes first can only change at a direction through a
    // point where their boundaries meet, so test one key ray between consecutive such
    // directions.
    const auto& points = light.overlap_points[static_cast<std::size_t>(overlap - light.overlapping_occluders.begin())];
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
        if (hi > lo && occluder_first(occluder, light.shape, x, arc.start + 0.5 * (lo + hi), hints))
          scratch.blocked.push_back({lo, hi});
      }
    }
  }
  // Blocked pieces that meet end to end come from different atan2 calls: a cover of the whole
  // arc can leave a residue of a few ulps of it, which is rounding, not a visible sliver.
  const double visible = arc.width - union_measure(scratch.blocked);
  return visible > kContactTolerance * arc.width ? visible : 0.0;
}

Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, ScalarScratch& scratch) {
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

}  // namespace par2d::detail
