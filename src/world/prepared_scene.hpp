// The validated scene in the form every renderer reads: canonical shapes, emissions,
// and which light/occluder pairs overlap (those need the general visibility test).
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "geometry/convex_shape.hpp"
#include "lighting/cookie_segments.hpp"
#include "world/occluder_bvh.hpp"
#include "world/world_normals.hpp"
#include "par2d/scene.hpp"

namespace par2d::detail {

// A light's game-model terms (docs/contract.md section 6) in the forms the renderers use:
// radians, ray directions, prepared (scaled) lengths. The defaults are "no term".
struct LightTerms {
  double range = std::numeric_limits<double>::infinity();  // scaled like the shapes; inf: none
  double falloff = 2.0;  // the range window's exponent
  bool has_cone = false;
  // The cone as seen in ray directions theta (light arrives along theta when it was emitted
  // along theta + pi): full weight within `cone_half - cone_fade` of `cone_center`, zero
  // beyond `cone_half`. Radians; cone_center in [0, 2 pi).
  double cone_center = 0.0, cone_half = kPi, cone_fade = 0.0;
  // The cookie's segments in ray directions (count 0: none; a light has a cone or a cookie).
  CookieSegments cookie;
  std::uint32_t mask = kAllMaskBits;
  double sin_elevation = 0.0, cos_elevation = 1.0;

  bool has_range() const noexcept { return range < std::numeric_limits<double>::infinity(); }
};

// Builds a light's terms; `scale` is the prepared scene's coordinate factor.
LightTerms light_terms(const Light& light, double scale) noexcept;

// An occluder's game-model terms.
struct OccluderTerms {
  Rgb transmittance{0.0, 0.0, 0.0};
  std::uint32_t mask = kAllMaskBits;
  bool lit_interior = false;
  // One bounce (docs/contract.md section 7): the reflected fraction, and for a reflecting
  // occluder its shape as given (world units; a polygon keeps its collinear vertices, which
  // cut pieces), from which its pieces are made.
  Rgb albedo{0.0, 0.0, 0.0};
  Shape bounce_shape;

  bool reflects() const noexcept { return albedo[0] != 0.0 || albedo[1] != 0.0 || albedo[2] != 0.0; }
  bool opaque() const noexcept { return transmittance[0] == 0.0 && transmittance[1] == 0.0 && transmittance[2] == 0.0; }
  // Whether this occluder acts on a light with these terms' mask (docs/contract.md section 6).
  bool acts_on(std::uint32_t light_mask) const noexcept { return (mask & light_mask) != 0; }
  // The plain occluder of docs/contract.md section 1.
  bool plain() const noexcept { return opaque() && mask == kAllMaskBits && !lit_interior; }
};

OccluderTerms occluder_terms(const Occluder& occluder);

// A directional light: rays theta in [start, start + width] radians (width < 2 pi) arrive
// with emission `emission` from infinitely far away.
struct PreparedDirectional {
  double start = 0.0, width = 0.0;
  Rgb emission{};
  std::uint32_t mask = kAllMaskBits;
  double sin_elevation = 0.0, cos_elevation = 1.0;
};

enum class NormalSource : std::uint8_t { none, constant, map };

// A light cut by an edge line of an occluder it overlaps: the light's part with side <= 0 of
// `line` (the occluder lies on side >= 0); the chord's ends are where the line crosses the
// light's boundary. See describe_overlap.
struct LightClip {
  Line line;
  Vec2 chord[2];
};

// What the renderers need of a light and an occluder that overlap or touch, found once when
// either shape changes, not again in every tile that sees the pair.
struct LightOverlap {
  // Where the two boundaries meet: the only directions at which the nearer of the two
  // shapes can change.
  std::vector<Vec2> points;
  bool contained = false;  // the light lies in the closed occluder (to within a contact)
  bool clips = false;      // an edge of the occluder cuts off a cap of the light inside it: `clip`
  LightClip clip;
};

struct PreparedLight {
  ConvexShape shape;
  Rgb emission{};  // intensity * color (of this part, for a light its shadow splits)
  // The light's share of e_max (docs/contract.md section 5): its largest channel of e_L, on the
  // first of a split light's two parts only, so that e_max counts each light once.
  double e_max_share = 0.0;
  LightTerms terms;
  // Occluders whose shape meets this light's (sorted). For such a pair the blocked
  // directions are not all-or-nothing per direction interval; see scalar_renderer.
  std::vector<std::uint32_t> overlapping_occluders;
  // For each of those, in the same order: how the two shapes meet.
  std::vector<LightOverlap> overlaps;
};

// Separating lines of disjoint light/occluder pairs (occluder on the positive side),
// computed the first time a tile asks and then shared by every tile and thread: a pair
// matters to many tiles, and the exact closest-point computation costs more than a tile.
class PairSeparators {
 public:
  // At most this many pairs are kept (2 MB of states, 64 MB of lines): a world with more
  // (thousands of concave pieces against thousands of occluders) finds each line anew when
  // asked, the same line, rather than holding gigabytes.
  static constexpr std::size_t kMaxCachedPairs = std::size_t{1} << 21;
  // All pairs unknown, for `lights` x `occluders`.
  void reset(std::size_t lights, std::size_t occluders);
  // Persistent worlds (single-threaded, between frames): room for `lights` x `occluders`
  // keeping what is known (grows capacity geometrically, so steady state never allocates);
  // forget a light's row or an occluder's column; erase a light (the lights above it take
  // the numbers one lower, keeping what is known of them: World::erase_lit); move an occluder
  // (swap-removal).
  void resize(std::size_t lights, std::size_t occluders);
  void forget_light(std::size_t light) noexcept;
  void forget_occluder(std::size_t occluder) noexcept;
  void erase_light(std::size_t light) noexcept;
  void move_occluder(std::size_t from, std::size_t to) noexcept;
  // The line for (light, occluder), or empty when the shapes touch or overlap.
  std::optional<Line> get(std::size_t light, std::size_t occluder, const ConvexShape& light_shape,
                          const ConvexShape& occluder_shape) const noexcept;

 private:
  enum : std::uint8_t { kUnknown = 0, kComputing = 1, kSeparated = 2, kTouching = 3 };
  void copy_pair(std::size_t from, std::size_t to) noexcept;
  static bool too_many(std::size_t lights, std::size_t occluders) noexcept;
  void drop() noexcept;  // keep nothing (too many pairs)
  std::size_t lights_ = 0, occluders_ = 0;
  std::size_t rows_ = 0, stride_ = 0;  // capacity: lights x occluders
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
  std::unique_ptr<Line[]> lines_;
  // Light l's pairs are in row row_[l] (a permutation of the rows_ rows), so that erasing a
  // light renumbers the lights above it without moving their rows.
  std::vector<std::uint32_t> row_;
};

// Coordinates are the scene's times a power of two chosen by scene_scale (exact, and
// irradiance does not depend on scale), so that no scene's products of coordinates
// underflow or overflow.
struct PreparedScene {
  int width = 0, height = 0;
  // The pixel grid frames sample: the width x height image of `view` extended past its edges.
  // The frame shows the grid's pixels (grid_x + i, grid_y + j) (a Renderer's view offset;
  // 0, 0 otherwise), so a pixel's position, tile and block follow the grid, not the frame.
  View view;
  std::int64_t grid_x = 0, grid_y = 0;
  // The world rectangle the frame shows (view shifted by the grid offset).
  View visible_view() const noexcept;
  std::vector<PreparedLight> lights;  // lights with non-zero emission only
  // Overlaps no light holds now, kept with their buffers (find_light_overlaps), and what
  // the pool of overlaps (these and the lights') is reserved for (reserve_overlaps).
  std::vector<LightOverlap> spare_overlaps;
  struct OverlapReserve {
    std::size_t lights = 0, per_light = 0, points = 0;  // reserved for
    std::size_t light_edges = 0, occluder_edges = 0;    // the most edges seen (never shrink)
  } overlap_reserve;
  std::vector<ConvexShape> occluders;
  double e_max = 0.0;  // docs/contract.md section 5
  // Largest distance from the view's center to any point of the view or of a shape's box.
  double extent = 0.0;
  OccluderBvh occluder_bvh;  // over the occluders' bounding boxes
  PairSeparators separators;

  // The game lighting model (docs/contract.md section 6). `occluder_terms` is parallel to
  // `occluders`. `model` is false when every term has its default (section 1 exactly: the
  // renderers take their plain paths).
  std::vector<OccluderTerms> occluder_terms;
  std::vector<PreparedDirectional> directionals;  // those with non-zero emission
  Rgb ambient{0.0, 0.0, 0.0};
  NormalSource normal_source = NormalSource::none;
  Vec3 normal{0.0, 0.0, 1.0};  // NormalSource::constant: unit, world axes
  // NormalSource::map: unit normals in world axes, one plane per component (shared: a World
  // keeps it across frames).
  std::shared_ptr<const WorldNormals> normal_map;
  bool model = false;
  // One bounce (docs/contract.md section 7): whether some occluder reflects, the piece length
  // in world units, and the power of two that took world coordinates to these (pieces are cut
  // in world units, then scaled, so every path cuts them alike).
  bool bounce = false;
  double bounce_piece = 4.0;
  int bounce_step = 1;  // the coarse bounce's grid step in pixels (1: every pixel exact)
  double scale = 1.0;

  // The unit surface normal (world axes) at pixel (i, j); (0, 0, 1) without a source.
  Vec3 normal_at(int i, int j) const noexcept {
    if (normal_source == NormalSource::map) {
      const auto at = static_cast<std::size_t>(i);
      return {normal_map->row(0, j)[at], normal_map->row(1, j)[at], normal_map->row(2, j)[at]};
    }
    return normal;
  }
};

// Fills the scene-wide model terms of `out` (ambient, directionals, normal source) from
// `scene`, then `model`. Occluder and light terms must already be set.
// A map's normals come from `converted` when given (already converted for this view), else
// are converted here.
void prepare_model_terms(const Scene& scene, PreparedScene& out,
                         std::shared_ptr<const WorldNormals> converted = nullptr);
// Recomputes `out.model` from its terms (after a light or occluder changed).
void update_model_flag(PreparedScene& out) noexcept;
// Whether pixels are shaded: a normal source exists and the options ask for shading.
inline bool shading_active(const PreparedScene& s, bool shaded) noexcept {
  return shaded && s.normal_source != NormalSource::none;
}

// The pieces a World prepares a scene with (world.hpp's prepare_scene), shape by shape.
// The power of two all prepared coordinates are scaled by (see PreparedScene).
double scene_scale(const View& view, double largest_coordinate) noexcept;
void scale_shape(ConvexShape& shape, double factor) noexcept;
// e_max (lights, directional lights and ambient) and extent of a prepared scene from its
// view, lights and occluders.
void update_scene_bounds(PreparedScene& scene) noexcept;
// light.overlapping_occluders / overlaps from scratch, with the scene's index. The old
// overlaps go to `spares` (buffers and all) and the new ones come from there: a pool shared
// by the lights of a World, so that lights moving to new places stop allocating once the
// pool holds as many overlaps, with as many points, as the scene has needed at once.
void find_light_overlaps(const PreparedScene& scene, PreparedLight& light, std::vector<std::uint32_t>& scratch,
                         std::vector<LightOverlap>& spares);
// The pool of overlaps reserved so that lights move anywhere without allocating: every light
// holds room for min(occluders, kReservedOverlapsPerLight) overlaps, the pool holds that many
// per light, and each has room for the most meeting points of any light and occluder of the
// scene (at most kReservedOverlapPoints, and kReservedPoolPoints over the pool). `light` / `occluder`: a shape just made (its edges
// may raise the most seen), or both null to look at every shape. Allocates only when the
// counts or the most edges grow; otherwise O(1).
inline constexpr std::size_t kReservedOverlapsPerLight = 16;
inline constexpr std::size_t kReservedOverlapPoints = 256;
inline constexpr std::size_t kReservedPoolPoints = std::size_t{1} << 18;  // 4 MiB of points in all
void reserve_overlaps(PreparedScene& scene, const ConvexShape* light, const ConvexShape* occluder);
// `out` for a light and an occluder that meet (meets_within_contact).
void describe_overlap(const ConvexShape& light, const ConvexShape& occluder, LightOverlap& out);

// World position of sample (sx, sy) in [0,1)^2 of pixel (i, j) of a width x height
// image of `view` (docs/contract.md section 2), the image's pixel grid extended past its
// edges: pixel (i, j) of a frame offset by (grid_x, grid_y) on it is its pixel
// (grid_x + i, grid_y + j). The column is one exact integer in double (|grid| <= 2^40), so a
// pixel's position depends on its place on the grid alone, whatever the offset.
inline Vec2 sample_position(const View& view, int width, int height, std::int64_t i, std::int64_t j, double sx,
                            double sy) noexcept {
  return {view.x0 + (static_cast<double>(i) + sx) * (view.x1 - view.x0) / width,
          view.y0 + (static_cast<double>(j) + sy) * (view.y1 - view.y0) / height};
}

// The same in the prepared scene's (scaled) coordinates, for pixel (i, j) of its frame.
inline Vec2 sample_position(const PreparedScene& s, int i, int j, double sx, double sy) noexcept {
  return sample_position(s.view, s.width, s.height, s.grid_x + i, s.grid_y + j, sx, sy);
}

// The rectangle of the grid offset by (x, y) pixels: the image of `view` moved by whole pixels.
inline View offset_view(const View& view, int width, int height, std::int64_t x, std::int64_t y) noexcept {
  if (x == 0 && y == 0) return view;
  const Vec2 a = sample_position(view, width, height, x, y, 0.0, 0.0);
  const Vec2 b = sample_position(view, width, height, x + width, y + height, 0.0, 0.0);
  return {a.x, a.y, b.x, b.y};
}

inline View PreparedScene::visible_view() const noexcept { return offset_view(view, width, height, grid_x, grid_y); }

}  // namespace par2d::detail
