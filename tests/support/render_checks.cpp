// Test-case helpers that report through doctest. Kept apart from random_scenes.cpp because the
// fuzz targets link random_scenes.cpp without doctest's runtime.
#include "support/render_checks.hpp"

#include "raycast/raycast_renderer.hpp"
#include "scene/scene_validate.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <variant>
#include <sstream>

namespace par2d::test {

RenderedImage render_or_fail(const Scene& scene, const RenderOptions& options, bool raycast) {
  Status status;
  RenderedImage image = render_image(scene, options, status, raycast);
  INFO("render: " << status.message());
  REQUIRE(status.ok());
  return image;
}

Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           double exempt) {
  return compare_renders(scene, ref, got, bound, [&](Vec2 p) { return near_boundary(scene, p, exempt); });
}

void check_simd_against_scalar(const Scene& scene, const RenderedImage& ref, const std::string& what,
                               const std::function<bool(Vec2)>& exempt, int min_checked,
                               const std::function<void(const RenderedImage&)>& visit) {
  const double bound = 1e-4 * emission_max_sum(scene);
  REQUIRE(!simd_isas_here().empty());
  for (Isa isa : simd_isas_here()) {
    for (bool culling : {true, false}) {
      const RenderedImage got = render_or_fail(scene, options_for(Backend::simd, isa, culling));
      if (visit) visit(got);
      const Comparison c = compare_renders(scene, ref, got, bound, exempt);
      INFO(what << " isa=" << std::string(isa_name(isa)) << " culling=" << culling << " checked=" << c.checked);
      CHECK_MESSAGE(c.over == 0, c.over << " values, first " << c.first_failure);
      CHECK(c.checked >= min_checked);
    }
  }
}

Comparison compare_renders(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound,
                           const std::function<bool(Vec2)>& exempt) {
  Comparison c;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      if (exempt(pixel_center(scene, i, j))) continue;
      ++c.checked;
      for (int ch = 0; ch < 3; ++ch) {
        const double err = std::abs(static_cast<double>(ref.at(i, j, ch)) - got.at(i, j, ch));
        c.max_error = std::max(c.max_error, err);
        if (!(err <= bound) && c.over++ == 0)
          c.first_failure = "pixel (" + std::to_string(i) + "," + std::to_string(j) + ") channel " +
                            std::to_string(ch) + ": reference " + std::to_string(ref.at(i, j, ch)) + ", got " +
                            std::to_string(got.at(i, j, ch));
      }
    }
  }
  return c;
}

int check_against_closed_form(const Scene& scene, const RenderedImage& image,
                              const std::function<Rgb(int, int, Vec2)>& expected, double skip) {
  const double tol = 1e-6 * emission_max_sum(scene);
  const double skip_dist = skip * pixel_width(scene);
  double worst = -1.0;
  std::string where;
  int compared = 0;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      if (near_boundary(scene, p, skip_dist)) continue;
      ++compared;
      const Rgb e = expected(i, j, p);
      for (int c = 0; c < 3; ++c) {
        const double err = std::fabs(image.at(i, j, c) - e[c]);
        if (err > worst) {
          worst = err;
          std::ostringstream s;
          s.precision(10);
          s << "pixel (" << i << ", " << j << ") at (" << p.x << ", " << p.y << ") channel " << c << ": expected "
            << e[c] << ", got " << image.at(i, j, c);
          where = s.str();
        }
      }
    }
  }
  INFO("worst: " << where << " (tolerance " << tol << ")");
  CHECK(worst <= tol);
  return compared;
}

Rgb emission(const Light& light) {
  const double k = normalize_scale(light);
  return {light.intensity * light.color[0] * k, light.intensity * light.color[1] * k, light.intensity * light.color[2] * k};
}

int boundary_complexity(const Shape& shape) {
  if (const auto* p = std::get_if<Polygon>(&shape)) return static_cast<int>(p->vertices.size());
  if (std::holds_alternative<Segment>(shape)) return 1;
  return std::numeric_limits<int>::max();
}

namespace {

// Half the jumps a shape can put into what a ray meets, as its direction turns: a convex
// silhouette has two ends (1 here); a concave outline can change at any vertex.
double silhouette_jumps(const Shape& shape) {
  if (!detail::needs_partition(shape)) return 1.0;
  return static_cast<double>(std::get<Polygon>(shape).vertices.size());
}

}  // namespace

Rgb stratification_bound(const Scene& scene, int rays, bool overlapping, bool shaded) {
  const double shading = shaded && (scene.normal || scene.normal_map) ? 2.0 : 0.0;
  Rgb bound{0, 0, 0};
  for (const Light& l : scene.lights) {
    double variation = 2.0 * silhouette_jumps(l.shape) + shading + (l.cone ? 2.0 : 0.0);
    for (const Occluder& o : scene.occluders) variation += 2.0 * silhouette_jumps(o.shape);
    if (l.cookie) {  // its weight's total variation around the circle
      for (std::size_t k = 0; k < l.cookie->knots.size(); ++k)
        variation += std::fabs(l.cookie->knots[(k + 1) % l.cookie->knots.size()].weight - l.cookie->knots[k].weight);
    }
    if (overlapping) {
      for (const Occluder& o : scene.occluders) {
        const bool circles = std::holds_alternative<Circle>(l.shape) && std::holds_alternative<Circle>(o.shape);
        variation += circles ? 2.0 : 2.0 * std::min(boundary_complexity(l.shape), boundary_complexity(o.shape));
      }
    }
    const Rgb e = emission(l);
    for (int c = 0; c < 3; ++c) bound[c] += e[c] * variation / rays;
  }
  for (const DirectionalLight& d : scene.directional_lights) {
    double variation = shading;
    for (const Occluder& o : scene.occluders) variation += 2.0 * silhouette_jumps(o.shape);
    const double share = (d.angle1 - d.angle0) / 360.0;
    for (int c = 0; c < 3; ++c) bound[c] += d.intensity * d.color[c] * share * variation / rays;
  }
  const double par_slack = 1e-6 * emission_max_sum(scene);
  for (double& b : bound) b += par_slack;
  return bound;
}

RaycastAgreement agreement_with_raycaster(const Scene& scene, const RenderedImage& image, int rays, double skip,
                                          bool overlapping) {
  const detail::RaycastRenderer caster(scene);
  const Rgb bound = stratification_bound(scene, rays, overlapping);
  RaycastAgreement out;
  for (int j = 0; j < scene.height; ++j) {
    for (int i = 0; i < scene.width; ++i) {
      const Vec2 p = pixel_center(scene, i, j);
      if (near_boundary(scene, p, skip)) continue;
      ++out.compared;
      const Rgb ray = caster.irradiance(p, rays, 0.5);
      for (int c = 0; c < 3; ++c) {
        const double ratio = std::fabs(image.at(i, j, c) - ray[c]) / bound[c];
        if (ratio > out.worst) {
          out.worst = ratio;
          std::ostringstream s;
          s << "pixel (" << i << ", " << j << ") channel " << c << ": image " << image.at(i, j, c) << ", rays "
            << ray[c];
          out.where = s.str();
        }
      }
    }
  }
  return out;
}

bool renderer_equals_snapshot(Renderer& renderer) {
  const std::vector<float> frame = frame_rgb(renderer);
  const Scene snapshot = renderer.snapshot();
  CHECK(snapshot.lights.size() == renderer.light_count());
  CHECK(snapshot.occluders.size() == renderer.occluder_count());
  return same_bits(frame, one_shot(snapshot, renderer.options()));
}

std::vector<float> frame_rgb(Renderer& r) {
  std::vector<float> pixels(static_cast<std::size_t>(r.width()) * r.height() * 3, -1.0f);
  const Status s = r.render(ImageView{pixels.data(), r.width(), r.height(), static_cast<std::ptrdiff_t>(r.width()) * 3});
  REQUIRE_MESSAGE(s.ok(), s.message());
  return pixels;
}

std::vector<float> one_shot(const Scene& scene, const RenderOptions& options) {
  Status s;
  RenderedImage image = render_image(scene, options, s);
  REQUIRE_MESSAGE(s.ok(), s.message());
  return image.pixels;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

FrameCounts frame_counts(const Renderer& renderer) {
  FrameCounts c;
  static_cast<FrameStats&>(c) = renderer.frame_stats();
  static_cast<FrameDiagnostics&>(c) = renderer.frame_diagnostics();
  return c;
}

FrameCounts frame_counts(const Scene& scene, RenderOptions options) {
  options.sample_needs = true;
  Renderer renderer;
  Status s = renderer.set_options(options);
  if (s.ok()) s = renderer.set_scene(scene);
  std::vector<float> pixels(static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3);
  if (s.ok()) s = renderer.render(ImageView{pixels.data(), scene.width, scene.height, 3 * static_cast<std::ptrdiff_t>(scene.width)});
  REQUIRE_MESSAGE(s.ok(), s.message());
  return frame_counts(renderer);
}

}  // namespace par2d::test
