// Scene JSON loading: text and files read byte by byte (NUL refused, size bounded), parser
// events and places for messages, checked integers, and the normal map resolved next to the
// scene. What each key and value means is the schema walk, in scene_json_schema.cpp.
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
#include "scene/scene_json_builder.hpp"
#include "scene/scene_validate.hpp"

namespace par2d {
namespace detail {
namespace {

using Json = nlohmann::json;

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

}  // namespace

// Keys are user text: quote anything unusual, escaped, so a message stays on one line.
std::string member_place(const std::string& parent, const std::string& key) {
  if (is_identifier(key)) return parent.empty() ? key : parent + "." + key;
  return parent + "[" + Json(key).dump(-1, ' ', true, Json::error_handler_t::replace) + "]";
}

std::string element_place(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

bool SceneBuilder::number_integer(Json::number_integer_t value) {
  Scalar v{Scalar::kInteger};
  v.integer = value;
  v.number = static_cast<double>(value);
  return scalar(v);
}

bool SceneBuilder::number_unsigned(Json::number_unsigned_t value) {
  Scalar v{Scalar::kUnsigned};
  v.unsigned_integer = value;
  v.number = static_cast<double>(value);
  return scalar(v);
}

bool SceneBuilder::number_float(Json::number_float_t value, const Json::string_t& /*text*/) {
  Scalar v{Scalar::kFloat};
  v.number = value;
  return scalar(v);
}

bool SceneBuilder::string(Json::string_t& value) {
  Scalar v{Scalar::kString};
  v.text = &value;
  return scalar(v);
}

bool SceneBuilder::key(Json::string_t& name) {
  Frame& frame = frames_.back();
  if (!frame.keys.insert(name).second) {
    problem_ = {member_place(frame.place, name), "duplicate key"};
    return false;
  }
  frame.key = std::move(name);
  if (!failed_) check_key(frame);
  return true;
}

bool SceneBuilder::parse_error(std::size_t /*byte*/, const std::string& token,
                               const nlohmann::detail::exception& error) {
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

bool SceneBuilder::open(bool object) {
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

bool SceneBuilder::close() {
  Frame frame = std::move(frames_.back());
  frames_.pop_back();
  if (!failed_) finish(frame);
  if (!frames_.empty() && !frames_.back().object) ++frames_.back().count;
  return true;
}

std::string SceneBuilder::next_place() const {
  if (frames_.empty()) return "";
  const Frame& frame = frames_.back();
  if (frame.object) return member_place(frame.place, frame.key);
  return element_place(frame.place, frame.count);
}

bool SceneBuilder::integer_in(const Scalar& v, const std::string& place, int lo, int hi, const std::string& range,
                              int& out) {
  bool in_range = false;
  if (v.kind == Scalar::kUnsigned) {
    in_range = v.unsigned_integer >= static_cast<std::uint64_t>(lo) && v.unsigned_integer <= static_cast<std::uint64_t>(hi);
  } else if (v.kind == Scalar::kInteger) {
    in_range = v.integer >= lo && v.integer <= hi;
  } else if (v.kind == Scalar::kFloat) {
    if (std::floor(v.number) != v.number) return fail(place, "expected an integer, got " + v.dump()), false;
    in_range = v.number >= static_cast<double>(lo) && v.number <= static_cast<double>(hi);
  } else {
    return fail(place, "expected an integer"), false;
  }
  if (!in_range) return fail(place, range + ", got " + v.dump()), false;
  out = static_cast<int>(v.number);
  return true;
}

void SceneBuilder::bounce_step(const Scalar& v, const std::string& place) {
  integer_in(v, place, 1, kMaxBounceStep, "must be an integer from 1 to " + std::to_string(kMaxBounceStep),
             scene_.bounce.step);
}

void SceneBuilder::image_side(const Scalar& v, const std::string& place, bool width) {
  if (!integer_in(v, place, 1, kMaxImageSide, detail::image_side_range_text(), width ? scene_.width : scene_.height))
    return;
  (width ? has_width_ : has_height_) = true;
}

void SceneBuilder::mask_value(const Scalar& v, const std::string& place, std::uint32_t& out) {
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

}  // namespace detail

namespace {

using Json = nlohmann::json;
using detail::SceneBuilder;

// Reading stops here so that a device file or a runaway file cannot eat all memory.
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;

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
