// JSON scene loading (SPEC.md section 3): strict schema, duplicate keys refused, every problem placed.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "par2d/scene.hpp"
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

// Thrown only inside this file and caught at the API boundary.
struct SceneError {
  detail::SceneProblem problem;
};

[[noreturn]] void fail(std::string place, std::string what) {
  throw SceneError{{std::move(place), std::move(what)}};
}

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

// Builds the document like nlohmann's own DOM parser, but refuses a key its object already
// holds (nlohmann would keep the last silently) and knows, at any error, where it is.
class DocumentBuilder {
 public:
  explicit DocumentBuilder(Json& root) : root_(root) {}

  bool null() { return add(Json(nullptr)); }
  bool boolean(bool value) { return add(Json(value)); }
  bool number_integer(Json::number_integer_t value) { return add(Json(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return add(Json(value)); }
  bool number_float(Json::number_float_t value, const Json::string_t& /*text*/) { return add(Json(value)); }
  bool string(Json::string_t& value) { return add(Json(std::move(value))); }
  bool binary(Json::binary_t& value) { return add(Json(Json::binary_t(std::move(value)))); }

  bool start_object(std::size_t /*size*/) { return open(Json::object()); }
  bool start_array(std::size_t /*size*/) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& name) {
    Frame& frame = frames_.back();
    if (frame.value->contains(name)) {
      problem_ = {member_place(frame.place, name), "duplicate key"};
      return false;
    }
    key_ = std::move(name);
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

  const detail::SceneProblem& problem() const { return problem_; }

 private:
  struct Frame {
    Json* value;
    std::string place;
  };

  // Where the next value goes: after a key in an object, or at the end of an array.
  std::string next_place() const {
    if (frames_.empty()) return "";
    const Frame& frame = frames_.back();
    if (frame.value->is_object()) return member_place(frame.place, key_);
    return element_place(frame.place, frame.value->size());
  }

  Json* add_slot(Json&& value) {
    if (frames_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Json& parent = *frames_.back().value;
    if (parent.is_object()) return &(parent[key_] = std::move(value));
    parent.push_back(std::move(value));
    return &parent.back();
  }

  bool add(Json&& value) {
    add_slot(std::move(value));
    return true;
  }

  bool open(Json&& container) {
    if (frames_.size() >= kMaxDepth) {
      // Name where the nesting went wrong, not the whole 64-level path.
      problem_ = {frames_[kReportedDepth].place, "nested too deeply (more than " + std::to_string(kMaxDepth) + " levels)"};
      return false;
    }
    std::string place = next_place();
    Json* slot = add_slot(std::move(container));
    frames_.push_back({slot, std::move(place)});
    return true;
  }

  bool close() {
    frames_.pop_back();
    return true;
  }

  Json& root_;
  std::vector<Frame> frames_;
  std::string key_;
  detail::SceneProblem problem_;
};

const Json* find(const Json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

void check_keys(const Json& object, const std::string& place, std::initializer_list<const char*> allowed) {
  for (const auto& item : object.items()) {
    bool known = false;
    for (const char* name : allowed) known = known || item.key() == name;
    if (known) continue;
    std::string list;
    for (const char* name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
    fail(member_place(place, item.key()), "unknown key (expected " + list + ")");
  }
}

const Json& require(const Json& object, const std::string& place, const char* key) {
  const Json* value = find(object, key);
  if (value == nullptr) fail(member_place(place, key), "missing (required)");
  return *value;
}

double read_number(const Json& value, const std::string& place) {
  if (!value.is_number()) fail(place, "expected a number");
  return value.get<double>();
}

// Integer-valued numbers only (64 or 64.0), range-checked before any cast so 1e30 or
// 2^63 cannot overflow an int.
int read_image_side(const Json& value, const std::string& place) {
  bool in_range = false;
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    in_range = v >= 1 && v <= static_cast<std::uint64_t>(kMaxImageSide);
  } else if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    in_range = v >= 1 && v <= kMaxImageSide;
  } else if (value.is_number_float()) {
    const double v = value.get<double>();
    if (std::floor(v) != v) fail(place, "expected an integer, got " + value.dump());
    in_range = v >= 1.0 && v <= static_cast<double>(kMaxImageSide);
  } else {
    fail(place, "expected an integer");
  }
  if (!in_range) fail(place, detail::image_side_range_text() + ", got " + value.dump());
  return static_cast<int>(value.get<double>());
}

Vec2 read_point(const Json& value, const std::string& place) {
  if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number()) {
    fail(place, "expected [x, y]");
  }
  return {value[0].get<double>(), value[1].get<double>()};
}

Polygon read_polygon(const Json& value, const std::string& place) {
  if (!value.is_array()) fail(place, "expected an array of [x, y] vertices");
  Polygon polygon;
  polygon.vertices.reserve(value.size());
  for (std::size_t i = 0; i < value.size(); ++i) polygon.vertices.push_back(read_point(value[i], element_place(place, i)));
  return polygon;
}

Circle read_circle(const Json& value, const std::string& place) {
  if (!value.is_object()) fail(place, "expected {\"center\": [x, y], \"radius\": r}");
  check_keys(value, place, {"center", "radius"});
  Circle circle;
  circle.center = read_point(require(value, place, "center"), member_place(place, "center"));
  circle.radius = read_number(require(value, place, "radius"), member_place(place, "radius"));
  return circle;
}

Segment read_segment(const Json& value, const std::string& place) {
  if (!value.is_array() || value.size() != 2) fail(place, "expected [[x, y], [x, y]]");
  return {read_point(value[0], element_place(place, 0)), read_point(value[1], element_place(place, 1))};
}

Shape read_shape(const Json& object, const std::string& place) {
  static constexpr const char* kShapes[] = {"polygon", "circle", "segment"};
  const char* found = nullptr;
  for (const char* name : kShapes) {
    if (find(object, name) == nullptr) continue;
    if (found != nullptr) {
      fail(place, std::string("has both ") + found + " and " + name + "; needs exactly one of polygon, circle, segment");
    }
    found = name;
  }
  if (found == nullptr) fail(place, "needs one of polygon, circle, segment");
  const Json& value = *find(object, found);
  const std::string shape_place = member_place(place, found);
  if (std::strcmp(found, "polygon") == 0) return read_polygon(value, shape_place);
  if (std::strcmp(found, "circle") == 0) return read_circle(value, shape_place);
  return read_segment(value, shape_place);
}

Light read_light(const Json& value, const std::string& place) {
  if (!value.is_object()) fail(place, "expected an object");
  check_keys(value, place, {"polygon", "circle", "segment", "color", "intensity"});
  Light light;
  light.shape = read_shape(value, place);
  if (const Json* color = find(value, "color")) {
    const std::string color_place = member_place(place, "color");
    if (!color->is_array() || color->size() != 3) fail(color_place, "expected [r, g, b]");
    for (std::size_t c = 0; c < 3; ++c) {
      if (!(*color)[c].is_number()) fail(color_place, "expected [r, g, b]");
      light.color[c] = (*color)[c].get<double>();
    }
  }
  if (const Json* intensity = find(value, "intensity")) {
    light.intensity = read_number(*intensity, member_place(place, "intensity"));
  }
  if (auto problem = detail::check_light(light, place)) throw SceneError{std::move(*problem)};
  return light;
}

Occluder read_occluder(const Json& value, const std::string& place) {
  if (!value.is_object()) fail(place, "expected an object");
  // Said plainly, because "unknown key" would suggest a typo rather than a misplaced emitter.
  for (const char* key : {"color", "intensity"}) {
    if (find(value, key) != nullptr) fail(member_place(place, key), "occluders take no color or intensity");
  }
  check_keys(value, place, {"polygon", "circle", "segment"});
  Occluder occluder{read_shape(value, place)};
  if (auto problem = detail::check_occluder(occluder, place)) throw SceneError{std::move(*problem)};
  return occluder;
}

const Json* read_array(const Json& root, const char* key) {
  const Json* value = find(root, key);
  if (value != nullptr && !value->is_array()) fail(key, "expected an array");
  return value;
}

Scene read_scene(const Json& root) {
  if (!root.is_object()) fail("", "expected a JSON object at the top level");
  check_keys(root, "", {"width", "height", "view", "lights", "occluders"});
  Scene scene;
  scene.width = read_image_side(require(root, "", "width"), "width");
  scene.height = read_image_side(require(root, "", "height"), "height");
  if (const Json* view = find(root, "view")) {
    if (!view->is_array() || view->size() != 4) fail("view", "expected [x0, y0, x1, y1]");
    double v[4];
    for (std::size_t i = 0; i < 4; ++i) {
      if (!(*view)[i].is_number()) fail("view", "expected [x0, y0, x1, y1]");
      v[i] = (*view)[i].get<double>();
    }
    scene.view = View{v[0], v[1], v[2], v[3]};
  } else {
    scene.view = View{0.0, 0.0, static_cast<double>(scene.width), static_cast<double>(scene.height)};
  }
  if (auto problem = detail::check_view(scene.view, scene.width, scene.height)) throw SceneError{std::move(*problem)};

  if (const Json* lights = read_array(root, "lights")) {
    scene.lights.reserve(lights->size());
    for (std::size_t i = 0; i < lights->size(); ++i) {
      scene.lights.push_back(read_light((*lights)[i], element_place("lights", i)));
    }
    if (auto problem = detail::check_emission_total(scene.lights)) throw SceneError{std::move(*problem)};
  }
  if (const Json* occluders = read_array(root, "occluders")) {
    scene.occluders.reserve(occluders->size());
    for (std::size_t i = 0; i < occluders->size(); ++i) {
      scene.occluders.push_back(read_occluder((*occluders)[i], element_place("occluders", i)));
    }
  }
  return scene;
}

Status out_of_memory(std::string_view name) {
  try {
    return Status(StatusCode::out_of_memory, std::string(name) + ": out of memory while loading the scene");
  } catch (...) {
    return Status(StatusCode::out_of_memory, std::string());
  }
}

}  // namespace

Status parse_scene(std::string_view json_text, std::string_view name, Scene& out) {
  try {
    Json root;
    DocumentBuilder builder(root);
    if (!Json::sax_parse(json_text.data(), json_text.data() + json_text.size(), &builder)) {
      return detail::scene_error(name, builder.problem());
    }
    Scene scene = read_scene(root);
    out = std::move(scene);
    return Status::success();
  } catch (const SceneError& error) {
    return detail::scene_error(name, error.problem);
  } catch (const std::bad_alloc&) {
    return out_of_memory(name);
  } catch (const std::exception& error) {
    // Not expected (every type is checked before use); still a status, never a crash.
    return Status(StatusCode::invalid_scene, std::string(name) + ": " + error.what());
  } catch (...) {
    return Status(StatusCode::invalid_scene, std::string(name) + ": unexpected error while loading the scene");
  }
}

Status load_scene_file(const std::string& path, Scene& out) {
  try {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) {
      const int error = errno;
      return Status(StatusCode::io_error, path + ": cannot open: " + std::strerror(error));
    }
    std::string text;
    char buffer[1 << 16];
    for (;;) {
      const std::size_t got = std::fread(buffer, 1, sizeof buffer, file.get());
      if (got < sizeof buffer && std::ferror(file.get())) {
        const int error = errno;  // before anything else can overwrite it
        return Status(StatusCode::io_error, path + ": cannot read: " + std::strerror(error));
      }
      text.append(buffer, got);
      if (text.size() > kMaxFileBytes) {
        return Status(StatusCode::io_error, path + ": cannot read: larger than " +
                                                std::to_string(kMaxFileBytes >> 20) + " MiB");
      }
      if (got < sizeof buffer) break;
    }
    return parse_scene(text, path, out);
  } catch (const std::bad_alloc&) {
    return out_of_memory(path);
  } catch (...) {
    return Status(StatusCode::io_error, path + ": unexpected error while reading the file");
  }
}

}  // namespace par2d
