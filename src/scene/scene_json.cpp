// JSON scene loading (docs/contract.md section 3): strict schema, duplicate keys refused, every problem placed.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <new>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "par2d/scene.hpp"
#include "io/input_file.hpp"
#include "scene/scene_validate.hpp"

namespace par2d {
namespace {

using Json = nlohmann::json;

// A valid scene nests five deep (top, lights, light, circle, center); far deeper input is
// garbage, and refusing it early keeps the document we build small.
constexpr std::size_t kMaxDepth = 64;
constexpr std::size_t kReportedDepth = 6;
// Reading stops here so that a device file or a runaway file cannot eat all memory.
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;

bool is_identifier(const std::string& key) {
  if (key.empty()) return false;
  for (char ch : key) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_';
    if (!ok) return false;
  }
  return true;
}

// nlohmann quotes the bytes it choked on, which may be broken UTF-8 or control characters.
std::string printable(const std::string& text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte >= 0x20 && byte < 0x7F) {
      out += ch;
    } else {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

// Keys are user text: quote anything unusual, escaped, so a message stays on one line.
std::string member_place(const std::string& parent, const std::string& key) {
  if (is_identifier(key)) return parent.empty() ? key : parent + "." + key;
  return parent + "[" + Json(key).dump(-1, ' ', true, Json::error_handler_t::replace) + "]";
}

std::string element_place(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

// Builds the Scene straight from the parser's events (no JSON document: memory stays a
// small multiple of the file, since a vertex costs 16 bytes against at least 6 of text).
// A problem with the scene's content is remembered and the rest of the text is still
// parsed, without building anything, so that syntax errors, duplicate keys and absurd
// nesting anywhere in the file are reported first, as a parser that built the whole
// document would; among content problems the first in the file is reported.
class SceneBuilder {
 public:
  bool null() { return scalar(Scalar{Scalar::kOther}); }
  bool boolean(bool /*value*/) { return scalar(Scalar{Scalar::kOther}); }
  bool number_integer(Json::number_integer_t value) {
    Scalar v{Scalar::kInteger};
    v.integer = value;
    v.number = static_cast<double>(value);
    return scalar(v);
  }
  bool number_unsigned(Json::number_unsigned_t value) {
    Scalar v{Scalar::kUnsigned};
    v.unsigned_integer = value;
    v.number = static_cast<double>(value);
    return scalar(v);
  }
  bool number_float(Json::number_float_t value, const Json::string_t& /*text*/) {
    Scalar v{Scalar::kFloat};
    v.number = value;
    return scalar(v);
  }
  bool string(Json::string_t& value) {
    Scalar v{Scalar::kString};
    v.text = &value;
    return scalar(v);
  }
  bool binary(Json::binary_t& /*value*/) { return scalar(Scalar{Scalar::kOther}); }

  bool start_object(std::size_t /*size*/) { return open(true); }
  bool start_array(std::size_t /*size*/) { return open(false); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& name) {
    Frame& frame = frames_.back();
    if (!frame.keys.insert(name).second) {
      problem_ = {member_place(frame.place, name), "duplicate key"};
      return false;
    }
    frame.key = std::move(name);
    if (!failed_) check_key(frame);
    return true;
  }

  bool parse_error(std::size_t /*byte*/, const std::string& token, const nlohmann::detail::exception& error) {
    if (error.id == 406) {  // a number too large for a double (1e400)
      // The token is user text of any length (a megabyte of digits): echo its start only.
      constexpr std::size_t kEcho = 32;
      const std::string shown = token.size() <= kEcho + 8
                                    ? token
                                    : token.substr(0, kEcho) + "... (" + std::to_string(token.size()) + " characters)";
      problem_ = {next_place(), "number out of range (" + printable(shown) + ")"};
      return false;
    }
    // nlohmann's text already says "parse error at line L, column C: ..."; drop its id prefix.
    std::string what = error.what();
    const std::size_t prefix_end = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && prefix_end != std::string::npos) what.erase(0, prefix_end + 2);
    problem_ = {"", printable(what)};
    return false;
  }

  // After sax_parse returned false: the syntax (or nesting, duplicate) problem.
  const detail::SceneProblem& problem() const { return problem_; }
  // After sax_parse returned true: the first content problem, if any.
  bool failed() const { return failed_; }
  const detail::SceneProblem& content_problem() const { return content_problem_; }
  Scene& scene() { return scene_; }

 private:
  // What a container holds, which decides what its values mean.
  // `numbers`: a fixed-length array of numbers (a color, a normal, angles) stored at `target`.
  enum class Role { root, skip, view, list, element, polygon, point, circle, segment, numbers, cone };
  enum class ListKind { lights, occluders, directionals };

  // Where a `numbers` array goes and what it must look like.
  struct Numbers {
    double* target = nullptr;
    std::size_t length = 0;
    const char* expected = "";
  };

  struct Frame {
    Role role;
    bool object;
    std::string place;
    std::size_t count = 0;  // arrays: values so far
    std::string key;        // objects: the current key
    std::unordered_set<std::string> keys;
    Numbers numbers;
  };

  struct Scalar {
    enum Kind { kOther, kString, kInteger, kUnsigned, kFloat } kind;
    std::int64_t integer = 0;
    std::uint64_t unsigned_integer = 0;
    double number = 0.0;
    const std::string* text = nullptr;  // kString
    bool is_number() const { return kind == kInteger || kind == kUnsigned || kind == kFloat; }
    std::string dump() const {
      if (kind == kInteger) return Json(integer).dump();
      if (kind == kUnsigned) return Json(unsigned_integer).dump();
      return Json(number).dump();
    }
  };

  // The light, occluder or directional light being read.
  struct Element {
    ListKind kind = ListKind::lights;
    bool light = true;  // kind == lights
    const char* shape = nullptr;  // "polygon", "circle" or "segment" once seen
    Light value;
    Occluder occluder;            // its terms (the shape is kept in `shape`'s member below)
    DirectionalLight directional;
    double angles[2] = {0, 0};
    bool has_angles = false;
    Cone cone;
    bool has_direction = false, has_half_angle = false;
    Polygon polygon;
    Circle circle;
    bool has_center = false, has_radius = false;
    Segment segment;
  };

  void fail(std::string place, std::string what) {
    if (failed_) return;
    failed_ = true;
    content_problem_ = {std::move(place), std::move(what)};
  }

  std::string next_place() const {
    if (frames_.empty()) return "";
    const Frame& frame = frames_.back();
    if (frame.object) return member_place(frame.place, frame.key);
    return element_place(frame.place, frame.count);
  }

  void check_key(const Frame& frame) {
    const std::string place = member_place(frame.place, frame.key);
    const std::string& k = frame.key;
    if (frame.role == Role::root) {
      if (k != "width" && k != "height" && k != "view" && k != "lights" && k != "occluders" && k != "ambient" &&
          k != "directional_lights" && k != "normal" && k != "normal_map")
        fail(place, "unknown key (expected width, height, view, lights, occluders, ambient, directional_lights, "
                    "normal, normal_map)");
    } else if (frame.role == Role::cone) {
      if (k != "direction" && k != "half_angle" && k != "fade")
        fail(place, "unknown key (expected direction, half_angle, fade)");
    } else if (frame.role == Role::element && element_.kind == ListKind::directionals) {
      if (k != "angles" && k != "color" && k != "intensity" && k != "mask" && k != "elevation")
        fail(place, "unknown key (expected angles, color, intensity, mask, elevation)");
    } else if (frame.role == Role::element) {
      const bool shape = k == "polygon" || k == "circle" || k == "segment";
      const bool light_term = k == "color" || k == "intensity" || k == "range" || k == "cone" || k == "mask" ||
                              k == "elevation";
      const bool occluder_term = k == "transmittance" || k == "mask" || k == "interior";
      if (!element_.light && (k == "color" || k == "intensity")) {
        fail(place, "occluders take no color or intensity");
      } else if (!shape && !(element_.light ? light_term : occluder_term)) {
        fail(place, element_.light
                        ? "unknown key (expected polygon, circle, segment, color, intensity, range, cone, mask, "
                          "elevation)"
                        : "unknown key (expected polygon, circle, segment, transmittance, mask, interior)");
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

  // A number or other non-container value in the current frame.
  bool scalar(const Scalar& v) {
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
          else fail(frame.key, "expected an array");
          break;
        case Role::view:
          if (!v.is_number() || frame.count >= 4) fail("view", "expected [x0, y0, x1, y1]");
          else view_[frame.count] = v.number;
          break;
        case Role::list: fail(place, "expected an object"); break;
        case Role::element: element_scalar(frame, v, place); break;
        case Role::polygon: fail(place, "expected [x, y]"); break;
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
        case Role::skip: break;
      }
    }
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().count;
    return true;
  }

  // Integer-valued numbers only (64 or 64.0), range-checked before any cast so 1e30 or
  // 2^63 cannot overflow an int.
  void image_side(const Scalar& v, const std::string& place, bool width) {
    bool in_range = false;
    if (v.kind == Scalar::kUnsigned) {
      in_range = v.unsigned_integer >= 1 && v.unsigned_integer <= static_cast<std::uint64_t>(kMaxImageSide);
    } else if (v.kind == Scalar::kInteger) {
      in_range = v.integer >= 1 && v.integer <= kMaxImageSide;
    } else if (v.kind == Scalar::kFloat) {
      if (std::floor(v.number) != v.number) return fail(place, "expected an integer, got " + v.dump());
      in_range = v.number >= 1.0 && v.number <= static_cast<double>(kMaxImageSide);
    } else {
      return fail(place, "expected an integer");
    }
    if (!in_range) return fail(place, detail::image_side_range_text() + ", got " + v.dump());
    (width ? scene_.width : scene_.height) = static_cast<int>(v.number);
    (width ? has_width_ : has_height_) = true;
  }

  // A 32-bit mask: integer-valued numbers only (5 or 5.0), range-checked before any cast.
  void mask_value(const Scalar& v, const std::string& place, std::uint32_t& out) {
    constexpr double kLargest = 4294967295.0;
    bool in_range = false;
    if (v.kind == Scalar::kUnsigned) {
      in_range = v.unsigned_integer <= 0xFFFFFFFFull;
    } else if (v.kind == Scalar::kInteger) {
      in_range = v.integer >= 0 && v.integer <= 0xFFFFFFFFll;
    } else if (v.kind == Scalar::kFloat) {
      in_range = std::floor(v.number) == v.number && v.number >= 0.0 && v.number <= kLargest;
    } else {
      return fail(place, "expected an integer");
    }
    if (!in_range) return fail(place, "must be an integer from 0 to 4294967295, got " + v.dump());
    out = static_cast<std::uint32_t>(v.number);
  }

  void normal_map_path(const Scalar& v, const std::string& place) {
    if (v.kind != Scalar::kString || v.text->empty()) return fail(place, "expected a PNG file path");
    if (v.text->find('\0') != std::string::npos) return fail(place, "the path contains a NUL character");
    NormalMap map;
    map.path = *v.text;
    scene_.normal_map = std::move(map);
  }

  void element_scalar(const Frame& frame, const Scalar& v, const std::string& place) {
    const std::string& k = frame.key;
    Element& e = element_;
    const bool directional = e.kind == ListKind::directionals;
    if (k == "intensity" || k == "range" || k == "elevation") {
      if (!v.is_number()) return fail(place, "expected a number");
      if (k == "intensity") (directional ? e.directional.intensity : e.value.intensity) = v.number;
      else if (k == "elevation") (directional ? e.directional.elevation : e.value.elevation) = v.number;
      else e.value.range = v.number;
    } else if (k == "mask") {
      mask_value(v, place, directional ? e.directional.mask : (e.light ? e.value.mask : e.occluder.mask));
    } else if (k == "interior") {
      if (v.kind != Scalar::kString) return fail(place, "expected \"dark\" or \"lit\"");
      if (*v.text == "dark") e.occluder.interior = Interior::dark;
      else if (*v.text == "lit") e.occluder.interior = Interior::lit;
      else fail(place, "must be \"dark\" or \"lit\", got " + Json(*v.text).dump(-1, ' ', true, Json::error_handler_t::replace));
    } else if (k == "color" || k == "transmittance") {
      fail(place, "expected [r, g, b]");
    } else if (k == "angles") {
      fail(place, "expected [a0, a1]");
    } else if (k == "cone") {
      fail(place, "expected {\"direction\": d, \"half_angle\": h, \"fade\": f}");
    } else if (k == "polygon") {
      fail(place, "expected an array of [x, y] vertices");
    } else if (k == "circle") {
      fail(place, "expected {\"center\": [x, y], \"radius\": r}");
    } else {
      fail(place, "expected [[x, y], [x, y]]");
    }
  }

  // The role of a container opening at `place` in the current frame; fails for one that
  // does not belong there.
  Role container_role(bool object, const std::string& place) {
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
        if (k == "circle") return object ? Role::circle : refuse(place, "expected {\"center\": [x, y], \"radius\": r}");
        if (k == "segment") return object ? refuse(place, "expected [[x, y], [x, y]]") : Role::segment;
        if (k == "color") {
          double* color = element_.kind == ListKind::directionals ? element_.directional.color.data()
                                                                  : element_.value.color.data();
          return numbers(object, place, color, 3, "expected [r, g, b]");
        }
        if (k == "transmittance")
          return numbers(object, place, element_.occluder.transmittance.data(), 3, "expected [r, g, b]");
        if (k == "angles") {
          element_.has_angles = true;
          return numbers(object, place, element_.angles, 2, "expected [a0, a1]");
        }
        if (k == "cone") {
          if (!object) return refuse(place, "expected {\"direction\": d, \"half_angle\": h, \"fade\": f}");
          element_.cone = Cone{};
          return Role::cone;
        }
        if (k == "interior") return refuse(place, "expected \"dark\" or \"lit\"");
        if (k == "mask") return refuse(place, "expected an integer");
        return refuse(place, "expected a number");  // intensity, range, elevation
      case Role::segment:
        if (frame.count >= 2) return refuse(frame.place, "expected [[x, y], [x, y]]");
        return object ? refuse(place, "expected [x, y]") : Role::point;
      case Role::polygon: return object ? refuse(place, "expected [x, y]") : Role::point;
      case Role::circle:
        if (k == "center") return object ? refuse(place, "expected [x, y]") : Role::point;
        return refuse(place, "expected a number");  // radius
      case Role::point: return refuse(frame.place, "expected [x, y]");
      case Role::numbers: return refuse(frame.place, frame.numbers.expected);
      case Role::cone: return refuse(place, "expected a number");
      case Role::skip: return Role::skip;
    }
    return Role::skip;
  }

  // A fixed-length number array opening (an object there is refused).
  Role numbers(bool object, const std::string& place, double* target, std::size_t length, const char* expected) {
    if (object) {
      fail(place, expected);
      return Role::skip;
    }
    pending_numbers_ = Numbers{target, length, expected};
    return Role::numbers;
  }

  bool open(bool object) {
    if (frames_.size() >= kMaxDepth) {
      // Name where the nesting went wrong, not the whole 64-level path.
      problem_ = {frames_[kReportedDepth].place, "nested too deeply (more than " + std::to_string(kMaxDepth) + " levels)"};
      return false;
    }
    std::string place = next_place();
    pending_numbers_ = Numbers{};
    const Role role = container_role(object, place);
    frames_.push_back(Frame{role, object, std::move(place), 0, {}, {}, pending_numbers_});
    return true;
  }

  bool close() {
    Frame frame = std::move(frames_.back());
    frames_.pop_back();
    if (!failed_) finish(frame);
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().count;
    return true;
  }

  // A container ended: check what needs all of it, and hand its value to its parent.
  void finish(const Frame& frame) {
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
      case Role::skip: return;
    }
  }

  void finish_element(const std::string& place) {
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
          occluder.interior != plain.interior) {
        Occluder terms;
        terms.transmittance = occluder.transmittance;
        terms.mask = occluder.mask;
        terms.interior = occluder.interior;
        occluder_terms_.emplace_back(occluder_shapes_.size(), std::move(terms));
      }
      occluder_shapes_.push_back(std::move(occluder.shape));
    }
  }

 public:
  // After a successful parse: scene().occluders from the compact store, reserved exactly and
  // filled while the store is freed block by block, so the peak is about 40 + 72 bytes per
  // occluder instead of a growing vector's 3 x 72.
  void build_occluders() {
    std::vector<Occluder>& out = scene_.occluders;
    out.clear();
    out.reserve(occluder_shapes_.size());
    std::size_t next_terms = 0;
    while (!occluder_shapes_.empty()) {
      Occluder occluder;
      if (next_terms < occluder_terms_.size() && occluder_terms_[next_terms].first == out.size()) {
        occluder = std::move(occluder_terms_[next_terms].second);
        ++next_terms;
      }
      occluder.shape = std::move(occluder_shapes_.front());
      occluder_shapes_.pop_front();
      out.push_back(std::move(occluder));
    }
    occluder_terms_.clear();
  }

 private:

  void finish_root() {
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
  }

  std::vector<Frame> frames_;
  detail::SceneProblem problem_;
  detail::SceneProblem content_problem_;
  bool failed_ = false;
  Scene scene_;
  bool has_width_ = false, has_height_ = false, has_view_ = false;
  double view_[4] = {0, 0, 0, 0};
  ListKind list_kind_ = ListKind::lights;
  Numbers pending_numbers_;
  bool has_normal_ = false;
  double normal_[3] = {0, 0, 0};
  std::deque<Shape> occluder_shapes_;
  std::vector<std::pair<std::size_t, Occluder>> occluder_terms_;  // (index, terms) of non-plain occluders
  Element element_;
  double point_[2] = {0, 0};
};

Status out_of_memory(std::string_view name) {
  try {
    return Status(StatusCode::out_of_memory, std::string(name) + ": out of memory while loading the scene");
  } catch (...) {
    return Status(StatusCode::out_of_memory, std::string());
  }
}


// Why `resolved` (the normal map's file) is not inside the folder of the scene `name` once
// symbolic links are followed, or "" when it is (weakly_canonical: links in the part that
// exists, the rest lexically, so "a/../../x" and a link out of the folder both leave it).
std::string outside_scene_folder(std::string_view name, const std::string& resolved) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::path folder = fs::path(std::string(name)).parent_path();
  if (folder.empty()) folder = ".";
  const fs::path base = fs::weakly_canonical(fs::absolute(folder, error), error);
  if (error) return "cannot resolve the scene's folder: " + error.message();
  const fs::path target = fs::weakly_canonical(fs::absolute(resolved, error), error);
  if (error) return "cannot resolve the path: " + error.message();
  auto t = target.begin();
  for (const fs::path& part : base) {
    if (part.empty()) continue;  // a trailing separator
    if (t == target.end() || part != *t) return "path leaves the scene's folder";
    ++t;
  }
  if (t == target.end()) return "path leaves the scene's folder";  // the folder itself
  return {};
}

// The scene's normal_map: `map.path` as written in the scene, resolved against the directory
// of the scene file `name`; kept as written so that the scene writes back the same text. Its
// size is checked from the PNG header before any pixel is decoded.
Status load_scene_normal_map(std::string_view name, NormalMap& map, int width, int height, const LoadOptions& options) {
  const std::string prefix = std::string(name) + ": normal_map: ";
  if (!options.allow_any_path && std::filesystem::path(map.path).is_absolute())
    return Status(StatusCode::invalid_scene, prefix + "path is absolute; it must be relative to the scene's folder");
  const std::string resolved = scene_relative_path(name, map.path);
  if (!options.allow_any_path) {
    if (const std::string problem = outside_scene_folder(name, resolved); !problem.empty())
      return Status(StatusCode::invalid_scene, prefix + problem);
  }
  NormalMap loaded;
  if (Status status = load_normal_map_png(resolved, loaded, width, height); !status) {
    return Status(status.code(), prefix + status.message());
  }
  loaded.path = map.path;
  map = std::move(loaded);
  return Status::success();
}

// Runs the builder: `run(builder)` calls Json::sax_parse on some input (text, a file).
template <class Run>
Status parse_with(Run&& run, std::string_view name, Scene& out, const LoadOptions& options) {
  SceneBuilder builder;
  if (!run(builder)) return detail::scene_error(name, builder.problem());
  if (builder.failed()) return detail::scene_error(name, builder.content_problem());
  builder.build_occluders();
  Scene& scene = builder.scene();
  if (scene.normal_map) {
    if (Status status = load_scene_normal_map(name, *scene.normal_map, scene.width, scene.height, options); !status)
      return status;
  }
  if (auto problem = detail::check_scene_terms(scene)) return detail::scene_error(name, *problem);
  out = std::move(scene);
  return Status::success();
}

// The scene's bytes for the parser, one at a time, stopping at the first NUL byte: the
// parser would take a NUL for the end of the input and accept any garbage after it. The
// position of a NUL is kept for the message.
template <class Source>
class ByteReader {
 public:
  explicit ByteReader(Source source) : source_(std::move(source)) {}

  // An input iterator over the bytes; a default-constructed one is the end.
  class Iterator {
   public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;
    Iterator() = default;
    explicit Iterator(ByteReader* reader) : reader_(reader) { reader_->advance(); }
    const char& operator*() const { return reader_->current_; }
    Iterator& operator++() {
      reader_->advance();
      return *this;
    }
    bool operator==(const Iterator& other) const { return done() == other.done(); }
    bool operator!=(const Iterator& other) const { return !(*this == other); }

   private:
    bool done() const { return reader_ == nullptr || reader_->done_; }
    ByteReader* reader_ = nullptr;
  };

  Iterator begin() { return Iterator(this); }
  Iterator end() { return Iterator(); }
  bool saw_nul() const { return saw_nul_; }
  // "NUL byte at offset N (line L)": where the first NUL is.
  std::string nul_place() const {
    return "NUL byte at offset " + std::to_string(offset_) + " (line " + std::to_string(line_) +
           "); a scene is JSON text only";
  }

 private:
  void advance() {
    if (done_) return;
    if (started_) {
      ++offset_;
      if (current_ == '\n') ++line_;
    }
    started_ = true;
    const int byte = source_();
    if (byte < 0 || byte == 0) {
      done_ = true;
      saw_nul_ = byte == 0;
      return;
    }
    current_ = static_cast<char>(byte);
  }

  Source source_;
  char current_ = 0;
  bool started_ = false;
  bool done_ = false;
  bool saw_nul_ = false;
  std::size_t offset_ = 0;
  std::size_t line_ = 1;
};

template <class Source>
ByteReader<Source> make_reader(Source source) {
  return ByteReader<Source>(std::move(source));
}

// Parses through `reader`; a NUL byte reached is the problem, whatever the parser made of it.
template <class Reader>
Status parse_bytes(Reader& reader, std::string_view name, Scene& out, const LoadOptions& options) {
  bool saw_nul = false;
  Status status = parse_with(
      [&](SceneBuilder& b) {
        const bool parsed = Json::sax_parse(reader.begin(), reader.end(), &b);
        saw_nul = reader.saw_nul();
        return parsed && !saw_nul;
      },
      name, out, options);
  if (saw_nul) return Status(StatusCode::invalid_scene, std::string(name) + ": " + reader.nul_place());
  return status;
}

}  // namespace

std::string scene_relative_path(std::string_view scene_name, const std::string& written) {
  const std::filesystem::path path(written);
  if (path.is_absolute()) return written;
  return (std::filesystem::path(std::string(scene_name)).parent_path() / path).string();
}

Status parse_scene(std::string_view json_text, std::string_view name, Scene& out) {
  return parse_scene(json_text, name, out, LoadOptions{});
}

Status parse_scene(std::string_view json_text, std::string_view name, Scene& out, const LoadOptions& options) {
  try {
    std::size_t next = 0;
    auto reader = make_reader([&]() -> int {
      return next < json_text.size() ? static_cast<unsigned char>(json_text[next++]) : -1;
    });
    return parse_bytes(reader, name, out, options);
  } catch (const std::bad_alloc&) {
    return out_of_memory(name);
  } catch (const std::exception& error) {
    // Not expected (every type is checked before use); still a status, never a crash.
    return Status(StatusCode::invalid_scene, std::string(name) + ": " + error.what());
  } catch (...) {
    return Status(StatusCode::invalid_scene, std::string(name) + ": unexpected error while loading the scene");
  }
}

Status load_scene_file(const std::string& path, Scene& out) { return load_scene_file(path, out, LoadOptions{}); }

Status load_scene_file(const std::string& path, Scene& out, const LoadOptions& options) {
  try {
    // Only regular files are read; their size is known, and nothing else is a scene.
    detail::FileHandle file(nullptr, &std::fclose);
    struct stat st {};
    if (Status s = detail::open_regular_file(path, file, st); !s.ok()) return s;
    if (static_cast<unsigned long long>(st.st_size) > kMaxFileBytes) {
      return Status(StatusCode::io_error, path + ": cannot read: larger than " +
                                              std::to_string(kMaxFileBytes >> 20) + " MiB");
    }
    // Parsed as it is read: no copy of the text is kept.
    std::FILE* const stream = file.get();
    auto reader = make_reader([stream]() -> int { return std::getc(stream); });
    Status status = parse_bytes(reader, path, out, options);
    if (std::ferror(stream)) {
      return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(errno ? errno : EIO));
    }
    return status;
  } catch (const std::bad_alloc&) {
    return out_of_memory(path);
  } catch (...) {
    return Status(StatusCode::io_error, path + ": unexpected error while reading the file");
  }
}

}  // namespace par2d
