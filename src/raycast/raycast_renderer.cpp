// Brute-force ray caster: exact ray/shape distances, stratified directions (the check on PAR).
//
// Deliberately shares no code with src/geometry beyond its vector arithmetic (vec2.hpp) and where
// the bounce pieces lie (bounce_pieces.hpp, which the contract defines and its own tests pin): it
// is what the PAR renderer is tested against, so a bug in the shared tangent/interval code must
// not hide here.
#include "raycast/raycast_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/bounce_pieces.hpp"
#include "geometry/vec2.hpp"
#include "lighting/degrees.hpp"
#include "raycast/ray_exact.hpp"

namespace par2d::detail {
namespace {

// e_L of docs/contract.md section 6, written out here again (not shared with the renderers):
// intensity * color, times pi / asin(min(1, rho / D)) with `normalize` D, rho the largest
// distance from the shape's centre (circle center, segment midpoint, polygon vertex mean).
Rgb emission_of(const Light& l) {
  double scale = 1.0;
  if (l.normalize) {
    double rho = 0.0;
    if (const auto* c = std::get_if<Circle>(&l.shape)) {
      rho = c->radius;
    } else if (const auto* s = std::get_if<Segment>(&l.shape)) {
      rho = 0.5 * std::hypot(s->b.x - s->a.x, s->b.y - s->a.y);
    } else {
      const std::vector<Vec2>& v = std::get<Polygon>(l.shape).vertices;
      Vec2 mean{0.0, 0.0};
      for (const Vec2& p : v) mean = {mean.x + p.x / static_cast<double>(v.size()), mean.y + p.y / static_cast<double>(v.size())};
      for (const Vec2& p : v) rho = std::max(rho, std::hypot(p.x - mean.x, p.y - mean.y));
    }
    scale = std::acos(-1.0) / std::asin(std::min(1.0, rho / *l.normalize));
  }
  Rgb e{};
  for (std::size_t c = 0; c < 3; ++c) e[c] = l.intensity * l.color[c] == 0.0 ? 0.0 : l.intensity * l.color[c] * scale;
  return e;
}

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 6.283185307179586476925286766559;
// A light hit this close behind the first occluder hit (relative to the distances and
// coordinates involved) is a contact: docs/contract.md has t_occ == t_L there, so the light
// is not visible, but the two distances round apart by a few ulps.
constexpr double kContactTolerance = 0x1p-40;


using ray_exact::power_of;
using ray_exact::ray_segment;
using ray_exact::side_of;

// Whether a ring of vertices bounds a convex region: with repeated vertices dropped, every
// turn on one side or straight on (signs exact), no edge doubling back on the one before, and
// the edges' directions turning once around (a star wound twice turns the same way at every
// vertex). A region's even-odd tests agree with the convex ones on convex rings, so a ring
// this leaves out only costs speed.
bool convex_ring(const std::vector<Vec2>& ring) {
  std::vector<Vec2> v;
  v.reserve(ring.size());
  for (const Vec2& p : ring)
    if (v.empty() || p.x != v.back().x || p.y != v.back().y) v.push_back(p);
  while (v.size() > 1 && v.back().x == v.front().x && v.back().y == v.front().y) v.pop_back();
  const std::size_t n = v.size();
  if (n < 3) return false;
  int turn_side = 0;
  double turning = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % n], c = v[(i + 2) % n];
    const double side = side_of(a, b, c);
    const Vec2 e = b - a, f = c - b;
    if (side == 0.0) {
      if (dot(e, f) < 0.0) return false;  // a fold
      continue;
    }
    const int s = side > 0.0 ? 1 : -1;
    if (turn_side != 0 && s != turn_side) return false;
    turn_side = s;
    turning += std::atan2(cross(e, f), dot(e, f));
  }
  // Once around is 2 pi; twice 4 pi (rounding moves either by far less than pi).
  return turn_side != 0 && std::fabs(turning) < 1.5 * kTwoPi;
}

}  // namespace

RaycastRenderer::RayShape RaycastRenderer::make_shape(const Shape& shape) {
  RayShape s;
  double bound_radius = 0.0;
  if (const auto* circle = std::get_if<Circle>(&shape)) {
    s.kind = Kind::circle;
    s.p0 = circle->center;
    s.radius2 = circle->radius * circle->radius;
    s.radius = circle->radius;
    s.bound_center = circle->center;
    bound_radius = circle->radius;
  } else if (const auto* segment = std::get_if<Segment>(&shape)) {
    s.kind = Kind::segment;
    s.p0 = segment->a;
    s.p1 = segment->b;
    s.bound_center = {0.5 * (segment->a.x + segment->b.x), 0.5 * (segment->a.y + segment->b.y)};
    bound_radius = 0.5 * std::hypot(segment->b.x - segment->a.x, segment->b.y - segment->a.y);
  } else {
    const auto& poly = std::get<Polygon>(shape);
    // Decided here from the rings as given, not by the product's validation or partition code
    // (a bug there that fills holes or takes a concave outline for convex must show here): a
    // ring convex by its own exact turns and no holes is a polygon, anything else a region.
    s.kind = poly.holes.empty() && convex_ring(poly.vertices) ? Kind::polygon : Kind::region;
    s.first = static_cast<std::uint32_t>(vertices_.size());
    s.count = static_cast<std::uint32_t>(poly.vertices.size());
    // A concave outline is met as it is: the ray caster does not partition (an independent check).
    // Centered at the bounding box middle; relative coordinates keep the shoelace sum
    // accurate for polygons far from the origin.
    double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
    for (const Vec2& v : poly.vertices) {
      x0 = std::min(x0, v.x);
      y0 = std::min(y0, v.y);
      x1 = std::max(x1, v.x);
      y1 = std::max(y1, v.y);
    }
    s.bound_center = {0.5 * (x0 + x1), 0.5 * (y0 + y1)};
    double area2 = 0.0;
    for (std::size_t i = 0; i < poly.vertices.size(); ++i) {
      const Vec2 a = poly.vertices[i] - s.bound_center;
      const Vec2 b = poly.vertices[(i + 1) % poly.vertices.size()] - s.bound_center;
      area2 += cross(a, b);
      bound_radius = std::max(bound_radius, std::hypot(a.x, a.y));
    }
    s.orientation = area2 >= 0.0 ? 1.0 : -1.0;
    vertices_.insert(vertices_.end(), poly.vertices.begin(), poly.vertices.end());
    s.ring_first = static_cast<std::uint32_t>(ring_ends_.size());
    s.holes = static_cast<std::uint32_t>(poly.holes.size());
    for (const std::vector<Vec2>& hole : poly.holes) {
      vertices_.insert(vertices_.end(), hole.begin(), hole.end());
      ring_ends_.push_back(static_cast<std::uint32_t>(vertices_.size()));
    }
  }
  // Inflated so that rounding in the early-out can never skip a real (grazing) hit.
  bound_radius = bound_radius * (1.0 + 1e-7) + 1e-300;
  s.bound_radius2 = bound_radius * bound_radius;
  return s;
}

namespace {

Shape scaled_shape(Shape shape, double f) {
  if (auto* c = std::get_if<Circle>(&shape)) {
    c->center = {f * c->center.x, f * c->center.y};
    c->radius *= f;
  } else if (auto* g = std::get_if<Segment>(&shape)) {
    g->a = {f * g->a.x, f * g->a.y};
    g->b = {f * g->b.x, f * g->b.y};
  } else {
    Polygon& p = std::get<Polygon>(shape);
    for (Vec2& v : p.vertices) v = {f * v.x, f * v.y};
    for (std::vector<Vec2>& hole : p.holes)
      for (Vec2& v : hole) v = {f * v.x, f * v.y};
  }
  return shape;
}

// The view brought to about 1024 units, unless a coordinate would pass 2^500 (whose square
// still fits a double); never beyond 2^1000 (views of normal pixels 2.2e-308 wide).
double scene_scale(const Scene& scene) {
  const View& v = scene.view;
  double largest = std::max({std::fabs(v.x0), std::fabs(v.x1), std::fabs(v.y0), std::fabs(v.y1)});
  auto grow = [&](const Shape& shape) {
    if (const auto* c = std::get_if<Circle>(&shape))
      largest = std::max({largest, std::fabs(c->center.x) + c->radius, std::fabs(c->center.y) + c->radius});
    else if (const auto* g = std::get_if<Segment>(&shape))
      largest = std::max({largest, std::fabs(g->a.x), std::fabs(g->a.y), std::fabs(g->b.x), std::fabs(g->b.y)});
    else
      for (const Vec2& p : std::get<Polygon>(shape).vertices) largest = std::max({largest, std::fabs(p.x), std::fabs(p.y)});
  };
  for (const auto& l : scene.lights) grow(l.shape);
  for (const auto& o : scene.occluders) grow(o.shape);
  int view_exponent = 0, coordinate_exponent = 0;
  std::frexp(std::max(std::fabs(v.x1 - v.x0), std::fabs(v.y1 - v.y0)), &view_exponent);
  std::frexp(largest, &coordinate_exponent);
  return std::ldexp(1.0, std::min({10 - view_exponent, 500 - coordinate_exponent, 1000}));
}

// The cookie's weight for light emitted in world direction `psi` (degrees), straight from
// the knots: the offset past the first knot in [0, 360), the segment holding it by a walk,
// linear between its knots (the last runs on to the first plus 360). The rotation and the
// first direction are reduced exactly before anything is added to them: psi minus a rotation
// of 1e20 would round psi away.
double cookie_weight(const Cookie& cookie, double psi) {
  const std::vector<CookieKnot>& k = cookie.knots;
  const double first = k[0].direction;
  double offset = std::fmod(std::fmod(psi - reduce_degrees(cookie.rotation), 360.0) - reduce_degrees(first), 360.0);
  if (offset < 0.0) offset += 360.0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    const double a = k[i].direction - first;
    const double b = i + 1 < k.size() ? k[i + 1].direction - first : 360.0;
    if (offset < b || i + 1 == k.size()) {
      const double w1 = k[(i + 1) % k.size()].weight;
      const double f = std::clamp((offset - a) / (b - a), 0.0, 1.0);
      return k[i].weight + f * (w1 - k[i].weight);
    }
  }
  return k[0].weight;
}

}  // namespace

RaycastRenderer::RaycastRenderer(const Scene& validated_scene) : scale_(scene_scale(validated_scene)) {
  std::size_t vertex_count = 0;
  const auto count_vertices = [&vertex_count](const Shape& shape) {
    if (const auto* p = std::get_if<Polygon>(&shape)) {
      vertex_count += p->vertices.size();
      for (const std::vector<Vec2>& hole : p->holes) vertex_count += hole.size();
    }
  };
  for (const auto& l : validated_scene.lights) count_vertices(l.shape);
  for (const auto& o : validated_scene.occluders) count_vertices(o.shape);
  vertices_.reserve(vertex_count);
  for (const auto& o : validated_scene.occluders) occluders_.push_back(make_shape(scaled_shape(o.shape, scale_)));
  for (const auto& l : validated_scene.lights) {
    lights_.push_back(make_shape(scaled_shape(l.shape, scale_)));
    emission_.push_back(emission_of(l));
  }
  // The game lighting model, read straight from the scene (degrees to radians here, directions
  // reduced exactly in degrees first).
  constexpr double kRadians = kTwoPi / 360.0;
  const Scene& scene = validated_scene;
  for (const auto& l : scene.lights) {
    LightModel m;
    if (l.range) m.range = *l.range * scale_;
    m.falloff = l.falloff;
    if (l.cone) {
      m.cone = true;
      m.cone_direction = reduce_degrees(l.cone->direction) * kRadians;
      m.cone_half = l.cone->half_angle * kRadians;
      m.cone_fade = l.cone->fade * kRadians;
    }
    m.cookie = l.cookie;
    m.mask = l.mask;
    m.elevation = l.elevation * kRadians;
    for (std::size_t c = 0; c < 3; ++c) m.shadow[c] = l.shadow.strength * (1.0 - l.shadow.color[c]);
    model_ = model_ || l.range || l.cone || l.cookie || l.mask != kAllMaskBits || m.shadow != Rgb{1.0, 1.0, 1.0};
    light_terms_.push_back(m);
  }
  for (const auto& o : scene.occluders) {
    OccluderModel m{o.transmittance, o.mask, o.interior == Interior::lit};
    model_ = model_ || m.transmittance != Rgb{0.0, 0.0, 0.0} || m.mask != kAllMaskBits || m.lit_interior;
    occluder_terms_.push_back(m);
  }
  for (const auto& d : scene.directional_lights) {
    // The sky keeps its width (a1 - a0, exact for huge angles a turn apart) from the reduced start.
    const double start = reduce_degrees(d.angle0);
    suns_.push_back({start * kRadians, (start + (d.angle1 - d.angle0)) * kRadians,
                     {d.intensity * d.color[0], d.intensity * d.color[1], d.intensity * d.color[2]}, d.mask,
                     d.elevation * kRadians});
    model_ = true;
  }
  ambient_ = scene.ambient;
  model_ = model_ || ambient_ != Rgb{0.0, 0.0, 0.0};
  // One bounce: the reflecting occluders' pieces, where each edge's or face's run starts.
  std::vector<BouncePiece> pieces;
  const double h = scene.bounce.piece;
  for (std::size_t b = 0; b < scene.occluders.size(); ++b) {
    const Occluder& o = scene.occluders[b];
    albedo_.push_back(o.albedo);
    if (o.albedo == Rgb{0.0, 0.0, 0.0}) continue;
    Reflector r;
    r.occluder = b;
    r.first = static_cast<std::uint32_t>(pieces.size());
    bounce_pieces(o.shape, h, scale_, pieces);
    r.count = static_cast<std::uint32_t>(pieces.size()) - r.first;
    std::uint32_t at = r.first;
    if (const auto* poly = std::get_if<Polygon>(&o.shape)) {
      const auto& v = poly->vertices;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const auto n = static_cast<std::uint32_t>(bounce_piece_count(Segment{v[i], v[(i + 1) % v.size()]}, h) / 2);
        r.run_first.push_back(at);
        r.run_count.push_back(n);
        at += n;
      }
    } else if (std::holds_alternative<Segment>(o.shape)) {
      const std::uint32_t n = r.count / 2;
      r.run_first = {r.first, r.first + n};
      r.run_count = {n, n};
    }
    reflectors_.push_back(std::move(r));
  }
  for (const BouncePiece& p : pieces) {
    piece_mid_.push_back(p.mid);
    piece_normal_.push_back(p.normal);
  }
  if (scene.normal) {
    // Divided by its largest component first (as the renderers do): the squares of components
    // near 1e-300 underflow to a zero length, and the normal would come out infinite.
    const Vec3 g = *scene.normal;
    const double largest = std::max({std::fabs(g.x), std::fabs(g.y), std::fabs(g.z)});
    const Vec3 n{g.x / largest, g.y / largest, g.z / largest};
    const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    normal_ = Vec3{n.x / len, n.y / len, n.z / len};
    model_ = true;
  } else if (scene.normal_map) {
    map_width_ = scene.normal_map->width;
    normal_map_ = scene.normal_map->normals;
    // Image +x is world +x unless the view mirrors x; image up is world -y (y grows down)
    // unless the view mirrors y.
    map_sign_x_ = scene.view.x1 > scene.view.x0 ? 1.0 : -1.0;
    map_sign_y_ = scene.view.y1 > scene.view.y0 ? -1.0 : 1.0;
    model_ = true;
  }
}

std::optional<Vec3> RaycastRenderer::normal_at(int i, int j) const {
  if (normal_) return normal_;
  if (normal_map_.empty()) return std::nullopt;
  const std::size_t p = 3 * (static_cast<std::size_t>(j) * static_cast<std::size_t>(map_width_) + static_cast<std::size_t>(i));
  const double x = map_sign_x_ * normal_map_[p], y = map_sign_y_ * normal_map_[p + 1], z = normal_map_[p + 2];
  const double len = std::sqrt(x * x + y * y + z * z);
  return Vec3{x / len, y / len, z / len};
}

bool RaycastRenderer::contains(const RayShape& s, Vec2 x) const noexcept {
  switch (s.kind) {
    case Kind::circle: {
      return power_of(s.p0, s.radius, x) <= 0.0;
    }
    case Kind::segment: {
      const Vec2 e = s.p1 - s.p0;
      const Vec2 w = x - s.p0;
      if (side_of(s.p0, s.p1, x) != 0.0) return false;
      const double u = dot(e, w);
      return u >= 0.0 && u <= dot(e, e);
    }
    case Kind::polygon: {
      // Closed convex polygon = intersection of the closed inner half-planes of its
      // edges; zero-length edges (repeated vertices) constrain nothing.
      const Vec2* v = vertices_.data() + s.first;
      for (std::uint32_t i = 0; i < s.count; ++i) {
        const Vec2 a = v[i];
        const Vec2 b = v[i + 1 == s.count ? 0 : i + 1];
        if (side_of(a, b, x) * s.orientation < 0.0) return false;
      }
      return true;
    }
    case Kind::region: {
      // Closed: on an edge is inside; elsewhere the even-odd count of edges a ray toward +x crosses.
      bool on_edge = false, odd = false;
      for_each_edge(s, [&](Vec2 a, Vec2 b) {
        if (side_of(a, b, x) == 0.0 && std::min(a.x, b.x) <= x.x && x.x <= std::max(a.x, b.x) &&
            std::min(a.y, b.y) <= x.y && x.y <= std::max(a.y, b.y))
          on_edge = true;
        if ((a.y > x.y) != (b.y > x.y)) {
          // The crossing lies right of x when x is on the left of the upward edge.
          const Vec2 lo = a.y < b.y ? a : b, hi = a.y < b.y ? b : a;
          if (side_of(lo, hi, x) > 0.0) odd = !odd;
        }
      });
      return on_edge || odd;
    }
  }
  return false;
}

double RaycastRenderer::hit_distance(const RayShape& s, Vec2 x, Vec2 d, double limit) const noexcept {
  // Early-out on the bounding circle when x is outside it: a ray that points away,
  // passes beside it, or enters it no nearer than `limit` cannot give a useful hit.
  const Vec2 m = s.bound_center - x;
  const double mm = dot(m, m);
  if (mm > s.bound_radius2) {
    const double b = dot(m, d);
    if (b <= 0.0) return kInf;
    const double perp = cross(m, d);  // accurate even when mm >> bound_radius2
    const double perp2 = perp * perp;
    if (perp2 > s.bound_radius2) return kInf;
    const double t_enter = b - std::sqrt(s.bound_radius2 - perp2);
    if (t_enter > limit * (1.0 + 1e-9)) return kInf;
  }
  switch (s.kind) {
    case Kind::circle: {
      const Vec2 mc = s.p0 - x;
      const double c = power_of(s.p0, s.radius, x);
      if (c <= 0.0) return 0.0;
      const double b = dot(mc, d);
      if (b <= 0.0) return kInf;
      const double perp = cross(mc, d);
      const double disc = s.radius2 - perp * perp;
      if (disc < 0.0) return kInf;
      // (|m|^2 - r^2) / (b + sqrt(disc)) = b - sqrt(disc) without the cancellation.
      return c / (b + std::sqrt(disc));
    }
    case Kind::segment:
      return ray_segment(x, d, s.p0, s.p1);
    case Kind::polygon:
    case Kind::region: {
      if (contains(s, x)) return 0.0;
      // From outside, the first boundary point is the first hit (convex or not).
      double t = kInf;
      for_each_edge(s, [&](Vec2 a, Vec2 b) { t = std::min(t, ray_segment(x, d, a, b)); });
      return t;
    }
  }
  return kInf;
}

void RaycastRenderer::region_entries(const RayShape& s, Vec2 x, Vec2 d, std::vector<double>& out) const {
  out.clear();
  bool inside = contains(s, x);
  if (inside) out.push_back(0.0);
  thread_local std::vector<double> crossings;
  crossings.clear();
  for_each_edge(s, [&](Vec2 a, Vec2 b) {
    const double sa = cross(d, a - x), sb = cross(d, b - x);
    if ((sa > 0.0) == (sb > 0.0)) return;
    // The crossing point's distance along d: a + u (b - a) with u = sa / (sa - sb).
    const double u = sa / (sa - sb);
    const double t = dot(a - x, d) + u * dot(b - a, d);
    if (t > 0.0) crossings.push_back(t);
  });
  std::sort(crossings.begin(), crossings.end());
  for (const double t : crossings) {
    inside = !inside;
    if (inside) out.push_back(t);
  }
}

Rgb RaycastRenderer::irradiance(Vec2 world, int rays, double jitter) const {
  return irradiance(world, rays, jitter, nullptr);
}

Rgb RaycastRenderer::irradiance(Vec2 world, int rays, double jitter, const Vec3* normal) const {
  Rgb e{0.0, 0.0, 0.0};
  if (term_ != BounceTerm::only)
    e = model_ ? model_irradiance(world, rays, jitter, normal) : plain_irradiance(world, rays, jitter);
  if (reflectors_.empty() || term_ == BounceTerm::excluded) return e;
  const Rgb b = bounce_irradiance(world, rays, jitter, normal);
  for (int c = 0; c < 3; ++c) e[c] += b[c];
  return e;
}

Rgb RaycastRenderer::plain_irradiance(Vec2 world, int rays, double jitter) const {
  const Vec2 x{scale_ * world.x, scale_ * world.y};
  Rgb sum{0.0, 0.0, 0.0};
  if (rays <= 0 || lights_.empty()) return sum;
  // Inside a closed occluder t_occ = 0 in every direction and no light is visible.
  for (const RayShape& o : occluders_) {
    const Vec2 m = o.bound_center - x;
    if (dot(m, m) <= o.bound_radius2 && contains(o, x)) return sum;
  }
  // Directions in blocks: one exact sincos per block, rotated by a small table of
  // exact offsets (angle addition loses ~1 ulp), since sincos dominated the run time.
  constexpr int kBlock = 16;
  const double step = kTwoPi / rays;
  double block_cos[kBlock], block_sin[kBlock];
  for (int j = 0; j < kBlock; ++j) {
    block_cos[j] = std::cos(step * j);
    block_sin[j] = std::sin(step * j);
  }
  double base_cos = 1.0, base_sin = 0.0;
  std::vector<double> entries;
  for (int k = 0; k < rays; ++k) {
    const int j = k % kBlock;
    if (j == 0) {
      const double theta = step * (k + jitter);
      base_cos = std::cos(theta);
      base_sin = std::sin(theta);
    }
    const Vec2 d{base_cos * block_cos[j] - base_sin * block_sin[j], base_sin * block_cos[j] + base_cos * block_sin[j]};
    double t_occ = kInf;
    for (const RayShape& o : occluders_) t_occ = std::min(t_occ, hit_distance(o, x, d, t_occ));
    // Lights do not block each other: every light in front of the first occluder counts.
    const double contact =
        t_occ < kInf ? kContactTolerance * std::max({t_occ, std::fabs(x.x), std::fabs(x.y)}) : 0.0;
    for (std::size_t l = 0; l < lights_.size(); ++l) {
      int count = 0;
      if (lights_[l].kind != Kind::region) {
        count = hit_distance(lights_[l], x, d, t_occ) < t_occ - contact ? 1 : 0;
      } else {  // a concave light: once per entry in front of the occluder
        region_entries(lights_[l], x, d, entries);
        for (const double t : entries) count += t < t_occ - contact ? 1 : 0;
      }
      sum[0] += count * emission_[l][0];
      sum[1] += count * emission_[l][1];
      sum[2] += count * emission_[l][2];
    }
  }
  const double inv = 1.0 / rays;
  return {sum[0] * inv, sum[1] * inv, sum[2] * inv};
}

double RaycastRenderer::distance_to(const RayShape& s, Vec2 x) const noexcept {
  // Euclidean distance from x to the closed shape: 0 inside, else to the nearest boundary point.
  auto to_segment = [](Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 e = b - a, w = p - a;
    const double ee = dot(e, e);
    const double u = ee > 0.0 ? std::clamp(dot(w, e) / ee, 0.0, 1.0) : 0.0;
    // Inside the segment, the distance to its line (the foot point would round to the end
    // points' magnitude).
    if (u > 0.0 && u < 1.0) return std::fabs(side_of(a, b, p)) / std::hypot(e.x, e.y);
    return std::hypot(w.x - u * e.x, w.y - u * e.y);
  };
  switch (s.kind) {
    case Kind::circle: {
      const Vec2 m = x - s.p0;
      const double power = power_of(s.p0, s.radius, x);
      return power <= 0.0 ? 0.0 : power / (std::hypot(m.x, m.y) + s.radius);
    }
    case Kind::segment: return to_segment(x, s.p0, s.p1);
    case Kind::polygon:
    case Kind::region: {
      if (contains(s, x)) return 0.0;
      double d = kInf;
      for_each_edge(s, [&](Vec2 a, Vec2 b) { d = std::min(d, to_segment(x, a, b)); });
      return d;
    }
  }
  return kInf;
}

// Occluder b acts on a light with `mask` seen from a point `inside` says which occluders hold
// (section 6: masks share a bit, and a lit interior is ignored from inside); `self` never acts.
bool RaycastRenderer::acting(std::size_t b, std::uint32_t mask, std::size_t self,
                             const std::vector<unsigned char>& inside) const noexcept {
  return b != self && (occluder_terms_[b].mask & mask) != 0 && !(inside[b] && occluder_terms_[b].lit_interior);
}

template <class Shade>
Rgb RaycastRenderer::lights_along_rays(Vec2 x, double start, double span, int rays, double jitter, std::size_t self,
                                       const std::vector<unsigned char>& inside, const Shade& shade) const {
  const std::size_t n_occ = occluders_.size();
  // Range windows, once per point: w = clamp(1 - (d/R)^2, 0, 1)^falloff, 0 from d = R on.
  std::vector<double> window(lights_.size(), 1.0);
  for (std::size_t l = 0; l < lights_.size(); ++l) {
    if (light_terms_[l].range <= 0.0) continue;
    const double d = distance_to(lights_[l], x);
    const double q = d / light_terms_[l].range;
    const double w = std::clamp(1.0 - q * q, 0.0, 1.0);
    window[l] = d >= light_terms_[l].range ? 0.0 : d == 0.0 ? 1.0 : std::pow(w, light_terms_[l].falloff);
  }
  std::vector<double> t_occ(n_occ);
  std::vector<double> entries;
  Rgb lit{0.0, 0.0, 0.0};
  for (int k = 0; k < rays; ++k) {
    const double theta = start + span * (k + jitter) / rays;
    const Vec2 d{std::cos(theta), std::sin(theta)};
    for (std::size_t b = 0; b < n_occ; ++b)
      t_occ[b] = b == self ? kInf : (inside[b] ? 0.0 : hit_distance(occluders_[b], x, d, kInf));
    for (std::size_t l = 0; l < lights_.size(); ++l) {
      if (!(window[l] > 0.0)) continue;
      if (lights_[l].kind == Kind::region) {
        region_entries(lights_[l], x, d, entries);  // a concave light: once per entry
      } else {
        entries.assign(1, hit_distance(lights_[l], x, d, kInf));
        if (!(entries[0] < kInf)) continue;
      }
      const LightModel& m = light_terms_[l];
      // Cone: emitted along psi = theta + pi; delta = |psi - phi| wrapped to [0, pi].
      double c = 1.0;
      if (m.cone) {
        const double delta = std::fabs(std::remainder(theta + 0.5 * kTwoPi - m.cone_direction, kTwoPi));
        if (delta <= m.cone_half - m.cone_fade)
          c = 1.0;
        else if (delta >= m.cone_half)
          c = 0.0;
        else
          c = (m.cone_half - delta) / m.cone_fade;
      }
      if (m.cookie) c = cookie_weight(*m.cookie, (theta + 0.5 * kTwoPi) * (360.0 / kTwoPi));
      const double weight = window[l] * c * shade(theta, d, m.elevation);
      if (!(weight > 0.0)) continue;
      for (const double t_light : entries) {
        Rgb v{1.0, 1.0, 1.0};
        for (std::size_t b = 0; b < n_occ; ++b) {
          if (!(t_occ[b] < kInf) || !acting(b, m.mask, self, inside)) continue;
          // In front when t_B <= t_L, contacts (as in section 1's path above) included.
          const double contact = kContactTolerance * std::max({t_occ[b], std::fabs(x.x), std::fabs(x.y)});
          if (t_light >= t_occ[b] - contact)
            for (int c3 = 0; c3 < 3; ++c3) v[c3] *= occluder_terms_[b].transmittance[c3];
        }
        // A light's shadow removes only the fraction k of what the occluders block.
        for (int c3 = 0; c3 < 3; ++c3)
          lit[c3] += emission_[l][c3] * weight * (1.0 - m.shadow[c3] + m.shadow[c3] * v[c3]);
      }
    }
  }
  return lit;
}

// Directional lights: their own stratified rays over [a0, a1]; every acting occluder a ray
// meets (t_B < inf, containing x included) is in front of a light at infinity.
template <class Shade>
void RaycastRenderer::add_directional(Vec2 x, int rays, double jitter, std::size_t self,
                                      const std::vector<unsigned char>& inside, const Shade& shade, Rgb& sum) const {
  const std::size_t n_occ = occluders_.size();
  for (const SunModel& sun : suns_) {
    const double width = sun.angle1 - sun.angle0;
    Rgb seen{0.0, 0.0, 0.0};
    for (int k = 0; k < rays; ++k) {
      const double theta = sun.angle0 + width * (k + jitter) / rays;
      const Vec2 d{std::cos(theta), std::sin(theta)};
      const double s = shade(theta, d, sun.elevation);
      if (!(s > 0.0)) continue;
      Rgb v{s, s, s};
      for (std::size_t b = 0; b < n_occ; ++b) {
        if (!acting(b, sun.mask, self, inside)) continue;
        if (inside[b] || hit_distance(occluders_[b], x, d, kInf) < kInf)
          for (int c3 = 0; c3 < 3; ++c3) v[c3] *= occluder_terms_[b].transmittance[c3];
      }
      for (int c3 = 0; c3 < 3; ++c3) seen[c3] += v[c3];
    }
    for (int c3 = 0; c3 < 3; ++c3) sum[c3] += sun.emission[c3] * seen[c3] * width / (kTwoPi * rays);
  }
}

Rgb RaycastRenderer::model_irradiance(Vec2 world, int rays, double jitter, const Vec3* normal) const {
  const Vec2 x{scale_ * world.x, scale_ * world.y};
  Rgb sum{0.0, 0.0, 0.0};
  if (rays <= 0) return sum;
  const std::size_t n_occ = occluders_.size();
  std::vector<unsigned char> inside(n_occ);
  for (std::size_t b = 0; b < n_occ; ++b) inside[b] = contains(occluders_[b], x) ? 1 : 0;
  auto shading = [&](double theta, Vec2, double elevation) {
    if (!normal) return 1.0;
    const double ce = std::cos(elevation);
    return std::max(0.0, normal->x * ce * std::cos(theta) + normal->y * ce * std::sin(theta) +
                             normal->z * std::sin(elevation));
  };
  const Rgb lit = lights_along_rays(x, 0.0, kTwoPi, rays, jitter, kNoOccluder, inside, shading);
  for (int c3 = 0; c3 < 3; ++c3) sum[c3] = lit[c3] / rays;
  add_directional(x, rays, jitter, kNoOccluder, inside, shading, sum);
  for (int c3 = 0; c3 < 3; ++c3) sum[c3] += ambient_[c3];
  return sum;
}

}  // namespace par2d::detail

namespace par2d::detail {

double RaycastRenderer::entry(const RayShape& s, Vec2 x, Vec2 d, std::uint32_t& edge) const noexcept {
  edge = 0;
  switch (s.kind) {
    case Kind::circle:
      if (power_of(s.p0, s.radius, x) <= 0.0) return kInf;
      return hit_distance(s, x, d, kInf);
    case Kind::segment: {
      // The face toward x: perp = (e.y, -e.x) faces x where cross(a - x, e) < 0.
      const double side = side_of(s.p0, s.p1, x);
      if (side == 0.0) return kInf;
      edge = side < 0.0 ? 0u : 1u;
      return ray_segment(x, d, s.p0, s.p1);
    }
    case Kind::region: return kInf;  // a concave occluder never reflects (check_occluder)
    case Kind::polygon: {
      if (contains(s, x)) return kInf;
      const Vec2* v = vertices_.data() + s.first;
      double t = kInf;
      for (std::uint32_t i = 0; i < s.count; ++i) {
        const double ti = ray_segment(x, d, v[i], v[i + 1 == s.count ? 0 : i + 1]);
        if (ti < t) {
          t = ti;
          edge = i;
        }
      }
      return t;
    }
  }
  return kInf;
}

std::uint32_t RaycastRenderer::piece_at(const Reflector& r, Vec2 x, Vec2 p, std::uint32_t edge) const noexcept {
  const RayShape& s = occluders_[r.occluder];
  (void)x;
  if (s.kind == Kind::circle) {
    double phi = std::atan2(p.y - s.p0.y, p.x - s.p0.x);
    if (phi < 0.0) phi += kTwoPi;
    const auto k = static_cast<std::uint32_t>(std::min<double>(r.count - 1, std::floor(phi / kTwoPi * r.count)));
    return r.first + k;
  }
  Vec2 a = s.p0, b = s.p1;
  if (s.kind == Kind::polygon) {
    const Vec2* v = vertices_.data() + s.first;
    a = v[edge];
    b = v[edge + 1 == s.count ? 0 : edge + 1];
  }
  const std::uint32_t n = r.run_count[edge];
  if (n == 0) return UINT32_MAX;
  const Vec2 e = b - a;
  const double u = std::clamp(dot(p - a, e) / dot(e, e), 0.0, 1.0);
  return r.run_first[edge] + std::min<std::uint32_t>(n - 1, static_cast<std::uint32_t>(std::floor(u * n)));
}

Rgb RaycastRenderer::piece_direct(const Reflector& r, std::size_t piece, int rays) const {
  const Vec2 x = piece_mid_[piece], n = piece_normal_[piece];
  const std::size_t self = r.occluder, n_occ = occluders_.size();
  std::vector<unsigned char> inside(n_occ);
  for (std::size_t b = 0; b < n_occ; ++b) inside[b] = b != self && contains(occluders_[b], x) ? 1 : 0;
  // Section 7's shading: the piece's normal in the plane, the light's elevation.
  auto shading = [&](double, Vec2 d, double elevation) { return std::max(0.0, std::cos(elevation) * dot(n, d)); };
  // The outward half circle (the other half has s = 0), stratified, each ray pi / rays wide:
  // (1 / 2 pi) * (pi / rays) per ray.
  const double base = std::atan2(n.y, n.x) - 0.25 * kTwoPi;
  Rgb sum = lights_along_rays(x, base, 0.5 * kTwoPi, rays, 0.5, self, inside, shading);
  for (int c3 = 0; c3 < 3; ++c3) sum[c3] *= 0.5 / rays;
  add_directional(x, rays, 0.5, self, inside, shading, sum);
  return sum;
}

std::vector<Rgb> RaycastRenderer::bounce_radiances(int rays) const {
  BounceCache& cache = *bounce_cache_;
  std::lock_guard<std::mutex> lock(cache.mutex);
  if (cache.rays != rays || cache.radiance.size() != piece_mid_.size()) {
    cache.radiance.assign(piece_mid_.size(), Rgb{0.0, 0.0, 0.0});
    for (const Reflector& r : reflectors_) {
      const Rgb& albedo = albedo_[r.occluder];
      for (std::uint32_t k = r.first; k < r.first + r.count; ++k) {
        const Rgb s = piece_direct(r, k, rays);
        for (int c = 0; c < 3; ++c) cache.radiance[k][c] = 0.5 * kTwoPi * albedo[c] * s[c];
      }
    }
    cache.rays = rays;
  }
  return cache.radiance;
}

Rgb RaycastRenderer::bounce_irradiance(Vec2 world, int rays, double jitter, const Vec3* normal) const {
  Rgb sum{0.0, 0.0, 0.0};
  if (rays <= 0) return sum;
  const Vec2 x{scale_ * world.x, scale_ * world.y};
  // The radiances stay put while every caller asks with the same ray count (one frame).
  const std::vector<Rgb>* radiance = nullptr;
  {
    BounceCache& cache = *bounce_cache_;
    std::unique_lock<std::mutex> lock(cache.mutex);
    if (cache.rays != rays) {
      lock.unlock();
      (void)bounce_radiances(rays);
      lock.lock();
    }
    radiance = &cache.radiance;
  }
  const std::size_t n_occ = occluders_.size();
  std::vector<unsigned char> inside(n_occ);
  for (std::size_t b = 0; b < n_occ; ++b) inside[b] = contains(occluders_[b], x) ? 1 : 0;
  std::vector<double> t_occ(n_occ);
  for (int k = 0; k < rays; ++k) {
    const double theta = kTwoPi * (k + jitter) / rays;
    const Vec2 d{std::cos(theta), std::sin(theta)};
    const double s = normal ? std::max(0.0, normal->x * d.x + normal->y * d.y) : 1.0;
    if (!(s > 0.0)) continue;
    for (std::size_t b = 0; b < n_occ; ++b) t_occ[b] = inside[b] ? 0.0 : hit_distance(occluders_[b], x, d, kInf);
    for (const Reflector& r : reflectors_) {
      if (inside[r.occluder]) continue;
      std::uint32_t edge = 0;
      const double t = entry(occluders_[r.occluder], x, d, edge);
      if (!(t < kInf)) continue;
      const std::uint32_t piece = piece_at(r, x, x + t * d, edge);
      if (piece == UINT32_MAX) continue;
      const Rgb& l = (*radiance)[piece];
      if (!(std::max({l[0], l[1], l[2]}) > 0.0)) continue;
      const OccluderModel& own = occluder_terms_[r.occluder];
      Rgb v{s, s, s};
      for (std::size_t b = 0; b < n_occ; ++b) {
        if (b == r.occluder || !(t_occ[b] < kInf)) continue;
        const OccluderModel& m = occluder_terms_[b];
        if ((m.mask & own.mask) == 0 || (inside[b] && m.lit_interior)) continue;
        const double contact = kContactTolerance * std::max({t_occ[b], std::fabs(x.x), std::fabs(x.y)});
        if (t >= t_occ[b] - contact)
          for (int c = 0; c < 3; ++c) v[c] *= m.transmittance[c];
      }
      for (int c = 0; c < 3; ++c) sum[c] += l[c] * v[c];
    }
  }
  for (int c = 0; c < 3; ++c) sum[c] /= rays;
  return sum;
}

}  // namespace par2d::detail
