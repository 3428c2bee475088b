// Scene model: lights and occluders as convex shapes, image size and view (docs/contract.md sections 2-3).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "par2d/status.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// World coordinates: x to the right, y down (docs/contract.md section 2).
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

// The holes of a polygon, each a ring of vertices (either winding, the first not repeated at
// the end). Kept out of line, so that a polygon without holes costs one null pointer more
// than its outline (levels hold many shapes); copies copy the rings.
class PolygonHoles {
 public:
  using Ring = std::vector<Vec2>;
  PolygonHoles() noexcept = default;
  PolygonHoles(std::vector<Ring> rings)  // NOLINT: implicit, so Polygon{outline, {hole, ...}} reads
      : rings_(rings.empty() ? nullptr : std::make_unique<std::vector<Ring>>(std::move(rings))) {}
  PolygonHoles(std::initializer_list<Ring> rings) : PolygonHoles(std::vector<Ring>(rings)) {}
  PolygonHoles(const PolygonHoles& other)
      : rings_(other.empty() ? nullptr : std::make_unique<std::vector<Ring>>(*other.rings_)) {}
  PolygonHoles(PolygonHoles&&) noexcept = default;
  PolygonHoles& operator=(const PolygonHoles& other) {
    if (this != &other) rings_ = other.empty() ? nullptr : std::make_unique<std::vector<Ring>>(*other.rings_);
    return *this;
  }
  PolygonHoles& operator=(PolygonHoles&&) noexcept = default;
  ~PolygonHoles() = default;

  bool empty() const noexcept { return !rings_ || rings_->empty(); }
  std::size_t size() const noexcept { return rings_ ? rings_->size() : 0; }
  const Ring& operator[](std::size_t i) const { return (*rings_)[i]; }
  Ring& operator[](std::size_t i) { return (*rings_)[i]; }
  const Ring* begin() const noexcept { return rings_ ? rings_->data() : nullptr; }
  const Ring* end() const noexcept { return rings_ ? rings_->data() + rings_->size() : nullptr; }
  Ring* begin() noexcept { return rings_ ? rings_->data() : nullptr; }
  Ring* end() noexcept { return rings_ ? rings_->data() + rings_->size() : nullptr; }
  void push_back(Ring ring) {
    if (!rings_) rings_ = std::make_unique<std::vector<Ring>>();
    rings_->push_back(std::move(ring));
  }
  void clear() noexcept { rings_.reset(); }

 private:
  std::unique_ptr<std::vector<Ring>> rings_;
};

// A closed polygon: its outline `vertices` and, optionally, holes. Either winding; repeated
// and collinear vertices are tolerated. A convex outline without holes is rendered as it is;
// a concave outline (a simple one: no edge crosses or touches another, adjacent edges do not
// fold back) or one with holes (each a simple ring strictly inside the outline, apart from
// the others) is rendered as an exact convex partition of its region under its one handle
// (docs/contract.md section 3). Such an occluder must be opaque, dark inside and not
// reflecting; such a light takes no range or normalize.
struct Polygon {
  std::vector<Vec2> vertices;
  PolygonHoles holes;
};

// A closed disc.
struct Circle {
  Vec2 center;
  double radius = 0.0;  // > 0
};

// A closed line segment between two distinct points.
struct Segment {
  Vec2 a;
  Vec2 b;
};

using Shape = std::variant<Polygon, Circle, Segment>;

// Linear RGB triple.
using Rgb = std::array<double, 3>;

// A direction in 3D world axes: x, y as in Vec2, +z toward the viewer.
struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

// Every bit set: the default light and occluder mask (docs/contract.md section 6).
inline constexpr std::uint32_t kAllMaskBits = 0xFFFFFFFFu;

// A spot light's emission cone, in degrees (docs/contract.md section 6): the light emits only
// in world directions within `half_angle` of `direction`, fading linearly to 0 over the last
// `fade` degrees inside the cone.
struct Cone {
  double direction = 0.0;     // world direction of the axis; 90 points down in the default view
  double half_angle = 180.0;  // 0 < half_angle <= 180
  double fade = 0.0;          // 0 <= fade <= half_angle
};

// A light's angular emission profile (a 1D "cookie", docs/contract.md section 6): the weight
// of light emitted in world direction psi is f(psi - rotation), f the periodic piecewise-linear
// function through the knots (degrees, strictly increasing, spanning less than 360; from the
// last knot it runs on to the first plus 360). Weights are in [0, 1]; one knot is a constant.
struct CookieKnot {
  double direction = 0.0;  // degrees
  double weight = 1.0;     // 0 .. 1
};
inline constexpr int kMaxCookieKnots = 32;
struct Cookie {
  double rotation = 0.0;  // degrees added to every knot's direction
  std::vector<CookieKnot> knots;  // 1 .. kMaxCookieKnots
};

// A sprite's 2D transform: a shape given in its own local frame is scaled per axis, rotated by
// `rotation` degrees (from +x toward +y: clockwise on screen, y down), then moved to `position`:
// world = position + R(rotation) (scale.x * local.x, scale.y * local.y). Turns by multiples of 90
// degrees are exact, so a tile turned a quarter stays on its grid. A negative scale mirrors.
struct Transform {
  Vec2 position{0.0, 0.0};
  double rotation = 0.0;  // degrees
  Vec2 scale{1.0, 1.0};   // non-zero; a circle needs |scale.x| == |scale.y| (a disc stays a disc)
};

// A light's shadow controls (docs/contract.md section 6): where an occluder blocks the light, it
// removes only the fraction k = strength * (1 - color) of it, per channel. The light then gives
// E = (1 - k) U + k S, U its irradiance as if no occluder acted on it and S the shadowed one.
// Strength 1 and color black (the defaults) are full shadows; strength 0 casts none; a colour
// tints the shadow (a red shadow colour lets the red part of the light through).
struct Shadow {
  double strength = 1.0;         // 0 .. 1
  Rgb color{0.0, 0.0, 0.0};      // each channel 0 .. 1
};

// A uniform emitter: every point of its shape emits `intensity * color` in every direction
// (or in its cone), optionally limited to a range.
struct Light {
  Shape shape;
  Rgb color{1.0, 1.0, 1.0};  // each channel >= 0. Default: white.
  double intensity = 1.0;    // >= 0. Default: 1.
  // The smooth window clamp(1 - (d/range)^2, 0, 1)^falloff, d the distance to the shape (0
  // at and beyond the range). Empty: none.
  std::optional<double> range;
  // The range window's exponent, 0 .. 16: 2 (default) eases out to the range, 1 is softer near
  // the light, higher values fall faster, 0 is a hard disc of full weight. Only with a range.
  double falloff = 2.0;
  // A reference distance D > 0 (world units): the emission becomes intensity * color * pi /
  // asin(min(1, rho / D)), rho the largest distance from the shape's centre (circle center,
  // segment midpoint, polygon vertex mean) to the shape, so that a circle light gives
  // `intensity` at distance D from its center whatever its radius: softness (the size) and
  // brightness set apart. Empty: intensity * color as given.
  std::optional<double> normalize;
  std::optional<Cone> cone;  // Empty: every direction.
  // Empty: the same weight in every direction. A light has a cone or a cookie, not both (a
  // cone is the cookie with knots at -h, -h + f, h - f, h, weights 0, 1, 1, 0, rotated to its axis).
  std::optional<Cookie> cookie;
  // Occluders shadow this light only where their masks share a bit with this one.
  std::uint32_t mask = kAllMaskBits;
  // Degrees above the plane, 0 .. 90; matters only when the scene has a normal source.
  double elevation = 0.0;
  // How much of the light the occluders acting on it remove. Default: all of it.
  Shadow shadow;
};

// What a point inside an occluder sees.
enum class Interior : std::uint8_t {
  dark,  // the occluder acts on every direction from inside it (the default)
  lit,   // the occluder is ignored from points inside it (sprites: they cast shadows, lit themselves)
};

// A shape that blocks light (opaque by default) and emits nothing.
struct Occluder {
  Shape shape;
  // Fraction of each channel that passes through, in [0, 1]. Default: 0 (opaque).
  Rgb transmittance{0.0, 0.0, 0.0};
  // Acts on a light only where the masks share a bit.
  std::uint32_t mask = kAllMaskBits;
  Interior interior = Interior::dark;
  // Fraction of each channel its surface reflects, diffusely, once (docs/contract.md section 7),
  // in [0, 1]. Default: 0 (reflects nothing; the scene is then exactly section 6).
  Rgb albedo{0.0, 0.0, 0.0};
};

// A sun or sky: radiance `intensity * color` arriving along ray directions theta in
// [angle0, angle1] degrees (angle0 < angle1, angle1 - angle0 < 360), from infinitely far away.
struct DirectionalLight {
  double angle0 = 0.0;
  double angle1 = 0.0;
  Rgb color{1.0, 1.0, 1.0};
  double intensity = 1.0;
  std::uint32_t mask = kAllMaskBits;
  double elevation = 0.0;  // degrees, 0 .. 90
};

// A surface normal per pixel, exactly the image's width x height. `normals` holds three
// floats per pixel, rows from the top, in image axes: x along image +x (right), y along image
// UP (the common 2D normal-map convention), z toward the viewer; any non-zero length (they are
// normalized). A PNG normal map decodes to n = 2 * rgb / 255 - 1.
struct NormalMap {
  std::string path;  // where it was loaded from (for messages and scene files); may be empty
  int width = 0;
  int height = 0;
  std::vector<float> normals;
};

// The world rectangle the image shows: pixel (i, j) is sampled at
// (x0 + (i + 0.5) * (x1 - x0) / width, y0 + (j + 0.5) * (y1 - y0) / height).
// x0 > x1 or y0 > y1 mirrors the image.
struct View {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

// Hard limits from docs/contract.md section 3.
inline constexpr int kMaxImageSide = 16384;
// The farthest a Renderer's view may be offset on its pixel grid, in pixels per axis.
inline constexpr std::int64_t kMaxViewOffset = std::int64_t{1} << 40;
// The most boundary pieces a scene's reflecting occluders may be cut into (section 7).
inline constexpr double kMaxBouncePieces = 1048576.0;

// One bounce of indirect light (docs/contract.md section 7): the boundaries of occluders with a
// non-zero albedo are cut into pieces about `piece` world units long, each a one-sided light.
// With `step` > 1 the bounce term is computed at the pixels of a coarser grid (every `step`-th
// pixel of the view's pixel grid in x and y) and interpolated in between, only across lines
// that meet no occluder (section 7, "Coarse bounce"); the direct light stays per pixel.
struct Bounce {
  double piece = 4.0;  // > 0, world units. Default: 4.
  int step = 1;        // 1 .. kMaxBounceStep pixels. Default: 1 (every pixel exact).
};
inline constexpr int kMaxBounceStep = 64;

struct Scene {
  int width = 0;   // 1 .. kMaxImageSide
  int height = 0;  // 1 .. kMaxImageSide
  View view;       // Default (as loaded from JSON): [0, 0, width, height].
  std::vector<Light> lights;
  std::vector<Occluder> occluders;
  // The game lighting model's scene-wide terms (docs/contract.md section 6).
  Rgb ambient{0.0, 0.0, 0.0};  // added to every pixel, each channel >= 0
  std::vector<DirectionalLight> directional_lights;
  // The normal source for shading; at most one of the two. Neither: plain irradiance.
  std::optional<Vec3> normal;  // world axes, one for every pixel (normalized; non-zero)
  std::optional<NormalMap> normal_map;
  Bounce bounce;  // used only where some occluder has a non-zero albedo
};

// Checks a scene built in code against docs/contract.md section 3 (sizes, finite numbers,
// convex non-degenerate shapes, non-negative colors). `name` prefixes messages.
Status validate_scene(const Scene& scene, std::string_view name = "scene");

// `local` placed by `transform` into `out` (a polygon keeps its vertex order; `out` may be
// `local` itself, and its vertex storage is reused). Refused, with `out` unchanged, where a
// value is not finite, a scale is 0, or a circle gets different scales on its two axes: a
// Status naming the field ("transform.scale: ..."). The placed shape is validated where it is
// used (a scale of 1e-300 can collapse a polygon).
Status transform_shape(const Shape& local, const Transform& transform, Shape& out);

// How a scene's file references (its `normal_map`) may reach the file system.
struct LoadOptions {
  // false (the default): a `normal_map` path must be relative and stay, after symbolic links,
  // inside the scene's folder; an absolute path or one that leaves it is refused before
  // anything is opened, so an untrusted scene cannot probe the file system. true: any path
  // (trusted scenes only).
  bool allow_any_path = false;
};

// Parses and validates a JSON scene. `name` (usually the file name) prefixes every
// message, e.g. `level.json: lights[2].polygon: edges 1 and 3 cross`. The scene's folder
// (for `normal_map`) is the folder part of `name`, the current directory when it has none.
// A NUL byte anywhere in the text is refused with its offset.
Status parse_scene(std::string_view json_text, std::string_view name, Scene& out);
Status parse_scene(std::string_view json_text, std::string_view name, Scene& out, const LoadOptions& options);

// Reads, parses and validates a JSON scene file; its folder is that of `path` as given.
Status load_scene_file(const std::string& path, Scene& out);
Status load_scene_file(const std::string& path, Scene& out, const LoadOptions& options);

// The file a scene's `normal_map` text names: `written` as is when absolute, else resolved
// against the folder of the scene file `scene_name` (the current directory when it has none).
std::string scene_relative_path(std::string_view scene_name, const std::string& written);

// Reads an 8-bit RGB PNG normal map (RGBA: alpha is ignored; gray and 16-bit PNGs are refused)
// into `out`: n = 2 * rgb / 255 - 1 per pixel, image axes, rows from the top; `out.path` becomes
// `path`. Messages start with `path`. Everything is checked from the PNG header before any
// pixel is decoded: at most kMaxImageSide per side here (a scene needs exactly its width x
// height: the second form refuses any other size before decoding).
Status load_normal_map_png(const std::string& path, NormalMap& out);
Status load_normal_map_png(const std::string& path, NormalMap& out, int width, int height);

// docs/contract.md section 5's e_max: the sum over lights and directional lights of the largest
// channel of intensity * color, plus the largest ambient channel.
double max_emission_sum(const Scene& scene) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
