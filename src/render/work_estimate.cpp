// The work estimate's one formula (render/work_estimate.hpp) and the refusal past the limit.
#include "render/work_estimate.hpp"

#include <cstdio>
#include <variant>

#include "geometry/bounce_pieces.hpp"

namespace par2d::detail {

WorkEstimate estimate_work(const WorkCounts& c) noexcept {
  WorkEstimate e;
  e.samples = c.pixels * c.spp;
  if (c.raycast) {
    // Every ray tests every shape; each piece's radiance takes `rays` rays of its own.
    e.raycast = c.rays * (e.samples + c.pieces) * (c.lights + c.occluders);
  } else {
    // A piece's radiance is the direct value at its midpoint; each sample walks every piece.
    e.bounce = c.pieces * (e.samples + c.lights * (c.occluders + 1.0));
    if (c.scalar && c.direct) e.scalar = e.samples * c.lights * (c.occluders + 1.0);
  }
  e.total = e.bounce + e.scalar + e.raycast;
  return e;
}

double bounce_pieces(const PreparedScene& scene) noexcept {
  if (!scene.bounce) return 0.0;
  double pieces = 0.0;
  for (const OccluderTerms& terms : scene.occluder_terms)
    if (terms.reflects()) pieces += bounce_piece_count(terms.bounce_shape, scene.bounce_piece, 2.0 * kMaxBouncePieces);
  return pieces;
}

double bounce_pieces(const Scene& scene) noexcept {
  double pieces = 0.0;
  for (const Occluder& o : scene.occluders)
    if (o.albedo[0] != 0.0 || o.albedo[1] != 0.0 || o.albedo[2] != 0.0)
      pieces += bounce_piece_count(o.shape, scene.bounce.piece, 2.0 * kMaxBouncePieces);
  return pieces;
}

WorkCounts work_counts(const PreparedScene& scene, double pixels, int spp, bool scalar, BounceTerm bounce) {
  WorkCounts c;
  c.pixels = pixels;
  c.spp = spp;
  c.lights = static_cast<double>(scene.lights.size() + scene.directionals.size());
  c.occluders = static_cast<double>(scene.occluders.size());
  c.pieces = bounce == BounceTerm::excluded ? 0.0 : bounce_pieces(scene);
  c.direct = bounce != BounceTerm::only;
  c.scalar = scalar;
  return c;
}

Status check_work(const WorkEstimate& estimate, double limit, const char* who) {
  if (limit == 0.0 || estimate.total <= limit) return {};
  char text[160];
  std::snprintf(text, sizeof text, "estimated work %.3g is past the work limit %.3g (bounce %.3g, scalar %.3g, raycast %.3g)",
                estimate.total, limit, estimate.bounce, estimate.scalar, estimate.raycast);
  return Status(StatusCode::work_limit, std::string(who) + ": " + text);
}

}  // namespace par2d::detail
