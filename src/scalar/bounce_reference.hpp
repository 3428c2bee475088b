// One bounce of indirect light by its definition (docs/contract.md section 7), in double
// precision: the pieces' radiances from the exact direct value at their midpoints, then each
// reflecting occluder's visible front as one-sided lights, shadowed by every other occluder
// with the same depth tests the reference uses for direct light.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/bounce_pieces.hpp"
#include "scalar/scalar_renderer.hpp"
#include "world/prepared_scene.hpp"

namespace par2d::detail {

// A reflecting occluder: its pieces (a run of BounceFrame::pieces) and its shape as a light
// (the shape of occluder `occluder`, with the other occluders it meets and how), so that its
// pieces' shadows come from the same depth test as a light's. Along a direction that meets a
// piece from its front the occluder is entered exactly at the piece, so its depth there is
// the piece's.
struct BounceSource {
  std::uint32_t occluder = 0;
  std::uint32_t first = 0, count = 0;
  PreparedLight light;
  bool lit = false;  // some piece has a non-zero radiance (finish_bounce_frame)
};

// What a frame's bounce needs, built once per frame: the pieces (prepared coordinates) and
// their radiances L_k.
struct BounceFrame {
  std::vector<BouncePiece> pieces;
  std::vector<Rgb> radiance;  // parallel to pieces
  std::vector<BounceSource> sources;
};

// Per-thread buffers for bounce_irradiance.
struct BounceScratch {
  ScalarScratch scalar;
  std::vector<ArcInterval> blocked;
  std::vector<std::uint32_t> blocked_occluder;
  std::vector<std::pair<double, int>> sweep;
  std::vector<std::uint32_t> active;
  struct Covered {
    double lo, hi;
    Rgb transmittance;
  };
  std::vector<Covered> coverage;  // the seen parts of an arc, each with its transmittance
  struct Emitter {
    double lo, hi;
    std::uint32_t piece;
  };
  std::vector<Emitter> emitters;
  // The occluders the index finds near x and the segments to a reflector, each one's span
  // from x found once per point (span_stamp == stamp).
  std::vector<std::uint32_t> near;
  std::vector<std::uint32_t> containing;
  std::vector<std::uint32_t> span_stamp;
  std::uint32_t stamp = 0;
  std::vector<Vec2> hull_points, hull;  // the hull of x and a reflector
  // Work counts for FrameStats, accumulated over calls until the owner resets them: lit
  // sources walked at a point, and occluders depth-tested against a source there.
  std::uint64_t source_walks = 0, depth_tests = 0;
};

// The pieces and sources of `scene` (radiances sized, not computed). Nothing when the scene
// has no reflecting occluder.
void build_bounce_sources(const PreparedScene& scene, BounceFrame& frame);

// L_k = pi * albedo * S_k for pieces [first, last): S_k is section 6's value without ambient at
// the piece's midpoint, its own occluder left out, shaded by the normal (n_k, 0). With `cull`,
// each light only against the occluders near the segments to it, and not where `hidden` (or
// null) hides it (piece_direct_light).
void bounce_radiances(const PreparedScene& scene, BounceFrame& frame, std::size_t first, std::size_t last,
                      ScalarScratch& scratch, bool cull, const LightHiddenTest* hidden = nullptr);

// Which sources have a lit piece, once every radiance is in.
void finish_bounce_frame(BounceFrame& frame) noexcept;

// All three, on this thread.
void prepare_bounce_frame(const PreparedScene& scene, BounceFrame& frame, ScalarScratch& scratch);

// The sources that may reach a region of points and, for each, the occluders that may stand
// between the region and it (bounce_tiles.hpp): source sources[i] (an index into
// frame.sources) has blockers[first[i] .. first[i + 1]), a superset of the occluders whose
// boxes meet the hull of any point of the region and the source.
struct BounceSourceSubset {
  const std::uint32_t* sources = nullptr;
  std::size_t count = 0;
  const std::uint32_t* first = nullptr;  // count + 1 offsets into blockers
  const std::uint32_t* blockers = nullptr;
};

// The bounce term at x: sum over pieces of L_k (1/2pi) * integral of V_k F_k s, shaded by
// `normal` (elevation 0) or plain when null. `subset`, when given, holds the only sources that
// may reach x (the others are proven to add nothing there, and are not walked) and their
// possible blockers (the occluder index is then not queried per point).
Rgb bounce_irradiance(const PreparedScene& scene, const BounceFrame& frame, Vec2 x, const Vec3* normal,
                      BounceScratch& scratch, const BounceSourceSubset* subset = nullptr);

}  // namespace par2d::detail
