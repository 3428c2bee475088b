// Builds the prepared scene: canonical shapes and the overlap relation between lights and occluders.
#include "world/prepared_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lighting/angular_profile.hpp"
#include "lighting/degrees.hpp"

namespace par2d::detail {
namespace {

// Whether `line` really has all of `positive` strictly on its positive side and `negative`
// strictly on the other: separating_line loses its way for shapes far longer than their gap
// (a segment from -1e17 to 1e17), and a wrong line would make the kernel's depth test and
// the culling wrong. A pair without a checked line takes the kernel's exact general path.
bool separates(const Line& line, const ConvexShape& positive, const ConvexShape& negative) noexcept {
  for (Vec2 v : positive.vertices)
    if (!(line.side(v) - positive.radius > 0.0)) return false;
  for (Vec2 v : negative.vertices)
    if (!(line.side(v) + negative.radius < 0.0)) return false;
  return true;
}

// A line across the gap between the shapes' bounding discs about their centroids, normal to
// the centroids' axis, where the discs lie well apart: any line that separates the pair
// orders it (the tile setup and the kernel need no more: a ray from the occluder's side
// leaves the occluder before it crosses the line, and meets the light only after), and this
// one costs a few dozen operations where the closest points' bisector (separating_line)
// costs thousands (docs/performance.md). Shapes nearer than
// twice their radii (walls, lights beside them) keep the bisector, which leaves more room on
// both sides of the line.
std::optional<Line> disc_separator(const ConvexShape& positive, const ConvexShape& negative) noexcept {
  const double r_positive = centroid_radius(positive), r_negative = centroid_radius(negative);
  const Vec2 axis = positive.centroid - negative.centroid;
  const double distance = length(axis);
  if (!(distance > 2.0 * (r_positive + r_negative))) return std::nullopt;
  const Vec2 n = (1.0 / distance) * axis;
  return Line{n, negative.centroid + (0.5 * (distance + r_negative - r_positive)) * n};
}

}  // namespace

bool PairSeparators::too_many(std::size_t lights, std::size_t occluders) noexcept {
  return occluders != 0 && lights > kMaxCachedPairs / occluders;
}

void PairSeparators::drop() noexcept {
  state_.reset();
  lines_.reset();
  rows_ = stride_ = 0;
  row_.clear();
}

void PairSeparators::reset(std::size_t lights, std::size_t occluders) {
  lights_ = lights;
  occluders_ = occluders;
  if (too_many(lights, occluders)) return drop();
  rows_ = lights;
  stride_ = occluders;
  state_ = std::make_unique<std::atomic<std::uint8_t>[]>(lights * occluders);
  lines_ = std::make_unique<Line[]>(lights * occluders);
  row_.resize(rows_);
  for (std::size_t l = 0; l < rows_; ++l) row_[l] = static_cast<std::uint32_t>(l);
}

void PairSeparators::resize(std::size_t lights, std::size_t occluders) {
  if (too_many(lights, occluders)) {
    drop();
  } else if (!state_ || lights > rows_ || occluders > stride_) {
    std::size_t rows = std::max(lights, 2 * rows_), stride = std::max(occluders, 2 * stride_);
    if (too_many(rows, stride)) rows = lights, stride = occluders;
    auto state = std::make_unique<std::atomic<std::uint8_t>[]>(rows * stride);  // value-initialized: kUnknown
    auto lines = std::make_unique<Line[]>(rows * stride);
    // Rows keep their places (rows not in use were forgotten when given up).
    for (std::size_t r = 0; state_ && r < rows_; ++r) {
      for (std::size_t k = 0; k < std::min(occluders_, stride_); ++k) {
        const std::uint8_t seen = state_[r * stride_ + k].load(std::memory_order_relaxed);
        // A slot some thread was computing is simply forgotten.
        if (seen == kSeparated || seen == kTouching) {
          state[r * stride + k].store(seen, std::memory_order_relaxed);
          lines[r * stride + k] = lines_[r * stride_ + k];
        }
      }
    }
    if (!state_) row_.clear();  // nothing kept: every row anew
    for (std::size_t r = row_.size(); r < rows; ++r) row_.push_back(static_cast<std::uint32_t>(r));
    state_ = std::move(state);
    lines_ = std::move(lines);
    rows_ = rows;
    stride_ = stride;
  }
  // Slots past the old counts are unknown: forget_* cleared them when they were given up.
  lights_ = lights;
  occluders_ = occluders;
}

void PairSeparators::forget_light(std::size_t light) noexcept {
  if (!state_ || light >= rows_) return;
  const std::size_t row = row_[light];
  for (std::size_t k = 0; k < stride_; ++k) state_[row * stride_ + k].store(kUnknown, std::memory_order_relaxed);
}

void PairSeparators::forget_occluder(std::size_t occluder) noexcept {
  if (!state_ || occluder >= stride_) return;
  for (std::size_t l = 0; l < rows_; ++l) state_[l * stride_ + occluder].store(kUnknown, std::memory_order_relaxed);
}

void PairSeparators::copy_pair(std::size_t from, std::size_t to) noexcept {
  const std::uint8_t seen = state_[from].load(std::memory_order_relaxed);
  const bool known = seen == kSeparated || seen == kTouching;
  state_[to].store(known ? seen : static_cast<std::uint8_t>(kUnknown), std::memory_order_relaxed);
  if (known) lines_[to] = lines_[from];
}

void PairSeparators::erase_light(std::size_t light) noexcept {
  if (!state_ || light >= rows_) return;
  forget_light(light);
  // The lights above take the numbers one lower with their rows; the freed row, forgotten,
  // goes past them (rows_ >= the light count), for the next light added.
  std::rotate(row_.begin() + static_cast<std::ptrdiff_t>(light), row_.begin() + static_cast<std::ptrdiff_t>(light) + 1,
              row_.end());
}

void PairSeparators::move_occluder(std::size_t from, std::size_t to) noexcept {
  if (!state_ || from >= stride_ || to >= stride_) return;
  for (std::size_t l = 0; l < rows_; ++l) copy_pair(l * stride_ + from, l * stride_ + to);
}

std::optional<Line> PairSeparators::get(std::size_t light, std::size_t occluder, const ConvexShape& light_shape,
                                        const ConvexShape& occluder_shape) const noexcept {
  auto compute = [&] {
    std::optional<Line> line = disc_separator(occluder_shape, light_shape);
    if (!line || !separates(*line, occluder_shape, light_shape)) {
      line = separating_line(occluder_shape, light_shape);
      if (line && !separates(*line, occluder_shape, light_shape)) line.reset();
    }
    return line;
  };
  if (!state_) return compute();  // too many pairs to keep: found anew each time
  const std::size_t index = row_[light] * stride_ + occluder;
  std::atomic<std::uint8_t>& state = state_[index];
  const std::uint8_t seen = state.load(std::memory_order_acquire);
  if (seen == kSeparated) return lines_[index];
  if (seen == kTouching) return std::nullopt;
  const std::optional<Line> line = compute();
  // Only the thread that claims the slot writes it; a thread that loses the race just
  // uses its own (identical) result.
  std::uint8_t expected = kUnknown;
  if (state.compare_exchange_strong(expected, kComputing, std::memory_order_acq_rel)) {
    if (line) lines_[index] = *line;
    state.store(line ? kSeparated : kTouching, std::memory_order_release);
  }
  return line;
}

void scale_shape(ConvexShape& s, double factor) noexcept {
  for (Vec2& v : s.vertices) v = factor * v;
  s.radius *= factor;
  s.bounds_min = factor * s.bounds_min;
  s.bounds_max = factor * s.bounds_max;
  s.centroid = factor * s.centroid;
}

// A power of two that brings the view to about 1024 units across (so products of
// coordinates neither underflow for views of 1e-200 units nor overflow for 1e200),
// unless that would push some coordinate past 2^500 (whose square still fits a double).
// Scaling by a power of two is exact, angles do not change, and pixel positions computed
// from the scaled view are the scaled positions, bit for bit.
double scene_scale(const View& view, double largest_coordinate) noexcept {
  int view_exponent = 0, coordinate_exponent = 0;
  std::frexp(std::max(std::abs(view.x1 - view.x0), std::abs(view.y1 - view.y0)), &view_exponent);
  std::frexp(largest_coordinate, &coordinate_exponent);
  // Capped at 2^1000: a view of normal pixels 2.2e-308 wide would otherwise ask for 2^1031 (inf).
  return std::ldexp(1.0, std::min({10 - view_exponent, 500 - coordinate_exponent, 1000}));
}

namespace {

constexpr double kRadiansPerDegree = kPi / 180.0;

double wrap_angle(double radians) noexcept {
  double a = std::fmod(radians, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a < kTwoPi ? a : 0.0;
}

}  // namespace

LightTerms light_terms(const Light& light, double scale) noexcept {
  LightTerms t;
  if (light.range) t.range = *light.range * scale;
  t.falloff = light.falloff;
  if (light.cone) {
    t.has_cone = true;
    // Emitted along phi, the light arrives along phi + pi.
    t.cone_center = wrap_angle(reduce_degrees(light.cone->direction) * kRadiansPerDegree + kPi);
    t.cone_half = light.cone->half_angle * kRadiansPerDegree;
    t.cone_fade = light.cone->fade * kRadiansPerDegree;
  }
  if (light.cookie) {
    static_assert(kMaxCookieSegments == kMaxCookieKnots, "one segment per knot");
    const std::vector<CookieKnot>& knots = light.cookie->knots;
    const int count = static_cast<int>(std::min<std::size_t>(knots.size(), kMaxCookieSegments));
    // Emitted along psi, the light arrives along psi + pi; the rotation and the first direction
    // each reduced exactly in degrees, the knots placed by their (small, exact) offsets from
    // the first.
    const double first = wrap_angle(wrap_angle(reduce_degrees(knots[0].direction) * kRadiansPerDegree) +
                                    wrap_angle(reduce_degrees(light.cookie->rotation) * kRadiansPerDegree) + kPi);
    t.cookie.count = count;
    t.cookie.first = first;
    double area = 0.0;
    for (int k = 0; k < count; ++k) {
      const CookieKnot& knot = knots[static_cast<std::size_t>(k)];
      const double offset = knot.direction - knots[0].direction;
      const double next = k + 1 < count ? knots[static_cast<std::size_t>(k) + 1].direction - knots[0].direction : 360.0;
      t.cookie.offset[k] = offset * kRadiansPerDegree;
      t.cookie.width[k] = (next - offset) * kRadiansPerDegree;
      t.cookie.value[k] = knot.weight;
      t.cookie.rise[k] = knots[static_cast<std::size_t>((k + 1) % count)].weight - knot.weight;
      t.cookie.area_before[k] = area;
      area += t.cookie.width[k] * (knot.weight + 0.5 * t.cookie.rise[k]);
    }
    t.cookie.area = area;
    finish_cookie_segments(t.cookie);
  }
  t.mask = light.mask;
  t.sin_elevation = std::sin(light.elevation * kRadiansPerDegree);
  t.cos_elevation = std::cos(light.elevation * kRadiansPerDegree);
  return t;
}

OccluderTerms occluder_terms(const Occluder& occluder) {
  OccluderTerms t;
  t.transmittance = occluder.transmittance;
  t.mask = occluder.mask;
  t.lit_interior = occluder.interior == Interior::lit;
  t.albedo = occluder.albedo;
  if (t.reflects()) t.bounce_shape = occluder.shape;
  return t;
}

void update_model_flag(PreparedScene& out) noexcept {
  bool model = !out.directionals.empty() || out.normal_source != NormalSource::none ||
               out.ambient[0] != 0.0 || out.ambient[1] != 0.0 || out.ambient[2] != 0.0;
  for (const PreparedLight& l : out.lights)
    model = model || l.terms.has_range() || l.terms.has_cone || l.terms.cookie.count > 0 || l.terms.mask != kAllMaskBits;
  for (const OccluderTerms& o : out.occluder_terms) model = model || !o.plain();
  out.model = model;
  bool bounce = false;
  for (const OccluderTerms& o : out.occluder_terms) bounce = bounce || o.reflects();
  out.bounce = bounce;
}

void prepare_model_terms(const Scene& scene, PreparedScene& out, std::shared_ptr<const WorldNormals> converted) {
  out.ambient = scene.ambient;
  out.bounce_piece = scene.bounce.piece;
  out.bounce_step = scene.bounce.step;
  out.directionals.clear();
  for (const DirectionalLight& d : scene.directional_lights) {
    PreparedDirectional p;
    for (std::size_t c = 0; c < 3; ++c) p.emission[c] = d.intensity * d.color[c];
    if (!(std::max({p.emission[0], p.emission[1], p.emission[2]}) > 0.0)) continue;
    p.start = wrap_angle(reduce_degrees(d.angle0) * kRadiansPerDegree);
    p.width = (d.angle1 - d.angle0) * kRadiansPerDegree;
    p.mask = d.mask;
    p.sin_elevation = std::sin(d.elevation * kRadiansPerDegree);
    p.cos_elevation = std::cos(d.elevation * kRadiansPerDegree);
    out.directionals.push_back(p);
  }
  out.normal_source = NormalSource::none;
  out.normal_map.reset();
  out.normal = {0.0, 0.0, 1.0};
  if (scene.normal) {
    // Divided by its largest component first: the squares of components near 1e-200 would
    // underflow to a zero length (NaN), those near 1e200 overflow to an infinite one (black).
    const Vec3 n = *scene.normal;
    const double largest = std::max(std::fabs(n.x), std::max(std::fabs(n.y), std::fabs(n.z)));
    const Vec3 u{n.x / largest, n.y / largest, n.z / largest};
    const double length = std::sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
    out.normal = {u.x / length, u.y / length, u.z / length};
    out.normal_source = NormalSource::constant;
  } else if (scene.normal_map) {
    out.normal_map = converted ? std::move(converted) : world_normals(*scene.normal_map, scene.view);
    // Only a validated map reaches here, and every validated normal converts.
    if (!out.normal_map) throw std::invalid_argument("normal_map: a normal did not convert to unit length");
    out.normal_source = NormalSource::map;
  }
  update_model_flag(out);
}

void update_scene_bounds(PreparedScene& out) noexcept {
  out.e_max = 0.0;
  for (const PreparedLight& l : out.lights) out.e_max += l.e_max_share;
  // docs/contract.md section 6: directional lights and the ambient term count too.
  for (const PreparedDirectional& d : out.directionals) out.e_max += std::max({d.emission[0], d.emission[1], d.emission[2]});
  out.e_max += std::max({out.ambient[0], out.ambient[1], out.ambient[2]});
  out.extent = 0.0;
  const View view = out.visible_view();
  const Vec2 center{0.5 * view.x0 + 0.5 * view.x1, 0.5 * view.y0 + 0.5 * view.y1};
  auto grow_extent = [&](Vec2 lo, Vec2 hi) {
    for (double v : {lo.x - center.x, hi.x - center.x, lo.y - center.y, hi.y - center.y})
      out.extent = std::max(out.extent, std::abs(v));
  };
  grow_extent({view.x0, view.y0}, {view.x1, view.y1});
  for (const PreparedLight& l : out.lights) grow_extent(l.shape.bounds_min, l.shape.bounds_max);
  for (const ConvexShape& o : out.occluders) grow_extent(o.bounds_min, o.bounds_max);
}

namespace {

// A light that overlaps a polygon occluder whose edge line cuts off a cap of the light lying
// inside the occluder: along any ray from a point outside the occluder whose first light point
// is in the cap, the occluder comes first (that point is in it), and such a ray meets the
// light's near part (side <= 0 of the line) only later. So everywhere the light can be replaced
// by its near part, which the edge line separates from the occluder (the occluder on side >= 0,
// in front of the near part exactly where side >= 0: a ray from there meets the occluder's side
// before crossing to the near part). The pair becomes an ordinary separated pair. Finds such an
// edge and the chord (where the line crosses the light's boundary); false if none qualifies.
bool clip_light_by_occluder(const ConvexShape& light, const ConvexShape& occluder, LightClip& clip) noexcept {
  if (occluder.kind != ShapeKind::polygon || light.kind == ShapeKind::segment) return false;
  const std::size_t n = occluder.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    // Occluder on side >= 0 (its inward normal).
    const Line line{occluder.edge_normals[i], occluder.vertices[i]};
    // The chord: where the light's boundary crosses the line.
    int found = 0;
    if (light.kind == ShapeKind::circle) {
      const double h = line.side(light.vertices[0]);
      if (!(std::abs(h) < light.radius)) continue;
      const Vec2 foot = light.vertices[0] - h * line.normal;
      const double half = std::sqrt(light.radius * light.radius - h * h);
      const Vec2 along{-line.normal.y, line.normal.x};
      clip.chord[0] = foot + half * along;
      clip.chord[1] = foot - half * along;
      found = 2;
    } else {
      const std::size_t m = light.vertices.size();
      for (std::size_t k = 0; k < m && found < 3; ++k) {
        const Vec2 a = light.vertices[k], b = light.vertices[(k + 1) % m];
        const double sa = line.side(a), sb = line.side(b);
        if ((sa > 0.0) == (sb > 0.0)) continue;
        if (found < 2) clip.chord[found] = a + (sa / (sa - sb)) * (b - a);
        ++found;
      }
    }
    if (found != 2) continue;
    // The cap inside the occluder: against every other edge, its least point is a chord end
    // or (a polygon light's vertex / the circle's extreme point) on the far side of the line.
    bool inside = true;
    for (std::size_t j = 0; j < n && inside; ++j) {
      if (j == i) continue;
      const Line edge{occluder.edge_normals[j], occluder.vertices[j]};
      inside = edge.side(clip.chord[0]) >= 0.0 && edge.side(clip.chord[1]) >= 0.0;
      if (light.kind == ShapeKind::circle) {
        const Vec2 extreme = light.vertices[0] - light.radius * edge.normal;
        if (line.side(extreme) > 0.0) inside = inside && edge.side(extreme) >= 0.0;
      } else {
        for (Vec2 v : light.vertices)
          if (line.side(v) > 0.0) inside = inside && edge.side(v) >= 0.0;
      }
    }
    if (!inside) continue;
    clip.line = line;
    return true;
  }
  return false;
}

// Edges of a shape's boundary as boundary_intersections walks them (none for a circle).
std::size_t boundary_edges(const ConvexShape& s) noexcept {
  if (s.kind == ShapeKind::circle) return 0;
  const std::size_t n = s.vertices.size();
  return n >= 3 ? n : n - 1;
}

// The most points boundary_intersections reports for shapes of these edge counts (0: a
// circle): two for two circles, two per edge against a circle, and otherwise at most four per
// pair of edges (where they cross, or the ends of the piece they share when collinear).
std::size_t meeting_points_bound(std::size_t a_edges, std::size_t b_edges) noexcept {
  if (a_edges == 0 && b_edges == 0) return 2;
  if (a_edges == 0 || b_edges == 0) return 2 * (a_edges + b_edges);
  return 4 * a_edges * b_edges;
}

}  // namespace

void reserve_overlaps(PreparedScene& scene, const ConvexShape* light, const ConvexShape* occluder) {
  PreparedScene::OverlapReserve& r = scene.overlap_reserve;
  if (light == nullptr && occluder == nullptr) {
    for (const PreparedLight& l : scene.lights) r.light_edges = std::max(r.light_edges, boundary_edges(l.shape));
    for (const ConvexShape& o : scene.occluders) r.occluder_edges = std::max(r.occluder_edges, boundary_edges(o));
  }
  if (light) r.light_edges = std::max(r.light_edges, boundary_edges(*light));
  if (occluder) r.occluder_edges = std::max(r.occluder_edges, boundary_edges(*occluder));
  const std::size_t lights = scene.lights.size();
  const std::size_t per_light = std::min(scene.occluders.size(), kReservedOverlapsPerLight);
  const std::size_t points =
      std::min(meeting_points_bound(r.light_edges, r.occluder_edges), kReservedOverlapPoints);
  if (lights <= r.lights && per_light <= r.per_light && points <= r.points) return;
  // Lights are counted up twofold, so that adding thousands of lights one by one (a concave
  // light's pieces) tops the pool up a few times, not once per light.
  if (lights > r.lights) r.lights = std::max(lights, 2 * r.lights);
  r.per_light = std::max(r.per_light, per_light);
  r.points = std::max(r.points, points);
  std::size_t in_use = 0;
  for (const PreparedLight& l : scene.lights) in_use += l.overlaps.size();
  const std::size_t pool = std::max(r.lights * r.per_light, in_use + scene.spare_overlaps.size());
  // Each overlap's room for points, within kReservedPoolPoints in all.
  const std::size_t room = std::min(r.points, kReservedPoolPoints / std::max<std::size_t>(pool, 1));
  for (PreparedLight& l : scene.lights) {
    l.overlaps.reserve(r.per_light);
    l.overlapping_occluders.reserve(scene.occluders.size());
    for (LightOverlap& o : l.overlaps) o.points.reserve(room);
  }
  for (LightOverlap& o : scene.spare_overlaps) o.points.reserve(room);
  // Every overlap can come back to the spares at once.
  scene.spare_overlaps.reserve(pool);
  while (in_use + scene.spare_overlaps.size() < pool) {
    scene.spare_overlaps.emplace_back();
    scene.spare_overlaps.back().points.reserve(room);
  }
}

void describe_overlap(const ConvexShape& light, const ConvexShape& occluder, LightOverlap& out) {
  out.points.clear();
  boundary_intersections(light, occluder, out.points);
  out.contained = contained_within_contact(light, occluder);
  out.clips = clip_light_by_occluder(light, occluder, out.clip);
}

void find_light_overlaps(const PreparedScene& scene, PreparedLight& light, std::vector<std::uint32_t>& near,
                         std::vector<LightOverlap>& spares) {
  light.overlapping_occluders.clear();
  while (!light.overlaps.empty()) {
    spares.push_back(std::move(light.overlaps.back()));
    light.overlaps.pop_back();
  }
  // The index reports each occluder at most once, and the light meets each at most once.
  near.reserve(scene.occluders.size());
  light.overlapping_occluders.reserve(scene.occluders.size());
  light.overlaps.reserve(scene.overlap_reserve.per_light);
  near.clear();
  const ConvexShape& ls = light.shape;
  scene.occluder_bvh.query_box({ls.bounds_min.x, ls.bounds_min.y, ls.bounds_max.x, ls.bounds_max.y}, near);
  for (std::uint32_t k : near) {
    const ConvexShape& occ = scene.occluders[k];
    if (!meets_within_contact(ls, occ)) continue;
    light.overlapping_occluders.push_back(k);
    if (spares.empty()) {
      light.overlaps.emplace_back();
    } else {
      light.overlaps.push_back(std::move(spares.back()));
      spares.pop_back();
    }
    // Room for the pair's points at once: the pool's buffers then grow only as far as the
    // shapes' vertex counts need, not with each new most of meeting points.
    light.overlaps.back().points.reserve(meeting_points_bound(boundary_edges(ls), boundary_edges(occ)));
    describe_overlap(ls, occ, light.overlaps.back());
  }
}

}  // namespace par2d::detail
