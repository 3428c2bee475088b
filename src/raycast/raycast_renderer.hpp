// Brute-force baseline: irradiance by casting stratified rays, first hit decides (docs/contract.md section 4).
#pragma once

#include <cstdint>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::detail {

// Ray casting against the scene's shapes, independent of the PAR geometry code so
// that it can check it. Built from a validated scene.
class RaycastRenderer {
 public:
  explicit RaycastRenderer(const Scene& validated_scene);

  // Irradiance at world point x from `rays` directions theta_k = 2*pi*(k + jitter)/rays,
  // k = 0..rays-1, jitter in [0, 1). Along each ray every light L with t_L < t_occ
  // (docs/contract.md section 1: lights do not block each other) adds e_L/rays.
  // Allocates nothing; safe to call from many threads at once.
  Rgb irradiance(Vec2 x, int rays, double jitter) const noexcept;

 private:
  enum class Kind : std::uint8_t { polygon, circle, segment };

  // One shape, flattened so the per-ray loop touches contiguous data. The bounding
  // circle (bound_center, bound_radius2) lets most rays skip the exact test.
  struct RayShape {
    Kind kind = Kind::circle;
    Vec2 bound_center;
    double bound_radius2 = 0.0;
    // circle: p0 = center, radius2 = r^2. segment: p0 = a, p1 = b.
    Vec2 p0, p1;
    double radius2 = 0.0;
    // polygon: vertices [first, first + count) of `vertices_`, closed, and the sign
    // (+1 or -1) that makes cross(edge, x - start) >= 0 mean "on the inner side".
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    double orientation = 1.0;
  };

  // Distance along the unit direction d from x to the shape, +inf when missed, 0 when
  // x lies in it (closed shapes). `limit`: a hit at t >= limit may be reported as +inf.
  double hit_distance(const RayShape& s, Vec2 x, Vec2 d, double limit) const noexcept;
  bool contains(const RayShape& s, Vec2 x) const noexcept;
  RayShape make_shape(const Shape& shape);

  std::vector<Vec2> vertices_;
  std::vector<RayShape> occluders_;
  std::vector<RayShape> lights_;
  std::vector<Rgb> emission_;  // e_L = intensity * color, parallel to lights_
  // Shapes are stored, and points scaled, by this power of two (exact) so that products of
  // coordinates neither overflow (coordinates of 1e300) nor underflow (views of 1e-300).
  double scale_ = 1.0;
};

}  // namespace par2d::detail
