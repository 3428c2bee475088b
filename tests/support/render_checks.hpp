// Test-case helpers that report through doctest (render_checks.cpp; doctest binaries only).
#pragma once

#include <functional>
#include <string>

#include "par2d/renderer.hpp"
#include "support/random_scenes.hpp"

namespace par2d::test {

// A render compared with a reference at the pixels docs/contract.md section 5 covers.
struct Comparison {
  double max_error = 0.0;  // over the checked pixels
  int checked = 0;         // pixels farther than `exempt` from every shape boundary
  int over = 0;            // channel values off by more than the bound
  std::string first_failure;
};

// Compares `got` with `ref` channel by channel at the pixels whose centers are farther than
// `exempt` world units from every shape boundary.
Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           double exempt);
// The same at the pixels whose centers `exempt` does not exempt.
Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           const std::function<bool(Vec2)>& exempt);

// The SIMD path on every ISA here, culling on and off, against the scalar reference `ref`:
// the contract's 1e-4 e_max at every pixel `exempt` leaves, and at least `min_checked` such
// pixels per render. `visit(got)`, when given, checks each SIMD render further.
void check_simd_against_scalar(const Scene& scene, const RenderedImage& ref, const std::string& what,
                               const std::function<bool(Vec2)>& exempt, int min_checked,
                               const std::function<void(const RenderedImage&)>& visit = nullptr);

// Whether a frame of `renderer` (float RGB, its whole size) equals a one-shot render of its
// snapshot with its options bit for bit (docs/contract.md section 5), the snapshot holding as
// many lights and occluders as the renderer counts.
bool renderer_equals_snapshot(Renderer& renderer);

// A Renderer's whole frame as float RGB (fails the test case on an error), a one-shot render
// of a scene likewise, and whether two such images are equal bit for bit.
std::vector<float> frame_rgb(Renderer& r);
std::vector<float> one_shot(const Scene& scene, const RenderOptions& options);
bool same_bits(const std::vector<float>& a, const std::vector<float>& b);

// Both reports of a frame, read as one set of counts (their field names differ): a Renderer's
// last frame, or one frame of `scene` by a Renderer with `options` and sample_needs set
// (failing the test case on an error).
struct FrameCounts : FrameStats, FrameDiagnostics {};
FrameCounts frame_counts(const Renderer& renderer);
FrameCounts frame_counts(const Scene& scene, RenderOptions options);

// The ray caster (`rays` directions, jitter 0.5) at every pixel center farther than `skip`
// world units from every shape boundary, against `image`: the worst |E_image - E_ray| over
// stratification_bound(scene, rays, overlapping) (at most 1 means they agree), the pixels
// compared, and where the worst was.
struct RaycastAgreement {
  double worst = 0.0;
  int compared = 0;
  std::string where;
};
RaycastAgreement agreement_with_raycaster(const Scene& scene, const RenderedImage& image, int rays, double skip,
                                          bool overlapping = false);

// Compares every pixel farther than `skip` pixel widths from every shape boundary with
// expected(i, j, pixel center): |got - expected| <= 1e-6 * e_max per channel (docs/contract.md
// section 5, the scalar path's bound). Reports the worst pixel; returns how many were compared.
int check_against_closed_form(const Scene& scene, const RenderedImage& image,
                              const std::function<Rgb(int, int, Vec2)>& expected, double skip = 1e-3);

// e_L of a light: intensity * color, times normalize_scale (random_scenes.hpp).
Rgb emission(const Light& light);
// Vertices of a polygon, 1 for a segment, "unbounded" for a circle: how often its boundary can
// cross another's.
int boundary_complexity(const Shape& shape);
// Per-channel bound on |E_par - E_ray| at any pixel for `rays` stratified directions (a jump
// of the integrand is misplaced by at most one stratum): 2 per light's arc end and per
// occluder, crossings of overlapping boundaries, 2 more for a cone's profile and for shading, a
// cookie's total variation, directional lights in proportion to their arc; plus section 5's
// 1e-6 e_max.
Rgb stratification_bound(const Scene& scene, int rays, bool overlapping, bool shaded = false);

}  // namespace par2d::test
