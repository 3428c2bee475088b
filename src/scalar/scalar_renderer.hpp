// The reference renderer: PAR in double precision with exact trigonometry, one point at a time.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/angular_intervals.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// Reusable buffers so that evaluating a point allocates nothing once warmed up.
struct ScalarScratch {
  std::vector<AngularSpan> occluder_spans;
  std::vector<ArcInterval> pieces;
  std::vector<ArcInterval> blocked;
  std::vector<double> events;
};

// E(x) of docs/contract.md section 1.
Rgb scalar_irradiance(const PreparedScene& scene, Vec2 x, ScalarScratch& scratch);

// Radians of light `light`'s arc seen from x that no occluder blocks. `occluder_spans`
// holds angular_span(occluder k, x) for every occluder; x must lie in no occluder.
double visible_measure(const PreparedScene& scene, std::size_t light, Vec2 x,
                       const std::vector<AngularSpan>& occluder_spans, ScalarScratch& scratch);

}  // namespace par2d::detail
