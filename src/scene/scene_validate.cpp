// Scene validation against docs/contract.md section 3, and the e_max bound of section 5.
#include "scene/scene_validate.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include "geometry/bounce_pieces.hpp"
#include "geometry/polygon_partition.hpp"
#include "lighting/light_emission.hpp"
#include "geometry/vec2.hpp"
#include "scene/shortest_double.hpp"

// A level holds many shapes: holes live out of line, so a polygon costs its outline's vector
// and one pointer (tests/test_scene_loading.cpp loads 8 MB of shapes within 3x the text).
static_assert(sizeof(par2d::Polygon) <= 32, "keep a Polygon's holes out of line");

namespace par2d {
namespace detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
// docs/contract.md section 3: a turn with |cross(e1, e2)| <= kStraightTolerance * |e1| * |e2| is straight.
constexpr double kStraightTolerance = 1e-9;

std::string indexed(const std::string& place, std::size_t index) {
  return place + "[" + std::to_string(index) + "]";
}

MaybeProblem check_finite(double value, const std::string& place) {
  if (!std::isfinite(value)) return SceneProblem{place, "not a finite number (" + format_number(value) + ")"};
  return std::nullopt;
}

MaybeProblem check_point(const Vec2& p, const std::string& place) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
    return SceneProblem{place, "not a finite point (" + format_number(p.x) + ", " + format_number(p.y) + ")"};
  }
  return std::nullopt;
}

// The polygon rule of docs/contract.md section 3. Coordinates are first scaled by a power of two
// (exact) into [-1, 1], so that edge vectors, cross products and the shoelace sum cannot
// overflow whatever finite coordinates come in; the tolerance test is scale-invariant, so
// the verdict is the one the unscaled numbers would give.
// `concave` (when given) is set where the vertices fail only for not being convex (a turn
// against the winding, or winding around more than once), so that the caller can try them as
// a concave outline.
MaybeProblem check_convex_ring(const std::vector<Vec2>& v, const std::string& place, bool* concave) {
  const std::size_t n = v.size();
  if (n < 3) return SceneProblem{place, "needs at least 3 vertices, got " + std::to_string(n)};

  double max_abs = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (auto problem = check_point(v[i], indexed(place, i))) return problem;
    max_abs = std::max({max_abs, std::fabs(v[i].x), std::fabs(v[i].y)});
  }
  if (max_abs == 0.0) return SceneProblem{place, "zero area (all vertices coincide)"};
  int exponent = 0;
  std::frexp(max_abs, &exponent);
  auto scaled = [&](std::size_t i) {
    return Vec2{std::ldexp(v[i].x, -exponent), std::ldexp(v[i].y, -exponent)};
  };

  // Zero-length edges (repeated consecutive vertices, including a closing repeat of vertex 0)
  // have no direction, so they are skipped; `end` is the vertex where the edge ends, which
  // is where the turn to the next kept edge happens.
  struct Edge {
    Vec2 d;
    std::size_t end;
  };
  // Reused per thread: a game's Renderer validates shapes every frame without allocating.
  thread_local std::vector<Edge> edges;
  edges.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const Vec2 a = scaled(i);
    const Vec2 b = scaled(j);
    const Vec2 d{b.x - a.x, b.y - a.y};
    if (d.x != 0.0 || d.y != 0.0) edges.push_back({d, j});
  }
  if (edges.empty()) return SceneProblem{place, "zero area (all vertices coincide)"};

  // Each turn: +1 left, -1 right, 0 straight. A near-straight turn that goes back the way
  // it came (dot < 0) is a fold; it keeps the sign of its cross product when there is one
  // (a needle-thin tip), and with an exactly zero cross product it has no side at all.
  struct Turn {
    int side;
    bool fold;
    double angle;
    std::size_t vertex;
  };
  thread_local std::vector<Turn> turns;
  turns.clear();
  turns.reserve(edges.size());
  int left = 0;
  int right = 0;
  int proper = 0;  // turns beyond the straight tolerance; without any, the vertices are collinear
  int first_side = 0;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const Vec2& e1 = edges[k].d;
    const Vec2& e2 = edges[(k + 1) % edges.size()].d;
    const double c = cross(e1, e2);
    const double d = dot(e1, e2);
    const double tolerance = kStraightTolerance * std::hypot(e1.x, e1.y) * std::hypot(e2.x, e2.y);
    Turn turn{0, false, std::atan2(c, d), edges[k].end};
    if (std::fabs(c) > tolerance || d < 0.0) {
      turn.side = c > 0.0 ? 1 : (c < 0.0 ? -1 : 0);
      turn.fold = std::fabs(c) <= tolerance;
      if (!turn.fold) ++proper;
    }
    if (turn.side > 0) ++left;
    if (turn.side < 0) ++right;
    if (first_side == 0) first_side = turn.side;
    turns.push_back(turn);
  }
  if (proper == 0) return SceneProblem{place, "zero area (all vertices are collinear)"};

  // The winding is the sign of the area; should that be zero (a symmetric bow-tie) the
  // majority of turns decides, so the vertex named is the odd one out.
  double area2 = 0.0;
  const Vec2 origin = scaled(0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec2 a = scaled(i);
    const Vec2 b = scaled(i + 1);
    area2 += cross(Vec2{a.x - origin.x, a.y - origin.y}, Vec2{b.x - origin.x, b.y - origin.y});
  }
  int winding = area2 > 0.0 ? 1 : (area2 < 0.0 ? -1 : 0);
  if (winding == 0) winding = left > right ? 1 : (right > left ? -1 : first_side);

  const Turn* bad = nullptr;
  for (const Turn& turn : turns) {
    const bool against = turn.side == -winding || (turn.fold && turn.side == 0);
    if (against && (bad == nullptr || turn.vertex < bad->vertex)) bad = &turn;
  }
  // Straight turns may not add up to a pocket: the boundary's direction, summed turn by turn
  // with the winding positive, never falls back by more than one straight turn's tolerance
  // below the highest it has reached. Each tolerated turn alone bends by at most ~1e-9 rad,
  // but a thousand of them against the winding make a dent that an exact convex treatment
  // (and the vertex cleanup of make_convex_shape) would fill. A turn beyond the tolerance with
  // the winding lifts the direction above every earlier maximum, so one lap started after such
  // a turn sees every run of straight turns whole, including one that wraps past vertex 0.
  if (bad == nullptr) {
    std::size_t start = 0;
    while (start < turns.size() && !(turns[start].side == winding && !turns[start].fold)) ++start;
    double direction = 0.0, highest = 0.0;
    for (std::size_t step = 1; start < turns.size() && step <= turns.size(); ++step) {
      const Turn& turn = turns[(start + step) % turns.size()];
      direction += turn.angle * static_cast<double>(winding);
      highest = std::max(highest, direction);
      if (highest - direction > kStraightTolerance) {
        bad = &turn;
        break;
      }
    }
  }
  if (bad != nullptr) {
    if (concave) *concave = true;
    return SceneProblem{place, "not convex at vertex " + std::to_string(bad->vertex)};
  }

  // Turns all to one side can still wind around more than once (a pentagram's vertex list):
  // a simple convex boundary turns through exactly one revolution.
  double total = 0.0;
  for (const Turn& turn : turns) total += turn.angle;
  const double revolutions = std::fabs(total) / (2.0 * kPi);
  if (!(revolutions > 0.5 && revolutions < 1.5)) {
    if (concave) *concave = true;
    return SceneProblem{place, "self-overlapping (its boundary winds around " +
                                   std::to_string(std::lround(revolutions)) + " times, not once)"};
  }
  if (area2 == 0.0) return SceneProblem{place, "zero area"};
  return std::nullopt;
}

// A convex polygon; where `concave_allowed`, else a simple outline, with or without holes, that
// has an exact convex partition (polygon_partition.hpp). `place` ends in ".polygon"; a
// hole's problem is placed at the sibling ".holes[k]".
MaybeProblem check_polygon(const Polygon& polygon, const std::string& place, bool concave_allowed) {
  bool concave = false;
  MaybeProblem problem = check_convex_ring(polygon.vertices, place, &concave);
  if (polygon.holes.empty() && (!problem || !concave || !concave_allowed)) return problem;
  constexpr std::string_view kSuffix = ".polygon";
  const std::string base =
      place.size() >= kSuffix.size() && place.compare(place.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0
          ? place.substr(0, place.size() - kSuffix.size())
          : place;
  if (!concave_allowed) return SceneProblem{base + ".holes", "only a light or an occluder's polygon may have holes"};
  for (std::size_t k = 0; k < polygon.holes.size(); ++k) {
    const std::string at = indexed(base + ".holes", k);
    if (polygon.holes[k].size() < 3)
      return SceneProblem{at, "needs at least 3 vertices, got " + std::to_string(polygon.holes[k].size())};
    for (std::size_t i = 0; i < polygon.holes[k].size(); ++i)
      if (auto bad = check_point(polygon.holes[k][i], indexed(at, i))) return bad;
  }
  std::string error;
  if (partition_polygon(polygon, error)) return std::nullopt;
  // The partition names rings: "outer: ..." is the outline's problem, "holes[k]: ..." a hole's
  // ("holes[1] and holes[2] overlap ..." is placed at the first).
  constexpr std::string_view kOuter = "outer: ";
  if (error.compare(0, kOuter.size(), kOuter) == 0) return SceneProblem{place, error.substr(kOuter.size())};
  constexpr std::string_view kHoles = "holes[";
  if (error.compare(0, kHoles.size(), kHoles) == 0) {
    // "holes[k]: what" and "holes[k] what" name one hole; "holes[j] and holes[k] ..." two.
    const std::size_t close = error.find(']');
    if (close != std::string::npos && error.compare(close + 1, 5, " and ") != 0) {
      const std::size_t what = error.compare(close + 1, 2, ": ") == 0 ? close + 3 : close + 2;
      return SceneProblem{base + "." + error.substr(0, close + 1), error.substr(std::min(what, error.size()))};
    }
    return SceneProblem{base + ".holes", error};
  }
  return SceneProblem{place, error};
}

bool polygon_needs_partition(const Polygon& polygon) {
  if (!polygon.holes.empty()) return true;
  bool concave = false;
  return check_convex_ring(polygon.vertices, std::string(), &concave) && concave;
}

MaybeProblem check_circle(const Circle& circle, const std::string& place) {
  if (auto problem = check_point(circle.center, place + ".center")) return problem;
  if (auto problem = check_finite(circle.radius, place + ".radius")) return problem;
  if (!(circle.radius > 0.0)) {
    return SceneProblem{place + ".radius", "must be > 0, got " + format_number(circle.radius)};
  }
  return std::nullopt;
}

MaybeProblem check_segment(const Segment& segment, const std::string& place) {
  if (auto problem = check_point(segment.a, indexed(place, 0))) return problem;
  if (auto problem = check_point(segment.b, indexed(place, 1))) return problem;
  if (segment.a.x == segment.b.x && segment.a.y == segment.b.y) {
    return SceneProblem{place, "the two points coincide"};
  }
  return std::nullopt;
}

MaybeProblem check_non_negative(double value, const std::string& place) {
  if (auto problem = check_finite(value, place)) return problem;
  if (!(value >= 0.0)) return SceneProblem{place, "must be >= 0, got " + format_number(value)};
  return std::nullopt;
}

MaybeProblem check_elevation(double value, const std::string& place) {
  if (auto problem = check_finite(value, place)) return problem;
  if (!(value >= 0.0 && value <= 90.0)) return SceneProblem{place, "must be between 0 and 90, got " + format_number(value)};
  return std::nullopt;
}

}  // namespace

bool needs_partition(const Shape& shape) {
  const auto* polygon = std::get_if<Polygon>(&shape);
  return polygon != nullptr && polygon_needs_partition(*polygon);
}

std::string image_side_range_text() {
  return "must be an integer from 1 to " + std::to_string(kMaxImageSide);
}

MaybeProblem check_image_size(int width, int height) {
  if (width < 1 || width > kMaxImageSide) {
    return SceneProblem{"width", image_side_range_text() + ", got " + std::to_string(width)};
  }
  if (height < 1 || height > kMaxImageSide) {
    return SceneProblem{"height", image_side_range_text() + ", got " + std::to_string(height)};
  }
  return std::nullopt;
}

MaybeProblem check_view(const View& view, int width, int height) {
  const std::array<double, 4> values{view.x0, view.y0, view.x1, view.y1};
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (auto problem = check_finite(values[i], indexed("view", i))) return problem;
  }
  if (view.x0 == view.x1) return SceneProblem{"view", "x0 and x1 are equal (the view has no width)"};
  if (view.y0 == view.y1) return SceneProblem{"view", "y0 and y1 are equal (the view has no height)"};
  // Pixel positions are computed from x1 - x0; an extent that overflows would make every one inf.
  if (!std::isfinite(view.x1 - view.x0) || !std::isfinite(view.y1 - view.y0)) {
    return SceneProblem{"view", "extent is too large to represent"};
  }
  // A subnormal pixel size has lost bits (1e-310 has 14 of 53 left): pixel centers would not be
  // the contract's, and rescaling the scene could not restore them.
  const double pixel = std::min(std::fabs(view.x1 - view.x0) / std::max(width, 1),
                                std::fabs(view.y1 - view.y0) / std::max(height, 1));
  if (!(pixel >= std::numeric_limits<double>::min())) {
    return SceneProblem{"view", "pixel size " + format_number(pixel) +
                                    " is below the smallest normal double (2.2250738585072014e-308)"};
  }
  return std::nullopt;
}

double concave_entries_bound(const Polygon& polygon) noexcept {
  double edges = static_cast<double>(polygon.vertices.size());
  for (const std::vector<Vec2>& hole : polygon.holes) edges += static_cast<double>(hole.size());
  return 1.0 + std::floor(0.5 * edges);
}

double light_entries_bound(const Light& light) {
  return needs_partition(light.shape) ? concave_entries_bound(std::get<Polygon>(light.shape)) : 1.0;
}

MaybeProblem check_emission_total(const std::vector<Light>& lights) {
  Rgb total{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const double entries = light_entries_bound(lights[i]);
    for (int c = 0; c < 3; ++c) {
      total[c] += entries * detail::light_emission(lights[i])[static_cast<std::size_t>(c)];
      if (!(total[c] <= kMaxTotalEmission)) {
        return SceneProblem{indexed("lights", i), "emission too large: the lights' total intensity * color (a concave "
                                                      "light's times the most times a ray enters it) reaches " +
                                                      format_number(total[c]) + " (at most 1e38, so that float32 "
                                                      "output stays finite)"};
      }
    }
  }
  return std::nullopt;
}

MaybeProblem check_shape(const Shape& shape, const std::string& place, bool concave_allowed) {
  if (const auto* polygon = std::get_if<Polygon>(&shape)) return check_polygon(*polygon, place + ".polygon", concave_allowed);
  if (const auto* circle = std::get_if<Circle>(&shape)) return check_circle(*circle, place + ".circle");
  if (const auto* segment = std::get_if<Segment>(&shape)) return check_segment(*segment, place + ".segment");
  return SceneProblem{place, "has no shape"};  // valueless_by_exception
}

// Knots strictly increasing within less than a turn, weights in [0, 1] (so no direction
// emits more than the light's emission: the accuracy bound's e_max stays intensity * color).
MaybeProblem check_cookie(const Cookie& cookie, const std::string& place) {
  if (!std::isfinite(cookie.rotation)) return check_finite(cookie.rotation, place + ".rotation");
  const std::size_t count = cookie.knots.size();
  if (count < 1 || count > static_cast<std::size_t>(kMaxCookieKnots)) {
    return SceneProblem{place + ".knots", "must hold 1 to " + std::to_string(kMaxCookieKnots) + " knots, got " +
                                              std::to_string(count)};
  }
  for (std::size_t k = 0; k < count; ++k) {
    const CookieKnot& knot = cookie.knots[k];
    if (!std::isfinite(knot.direction)) return check_finite(knot.direction, indexed(place + ".knots", k) + "[0]");
    if (!(knot.weight >= 0.0 && knot.weight <= 1.0)) {
      const std::string at = indexed(place + ".knots", k) + "[1]";
      if (auto problem = check_finite(knot.weight, at)) return problem;
      return SceneProblem{at, "weight must be between 0 and 1, got " + format_number(knot.weight)};
    }
    if (k > 0 && !(knot.direction > cookie.knots[k - 1].direction)) {
      return SceneProblem{indexed(place + ".knots", k) + "[0]",
                          "directions must increase, got " + format_number(knot.direction) + " after " +
                              format_number(cookie.knots[k - 1].direction)};
    }
  }
  if (!(cookie.knots.back().direction - cookie.knots.front().direction < 360.0)) {
    return SceneProblem{indexed(place + ".knots", count - 1) + "[0]",
                        "must be less than 360 degrees past the first knot's direction, got " +
                            format_number(cookie.knots.back().direction)};
  }
  return std::nullopt;
}

MaybeProblem check_light(const Light& light, const std::string& place) {
  if (auto problem = check_shape(light.shape, place, true)) return problem;
  // A concave light is lit as its convex pieces (World::push_light), exact for terms that
  // depend on the direction alone; a range window (the distance to the shape) and normalize
  // (its size) would be each piece's, not the light's.
  if ((light.range || light.normalize) && needs_partition(light.shape))
    return SceneProblem{place + (light.range ? ".range" : ".normalize"),
                        "a concave light takes no range or normalize (split it into convex lights)"};
  for (std::size_t c = 0; c < light.color.size(); ++c) {
    if (auto problem = check_non_negative(light.color[c], indexed(place + ".color", c))) return problem;
  }
  if (auto problem = check_non_negative(light.intensity, place + ".intensity")) return problem;
  // Each place is built only once a value is refused (no allocation per valid update).
  if (light.range && !(std::isfinite(*light.range) && *light.range > 0.0)) {
    if (auto problem = check_finite(*light.range, place + ".range")) return problem;
    return SceneProblem{place + ".range", "must be > 0, got " + format_number(*light.range)};
  }
  if (!(light.falloff >= 0.0 && light.falloff <= 16.0)) {
    if (auto problem = check_finite(light.falloff, place + ".falloff")) return problem;
    return SceneProblem{place + ".falloff", "must be between 0 and 16, got " + format_number(light.falloff)};
  }
  if (light.normalize && !(std::isfinite(*light.normalize) && *light.normalize > 0.0)) {
    if (auto problem = check_finite(*light.normalize, place + ".normalize")) return problem;
    return SceneProblem{place + ".normalize", "must be > 0, got " + format_number(*light.normalize)};
  }
  if (light.cone) {
    const Cone& cone = *light.cone;
    if (!std::isfinite(cone.direction)) return check_finite(cone.direction, place + ".cone.direction");
    if (!(std::isfinite(cone.half_angle) && cone.half_angle > 0.0 && cone.half_angle <= 180.0)) {
      if (auto problem = check_finite(cone.half_angle, place + ".cone.half_angle")) return problem;
      return SceneProblem{place + ".cone.half_angle", "must be > 0 and <= 180, got " + format_number(cone.half_angle)};
    }
    if (!(std::isfinite(cone.fade) && cone.fade >= 0.0 && cone.fade <= cone.half_angle)) {
      if (auto problem = check_finite(cone.fade, place + ".cone.fade")) return problem;
      return SceneProblem{place + ".cone.fade", "must be between 0 and half_angle, got " + format_number(cone.fade)};
    }
  }
  if (light.cookie) {
    if (auto problem = check_cookie(*light.cookie, place + ".cookie")) return problem;
    if (light.cone) return SceneProblem{place + ".cookie", "a light takes a cone or a cookie, not both"};
  }
  if (!(light.shadow.strength >= 0.0 && light.shadow.strength <= 1.0)) {
    if (auto problem = check_finite(light.shadow.strength, place + ".shadow.strength")) return problem;
    return SceneProblem{place + ".shadow.strength",
                        "must be between 0 and 1, got " + format_number(light.shadow.strength)};
  }
  for (std::size_t c = 0; c < light.shadow.color.size(); ++c) {
    const double v = light.shadow.color[c];
    if (v >= 0.0 && v <= 1.0) continue;
    const std::string at = indexed(place + ".shadow.color", c);
    if (auto problem = check_finite(v, at)) return problem;
    return SceneProblem{at, "must be between 0 and 1, got " + format_number(v)};
  }
  if (light.elevation >= 0.0 && light.elevation <= 90.0) return std::nullopt;
  return check_elevation(light.elevation, place + ".elevation");
}

MaybeProblem check_occluder(const Occluder& occluder, const std::string& place) {
  if (auto problem = check_shape(occluder.shape, place, true)) return problem;
  // Its convex pieces stand for it: a ray crossing two of them would count a transmittance
  // twice, a point inside one piece would still be shadowed by the others, and the pieces'
  // inner edges would reflect. Only the opaque, dark, non-reflecting union is exact.
  if ((occluder.transmittance != Rgb{0.0, 0.0, 0.0} || occluder.interior != Interior::dark ||
       occluder.albedo != Rgb{0.0, 0.0, 0.0}) &&
      needs_partition(occluder.shape)) {
    const char* term = occluder.transmittance != Rgb{0.0, 0.0, 0.0} ? ".transmittance"
                       : occluder.interior != Interior::dark          ? ".interior"
                                                                       : ".albedo";
    return SceneProblem{place + term, "a concave occluder must be opaque, dark inside and not reflecting "
                                      "(split it into convex occluders)"};
  }
  // Places are built only for a problem: a game's Renderer validates every frame's updates
  // without allocating.
  for (std::size_t c = 0; c < occluder.transmittance.size(); ++c) {
    const double t = occluder.transmittance[c];
    if (t >= 0.0 && t <= 1.0) continue;
    const std::string at = indexed(place + ".transmittance", c);
    if (auto problem = check_finite(t, at)) return problem;
    return SceneProblem{at, "must be between 0 and 1, got " + format_number(t)};
  }
  if (occluder.interior != Interior::dark && occluder.interior != Interior::lit) {
    return SceneProblem{place + ".interior", "must be dark or lit"};
  }
  for (std::size_t c = 0; c < occluder.albedo.size(); ++c) {
    const double a = occluder.albedo[c];
    if (a >= 0.0 && a <= 1.0) continue;
    const std::string at = indexed(place + ".albedo", c);
    if (auto problem = check_finite(a, at)) return problem;
    return SceneProblem{at, "must be between 0 and 1, got " + format_number(a)};
  }
  return std::nullopt;
}

MaybeProblem check_bounce(const Bounce& bounce) {
  if (!(bounce.step >= 1 && bounce.step <= kMaxBounceStep))
    return SceneProblem{"bounce.step", "must be an integer from 1 to " + std::to_string(kMaxBounceStep) + ", got " +
                                           std::to_string(bounce.step)};
  if (std::isfinite(bounce.piece) && bounce.piece > 0.0) return std::nullopt;
  if (auto problem = check_finite(bounce.piece, "bounce.piece")) return problem;
  return SceneProblem{"bounce.piece", "must be > 0, got " + format_number(bounce.piece)};
}

std::string bounce_pieces_text(double pieces) {
  return "cuts the reflecting occluders into more than 1048576 pieces (" +
         (pieces < 1e15 ? std::to_string(static_cast<long long>(pieces)) : format_number(pieces)) +
         " so far); use a longer piece";
}

MaybeProblem check_bounce_pieces(const Scene& scene) {
  double pieces = 0.0;
  for (const Occluder& o : scene.occluders) {
    if (o.albedo == Rgb{0.0, 0.0, 0.0}) continue;
    pieces += bounce_piece_count(o.shape, scene.bounce.piece, kMaxBouncePieces);
    if (pieces > kMaxBouncePieces) return SceneProblem{"bounce.piece", bounce_pieces_text(pieces)};
  }
  return std::nullopt;
}

MaybeProblem check_ambient(const Rgb& ambient) {
  for (std::size_t c = 0; c < ambient.size(); ++c) {
    if (auto problem = check_non_negative(ambient[c], indexed("ambient", c))) return problem;
  }
  return std::nullopt;
}

MaybeProblem check_directional(const DirectionalLight& light, const std::string& place) {
  if (auto problem = check_finite(light.angle0, place + ".angles[0]")) return problem;
  if (auto problem = check_finite(light.angle1, place + ".angles[1]")) return problem;
  const double width = light.angle1 - light.angle0;
  if (!(light.angle0 < light.angle1 && width < 360.0)) {
    return SceneProblem{place + ".angles", "must satisfy a0 < a1 < a0 + 360, got [" + format_number(light.angle0) +
                                               ", " + format_number(light.angle1) + "]"};
  }
  for (std::size_t c = 0; c < light.color.size(); ++c) {
    if (auto problem = check_non_negative(light.color[c], indexed(place + ".color", c))) return problem;
  }
  if (auto problem = check_non_negative(light.intensity, place + ".intensity")) return problem;
  return check_elevation(light.elevation, place + ".elevation");
}

MaybeProblem check_normal(const Vec3& normal) {
  const double v[3] = {normal.x, normal.y, normal.z};
  for (std::size_t c = 0; c < 3; ++c) {
    if (auto problem = check_finite(v[c], indexed("normal", c))) return problem;
  }
  // Scaled first, so that a tiny or huge finite normal has a length too.
  const double largest = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
  if (!(largest > 0.0)) return SceneProblem{"normal", "must have a non-zero length"};
  return std::nullopt;
}

MaybeProblem check_normal_map(const NormalMap& map, int width, int height, NormalsCheck check) {
  if (map.width != width || map.height != height) {
    return SceneProblem{"normal_map", "is " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                                          " but the image is " + std::to_string(width) + "x" +
                                          std::to_string(height) + " (it must be exactly the image's size)"};
  }
  const std::size_t expected = 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (map.normals.size() != expected) {
    return SceneProblem{"normal_map.normals", "expected 3 * width * height = " + std::to_string(expected) +
                                                  " floats, got " + std::to_string(map.normals.size())};
  }
  if (check == NormalsCheck::size_only) return std::nullopt;
  // Every render validates the whole map: branch-free passes over blocks of pixels (they
  // vectorize) find the first block with a bad normal, walked below for its message.
  std::size_t first_bad = expected;
  constexpr std::size_t kBlock = 3 * 1024;
  constexpr float kLargest = std::numeric_limits<float>::max();
  const float* normals = map.normals.data();
  for (std::size_t b = 0; b < expected; b += kBlock) {
    const std::size_t end = std::min(expected, b + kBlock);
    int bad = 0;
    for (std::size_t k = b; k < end; ++k) bad |= static_cast<int>(!(std::fabs(normals[k]) <= kLargest));
    for (std::size_t p = b; p < end; p += 3)
      bad |= static_cast<int>(normals[p] == 0.0f) & static_cast<int>(normals[p + 1] == 0.0f) &
             static_cast<int>(normals[p + 2] == 0.0f);
    if (bad) {
      first_bad = b;
      break;
    }
  }
  for (std::size_t p = first_bad; p < expected; p += 3) {
    const float* n = map.normals.data() + p;
    const bool finite = std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]);
    if (finite && !(n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f)) continue;
    // The place string only for the refused pixel: every render validates the whole map.
    const std::size_t pixel = p / 3;
    const std::string at = "normal_map: pixel (" + std::to_string(pixel % static_cast<std::size_t>(width)) + ", " +
                           std::to_string(pixel / static_cast<std::size_t>(width)) + ")";
    if (!finite) {
      return SceneProblem{at, "not a finite normal (" + format_number(n[0]) + ", " + format_number(n[1]) + ", " +
                                  format_number(n[2]) + ")"};
    }
    return SceneProblem{at, "has a zero normal"};
  }
  return std::nullopt;
}

MaybeProblem check_scene_terms(const Scene& scene, NormalsCheck normals) {
  if (scene.normal && scene.normal_map) {
    return SceneProblem{"normal_map", "the scene has both normal and normal_map (at most one normal source)"};
  }
  if (scene.normal_map) {
    if (auto problem = check_normal_map(*scene.normal_map, scene.width, scene.height, normals)) return problem;
  }
  // Every term adds to E: its total must stay finite in float32 output, as the lights' does.
  Rgb total{0.0, 0.0, 0.0};
  for (const Light& light : scene.lights) {
    const Rgb e = detail::light_emission(light);
    const double entries = light_entries_bound(light);
    for (std::size_t c = 0; c < 3; ++c) total[c] += entries * e[c];
  }
  auto over = [&](const std::string& place) -> MaybeProblem {
    for (std::size_t c = 0; c < 3; ++c) {
      if (!(total[c] <= kMaxTotalEmission)) {
        return SceneProblem{place, "emission too large: the total intensity * color of lights, directional "
                                   "lights and ambient reaches " + format_number(total[c]) +
                                   " (at most 1e38, so that float32 output stays finite)"};
      }
    }
    return std::nullopt;
  };
  for (std::size_t i = 0; i < scene.directional_lights.size(); ++i) {
    const DirectionalLight& d = scene.directional_lights[i];
    for (std::size_t c = 0; c < 3; ++c) total[c] += d.intensity * d.color[c];
    if (auto problem = over(indexed("directional_lights", i))) return problem;
  }
  for (std::size_t c = 0; c < 3; ++c) total[c] += scene.ambient[c];
  return over("ambient");
}

Status scene_error(std::string_view name, const SceneProblem& problem) {
  std::string message(name);
  message += ": ";
  if (!problem.place.empty()) {
    message += problem.place;
    message += ": ";
  }
  message += problem.what;
  return Status(StatusCode::invalid_scene, std::move(message));
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return detail::shortest_double(value);
}

Status validate_scene(const Scene& scene, std::string_view name, NormalsCheck normals) {
  try {
    detail::MaybeProblem problem = detail::check_image_size(scene.width, scene.height);
    if (!problem) problem = detail::check_view(scene.view, scene.width, scene.height);
    for (std::size_t i = 0; !problem && i < scene.lights.size(); ++i) {
      problem = detail::check_light(scene.lights[i], "lights[" + std::to_string(i) + "]");
    }
    if (!problem) problem = detail::check_emission_total(scene.lights);
    for (std::size_t i = 0; !problem && i < scene.occluders.size(); ++i) {
      problem = detail::check_occluder(scene.occluders[i], "occluders[" + std::to_string(i) + "]");
    }
    if (!problem) problem = detail::check_ambient(scene.ambient);
    for (std::size_t i = 0; !problem && i < scene.directional_lights.size(); ++i) {
      problem = detail::check_directional(scene.directional_lights[i], "directional_lights[" + std::to_string(i) + "]");
    }
    if (!problem && scene.normal) problem = detail::check_normal(*scene.normal);
    if (!problem) problem = detail::check_bounce(scene.bounce);
    if (!problem) problem = detail::check_bounce_pieces(scene);
    if (!problem) problem = detail::check_scene_terms(scene, normals);
    if (problem) return detail::scene_error(name, *problem);
    return Status::success();
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, std::string(name) + ": out of memory while validating the scene");
  }
}

}  // namespace detail

Status validate_scene(const Scene& scene, std::string_view name) {
  return detail::validate_scene(scene, name, detail::NormalsCheck::each);
}

double max_emission_sum(const Scene& scene) noexcept {
  double sum = 0.0;
  for (const Light& light : scene.lights) {
    const Rgb e = detail::light_emission(light);
    sum += std::max({e[0], e[1], e[2]});
  }
  for (const DirectionalLight& light : scene.directional_lights) {
    double largest = 0.0;
    for (double channel : light.color) largest = std::max(largest, light.intensity * channel);
    sum += largest;
  }
  return sum + std::max({scene.ambient[0], scene.ambient[1], scene.ambient[2]});
}

}  // namespace par2d
