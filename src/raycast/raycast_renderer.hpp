// Brute-force baseline: irradiance by casting stratified rays, first hit decides (docs/contract.md section 4).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "par2d/scene.hpp"
#include "par2d/types.hpp"

namespace par2d::detail {

// Ray casting against the scene's shapes, independent of the PAR geometry code so
// that it can check it. Built from a validated scene.
class RaycastRenderer {
 public:
  explicit RaycastRenderer(const Scene& validated_scene);

  // Irradiance at world point x from `rays` directions theta_k = 2*pi*(k + jitter)/rays,
  // k = 0..rays-1, jitter in [0, 1). Along each ray every light L with t_L < t_occ
  // (docs/contract.md section 1: lights do not block each other) adds e_L/rays.
  // Allocates nothing for scenes without the game lighting model's terms; safe to call from
  // many threads at once. Scenes with them: as the overload below, plain (s = 1).
  Rgb irradiance(Vec2 x, int rays, double jitter) const;

  // docs/contract.md section 6 applied literally, ray by ray: along each of the `rays`
  // directions every light L adds e_L * w_L(x) * V_L * c_L * s / rays, V_L the product of the
  // transmittances of the acting occluders B with t_B <= t_L (ties to the occluder); each
  // directional light D casts its own `rays` stratified directions over [a0, a1], each adding
  // e_D * V_D * s * (a1 - a0) / (2 pi rays), V_D over the acting occluders the ray meets; then
  // the ambient term. s is the clamped cosine for `normal` (unit, world axes), or 1 when null.
  Rgb irradiance(Vec2 x, int rays, double jitter, const Vec3* normal) const;

  // With reflecting occluders (docs/contract.md section 7) both overloads above add the bounce
  // term, also ray by ray: each piece's radiance L_k = pi * albedo * S_k from `rays` stratified
  // directions over the outward half circle at its midpoint (its own occluder left out, shaded
  // by (n_k, 0) and each light's elevation); then along each of the `rays` directions from x,
  // every reflecting occluder the ray enters from outside adds the radiance of the piece it
  // enters by, times the transmittances of the acting occluders met no later (its own never)
  // and the pixel's shading at elevation 0, over rays.
  // Which terms the two overloads above return (RenderOptions::bounce): both by default, or
  // the direct light (with the ambient) alone, or the bounce alone.
  void set_bounce_term(BounceTerm term) noexcept { term_ = term; }
  // The piece radiances for `rays` (cached for the last count asked).
  std::vector<Rgb> bounce_radiances(int rays) const;

  // The surface normal of pixel (i, j) (unit, world axes) from the scene's normal source, or
  // empty when the scene has none (docs/contract.md section 6).
  std::optional<Vec3> normal_at(int i, int j) const;

 private:
  // region: a polygon with holes or a concave outline (its rings as given, an even-odd region),
  // told apart from a convex polygon by the ray caster itself (make_shape).
  enum class Kind : std::uint8_t { polygon, circle, segment, region };

  // One shape, flattened so the per-ray loop touches contiguous data. The bounding
  // circle (bound_center, bound_radius2) lets most rays skip the exact test.
  struct RayShape {
    Kind kind = Kind::circle;
    Vec2 bound_center;
    double bound_radius2 = 0.0;
    // circle: p0 = center, radius2 = r^2. segment: p0 = a, p1 = b.
    Vec2 p0, p1;
    double radius2 = 0.0, radius = 0.0;
    // polygon: vertices [first, first + count) of `vertices_`, closed, and the sign
    // (+1 or -1) that makes cross(edge, x - start) >= 0 mean "on the inner side".
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    double orientation = 1.0;
    // region: after its outline, `holes` rings of vertices_, hole r ending (exclusive) at
    // vertices_ index ring_ends_[ring_first + r].
    std::uint32_t ring_first = 0, holes = 0;
  };
  // Calls f(a, b) for every edge of a polygon or region (a region's holes too).
  template <class F>
  void for_each_edge(const RayShape& s, F&& f) const {
    const auto ring = [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t i = begin; i < end; ++i) f(vertices_[i], vertices_[i + 1 == end ? begin : i + 1]);
    };
    ring(s.first, s.first + s.count);
    std::uint32_t begin = s.first + s.count;
    for (std::uint32_t r = 0; r < s.holes; ++r) {
      const std::uint32_t end = ring_ends_[s.ring_first + r];
      ring(begin, end);
      begin = end;
    }
  }

  // Distance along the unit direction d from x to the shape, +inf when missed, 0 when
  // x lies in it (closed shapes). `limit`: a hit at t >= limit may be reported as +inf.
  double hit_distance(const RayShape& s, Vec2 x, Vec2 d, double limit) const noexcept;
  bool contains(const RayShape& s, Vec2 x) const noexcept;
  // The distances t >= 0, increasing, at which the ray x + t d enters a concave region from
  // outside (0 first when x lies in it) into `out` (cleared): a concave light adds once per
  // entry (docs/contract.md section 3). Each boundary crossing toggles inside and outside;
  // an edge is crossed when its ends lie on different sides of the ray's line, an end on the
  // line counting with the side cross(d, p - x) <= 0, so a ray through a vertex crosses there
  // once or not at all.
  void region_entries(const RayShape& s, Vec2 x, Vec2 d, std::vector<double>& out) const;
  RayShape make_shape(const Shape& shape);

  std::vector<Vec2> vertices_;
  std::vector<std::uint32_t> ring_ends_;  // holes of regions (RayShape::ring_first)
  std::vector<RayShape> occluders_;
  std::vector<RayShape> lights_;
  std::vector<Rgb> emission_;  // e_L = intensity * color, parallel to lights_

  // The game lighting model's terms (docs/contract.md section 6), in radians and scaled lengths.
  struct LightModel {
    double range = 0.0;  // 0: none
    double falloff = 2.0;
    bool cone = false;
    double cone_direction = 0.0, cone_half = 0.0, cone_fade = 0.0;  // world emission directions
    std::optional<Cookie> cookie;  // as in the scene (degrees)
    std::uint32_t mask = 0xFFFFFFFFu;
    double elevation = 0.0;
    Rgb shadow{1.0, 1.0, 1.0};  // the fraction an occluder's shadow removes: strength * (1 - color)
  };
  struct OccluderModel {
    Rgb transmittance{0.0, 0.0, 0.0};
    std::uint32_t mask = 0xFFFFFFFFu;
    bool lit_interior = false;
  };
  struct SunModel {
    double angle0 = 0.0, angle1 = 0.0;
    Rgb emission{0.0, 0.0, 0.0};
    std::uint32_t mask = 0xFFFFFFFFu;
    double elevation = 0.0;
  };
  Rgb model_irradiance(Vec2 x, int rays, double jitter, const Vec3* normal) const;
  // Section 6 at x (prepared coordinates), shared by the pixels' direct light and the bounce
  // pieces' radiances. `inside[b]`: x lies in occluder b; occluder `self` never acts (a piece's
  // own; kNoOccluder: none); shade(theta, d, elevation) weights a direction.
  static constexpr std::size_t kNoOccluder = static_cast<std::size_t>(-1);
  bool acting(std::size_t b, std::uint32_t mask, std::size_t self, const std::vector<unsigned char>& inside) const noexcept;
  // Over `rays` stratified directions theta_k = start + span (k + jitter) / rays, the sum of
  // each light's emission x range window x cone x shade x the transmittances of the acting
  // occluders in front of it (unnormalized: the caller divides by its rays' measure).
  template <class Shade>
  Rgb lights_along_rays(Vec2 x, double start, double span, int rays, double jitter, std::size_t self,
                        const std::vector<unsigned char>& inside, const Shade& shade) const;
  // Adds each directional light's part to `sum`: its own `rays` stratified directions over its
  // angles, through the acting occluders each meets.
  template <class Shade>
  void add_directional(Vec2 x, int rays, double jitter, std::size_t self, const std::vector<unsigned char>& inside,
                       const Shade& shade, Rgb& sum) const;
  Rgb plain_irradiance(Vec2 x, int rays, double jitter) const;

  // One bounce (docs/contract.md section 7). A reflecting occluder: its index, its pieces
  // [first, first + count) of `pieces_`, and per polygon edge (as given) or segment face the
  // first piece and count, so that a ray's entry point names its piece.
  struct Reflector {
    std::size_t occluder = 0;
    std::uint32_t first = 0, count = 0;
    std::vector<std::uint32_t> run_first, run_count;  // polygon: per edge; segment: per face
  };
  struct BounceCache {
    std::mutex mutex;
    int rays = 0;
    std::vector<Rgb> radiance;
  };
  // Distance to the shape's boundary entry from outside along d, and which edge (polygon) it
  // enters by; +inf when missed.
  double entry(const RayShape& s, Vec2 x, Vec2 d, std::uint32_t& edge) const noexcept;
  std::uint32_t piece_at(const Reflector& r, Vec2 x, Vec2 p, std::uint32_t edge) const noexcept;
  Rgb piece_direct(const Reflector& r, std::size_t piece, int rays) const;
  Rgb bounce_irradiance(Vec2 x, int rays, double jitter, const Vec3* normal) const;
  std::vector<Reflector> reflectors_;
  std::vector<Vec2> piece_mid_, piece_normal_;  // scaled coordinates
  std::vector<Rgb> albedo_;                     // parallel to occluders_
  std::unique_ptr<BounceCache> bounce_cache_ = std::make_unique<BounceCache>();
  double distance_to(const RayShape& s, Vec2 x) const noexcept;

  BounceTerm term_ = BounceTerm::included;
  bool model_ = false;  // any term of section 6 differs from its default
  std::vector<LightModel> light_terms_;
  std::vector<OccluderModel> occluder_terms_;
  std::vector<SunModel> suns_;
  Rgb ambient_{0.0, 0.0, 0.0};
  std::optional<Vec3> normal_;  // constant normal source, unit
  int map_width_ = 0;
  std::vector<float> normal_map_;  // image axes, as in NormalMap
  double map_sign_x_ = 1.0, map_sign_y_ = -1.0;  // image axes to world axes for the view
  // Shapes are stored, and points scaled, by this power of two (exact) so that products of
  // coordinates neither overflow (coordinates of 1e300) nor underflow (views of 1e-300).
  double scale_ = 1.0;
};

}  // namespace par2d::detail
