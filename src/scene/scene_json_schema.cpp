// The scene schema walk: what each key and value of a scene file means, checked as the parser's
// events arrive (unknown keys, wrong types, missing members, one shape per element), each light,
// occluder and directional light validated as it closes. The events themselves, numbers and
// places are read in scene_json.cpp.
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "par2d/scene.hpp"
#include "scene/scene_json_builder.hpp"
#include "geometry/bounce_pieces.hpp"
#include "scene/scene_validate.hpp"

namespace par2d::detail {

namespace {
constexpr const char* kCookieExpected = "expected {\"rotation\": r, \"knots\": [[direction, weight], ...]}";
constexpr const char* kKnotsExpected = "expected an array of [direction, weight] knots";
constexpr const char* kShadowExpected = "expected {\"strength\": s, \"color\": [r, g, b]}";
}  // namespace

void SceneBuilder::fail(std::string place, std::string what) {
  if (failed_) return;
  failed_ = true;
  content_problem_ = {std::move(place), std::move(what)};
}

void SceneBuilder::check_key(const Frame& frame) {
  const std::string place = member_place(frame.place, frame.key);
  const std::string& k = frame.key;
  if (frame.role == Role::root) {
    if (k != "width" && k != "height" && k != "view" && k != "lights" && k != "occluders" && k != "ambient" &&
        k != "directional_lights" && k != "normal" && k != "normal_map" && k != "bounce")
      fail(place, "unknown key (expected width, height, view, lights, occluders, ambient, directional_lights, "
                  "normal, normal_map, bounce)");
  } else if (frame.role == Role::bounce) {
    if (k != "piece" && k != "step") fail(place, "unknown key (expected piece, step)");
  } else if (frame.role == Role::cookie) {
    if (k != "rotation" && k != "knots") fail(place, "unknown key (expected rotation, knots)");
  } else if (frame.role == Role::shadow) {
    if (k != "strength" && k != "color") fail(place, "unknown key (expected strength, color)");
  } else if (frame.role == Role::cone) {
    if (k != "direction" && k != "half_angle" && k != "fade")
      fail(place, "unknown key (expected direction, half_angle, fade)");
  } else if (frame.role == Role::element && element_.kind == ListKind::directionals) {
    if (k != "angles" && k != "color" && k != "intensity" && k != "mask" && k != "elevation")
      fail(place, "unknown key (expected angles, color, intensity, mask, elevation)");
  } else if (frame.role == Role::element) {
    const bool shape = k == "polygon" || k == "circle" || k == "segment";
    const bool holes = k == "holes";
    const bool light_term = k == "color" || k == "intensity" || k == "range" || k == "falloff" ||
                            k == "normalize" || k == "cone" || k == "cookie" || k == "mask" ||
                            k == "elevation" || k == "shadow";
    const bool occluder_term = k == "transmittance" || k == "mask" || k == "interior" || k == "albedo";
    if (!element_.light && (k == "color" || k == "intensity")) {
      fail(place, "occluders take no color or intensity");
    } else if (!shape && !holes && !(element_.light ? light_term : occluder_term)) {
      fail(place, element_.light
                      ? "unknown key (expected polygon, circle, segment, color, intensity, range, falloff, "
                        "normalize, cone, cookie, mask, elevation, shadow)"
                      : "unknown key (expected polygon, circle, segment, transmittance, mask, interior, albedo)");
    } else if (shape && element_.shape != nullptr) {
      // Named in a fixed order, whatever the order in the file.
      static constexpr const char* kShapes[] = {"polygon", "circle", "segment"};
      const char* first = nullptr;
      const char* second = nullptr;
      for (const char* name : kShapes) {
        if (name != k && std::strcmp(name, element_.shape) != 0) continue;
        (first == nullptr ? first : second) = name;
      }
      fail(frame.place, std::string("has both ") + first + " and " + second +
                            "; needs exactly one of polygon, circle, segment");
    } else if (shape) {
      element_.shape = k == "polygon" ? "polygon" : (k == "circle" ? "circle" : "segment");
    }
  } else if (frame.role == Role::circle) {
    if (k != "center" && k != "radius") fail(place, "unknown key (expected center, radius)");
  }
}

bool SceneBuilder::scalar(const Scalar& v) {
  const std::string place = next_place();
  if (frames_.empty()) {
    fail("", "expected a JSON object at the top level");
  } else if (!failed_) {
    Frame& frame = frames_.back();
    switch (frame.role) {
      case Role::root:
        if (frame.key == "width" || frame.key == "height") image_side(v, place, frame.key == "width");
        else if (frame.key == "view") fail("view", "expected [x0, y0, x1, y1]");
        else if (frame.key == "ambient") fail(place, "expected [r, g, b]");
        else if (frame.key == "normal") fail(place, "expected [nx, ny, nz]");
        else if (frame.key == "normal_map") normal_map_path(v, place);
        else if (frame.key == "bounce") fail(place, "expected {\"piece\": h, \"step\": n}");
        else fail(frame.key, "expected an array");
        break;
      case Role::view:
        if (!v.is_number() || frame.count >= 4) fail("view", "expected [x0, y0, x1, y1]");
        else view_[frame.count] = v.number;
        break;
      case Role::list: fail(place, "expected an object"); break;
      case Role::element: element_scalar(frame, v, place); break;
      case Role::polygon:
      case Role::ring: fail(place, "expected [x, y]"); break;
      case Role::holes: fail(place, "expected an array of [x, y] vertices"); break;
      case Role::point:
        if (!v.is_number() || frame.count >= 2) fail(frame.place, "expected [x, y]");
        else point_[frame.count] = v.number;
        break;
      case Role::circle:
        if (frame.key == "radius") {
          if (!v.is_number()) fail(place, "expected a number");
          element_.circle.radius = v.number;
          element_.has_radius = true;
        } else {
          fail(place, "expected [x, y]");
        }
        break;
      case Role::segment:
        if (frame.count >= 2) fail(frame.place, "expected [[x, y], [x, y]]");
        else fail(place, "expected [x, y]");
        break;
      case Role::numbers:
        if (!v.is_number() || frame.count >= frame.numbers.length) fail(frame.place, frame.numbers.expected);
        else frame.numbers.target[frame.count] = v.number;
        break;
      case Role::cone:
        if (!v.is_number()) {
          fail(place, "expected a number");
        } else if (frame.key == "direction") {
          element_.cone.direction = v.number;
          element_.has_direction = true;
        } else if (frame.key == "half_angle") {
          element_.cone.half_angle = v.number;
          element_.has_half_angle = true;
        } else {
          element_.cone.fade = v.number;
        }
        break;
      case Role::cookie:
        if (frame.key == "knots") fail(place, kKnotsExpected);
        else if (!v.is_number()) fail(place, "expected a number");
        else element_.cookie.rotation = v.number;
        break;
      case Role::shadow:
        if (frame.key == "color") fail(place, "expected [r, g, b]");
        else if (!v.is_number()) fail(place, "expected a number");
        else element_.value.shadow.strength = v.number;
        break;
      case Role::knots: fail(place, "expected [direction, weight]"); break;
      case Role::knot:
        if (!v.is_number() || frame.count >= 2) fail(frame.place, "expected [direction, weight]");
        else point_[frame.count] = v.number;
        break;
      case Role::bounce:
        if (!v.is_number()) fail(place, "expected a number");
        else if (frame.key == "piece") scene_.bounce.piece = v.number;
        else bounce_step(v, place);
        break;
      case Role::skip: break;
    }
  }
  if (!frames_.empty() && !frames_.back().object) ++frames_.back().count;
  return true;
}

void SceneBuilder::element_scalar(const Frame& frame, const Scalar& v, const std::string& place) {
  const std::string& k = frame.key;
  Element& e = element_;
  const bool directional = e.kind == ListKind::directionals;
  if (k == "intensity" || k == "range" || k == "falloff" || k == "normalize" || k == "elevation") {
    if (!v.is_number()) return fail(place, "expected a number");
    if (k == "intensity") (directional ? e.directional.intensity : e.value.intensity) = v.number;
    else if (k == "elevation") (directional ? e.directional.elevation : e.value.elevation) = v.number;
    else if (k == "falloff") e.value.falloff = v.number;
    else if (k == "normalize") e.value.normalize = v.number;
    else e.value.range = v.number;
  } else if (k == "mask") {
    mask_value(v, place, directional ? e.directional.mask : (e.light ? e.value.mask : e.occluder.mask));
  } else if (k == "interior") {
    if (v.kind != Scalar::kString) return fail(place, "expected \"dark\" or \"lit\"");
    if (*v.text == "dark") e.occluder.interior = Interior::dark;
    else if (*v.text == "lit") e.occluder.interior = Interior::lit;
    else fail(place, "must be \"dark\" or \"lit\", got " + Json(*v.text).dump(-1, ' ', true, Json::error_handler_t::replace));
  } else if (k == "color" || k == "transmittance" || k == "albedo") {
    fail(place, "expected [r, g, b]");
  } else if (k == "angles") {
    fail(place, "expected [a0, a1]");
  } else if (k == "cone") {
    fail(place, "expected {\"direction\": d, \"half_angle\": h, \"fade\": f}");
  } else if (k == "cookie") {
    fail(place, kCookieExpected);
  } else if (k == "shadow") {
    fail(place, kShadowExpected);
  } else if (k == "polygon") {
    fail(place, "expected an array of [x, y] vertices");
  } else if (k == "circle") {
    fail(place, "expected {\"center\": [x, y], \"radius\": r}");
  } else {
    fail(place, "expected [[x, y], [x, y]]");
  }
}

void SceneBuilder::normal_map_path(const Scalar& v, const std::string& place) {
  if (v.kind != Scalar::kString || v.text->empty()) return fail(place, "expected a PNG file path");
  if (v.text->find('\0') != std::string::npos) return fail(place, "the path contains a NUL character");
  NormalMap map;
  map.path = *v.text;
  scene_.normal_map = std::move(map);
}

SceneBuilder::Role SceneBuilder::container_role(bool object, const std::string& place) {
  if (frames_.empty()) {
    if (!object) fail("", "expected a JSON object at the top level");
    return object ? Role::root : Role::skip;
  }
  if (failed_) return Role::skip;
  Frame& frame = frames_.back();
  const std::string& k = frame.key;
  auto refuse = [&](std::string at, const char* what) {
    fail(std::move(at), what);
    return Role::skip;
  };
  switch (frame.role) {
    case Role::root:
      if (k == "width" || k == "height") return refuse(place, "expected an integer");
      if (k == "view") return object ? refuse("view", "expected [x0, y0, x1, y1]") : Role::view;
      if (k == "normal_map") return refuse(place, "expected a PNG file path");
      if (k == "bounce") return object ? Role::bounce : refuse(place, "expected {\"piece\": h, \"step\": n}");
      if (k == "ambient") return numbers(object, place, scene_.ambient.data(), 3, "expected [r, g, b]");
      if (k == "normal") {
        has_normal_ = true;
        return numbers(object, place, normal_, 3, "expected [nx, ny, nz]");
      }
      if (object) return refuse(k, "expected an array");
      list_kind_ = k == "lights" ? ListKind::lights : (k == "occluders" ? ListKind::occluders : ListKind::directionals);
      return Role::list;
    case Role::view: return refuse("view", "expected [x0, y0, x1, y1]");
    case Role::list:
      if (!object) return refuse(place, "expected an object");
      element_ = Element{};
      element_.kind = list_kind_;
      element_.light = list_kind_ == ListKind::lights;
      return Role::element;
    case Role::element:
      if (k == "polygon") return object ? refuse(place, "expected an array of [x, y] vertices") : Role::polygon;
      if (k == "holes") {
        if (object) return refuse(place, "expected an array of holes, each an array of [x, y] vertices");
        element_.has_holes = true;
        return Role::holes;
      }
      if (k == "circle") return object ? Role::circle : refuse(place, "expected {\"center\": [x, y], \"radius\": r}");
      if (k == "segment") return object ? refuse(place, "expected [[x, y], [x, y]]") : Role::segment;
      if (k == "color") {
        double* color = element_.kind == ListKind::directionals ? element_.directional.color.data()
                                                                : element_.value.color.data();
        return numbers(object, place, color, 3, "expected [r, g, b]");
      }
      if (k == "transmittance")
        return numbers(object, place, element_.occluder.transmittance.data(), 3, "expected [r, g, b]");
      if (k == "albedo") return numbers(object, place, element_.occluder.albedo.data(), 3, "expected [r, g, b]");
      if (k == "angles") {
        element_.has_angles = true;
        return numbers(object, place, element_.angles, 2, "expected [a0, a1]");
      }
      if (k == "cone") {
        if (!object) return refuse(place, "expected {\"direction\": d, \"half_angle\": h, \"fade\": f}");
        element_.cone = Cone{};
        return Role::cone;
      }
      if (k == "cookie") {
        if (!object) return refuse(place, kCookieExpected);
        element_.cookie = Cookie{};
        element_.has_knots = false;
        return Role::cookie;
      }
      if (k == "shadow") return object ? Role::shadow : refuse(place, kShadowExpected);
      if (k == "interior") return refuse(place, "expected \"dark\" or \"lit\"");
      if (k == "mask") return refuse(place, "expected an integer");
      return refuse(place, "expected a number");  // intensity, range, falloff, normalize, elevation
    case Role::segment:
      if (frame.count >= 2) return refuse(frame.place, "expected [[x, y], [x, y]]");
      return object ? refuse(place, "expected [x, y]") : Role::point;
    case Role::polygon:
    case Role::ring: return object ? refuse(place, "expected [x, y]") : Role::point;
    case Role::holes:
      if (object) return refuse(place, "expected an array of [x, y] vertices");
      element_.polygon.holes.push_back({});
      return Role::ring;
    case Role::circle:
      if (k == "center") return object ? refuse(place, "expected [x, y]") : Role::point;
      return refuse(place, "expected a number");  // radius
    case Role::point: return refuse(frame.place, "expected [x, y]");
    case Role::numbers: return refuse(frame.place, frame.numbers.expected);
    case Role::cookie:
      if (k != "knots") return refuse(place, "expected a number");
      if (object) return refuse(place, kKnotsExpected);
      element_.has_knots = true;
      return Role::knots;
    case Role::knots: return object ? refuse(place, "expected [direction, weight]") : Role::knot;
    case Role::knot: return refuse(frame.place, "expected [direction, weight]");
    case Role::shadow:
      if (k == "color") return numbers(object, place, element_.value.shadow.color.data(), 3, "expected [r, g, b]");
      return refuse(place, "expected a number");  // strength
    case Role::cone:
    case Role::bounce: return refuse(place, "expected a number");
    case Role::skip: return Role::skip;
  }
  return Role::skip;
}

SceneBuilder::Role SceneBuilder::numbers(bool object, const std::string& place, double* target, std::size_t length,
                                         const char* expected) {
  if (object) {
    fail(place, expected);
    return Role::skip;
  }
  pending_numbers_ = Numbers{target, length, expected};
  return Role::numbers;
}

void SceneBuilder::finish(const Frame& frame) {
  switch (frame.role) {
    case Role::view:
      if (frame.count != 4) return fail("view", "expected [x0, y0, x1, y1]");
      has_view_ = true;
      return;
    case Role::point: {
      if (frame.count != 2) return fail(frame.place, "expected [x, y]");
      const Vec2 p{point_[0], point_[1]};
      const Frame& parent = frames_.back();
      if (parent.role == Role::polygon) {
        element_.polygon.vertices.push_back(p);
      } else if (parent.role == Role::ring) {
        element_.polygon.holes[element_.polygon.holes.size() - 1].push_back(p);
      } else if (parent.role == Role::circle) {
        element_.circle.center = p;
        element_.has_center = true;
      } else {
        (parent.count == 0 ? element_.segment.a : element_.segment.b) = p;
      }
      return;
    }
    case Role::segment:
      if (frame.count != 2) return fail(frame.place, "expected [[x, y], [x, y]]");
      return;
    case Role::numbers:
      if (frame.count != frame.numbers.length) return fail(frame.place, frame.numbers.expected);
      return;
    case Role::knot:
      if (frame.count != 2) return fail(frame.place, "expected [direction, weight]");
      // More than the limit is refused when the light is validated; stop storing well past it.
      if (element_.cookie.knots.size() <= static_cast<std::size_t>(kMaxCookieKnots))
        element_.cookie.knots.push_back(CookieKnot{point_[0], point_[1]});
      else
        element_.cookie.knots.back() = CookieKnot{point_[0], point_[1]};
      return;
    case Role::cookie:
      if (!element_.has_knots) return fail(member_place(frame.place, "knots"), "missing (required)");
      element_.value.cookie = element_.cookie;
      return;
    case Role::cone:
      if (!element_.has_direction) return fail(member_place(frame.place, "direction"), "missing (required)");
      if (!element_.has_half_angle) return fail(member_place(frame.place, "half_angle"), "missing (required)");
      element_.value.cone = element_.cone;
      return;
    case Role::circle:
      if (!element_.has_center) return fail(member_place(frame.place, "center"), "missing (required)");
      if (!element_.has_radius) return fail(member_place(frame.place, "radius"), "missing (required)");
      return;
    case Role::element: return finish_element(frame.place);
    case Role::root: return finish_root();
    case Role::list:
      if (list_kind_ == ListKind::lights) {
        if (auto problem = detail::check_emission_total(scene_.lights)) fail(problem->place, problem->what);
      }
      return;
    case Role::polygon:
    case Role::holes:
    case Role::ring:
    case Role::knots:
    case Role::shadow:
    case Role::bounce:
    case Role::skip: return;
  }
}

void SceneBuilder::finish_element(const std::string& place) {
  Element& e = element_;
  if (e.kind == ListKind::directionals) {
    if (!e.has_angles) return fail(member_place(place, "angles"), "missing (required)");
    e.directional.angle0 = e.angles[0];
    e.directional.angle1 = e.angles[1];
    if (auto problem = detail::check_directional(e.directional, place)) return fail(problem->place, problem->what);
    scene_.directional_lights.push_back(e.directional);
    return;
  }
  if (e.shape == nullptr) return fail(place, "needs one of polygon, circle, segment");
  if (e.has_holes && e.shape[0] != 'p') return fail(member_place(place, "holes"), "only a polygon has holes");
  Shape shape;
  if (e.shape[0] == 'p') shape = std::move(e.polygon);
  else if (e.shape[0] == 'c') shape = e.circle;
  else shape = e.segment;
  if (e.light) {
    e.value.shape = std::move(shape);
    if (auto problem = detail::check_light(e.value, place)) return fail(problem->place, problem->what);
    scene_.lights.push_back(std::move(e.value));
  } else {
    Occluder occluder = std::move(e.occluder);
    occluder.shape = std::move(shape);
    if (auto problem = detail::check_occluder(occluder, place)) return fail(problem->place, problem->what);
    // Shapes alone (40 bytes) until the end: an Occluder is 72, and a level is mostly
    // plain occluders; the few with other terms are kept aside with their index.
    const Occluder plain;
    if (occluder.transmittance != plain.transmittance || occluder.mask != plain.mask ||
        occluder.interior != plain.interior || occluder.albedo != plain.albedo) {
      Occluder terms;
      terms.transmittance = occluder.transmittance;
      terms.mask = occluder.mask;
      terms.interior = occluder.interior;
      terms.albedo = occluder.albedo;
      // A reflecting occluder's shape is kept with its terms too, for the piece count.
      if (occluder.albedo != plain.albedo) terms.shape = occluder.shape;
      occluder_terms_.emplace_back(occluder_kinds_.size(), std::move(terms));
    }
    if (auto* p = std::get_if<Polygon>(&occluder.shape)) {
      occluder_kinds_.push_back(0);
      occluder_polygons_.push_back(std::move(*p));
    } else if (auto* c = std::get_if<Circle>(&occluder.shape)) {
      occluder_kinds_.push_back(1);
      occluder_circles_.push_back(*c);
    } else {
      occluder_kinds_.push_back(2);
      occluder_segments_.push_back(std::get<Segment>(occluder.shape));
    }
  }
}

void SceneBuilder::finish_root() {
  if (!has_width_) return fail("width", "missing (required)");
  if (!has_height_) return fail("height", "missing (required)");
  scene_.view = has_view_ ? View{view_[0], view_[1], view_[2], view_[3]}
                          : View{0.0, 0.0, static_cast<double>(scene_.width), static_cast<double>(scene_.height)};
  if (auto problem = detail::check_view(scene_.view, scene_.width, scene_.height)) return fail(problem->place, problem->what);
  if (auto problem = detail::check_ambient(scene_.ambient)) return fail(problem->place, problem->what);
  if (has_normal_) {
    scene_.normal = Vec3{normal_[0], normal_[1], normal_[2]};
    if (auto problem = detail::check_normal(*scene_.normal)) return fail(problem->place, problem->what);
  }
  if (scene_.normal && scene_.normal_map) {
    return fail("normal_map", "the scene has both normal and normal_map (at most one normal source)");
  }
  if (auto problem = detail::check_bounce(scene_.bounce)) return fail(problem->place, problem->what);
  // The reflecting occluders are among those kept aside with their terms.
  double pieces = 0.0;
  for (const auto& entry : occluder_terms_) {
    const Occluder& terms = entry.second;
    if (terms.albedo == Rgb{0.0, 0.0, 0.0}) continue;
    pieces += bounce_piece_count(terms.shape, scene_.bounce.piece, kMaxBouncePieces);
    if (pieces > kMaxBouncePieces) return fail("bounce.piece", bounce_pieces_text(pieces));
  }
}

void SceneBuilder::build_occluders() {
  std::vector<Occluder>& out = scene_.occluders;
  out.clear();
  out.reserve(occluder_kinds_.size());
  std::size_t next_terms = 0;
  while (!occluder_kinds_.empty()) {
    Occluder occluder;
    if (next_terms < occluder_terms_.size() && occluder_terms_[next_terms].first == out.size()) {
      occluder = std::move(occluder_terms_[next_terms].second);
      ++next_terms;
    }
    const std::uint8_t kind = occluder_kinds_.front();
    occluder_kinds_.pop_front();
    if (kind == 0) {
      occluder.shape = std::move(occluder_polygons_.front());
      occluder_polygons_.pop_front();
    } else if (kind == 1) {
      occluder.shape = occluder_circles_.front();
      occluder_circles_.pop_front();
    } else {
      occluder.shape = occluder_segments_.front();
      occluder_segments_.pop_front();
    }
    out.push_back(std::move(occluder));
  }
  occluder_terms_.clear();
}

}  // namespace par2d::detail
