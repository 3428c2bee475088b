// A frame's work estimated from counts before it runs (WorkEstimate, docs/api.md "Long renders"),
// shared by the Renderer's frames, the one-shot front door and the ray caster, so that each
// path is bounded by one formula.
#pragma once

#include <string>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// What the estimate reads of a frame.
struct WorkCounts {
  double pixels = 0.0;     // pixels the frame computes
  int spp = 1;
  double lights = 0.0;     // lights and directional lights
  double occluders = 0.0;
  double pieces = 0.0;     // bounce pieces (0: no bounce term computed)
  bool direct = true;      // the direct light is computed (not BounceTerm::only)
  bool scalar = false;     // the direct light by the scalar reference
  bool raycast = false;    // render_raycast (rays per sample: `rays`)
  int rays = 0;
};

WorkEstimate estimate_work(const WorkCounts& counts) noexcept;

// The counts of a prepared frame computing `pixels` pixels with these settings (`pieces`:
// bounce_pieces(scene), or 0 when the options leave the bounce out).
WorkCounts work_counts(const PreparedScene& scene, double pixels, int spp, bool scalar, BounceTerm bounce);

// The bounce pieces a validated scene's reflecting occluders are cut into (0 without any).
double bounce_pieces(const PreparedScene& scene) noexcept;
double bounce_pieces(const Scene& scene) noexcept;

// Null when the estimate is within `limit` (0: none); else the refusal, `who` first.
Status check_work(const WorkEstimate& estimate, double limit, const char* who);

}  // namespace par2d::detail
