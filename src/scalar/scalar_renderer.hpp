// The reference renderer: PAR in double precision with exact trigonometry, one point at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/aabb.hpp"
#include "geometry/angular_intervals.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Reusable buffers so that evaluating a point allocates nothing once warmed up.
struct ScalarScratch {
  std::vector<AngularSpan> occluder_spans;
  std::vector<ArcInterval> pieces;
  std::vector<ArcInterval> blocked;
  std::vector<double> events;
  // The game lighting model (docs/contract.md section 6): which occluders contain the point,
  // the blocked pieces of one light's arc with the occluder that blocks each, and the sweep.
  std::vector<unsigned char> inside;
  std::vector<ArcInterval> piece_lo_hi;
  std::vector<std::uint32_t> piece_occluder;
  std::vector<std::pair<double, int>> sweep;
  std::vector<std::uint32_t> active;
  // The occluders one light is evaluated against, and which occluders' spans this point has
  // (span_stamp[k] == stamp).
  std::vector<std::uint32_t> chosen, every_occluder;
  std::vector<std::uint32_t> span_stamp;
  std::uint32_t stamp = 0;
  std::vector<Vec2> hull_points, hull;
};

// E(x) of docs/contract.md section 1; with the game lighting model's terms (scene.model) those
// of section 6, plain (s = 1).
Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, ScalarScratch& scratch);

// E(x) of docs/contract.md section 6 with the surface normal `normal` (unit, world axes) for
// the shading term, or plain irradiance when `normal` is null. Scenes without model terms
// take the section 1 path (the normal is then ignored: such scenes have no normal source).
Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, const Vec3* normal, ScalarScratch& scratch);

// Section 6's value at x without the ambient term, shaded by `normal`, with occluder `skip` left
// out as if absent (docs/contract.md section 7: a piece's direct light on its own occluder's
// boundary, approached from outside, where the shading keeps only the outward directions).
Rgb direct_without(const PreparedScene& scene, Vec2 x, const Vec3& normal, std::size_t skip, ScalarScratch& scratch);

// The same for a bounce piece's midpoint x with in-plane normal n (elevation as each light's),
// over fewer occluders and lights: those whose absence provably changes nothing (a light
// wholly behind the piece's line, occluders off every segment from x to a light). The sum
// runs over the same blocked pieces in the same order, so it equals direct_without but where a
// left-out light's shading would have rounded to a tiny non-zero value.
// `hidden` (or null) leaves out the lights it proves hide every point of a box around x (the
// frame's light reach, from a room above this one).
class LightHiddenTest {
 public:
  virtual bool hides(std::size_t light, const Aabb& box) const noexcept = 0;

 protected:
  ~LightHiddenTest() = default;
};
Rgb piece_direct_light(const PreparedScene& scene, Vec2 x, Vec2 n, std::size_t skip, ScalarScratch& scratch,
                       const LightHiddenTest* hidden = nullptr);

// Appends to `out` the pieces (in the frame of `arc`, a part of the light's own arc seen from
// x) that occluder k (`occluder`) is in front of, contacts counting as in front: the depth test
// the reference uses for every light, with the overlap events of `light`. x in neither shape;
// `span` is angular_span(occluder, x). Uses scratch.pieces and scratch.events.
void blocked_pieces(const PreparedLight& light, const ConvexShape& occluder, std::size_t k, Vec2 x, const AngularSpan& arc,
                    const AngularSpan& span, ScalarScratch& scratch, std::vector<ArcInterval>& out);

// Radians of light `light`'s arc seen from x that no occluder blocks. `occluder_spans`
// holds angular_span(occluder k, x) for every occluder; x must lie in no occluder.
double visible_measure(const PreparedScene& scene, std::size_t light, Vec2 x,
                       const std::vector<AngularSpan>& occluder_spans, ScalarScratch& scratch);

// What point x needs of light `light_index` among the occluders `ids` (FrameStats' sampled
// counts): whether some direction reaches the light with none of them in front, and if so
// how many of them are in front of a part of its arc (0 when it is hidden). Geometry only: the lighting model's
// transmittance, cone and range are not looked at.
struct LightNeeds {
  bool visible = false;
  std::uint32_t blocking = 0;
};
LightNeeds light_needs(const PreparedScene& scene, std::size_t light_index, Vec2 x, const std::vector<std::uint32_t>& ids,
                       ScalarScratch& scratch);

}  // namespace par2d::detail
