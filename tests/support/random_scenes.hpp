// Deterministic random scenes for tests (same scene for a seed on every platform) and pixel helpers.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"

namespace par2d::test {

// Portable uniform numbers from std::mt19937 (whose output the standard fixes);
// std::uniform_*_distribution differ between standard libraries, so they are not used.
class PortableRandom {
 public:
  explicit PortableRandom(std::uint32_t seed) : engine_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double uniform() noexcept;
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi] (inclusive); hi >= lo.
  int integer(int lo, int hi) noexcept;
  bool chance(double p) noexcept { return uniform() < p; }

 private:
  std::mt19937 engine_;
};

struct RandomSceneOptions {
  // Image size in pixels. Default: 24 x 18.
  int width = 24;
  int height = 18;
  // World rectangle shown; empty means [0, 0, width, height]. Shapes are placed in
  // (and a little around) this rectangle, sized relative to its smaller side, so
  // e.g. [1e5, 1e5, 1e5 + W, 1e5 + H] tests far-from-origin precision and
  // [W, 0, 0, H] a mirrored image. Default: empty.
  std::optional<View> view;
  // Counts, each drawn uniformly from [min, max]. Default: 1..4 lights, 0..12 occluders.
  int min_lights = 1;
  int max_lights = 4;
  int min_occluders = 0;
  int max_occluders = 12;
  // Which shape kinds may appear. Default: all three.
  bool polygons = true;
  bool circles = true;
  bool segments = true;
  // Most polygon vertices (at least 3). Default: 8.
  int max_polygon_vertices = 8;
  // Shape bounding radius range, as a fraction of the view's smaller side.
  // Default: 0.02 .. 0.2.
  double min_size = 0.02;
  double max_size = 0.2;
  // How far outside the view shape centers may lie, as a fraction of its size. Default: 0.15.
  double outside = 0.15;
  // Keep every light disjoint from every occluder (docs/contract.md section 5's accuracy
  // bounds need it): bounding circles must be apart by at least `gap` (a fraction
  // of the view's smaller side). A shape that does not fit after 200 tries is left
  // out, so a scene may have fewer shapes than drawn. Default: true, 0.01.
  bool lights_disjoint_from_occluders = true;
  double gap = 0.01;
  // Whether occluders may overlap each other (if false, they are kept apart like
  // lights and occluders). Default: true.
  bool occluders_may_overlap = true;
  // Intensity range; colors are uniform in [0, 1] per channel. Default: 0.25 .. 4.
  double min_intensity = 0.25;
  double max_intensity = 4.0;

  // The game lighting model's terms (docs/contract.md section 6). They are drawn from a
  // second generator seeded from the same seed, after the shapes: a scene has exactly the
  // shapes, colors and intensities it has with every flag off. Default: all off.
  bool ranges = false;         // about half the lights: range 0.2 .. 1.5 view sizes
  bool falloffs = false;       // ranged lights: falloff 0 .. 6 (some 0, 1 and 2)
  bool normalizes = false;     // about a third of the lights: normalize at 0.1 .. 2 view sizes
  bool cones = false;          // about half the lights: a cone (some with fade 0, some with half angle 180)
  bool cookies = false;        // about 60 % of the lights without a cone: a cookie of 1 .. 6 knots
  bool shadows = false;        // about 40 % of the lights: shadow strength 0 .. 1, half with a shadow colour
  bool masks = false;          // lights, occluders and directional lights: masks of a few bits, some disjoint
  bool translucent = false;    // about half the occluders: a transmittance in [0, 1] per channel
  bool lit_interiors = false;  // about a third of the occluders: interior "lit"
  int directional_lights = 0;  // this many directional lights (random arcs, some narrow)
  bool ambient = false;        // a random ambient term
  bool elevations = false;     // random elevations 0 .. 90 (lights and directional lights; some 0 and 90)
  enum class Normals { none, constant, map };
  // The normal source: one random unit normal (possibly facing away, z < 0), or a
  // width x height map of random normals (some facing away). Default: none.
  Normals normals = Normals::none;
  // Redraws the terms switched on above from the value classes where arithmetic breaks, in a
  // pass of its own after them (so it changes nothing else): ranges of 1e-300, subnormal and
  // 1e300 view sizes, cone fades and half angles at subnormals, 1e-40 .. 1e-4 degrees and their
  // boundaries (fade 0, fade = half, half just under 180), elevations 0, 1e-300 and just under
  // 90, directional arcs 1e-9 degrees wide or just under 360, transmittances and ambient at
  // subnormals and just under 1, normals whose components are all scaled by 1e-300, 1e300 or
  // a subnormal, normal-map normals with float lengths 1e-40 .. 3e38, cookie knots 1 ulp to
// 1e-4 degrees apart and cookies spanning just under 360 degrees. Default: off.
  bool extreme_values = false;
};

// Every term of RandomSceneOptions switched on (normal map, 2 directional lights).
RandomSceneOptions with_every_model_term(RandomSceneOptions options);

// A valid scene (docs/contract.md section 3) drawn from `seed`: the same seed and options give
// the same scene on every platform. Polygons are random points on a rotated ellipse
// (hence convex), in random winding.
Scene random_scene(std::uint32_t seed, const RandomSceneOptions& options = {});

// Euclidean distance from p to the boundary of `shape` (for a segment: to the segment).
double distance_to_boundary(const Shape& shape, Vec2 p) noexcept;

// Whether p lies within `dist` of the boundary of any light or occluder. Tests use it
// to skip the pixels that docs/contract.md section 5 exempts.
bool near_boundary(const Scene& scene, Vec2 p, double dist) noexcept;

// World position of the center of pixel (i, j) (docs/contract.md section 2).
Vec2 pixel_center(const Scene& scene, int i, int j) noexcept;

// docs/contract.md section 2's pixel width: min(|x1 - x0| / width, |y1 - y0| / height).
double pixel_width(const Scene& scene) noexcept;

// Sum over lights and directional lights of the largest channel of intensity * color, plus
// the largest ambient channel (docs/contract.md section 5's e_max, extended by section 6),
// computed here so tests do not depend on the library's own version.
double emission_max_sum(const Scene& scene) noexcept;
// The factor a light's `normalize` puts on intensity * color (docs/contract.md section 6), written
// out here again: pi / asin(min(1, rho / D)); 1 without normalize.
double normalize_scale(const Light& light) noexcept;

// A rendered float RGB image, tightly packed, top row first.
struct RenderedImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
  float at(int i, int j, int c) const { return pixels[(static_cast<std::size_t>(j) * width + i) * 3 + c]; }
};

// Renders through the public API; `status` receives the result of par2d::render (with
// `raycast`, of the baseline par2d::render_raycast).
RenderedImage render_image(const Scene& scene, const RenderOptions& options, Status& status, bool raycast = false);

// Renders, or fails the test case with par2d's message (render_checks.cpp; doctest binaries only).
RenderedImage render_or_fail(const Scene& scene, const RenderOptions& options, bool raycast = false);

// The SIMD levels this CPU runs (tests force each in turn).
std::vector<Isa> simd_isas_here();

// Options for one backend (and ISA), culling on or off, 2 threads.
RenderOptions options_for(Backend backend, std::optional<Isa> isa = std::nullopt, bool culling = true);

}  // namespace par2d::test
