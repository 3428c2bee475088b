// Per-part scene checks shared by validate_scene and the JSON loader, so both word problems alike.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "par2d/scene.hpp"
#include "par2d/status.hpp"

namespace par2d::detail {

// What is wrong and where: `place` is JSON-path-like ("lights[2].polygon"), empty for the whole scene.
struct SceneProblem {
  std::string place;
  std::string what;
};

using MaybeProblem = std::optional<SceneProblem>;

// The text every refused image side gets, so the loader (which sees doubles and 64-bit
// integers before it may cast) and validate_scene agree word for word.
std::string image_side_range_text();

MaybeProblem check_image_size(int width, int height);
// Also needs the image size: a view's pixel size must be a normal double.
MaybeProblem check_view(const View& view, int width, int height);

// Largest total emission per channel: E never exceeds the lights' total (docs/contract.md),
// and this keeps it, and every float the SIMD path forms from it, finite in float32 output
// (FLT_MAX is 3.4e38; the margin covers 2*pi-scaled partial sums and rounding).
inline constexpr double kMaxTotalEmission = 1e38;
// The first light at which the running total of some channel, each light counted as
// light_entries_bound times its emission, passes kMaxTotalEmission.
MaybeProblem check_emission_total(const std::vector<Light>& lights);
// The most times a ray enters a concave (or holed) polygon light: a line crosses each of its
// n edges (outline and holes) at most once and enters at every other crossing, or at 0 from
// inside: 1 + floor(n / 2). A concave light adds its emission once per entry (docs/contract.md
// section 3), so E can reach this multiple of it.
double concave_entries_bound(const Polygon& polygon) noexcept;
// That bound for a valid light: 1 for a convex shape, concave_entries_bound for a partitioned one.
double light_entries_bound(const Light& light);

// `place` names the light or occluder ("lights[2]"); shape problems add ".polygon" etc.
// With `concave_allowed` (lights and occluders) a polygon may be a concave simple outline
// that partitions; without, it must be convex.
MaybeProblem check_shape(const Shape& shape, const std::string& place, bool concave_allowed = false);
// Whether a valid shape is rendered as a convex partition of it: a polygon whose outline is
// not convex (within the tolerance the convex check allows).
bool needs_partition(const Shape& shape);
MaybeProblem check_light(const Light& light, const std::string& place);
MaybeProblem check_occluder(const Occluder& occluder, const std::string& place);
// The game lighting model's scene-wide terms (docs/contract.md section 6).
MaybeProblem check_ambient(const Rgb& ambient);
MaybeProblem check_directional(const DirectionalLight& light, const std::string& place);
MaybeProblem check_normal(const Vec3& normal);
// One bounce (docs/contract.md section 7): the piece length, and how many pieces the
// reflecting occluders are cut into (at most kMaxBouncePieces, the problem named bounce.piece).
MaybeProblem check_bounce(const Bounce& bounce);
MaybeProblem check_bounce_pieces(const Scene& scene);
std::string bounce_pieces_text(double pieces);
// Whether a normal map's check covers each normal, or only its size: a caller that has
// converted the map (world_normals) has checked every normal in that pass already.
enum class NormalsCheck { each, size_only };
// The map's size against the image's, its buffer's length, each normal finite and non-zero.
MaybeProblem check_normal_map(const NormalMap& map, int width, int height, NormalsCheck normals = NormalsCheck::each);
// Every term that needs the whole scene: at most one normal source, the normal source's size,
// and the total emission (lights as light_entries_bound times theirs, directional lights and
// ambient) within kMaxTotalEmission.
MaybeProblem check_scene_terms(const Scene& scene, NormalsCheck normals = NormalsCheck::each);
// par2d::validate_scene, with the normal map's normals checked as `normals` says.
Status validate_scene(const Scene& scene, std::string_view name, NormalsCheck normals);

// `NAME: PLACE: WHAT` (or `NAME: WHAT` without a place) as an invalid_scene status.
Status scene_error(std::string_view name, const SceneProblem& problem);

// Shortest text that reads back as the same double ("0.1", "1e+300", "inf").
std::string format_number(double value);

}  // namespace par2d::detail
