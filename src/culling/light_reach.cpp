// Light reach: per-sector proofs that the occluders around a light hide it from everything farther away.
#include "culling/light_reach.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace par2d::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSectorWidth = kTwoPi / LightReach::kSectors;
// Radii tried: the light's radius plus this many pixels times a power of two.
constexpr double kFirstStepPixels = 8.0;
constexpr int kMaxRadii = 24;
// Strips one sector proof may use: proofs that need more are rare and not worth their cost.
constexpr int kStripBudget = 32;

// Whether everything at distance >= r from the center within the sector of directions
// [mid - width / 2, mid + width / 2] is hidden from the light.
//
// A segment from such a point x to a light point y passes within `radius` of the center, so
// it crosses the circle of radius r at an angle within asin(radius / r) of x's: inside the
// sector widened by that much on both sides. There it crosses the chord joining the widened
// arc's ends first (y lies on the center's side of the chord, the arc on the other). So
// when every segment from the chord to the light is blocked strictly between the two, so
// is every segment from x.
bool sector_hidden(const PreparedScene& scene, std::size_t light_index, const LightReach& reach, double mid,
                   double width, double r, LightReachScratch& scratch) {
  const ConvexShape& light = scene.lights[light_index].shape;
  const double half = 0.5 * width + std::asin(std::min(1.0, reach.radius / r)) + 1e-9;
  if (!(half < 0.5 * kPi) || !(r * std::cos(half) > reach.radius)) return false;
  const Vec2 c = reach.center;
  const Vec2 chord[2] = {c + r * Vec2{std::cos(mid - half), std::sin(mid - half)},
                         c + r * Vec2{std::cos(mid + half), std::sin(mid + half)}};
  hull_with_shape(chord, 2, light, scratch.hull_points, scratch.hull);
  // The answer depends on the occluders meeting this hull and nothing else.
  for (const Vec2 p : scratch.hull) grow(scratch.depends_on, p);
  scratch.candidates.clear();
  scene.occluder_bvh.query_convex(scratch.hull.data(), static_cast<int>(scratch.hull.size()), scratch.candidates);
  if (scene.model) {
    // Only opaque, dark occluders acting on the light may prove it hidden (section 6).
    const std::uint32_t mask = scene.lights[light_index].terms.mask;
    scratch.candidates.erase(std::remove_if(scratch.candidates.begin(), scratch.candidates.end(),
                                            [&](std::uint32_t id) {
                                              const OccluderTerms& t = scene.occluder_terms[id];
                                              return !(t.opaque() && !t.lit_interior && t.acts_on(mask));
                                            }),
                             scratch.candidates.end());
  }
  if (scratch.candidates.empty()) return false;
  const Vec2 toward_light{-std::cos(mid), -std::sin(mid)};
  return segments_blocked(chord, 2, toward_light, light, scene.occluders, scratch.candidates.data(),
                          scratch.candidates.size(), kStripBudget, scratch.proof);
}

}  // namespace

bool LightReach::hides(const Aabb& box) const noexcept {
  const double dx = std::max({box.min_x - center.x, 0.0, center.x - box.max_x});
  const double dy = std::max({box.min_y - center.y, 0.0, center.y - box.max_y});
  const double distance = std::hypot(dx, dy);
  if (!(distance > radius)) return false;
  // Beyond every sector's reach, or short of every sector's: the answer does not depend on
  // which sectors the box spans.
  if (farthest <= distance) return true;
  if (distance < nearest) return false;
  // The box's directions from the center: an arc narrower than pi (the center is outside),
  // from the corner every other corner lies counter-clockwise of (or along) to the corner
  // every other lies clockwise of. Two atan2 for those two corners, where measuring all four
  // against the box's middle direction takes five (most of this function's cost).
  const Vec2 v[4] = {Vec2{box.min_x, box.min_y} - center, Vec2{box.max_x, box.min_y} - center,
                     Vec2{box.max_x, box.max_y} - center, Vec2{box.min_x, box.max_y} - center};
  int clockwise_end = -1, counter_clockwise_end = -1;
  for (int i = 0; i < 4; ++i) {
    bool first = true, last = true;
    for (int j = 0; j < 4; ++j) {
      const double c = cross(v[i], v[j]);
      first = first && c >= 0.0;
      last = last && c <= 0.0;
    }
    if (first && clockwise_end < 0) clockwise_end = i;
    if (last && counter_clockwise_end < 0) counter_clockwise_end = i;
  }
  // Rounding can leave no corner first among corners on nearly one ray (or overflowed cross
  // products none at all): not proven hidden then, which only leaves the light to the tile setup.
  if (clockwise_end < 0 || counter_clockwise_end < 0) return false;
  const double lo = std::atan2(v[clockwise_end].y, v[clockwise_end].x);
  double hi = std::atan2(v[counter_clockwise_end].y, v[counter_clockwise_end].x);
  if (hi < lo) hi += kTwoPi;
  if (!(hi - lo < kPi)) return false;  // not an arc narrower than pi: NaN or overflowed corners
  const double margin = 1e-9;  // atan2's rounding at sector edges
  const int first = static_cast<int>(std::floor((lo - margin + kPi) / kSectorWidth));
  const int last = static_cast<int>(std::floor((hi + margin + kPi) / kSectorWidth));
  for (int k = first; k <= last; ++k) {
    const int sector = ((k % kSectors) + kSectors) % kSectors;
    if (!(reach[static_cast<std::size_t>(sector)] <= distance)) return false;
  }
  return true;
}

void LightReachScratch::reserve_for(std::size_t occluders, std::size_t max_vertices) {
  // A chord's two ends and the light's vertices (a circle's box corners), and their hull.
  const std::size_t points = 2 + std::max<std::size_t>(4, max_vertices);
  hull_points.reserve(points);
  hull.reserve(2 * points + 1);
  candidates.reserve(occluders);  // the index reports each occluder at most once
  proof.reserve_for(occluders, max_vertices, kStripBudget);
}

double reach_farthest(const PreparedScene& scene, std::size_t light, Vec2 center, double radius) noexcept {
  const View view = scene.visible_view();
  double farthest = 0.0;
  for (const Vec2 corner : {Vec2{view.x0, view.y0}, Vec2{view.x1, view.y0}, Vec2{view.x0, view.y1}, Vec2{view.x1, view.y1}})
    farthest = std::max(farthest, length(corner - center));
  // A ranged light reaches no point farther than its range from its shape (section 6): at
  // distance radius + range from the center the window is 0. Proofs need go no farther.
  const LightTerms& terms = scene.lights[light].terms;
  if (scene.model && terms.has_range()) farthest = std::min(farthest, radius + terms.range);
  return farthest;
}

LightReach compute_light_reach(const PreparedScene& scene, std::size_t light_index, LightReachScratch& scratch) {
  const ConvexShape& light = scene.lights[light_index].shape;
  LightReach reach;
  reach.reach.fill(kInf);
  scratch.depends_on = kEmptyBox;
  reach.center = light.centroid;
  if (light.kind == ShapeKind::circle) {
    reach.radius = light.radius;
  } else {
    for (const Vec2 v : light.vertices) reach.radius = std::max(reach.radius, length(v - reach.center));
  }
  // Radii in pixels of the grid (the same wherever the view is offset on it).
  const View& grid = scene.view;
  const double pixel = std::max(std::abs(grid.x1 - grid.x0) / scene.width, std::abs(grid.y1 - grid.y0) / scene.height);
  const double farthest = reach_farthest(scene, light_index, reach.center, reach.radius);
  const LightTerms& terms = scene.lights[light_index].terms;
  if (scene.model && terms.has_range()) reach.reach.fill(reach.radius + terms.range);
  // No pixel lies beyond the farthest view corner, so larger radii would hide nothing.
  double radii[kMaxRadii];
  int count = 0;
  double step = kFirstStepPixels * pixel;
  for (; count < kMaxRadii && reach.radius + step <= farthest; step *= 2.0) radii[count++] = reach.radius + step;
  scratch.farthest_low = count == 0 ? -kInf : radii[count - 1];
  scratch.farthest_high = count == kMaxRadii ? kInf : reach.radius + step;
  // Each sector's smallest radius that its proof holds for. Next to a sector open to the
  // view (every sector of a lamp in the open) the largest radius is tried first: where it
  // fails no smaller one can hold, and one proof settles the sector instead of a bisection's
  // four or five. Elsewhere (walls all around) that extra proof, the costliest, would not pay.
  bool previous_open = true;
  for (int k = 0; k < LightReach::kSectors; ++k) {
    const double mid = -kPi + (k + 0.5) * kSectorWidth;
    auto hidden_at = [&](int at) { return sector_hidden(scene, light_index, reach, mid, kSectorWidth, radii[at], scratch); };
    int lo = 0, hi = count - 1, found = count;
    if (previous_open && count != 0) {
      if (!hidden_at(count - 1)) continue;  // still open
      found = hi--;
    }
    while (lo <= hi) {
      const int at = (lo + hi) / 2;
      if (hidden_at(at)) {
        found = at;
        hi = at - 1;
      } else {
        lo = at + 1;
      }
    }
    previous_open = found == count;
    if (!previous_open) reach.reach[static_cast<std::size_t>(k)] = radii[found];
  }
  reach.nearest = *std::min_element(reach.reach.begin(), reach.reach.end());
  reach.farthest = *std::max_element(reach.reach.begin(), reach.reach.end());
  return reach;
}

}  // namespace par2d::detail
