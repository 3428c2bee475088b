// The scene schema walk as a SAX handler for nlohmann::json: SceneBuilder builds a Scene straight
// from the parser's events. Internal to the JSON loader: its event handling, numbers and places
// are in scene_json.cpp, the schema walk (what each key and value means) in scene_json_schema.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "par2d/scene.hpp"
#include "scene/scene_validate.hpp"

namespace par2d::detail {

// Places as messages name them: `lights[3].circle.radius`. Keys are user text: anything
// unusual is quoted, escaped, so a message stays on one line.
std::string member_place(const std::string& parent, const std::string& key);
std::string element_place(const std::string& parent, std::size_t index);

// Builds the Scene straight from the parser's events (no JSON document: memory stays a
// small multiple of the file, since a vertex costs 16 bytes against at least 6 of text).
// A problem with the scene's content is remembered and the rest of the text is still
// parsed, without building anything, so that syntax errors, duplicate keys and absurd
// nesting anywhere in the file are reported first, as a parser that built the whole
// document would; among content problems the first in the file is reported.
class SceneBuilder {
 public:
  using Json = nlohmann::json;

  bool null() { return scalar(Scalar{Scalar::kOther}); }
  bool boolean(bool /*value*/) { return scalar(Scalar{Scalar::kOther}); }
  bool number_integer(Json::number_integer_t value);
  bool number_unsigned(Json::number_unsigned_t value);
  bool number_float(Json::number_float_t value, const Json::string_t& /*text*/);
  bool string(Json::string_t& value);
  bool binary(Json::binary_t& /*value*/) { return scalar(Scalar{Scalar::kOther}); }

  bool start_object(std::size_t /*size*/) { return open(true); }
  bool start_array(std::size_t /*size*/) { return open(false); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& name);

  bool parse_error(std::size_t /*byte*/, const std::string& token, const nlohmann::detail::exception& error);

  // After sax_parse returned false: the syntax (or nesting, duplicate) problem.
  const detail::SceneProblem& problem() const { return problem_; }
  // After sax_parse returned true: the first content problem, if any.
  bool failed() const { return failed_; }
  const detail::SceneProblem& content_problem() const { return content_problem_; }
  Scene& scene() { return scene_; }
  // After a successful parse: scene().occluders from the compact store, reserved exactly and
  // filled while the store is freed block by block, so the peak is about 40 + 72 bytes per
  // occluder instead of a growing vector's 3 x 72.
  void build_occluders();

 private:
  // A valid scene nests five deep (top, lights, light, circle, center); far deeper input is
  // garbage, and refusing it early keeps the document we build small.
  static constexpr std::size_t kMaxDepth = 64;
  static constexpr std::size_t kReportedDepth = 6;

  // What a container holds, which decides what its values mean.
  // `numbers`: a fixed-length array of numbers (a color, a normal, angles) stored at `target`.
  enum class Role { root, skip, view, list, element, polygon, holes, ring, point, circle, segment, numbers, cone, cookie, knots, knot, shadow, bounce };
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
    Cookie cookie;
    bool has_knots = false;
    Polygon polygon;
    bool has_holes = false;  // a "holes" key was read (only a polygon takes one)
    Circle circle;
    bool has_center = false, has_radius = false;
    Segment segment;
  };

  // Reading (scene_json.cpp): containers opening and closing, places, checked integers.
  bool open(bool object);
  bool close();
  std::string next_place() const;
  // Integer-valued numbers only (64 or 64.0), range-checked before any cast so 1e30 or
  // 2^63 cannot overflow an int.
  void image_side(const Scalar& v, const std::string& place, bool width);
  void bounce_step(const Scalar& v, const std::string& place);
  // Stores v in `out` when it is an integer in [lo, hi]; otherwise fails with `range` (false).
  bool integer_in(const Scalar& v, const std::string& place, int lo, int hi, const std::string& range, int& out);
  // A 32-bit mask: integer-valued numbers only (5 or 5.0), range-checked before any cast.
  void mask_value(const Scalar& v, const std::string& place, std::uint32_t& out);

  // The schema walk (scene_json_schema.cpp).
  void fail(std::string place, std::string what);
  void check_key(const Frame& frame);
  // A number or other non-container value in the current frame.
  bool scalar(const Scalar& v);
  void element_scalar(const Frame& frame, const Scalar& v, const std::string& place);
  void normal_map_path(const Scalar& v, const std::string& place);
  // The role of a container opening at `place` in the current frame; fails for one that
  // does not belong there.
  Role container_role(bool object, const std::string& place);
  // A fixed-length number array opening (an object there is refused).
  Role numbers(bool object, const std::string& place, double* target, std::size_t length, const char* expected);
  // A container ended: check what needs all of it, and hand its value to its parent.
  void finish(const Frame& frame);
  void finish_element(const std::string& place);
  void finish_root();

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
  // The occluders' shapes, each kind in its own store (a circle takes 24 bytes there, a Shape 40)
  // and the kinds in file order (0 polygon, 1 circle, 2 segment): with an Occluder of 96 bytes
  // a level of circles still loads within 3x its text.
  std::deque<std::uint8_t> occluder_kinds_;
  std::deque<Polygon> occluder_polygons_;
  std::deque<Circle> occluder_circles_;
  std::deque<Segment> occluder_segments_;
  std::vector<std::pair<std::size_t, Occluder>> occluder_terms_;  // (index, terms) of non-plain occluders
  Element element_;
  double point_[2] = {0, 0};
};

}  // namespace par2d::detail
