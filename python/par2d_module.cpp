// Python bindings (`import par2d`): scenes from dicts, JSON text or files, rendered into NumPy float32 arrays.
//
// Only the public C++ API (include/par2d/) is used. Scenes cross into C++ as JSON text, so a
// dict is checked by the same loader as a file and its errors read the same
// (`<dict>: lights[2].polygon: not convex at vertex 3`, docs/contract.md section 3).
// Rendering goes through render_into(), the one place that touches the output array and
// releases the GIL. par2d.Renderer wraps par2d::Renderer: a world kept across frames, changed
// through integer handles, rendered into float32 or sRGB uint8 arrays.
//
// Every argument arrives as a plain object and is converted here, so that a wrong one raises
// par2d.Error naming it (`region: needs (x0, y0, x1, y1) integers, got (0.5, 0, 4, 4)`), never
// pybind11's TypeError or cast error; numbers and handles are anything integer-like
// (__index__) or real, NumPy scalars included.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "par2d/par2d.hpp"

namespace py = pybind11;

namespace {

// par2d.Error, created in PYBIND11_MODULE; every failed par2d call raises it.
PyObject* g_error_type = nullptr;

// StatusCode as a Python identifier (status_code_name gives words meant for messages).
const char* code_identifier(par2d::StatusCode code) {
  switch (code) {
    case par2d::StatusCode::ok: return "ok";
    case par2d::StatusCode::invalid_argument: return "invalid_argument";
    case par2d::StatusCode::invalid_scene: return "invalid_scene";
    case par2d::StatusCode::io_error: return "io_error";
    case par2d::StatusCode::out_of_memory: return "out_of_memory";
    case par2d::StatusCode::unsupported: return "unsupported";
  }
  return "unknown";
}

// Raises par2d.Error(message) with `code` set to the status code's name ("invalid_scene", ...).
[[noreturn]] void raise(const par2d::Status& status) {
  py::object error = py::reinterpret_borrow<py::object>(g_error_type)(status.message());
  error.attr("code") = code_identifier(status.code());
  PyErr_SetObject(g_error_type, error.ptr());
  throw py::error_already_set();
}

[[noreturn]] void raise(par2d::StatusCode code, std::string message) { raise(par2d::Status(code, std::move(message))); }

void check(const par2d::Status& status) {
  if (!status.ok()) raise(status);
}

// ---- Arguments ---------------------------------------------------------------------------
// Each converter names the argument (`place`) in its error, one line, code invalid_argument.

[[noreturn]] void bad_argument(const std::string& place, const std::string& what) {
  raise(par2d::StatusCode::invalid_argument, place + ": " + what);
}

std::string type_name(const py::handle& obj) {
  return py::str(py::type::of(obj).attr("__name__")).cast<std::string>();
}

// "a set", "an ndarray".
std::string a_type(const py::handle& obj) {
  const std::string name = type_name(obj);
  return (name.find_first_of("aeiouAEIOU") == 0 ? "an " : "a ") + name;
}

// A short one-line repr of a value for a message, or its type when the repr is long or odd.
std::string describe(const py::handle& obj) {
  std::string text;
  PyObject* repr = PyObject_Repr(obj.ptr());
  if (repr != nullptr) {
    Py_ssize_t size = 0;
    const char* utf8 = PyUnicode_AsUTF8AndSize(repr, &size);
    if (utf8 != nullptr) text.assign(utf8, static_cast<std::size_t>(size));
    Py_DECREF(repr);
  }
  PyErr_Clear();
  if (text.empty() || text.size() > 60 || text.find_first_of("\r\n") != std::string::npos)
    return a_type(obj);
  return text;
}

// A Python error's message on one line.
std::string one_line(const py::error_already_set& e) {
  std::string text = py::str(e.value()).cast<std::string>();
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

bool is_text(const py::handle& obj) { return PyUnicode_Check(obj.ptr()) || PyBytes_Check(obj.ptr()); }

// An integer-like object (int, numpy.int64, anything with __index__; not bool) as a long long.
std::optional<long long> as_integer(const py::handle& obj) {
  if (PyBool_Check(obj.ptr()) || !PyIndex_Check(obj.ptr())) return std::nullopt;
  PyObject* index = PyNumber_Index(obj.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  int overflow = 0;
  const long long value = PyLong_AsLongLongAndOverflow(index, &overflow);
  Py_DECREF(index);
  if (overflow != 0 || (value == -1 && PyErr_Occurred())) {
    PyErr_Clear();
    return std::nullopt;
  }
  return value;
}

// A real number (int, float, numpy scalars, anything with __float__ or __index__; not bool or text).
std::optional<double> as_number(const py::handle& obj) {
  if (PyBool_Check(obj.ptr()) || is_text(obj)) return std::nullopt;
  if (!PyFloat_Check(obj.ptr()) && !PyIndex_Check(obj.ptr()) &&
      (Py_TYPE(obj.ptr())->tp_as_number == nullptr || Py_TYPE(obj.ptr())->tp_as_number->nb_float == nullptr))
    return std::nullopt;
  const double value = PyFloat_AsDouble(obj.ptr());
  if (value == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    return std::nullopt;
  }
  return value;
}

int to_int(const py::handle& obj, const char* place) {
  const std::optional<long long> value = as_integer(obj);
  if (!value) {
    if (!PyBool_Check(obj.ptr()) && PyIndex_Check(obj.ptr())) bad_argument(place, describe(obj) + " is out of range");
    bad_argument(place, "must be an integer, not " + type_name(obj));
  }
  if (*value < std::numeric_limits<int>::min() || *value > std::numeric_limits<int>::max())
    bad_argument(place, std::to_string(*value) + " is out of range");
  return static_cast<int>(*value);
}

double to_double(const py::handle& obj, const char* place) {
  const std::optional<double> value = as_number(obj);
  if (!value) bad_argument(place, "must be a number, not " + type_name(obj));
  return *value;
}

bool to_bool(const py::handle& obj, const char* place) {
  if (PyBool_Check(obj.ptr())) return obj.ptr() == Py_True;
  if (type_name(obj) == "bool_") return PyObject_IsTrue(obj.ptr()) == 1;  // numpy.bool_
  if (PyLong_CheckExact(obj.ptr())) {
    const std::optional<long long> value = as_integer(obj);
    if (value && (*value == 0 || *value == 1)) return *value == 1;
  }
  bad_argument(place, "must be True or False, not " + describe(obj));
}

std::string to_text(const py::handle& obj, const char* place) {
  if (!PyUnicode_Check(obj.ptr())) bad_argument(place, "must be a str, not " + type_name(obj));
  Py_ssize_t size = 0;
  const char* utf8 = PyUnicode_AsUTF8AndSize(obj.ptr(), &size);
  if (utf8 == nullptr) {
    PyErr_Clear();
    bad_argument(place, "is not valid text (it cannot be encoded as UTF-8)");
  }
  return std::string(utf8, static_cast<std::size_t>(size));
}

std::optional<std::string> to_optional_text(const py::handle& obj, const char* place) {
  if (obj.is_none()) return std::nullopt;
  return to_text(obj, place);
}

// A file path: a str or an os.PathLike (pathlib.Path).
std::string to_path(const py::handle& obj, const char* place) {
  if (PyUnicode_Check(obj.ptr())) return to_text(obj, place);
  PyObject* fs = PyOS_FSPath(obj.ptr());
  if (fs == nullptr) {
    PyErr_Clear();
    bad_argument(place, "must be a str or os.PathLike, not " + type_name(obj));
  }
  py::object path = py::reinterpret_steal<py::object>(fs);
  if (PyBytes_Check(path.ptr())) {
    PyObject* decoded = PyUnicode_DecodeFSDefaultAndSize(PyBytes_AS_STRING(path.ptr()), PyBytes_GET_SIZE(path.ptr()));
    if (decoded == nullptr) {
      PyErr_Clear();
      bad_argument(place, "is not a valid file name");
    }
    path = py::reinterpret_steal<py::object>(decoded);
  }
  return to_text(path, place);
}

// A sequence (not text) of exactly n items, or nothing.
std::optional<std::vector<py::object>> as_items(const py::handle& obj, std::size_t n) {
  if (is_text(obj) || !PySequence_Check(obj.ptr())) return std::nullopt;
  const Py_ssize_t size = PySequence_Size(obj.ptr());
  if (size < 0) {
    PyErr_Clear();
    return std::nullopt;
  }
  if (static_cast<std::size_t>(size) != n) return std::nullopt;
  std::vector<py::object> items;
  for (Py_ssize_t i = 0; i < size; ++i) {
    PyObject* item = PySequence_GetItem(obj.ptr(), i);
    if (item == nullptr) {
      PyErr_Clear();
      return std::nullopt;
    }
    items.push_back(py::reinterpret_steal<py::object>(item));
  }
  return items;
}

// Three numbers: a color (r, g, b), an ambient term, a normal (nx, ny, nz).
std::array<double, 3> to_three(const py::handle& obj, const char* place, const char* form) {
  const auto items = as_items(obj, 3);
  std::array<double, 3> out{};
  bool ok = items.has_value();
  for (std::size_t i = 0; ok && i < 3; ++i) {
    const std::optional<double> v = as_number((*items)[i]);
    if (v) out[i] = *v;
    else ok = false;
  }
  if (!ok) bad_argument(place, std::string("needs 3 numbers ") + form + ", got " + describe(obj));
  return out;
}

// (x0, y0, x1, y1) pixels, unchecked against the frame (that needs the world, under its lock).
std::optional<std::array<long long, 4>> to_region(const py::handle& obj) {
  if (obj.is_none()) return std::nullopt;
  const auto items = as_items(obj, 4);
  std::array<long long, 4> out{};
  bool ok = items.has_value();
  for (std::size_t i = 0; ok && i < 4; ++i) {
    const std::optional<long long> v = as_integer((*items)[i]);
    if (v) out[i] = *v;
    else ok = false;
  }
  if (!ok) bad_argument("region", "needs (x0, y0, x1, y1) integers, got " + describe(obj));
  return out;
}

std::optional<par2d::View> to_view(const py::handle& obj) {
  if (obj.is_none()) return std::nullopt;
  const auto items = as_items(obj, 4);
  std::array<double, 4> v{};
  bool ok = items.has_value();
  for (std::size_t i = 0; ok && i < 4; ++i) {
    const std::optional<double> d = as_number((*items)[i]);
    if (d) v[i] = *d;
    else ok = false;
  }
  if (!ok) bad_argument("view", "needs (x0, y0, x1, y1) numbers, got " + describe(obj));
  return par2d::View{v[0], v[1], v[2], v[3]};
}

// A light or occluder handle: any integer-like object (int, numpy.uint64, ...). An integer
// that no 64-bit id can be (negative, too large) names nothing, as the library says of
// unknown ids.
std::uint64_t handle_id(const py::handle& handle, const char* kind) {
  if (PyBool_Check(handle.ptr()) || !PyIndex_Check(handle.ptr()))
    bad_argument("handle", std::string("must be an integer (a ") + kind + " handle), not " + type_name(handle));
  PyObject* index = PyNumber_Index(handle.ptr());
  if (index != nullptr) {
    const unsigned long long value = PyLong_AsUnsignedLongLong(index);
    const bool failed = value == static_cast<unsigned long long>(-1) && PyErr_Occurred();
    py::object index_repr = py::reinterpret_steal<py::object>(index);
    if (!failed) return value;
    PyErr_Clear();
    raise(par2d::StatusCode::invalid_argument, std::string("unknown ") + kind + " handle " + describe(index_repr));
  }
  PyErr_Clear();
  bad_argument("handle", std::string("must be an integer (a ") + kind + " handle), not " + type_name(handle));
}

// ---- Dicts as JSON ------------------------------------------------------------------------
// Dicts cross into C++ as JSON text for the scene loader. JSON has no NaN or infinity, and
// json.dumps would write them as bare tokens that the loader can only place by column; so
// the dict is walked first and such a value is reported at its path, in the loader's words
// (`lights[0].intensity: not a finite number (nan)`), as is anything JSON cannot hold.

constexpr int kMaxJsonDepth = 64;  // the loader's limit too

bool is_identifier(const std::string& key) {
  if (key.empty()) return false;
  for (char ch : key)
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
  return true;
}

std::string member_place(const std::string& parent, const py::handle& key) {
  const std::string text = to_text(key, "key");
  if (is_identifier(text)) return parent.empty() ? text : parent + "." + text;
  return parent + "[" + py::module_::import("json").attr("dumps")(key).cast<std::string>() + "]";
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  return value > 0 ? "inf" : "-inf";
}

struct JsonProblem {
  std::string place, what;
};

std::optional<JsonProblem> find_json_problem(const py::handle& obj, const std::string& place, int depth) {
  if (depth > kMaxJsonDepth) return JsonProblem{place, "nested too deeply (more than 64 levels)"};
  PyObject* p = obj.ptr();
  if (p == Py_None || PyBool_Check(p) || PyUnicode_Check(p) || PyLong_Check(p)) return std::nullopt;
  if (PyFloat_Check(p)) {
    const double v = PyFloat_AS_DOUBLE(p);
    if (!std::isfinite(v)) return JsonProblem{place, "not a finite number (" + format_number(v) + ")"};
    return std::nullopt;
  }
  if (PyDict_Check(p)) {
    for (auto item : py::reinterpret_borrow<py::dict>(obj)) {
      if (!PyUnicode_Check(item.first.ptr()))
        return JsonProblem{place, "a key must be a string, not " + type_name(item.first)};
      if (auto problem = find_json_problem(item.second, member_place(place, item.first), depth + 1)) return problem;
    }
    return std::nullopt;
  }
  if (PyList_Check(p) || PyTuple_Check(p)) {
    const py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
    for (std::size_t i = 0; i < seq.size(); ++i)
      if (auto problem = find_json_problem(seq[i], place + "[" + std::to_string(i) + "]", depth + 1)) return problem;
    return std::nullopt;
  }
  // NumPy scalars and other numbers: written as what they are (see json_default).
  if (PyIndex_Check(p)) return std::nullopt;
  if (const std::optional<double> v = as_number(obj)) {
    if (!std::isfinite(*v)) return JsonProblem{place, "not a finite number (" + format_number(*v) + ")"};
    return std::nullopt;
  }
  return JsonProblem{place, a_type(obj) + " is not a JSON value"};
}

// JSON text of a dict or list (already walked): numbers that are not int or float are
// written as the int or float they stand for.
std::string json_text(const py::handle& obj, const std::string& name, const std::string& root) {
  if (auto problem = find_json_problem(obj, root, 0))
    raise(par2d::StatusCode::invalid_scene,
          name + ": " + (problem->place.empty() ? "" : problem->place + ": ") + problem->what);
  const py::cpp_function json_default([](const py::handle& o) -> py::object {
    if (PyIndex_Check(o.ptr())) return py::reinterpret_steal<py::object>(PyNumber_Index(o.ptr()));
    return py::float_(PyFloat_AsDouble(o.ptr()));
  });
  try {
    return py::module_::import("json").attr("dumps")(obj, py::arg("default") = json_default).cast<std::string>();
  } catch (py::error_already_set& e) {
    raise(par2d::StatusCode::invalid_scene, name + ": " + one_line(e));
  }
}

// ---- Scenes ---------------------------------------------------------------------------------

// A validated scene. Immutable from Python: edit its dict and build a new one, so a Scene
// object is always one that renders.
class PyScene {
 public:
  explicit PyScene(par2d::Scene scene) : scene_(std::move(scene)) {}

  static PyScene from_json_text(const std::string& text, const std::string& name) {
    par2d::Scene scene;
    check(par2d::parse_scene(text, name, scene));
    return PyScene(std::move(scene));
  }

  static PyScene from_json(const py::object& text, const py::object& name) {
    const std::string n = to_text(name, "name");
    return from_json_text(to_text(text, "text"), n);
  }

  static PyScene from_dict_named(const py::object& dict, const std::string& name) {
    if (!py::isinstance<py::dict>(dict))
      raise(par2d::StatusCode::invalid_scene, name + ": a scene must be a dict, not " + type_name(dict));
    return from_json_text(json_text(dict, name, ""), name);
  }

  static PyScene from_dict(const py::object& dict, const py::object& name) {
    return from_dict_named(dict, to_text(name, "name"));
  }

  static PyScene load(const py::object& path) {
    par2d::Scene scene;
    check(par2d::load_scene_file(to_path(path, "path"), scene));
    return PyScene(std::move(scene));
  }

  const par2d::Scene& scene() const { return scene_; }
  std::string to_json() const { return par2d::scene_to_json(scene_); }
  py::object to_dict() const { return py::module_::import("json").attr("loads")(to_json()); }
  void save(const py::object& path) const { check(par2d::save_scene_file(to_path(path, "path"), scene_)); }

 private:
  par2d::Scene scene_;
};

// The `scene` argument: a Scene, or a dict checked by the loader under the name "<dict>".
const PyScene& as_scene(const py::object& scene, std::optional<PyScene>& holder) {
  if (py::isinstance<PyScene>(scene)) return scene.cast<const PyScene&>();
  if (!py::isinstance<py::dict>(scene)) bad_argument("scene", "must be a par2d.Scene or a dict, not " + type_name(scene));
  holder = PyScene::from_dict_named(scene, "<dict>");
  return *holder;
}

par2d::RenderOptions make_options(const py::object& backend_arg, const py::object& threads, const py::object& spp,
                                  int rays, const py::object& isa_arg, const py::object& culling) {
  par2d::RenderOptions options;
  const std::string backend = to_text(backend_arg, "backend");
  const auto parsed_backend = par2d::parse_backend(backend.c_str());
  if (!parsed_backend)
    raise(par2d::StatusCode::invalid_argument, "backend: unknown name \"" + backend + "\" (auto, simd, scalar, raycast)");
  options.backend = *parsed_backend;
  if (const std::optional<std::string> isa = to_optional_text(isa_arg, "isa")) {
    options.isa = par2d::parse_isa(*isa);
    if (!options.isa) raise(par2d::StatusCode::invalid_argument, "isa: unknown name \"" + *isa + "\" (scalar, sse4, avx2, avx512)");
  }
  options.threads = to_int(threads, "threads");
  options.spp = to_int(spp, "spp");
  options.rays = rays;
  options.culling = to_bool(culling, "culling");
  return options;
}

using FloatArray = py::array_t<float, py::array::c_style>;

// Renders into `out`, an (H, W, 3) float32 array whose pixels and channels are packed (rows
// may be padded), with the GIL released so other Python threads run meanwhile.
void render_into(const par2d::Scene& scene, const par2d::RenderOptions& options, const py::object& out_arg,
                 py::array& out) {
  const bool fits = py::isinstance<py::array>(out_arg);
  if (fits) out = py::reinterpret_borrow<py::array>(out_arg);
  if (!fits || !py::isinstance<py::array_t<float>>(out) || out.ndim() != 3 || out.shape(2) != 3 ||
      out.shape(0) != scene.height || out.shape(1) != scene.width || out.strides(2) != sizeof(float) ||
      out.strides(1) != 3 * sizeof(float) || out.strides(0) % sizeof(float) != 0 ||
      out.strides(0) < static_cast<py::ssize_t>(3 * sizeof(float)) * scene.width || !out.writeable())
    raise(par2d::StatusCode::invalid_argument,
          "out: needs a writable float32 array of shape (" + std::to_string(scene.height) + ", " +
              std::to_string(scene.width) + ", 3) with packed pixels (rows may be padded)");
  par2d::ImageView view{static_cast<float*>(out.mutable_data()), scene.width, scene.height,
                        static_cast<std::ptrdiff_t>(out.strides(0) / static_cast<py::ssize_t>(sizeof(float)))};
  par2d::Status status;
  {
    py::gil_scoped_release release;
    status = par2d::render(scene, options, view);
  }
  check(status);
}

py::tuple rgb_tuple(const par2d::Rgb& c) { return py::make_tuple(c[0], c[1], c[2]); }

py::list directional_dicts(const std::vector<par2d::DirectionalLight>& lights) {
  py::list out;
  for (const par2d::DirectionalLight& d : lights) {
    py::dict e;
    e["angles"] = py::make_tuple(d.angle0, d.angle1);
    e["color"] = rgb_tuple(d.color);
    e["intensity"] = d.intensity;
    e["mask"] = d.mask;
    e["elevation"] = d.elevation;
    out.append(e);
  }
  return out;
}

py::object normal_tuple(const std::optional<par2d::Vec3>& n) {
  if (!n) return py::none();
  return py::make_tuple(n->x, n->y, n->z);
}

// A normal map as a new (height, width, 3) float32 array in image axes (y up), or None.
py::object normal_map_array(const std::optional<par2d::NormalMap>& map) {
  if (!map) return py::none();
  FloatArray a({static_cast<py::ssize_t>(map->height), static_cast<py::ssize_t>(map->width), py::ssize_t{3}});
  std::copy(map->normals.begin(), map->normals.end(), a.mutable_data());
  return std::move(a);
}

// A normal map from an (H, W, 3) array of numbers (converted to float32) or a PNG path.
par2d::NormalMap to_normal_map(const py::object& source) {
  par2d::NormalMap map;
  if (PyUnicode_Check(source.ptr()) || PyObject_HasAttrString(source.ptr(), "__fspath__")) {
    check(par2d::load_normal_map_png(to_path(source, "normal_map"), map));
    return map;
  }
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(source);
  if (!a || a.ndim() != 3 || a.shape(2) != 3)
    bad_argument("normal_map", "needs a PNG path or an array of shape (height, width, 3), got " + describe(source));
  map.height = static_cast<int>(a.shape(0));
  map.width = static_cast<int>(a.shape(1));
  map.normals.assign(a.data(), a.data() + a.size());
  return map;
}

// One light or occluder from a dict shaped like an entry of the scene file's "lights" or
// "occluders" list: parsed by the scene loader inside a one-entry scene, so it is checked by
// the same rules, and the loader's "lights[0]." prefix is dropped from its messages.
template <typename T>
T parse_entry(const py::object& dict, const char* list, const std::string& name) {
  if (!py::isinstance<py::dict>(dict))
    raise(par2d::StatusCode::invalid_scene, name + ": must be a dict, not " + type_name(dict));
  const std::string text = std::string("{\"width\": 1, \"height\": 1, \"") + list + "\": [" + json_text(dict, name, "") + "]}";
  par2d::Scene scene;
  const par2d::Status status = par2d::parse_scene(text, name, scene);
  if (!status.ok()) {
    std::string message = status.message();
    const std::string prefix = name + ": " + list + "[0]";
    if (message.compare(0, prefix.size(), prefix) == 0) {
      std::size_t rest = prefix.size();
      if (rest < message.size() && message[rest] == '.') ++rest;
      message = name + ": " + message.substr(rest);
    }
    raise(par2d::Status(status.code(), message));
  }
  if constexpr (std::is_same_v<T, par2d::Light>)
    return scene.lights.at(0);
  else
    return scene.occluders.at(0);
}

// ---- Renderer -------------------------------------------------------------------------------

// par2d::Renderer for Python: a persistent world changed through integer handles.
//
// The C++ class is one-thread-at-a-time, so every entry point below first converts its
// arguments (which may run Python code: __index__, __float__, __fspath__), then takes the
// world's lock, and only then reads or changes any state: a frame is rendered at the size
// and view of the moment it holds the lock, never a size read before. Errors are raised
// after the lock is let go. The lock is taken with the GIL released when it is busy, and
// the GIL is taken again while holding it (never the other order), so a render that holds
// the lock with the GIL released does not stall other Python threads, and nothing deadlocks.
class PyRenderer {
 public:
  PyRenderer(const py::object& scene, const py::object& backend, const py::object& threads, const py::object& isa,
             const py::object& spp, const py::object& culling) {
    set_options(backend, threads, isa, spp, culling);
    if (!scene.is_none()) set_scene(scene);
  }

  void set_options(const py::object& backend, const py::object& threads, const py::object& isa, const py::object& spp,
                   const py::object& culling) {
    const par2d::RenderOptions options = make_options(backend, threads, spp, 1024, isa, culling);
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_options(options);
    }
    check(status);
  }

  py::tuple set_scene(const py::object& scene_or_dict) {
    std::optional<PyScene> holder;
    const PyScene& scene = as_scene(scene_or_dict, holder);
    std::vector<par2d::LightHandle> lights;
    std::vector<par2d::OccluderHandle> occluders;
    std::vector<std::uint64_t> light_ids, occluder_ids;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_scene(scene.scene(), &lights, &occluders);
      if (status.ok()) {
        lights_.clear();
        occluders_.clear();
        for (const auto& h : lights) lights_.push_back(h.id);
        for (const auto& h : occluders) occluders_.push_back(h.id);
        light_ids = lights_;
        occluder_ids = occluders_;
      }
    }
    check(status);
    return py::make_tuple(light_ids, occluder_ids);
  }

  void set_frame(const py::object& width_arg, const py::object& height_arg, const py::object& view_arg) {
    const int width = to_int(width_arg, "width"), height = to_int(height_arg, "height");
    const std::optional<par2d::View> view = to_view(view_arg);
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = view ? renderer_.set_frame(width, height, *view) : renderer_.set_frame(width, height);
    }
    check(status);
  }

  std::uint64_t add_light(const py::object& dict) {
    const par2d::Light light = parse_entry<par2d::Light>(dict, "lights", "add_light");
    par2d::LightHandle handle;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.add_light(light, &handle);
      if (status.ok()) lights_.push_back(handle.id);
    }
    check(status);
    return handle.id;
  }
  void update_light(const py::object& handle, const py::object& dict) {
    const std::uint64_t id = handle_id(handle, "light");
    const par2d::Light light = parse_entry<par2d::Light>(dict, "lights", "light " + std::to_string(id));
    locked_check([&] { return renderer_.update_light(par2d::LightHandle{id}, light); });
  }
  void set_light_emission(const py::object& handle, const py::object& color_arg, const py::object& intensity_arg) {
    const std::uint64_t id = handle_id(handle, "light");
    const std::array<double, 3> color = to_three(color_arg, "color", "(r, g, b)");
    const double intensity = to_double(intensity_arg, "intensity");
    locked_check([&] {
      return renderer_.set_light_emission(par2d::LightHandle{id}, par2d::Rgb{color[0], color[1], color[2]}, intensity);
    });
  }
  void remove_light(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "light");
    locked_check([&] {
      par2d::Status status = renderer_.remove_light(par2d::LightHandle{id});
      if (status.ok()) lights_.erase(std::remove(lights_.begin(), lights_.end(), id), lights_.end());
      return status;
    });
  }

  std::uint64_t add_occluder(const py::object& dict) {
    const par2d::Occluder occluder = parse_entry<par2d::Occluder>(dict, "occluders", "add_occluder");
    par2d::OccluderHandle handle;
    locked_check([&] {
      par2d::Status status = renderer_.add_occluder(occluder, &handle);
      if (status.ok()) occluders_.push_back(handle.id);
      return status;
    });
    return handle.id;
  }
  void update_occluder(const py::object& handle, const py::object& dict) {
    const std::uint64_t id = handle_id(handle, "occluder");
    const par2d::Occluder occluder = parse_entry<par2d::Occluder>(dict, "occluders", "occluder " + std::to_string(id));
    locked_check([&] { return renderer_.update_occluder(par2d::OccluderHandle{id}, occluder); });
  }
  void remove_occluder(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "occluder");
    locked_check([&] {
      par2d::Status status = renderer_.remove_occluder(par2d::OccluderHandle{id});
      if (status.ok()) occluders_.erase(std::remove(occluders_.begin(), occluders_.end(), id), occluders_.end());
      return status;
    });
  }

  // Float RGB frame (or region) into `out` or a new (h, w, 3) float32 array.
  py::array render(const py::object& out, const py::object& region) {
    return render_format(par2d::PixelFormat::rgb_f32, 1.0, out, region);
  }
  py::array render_rgba8(const py::object& exposure, const py::object& out, const py::object& region) {
    return render_format(par2d::PixelFormat::rgba8_srgb, to_double(exposure, "exposure"), out, region);
  }

  py::dict stats() const {
    par2d::RendererStats s;
    {
      WorldLock lock(mutex_);
      s = renderer_.stats();
    }
    py::dict d;
    d["frames"] = s.frames;
    d["index_builds"] = s.index_builds;
    d["index_updates"] = s.index_updates;
    d["reach_computations"] = s.reach_computations;
    d["full_prepares"] = s.full_prepares;
    return d;
  }

  // The scene-wide lighting-model terms (docs/contract.md section 6).
  void set_ambient(const py::object& rgb_arg) {
    const std::array<double, 3> rgb = to_three(rgb_arg, "rgb", "(r, g, b)");
    locked_check([&] { return renderer_.set_ambient({rgb[0], rgb[1], rgb[2]}); });
  }
  // A list of dicts shaped like the scene file's "directional_lights", checked by its loader.
  void set_directional_lights(const py::object& list) {
    const std::string name = "set_directional_lights";
    const std::string text =
        "{\"width\": 1, \"height\": 1, \"directional_lights\": " + json_text(list, name, "directional_lights") + "}";
    par2d::Scene scene;
    check(par2d::parse_scene(text, name, scene));
    locked_check([&] { return renderer_.set_directional_lights(scene.directional_lights); });
  }
  void set_normal(const py::object& normal) {
    const std::array<double, 3> n = to_three(normal, "normal", "(nx, ny, nz)");
    locked_check([&] { return renderer_.set_normal({n[0], n[1], n[2]}); });
  }
  void set_normal_map(const py::object& source) {
    const par2d::NormalMap map = to_normal_map(source);
    locked_check([&] { return renderer_.set_normal_map(map); });
  }
  void clear_normal_source() {
    locked_check([&] { return renderer_.clear_normal_source(); });
  }

  PyScene snapshot() const {
    WorldLock lock(mutex_);
    return PyScene(renderer_.snapshot());
  }

  // The frame and the handles as one consistent reading.
  struct Summary {
    int width = 0, height = 0, threads = 0;
    par2d::View view{};
    std::size_t light_count = 0, occluder_count = 0;
  };
  Summary summary() const {
    WorldLock lock(mutex_);
    return Summary{renderer_.width(),      renderer_.height(),      renderer_.threads(), renderer_.view(),
                   renderer_.light_count(), renderer_.occluder_count()};
  }
  std::vector<std::uint64_t> lights() const {
    WorldLock lock(mutex_);
    return lights_;
  }
  std::vector<std::uint64_t> occluders() const {
    WorldLock lock(mutex_);
    return occluders_;
  }

 private:
  // Holds the world's mutex; waits for it with the GIL released.
  class WorldLock {
   public:
    explicit WorldLock(std::mutex& mutex) : mutex_(mutex) {
      if (!mutex_.try_lock()) {
        py::gil_scoped_release release;
        mutex_.lock();
      }
    }
    ~WorldLock() { mutex_.unlock(); }
    WorldLock(const WorldLock&) = delete;
    WorldLock& operator=(const WorldLock&) = delete;

   private:
    std::mutex& mutex_;
  };

  // Runs fn (which returns a Status) under the lock; raises its error after letting go.
  template <class Fn>
  void locked_check(Fn&& fn) {
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = fn();
    }
    check(status);
  }

  py::array render_format(par2d::PixelFormat format, double exposure, const py::object& out_arg,
                          const py::object& region_arg) {
    const std::optional<std::array<long long, 4>> region = to_region(region_arg);
    const bool out_given = !out_arg.is_none();
    const bool bytes = format == par2d::PixelFormat::rgba8_srgb;
    const py::ssize_t channels = bytes ? 4 : 3, item = bytes ? 1 : static_cast<py::ssize_t>(sizeof(float));
    py::array image;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      const int width = renderer_.width(), height = renderer_.height();
      par2d::PixelRect rect{0, 0, width, height};
      if (region) {
        const auto& r = *region;
        if (r[0] < 0 || r[1] < 0 || r[2] > width || r[3] > height || r[0] >= r[2] || r[1] >= r[3]) {
          status = par2d::Status(par2d::StatusCode::invalid_argument,
                                 "region: (" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
                                     std::to_string(r[2]) + ", " + std::to_string(r[3]) +
                                     ") is not a non-empty rectangle inside the " + std::to_string(width) + "x" +
                                     std::to_string(height) + " frame");
        } else {
          rect = {static_cast<int>(r[0]), static_cast<int>(r[1]), static_cast<int>(r[2]), static_cast<int>(r[3])};
        }
      }
      const py::ssize_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
      if (status.ok() && out_given) {
        bool fits = py::isinstance<py::array>(out_arg);
        if (fits) {
          image = py::reinterpret_borrow<py::array>(out_arg);
          const bool dtype_ok =
              bytes ? py::isinstance<py::array_t<std::uint8_t>>(image) : py::isinstance<py::array_t<float>>(image);
          fits = dtype_ok && image.ndim() == 3 && image.shape(0) == h && image.shape(1) == w &&
                 image.shape(2) == channels && image.strides(2) == item && image.strides(1) == channels * item &&
                 image.strides(0) >= w * channels * item && image.writeable();
        }
        if (!fits)
          status = par2d::Status(par2d::StatusCode::invalid_argument,
                                 std::string("out: needs a writable ") + (bytes ? "uint8" : "float32") +
                                     " array of shape (" + std::to_string(h) + ", " + std::to_string(w) + ", " +
                                     std::to_string(channels) + ") with packed pixels (rows may be padded)");
      } else if (status.ok()) {
        try {
          if (bytes) image = py::array_t<std::uint8_t, py::array::c_style>({h, w, channels});
          else image = FloatArray({h, w, channels});
        } catch (py::error_already_set&) {
          PyErr_Clear();
          status = par2d::Status(par2d::StatusCode::out_of_memory,
                                 "out: no memory for a (" + std::to_string(h) + ", " + std::to_string(w) + ", " +
                                     std::to_string(channels) + ") array");
        }
      }
      if (status.ok()) {
        par2d::FrameBuffer buffer;
        buffer.data = image.mutable_data();
        buffer.format = format;
        buffer.row_stride = static_cast<std::ptrdiff_t>(image.strides(0));
        buffer.exposure = exposure;
        py::gil_scoped_release release;
        status = region ? renderer_.render(buffer, rect) : renderer_.render(buffer);
      }
    }
    check(status);
    return image;
  }

  mutable std::mutex mutex_;
  par2d::Renderer renderer_;
  std::vector<std::uint64_t> lights_, occluders_;
};

}  // namespace
PYBIND11_MODULE(par2d, m) {
  m.doc() = "Exact 2D soft shadows (Probabilistic Angular Radiance): scenes in, float32 RGB irradiance out.";
  m.attr("__version__") = par2d::kVersion;

  // One exception type with the status code attached; its message is par2d's one line.
  struct ErrorTag {};
  static py::exception<ErrorTag> error(m, "Error", PyExc_Exception);
  g_error_type = error.ptr();

  // pybind11 (2.10) sets up its NumPy API table on first use in a function-local static whose
  // initialization imports NumPy; two threads using an array for the first time at once can
  // deadlock there (one waits on the static holding the GIL, the other on the GIL inside it).
  // Using it once here, on the importing thread, settles it before any other thread can.
  FloatArray({py::ssize_t{1}, py::ssize_t{1}, py::ssize_t{3}});
  py::array_t<std::uint8_t, py::array::c_style>({py::ssize_t{1}, py::ssize_t{1}, py::ssize_t{4}});

  // A C++ allocation failure inside any call is par2d.Error("out_of_memory"), not MemoryError.
  py::register_local_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::bad_alloc&) {
      py::object e = py::reinterpret_borrow<py::object>(g_error_type)("out of memory");
      e.attr("code") = "out_of_memory";
      PyErr_SetObject(g_error_type, e.ptr());
    }
  });
  error.doc() =
      "A failed par2d call. str(e) is par2d's one-line message (`FILE: PLACE: what is wrong`); "
      "e.code names the kind: invalid_scene, invalid_argument, io_error, out_of_memory, unsupported.";

  py::class_<PyScene>(m, "Scene",
                      "A validated scene (docs/contract.md section 3). Build one with Scene.from_dict, "
                      "Scene.from_json or Scene.load; edit a copy of to_dict() and build again to change it.")
      .def_static("from_dict", &PyScene::from_dict, py::arg("scene"), py::arg("name") = "<dict>",
                  "Scene from a dict shaped like the JSON file; `name` prefixes error messages. A relative\n"
                  "normal_map path is read relative to the directory part of `name` (none: the current one).")
      .def_static("from_json", &PyScene::from_json, py::arg("text"), py::arg("name") = "<json>",
                  "Scene from JSON text; `name` prefixes error messages.")
      .def_static("load", &PyScene::load, py::arg("path"), "Scene from a JSON file (path: str or os.PathLike).")
      .def("to_dict", &PyScene::to_dict, "The scene as a new dict (color and intensity always written; the lighting-model terms only where they differ from their defaults).")
      .def("to_json", &PyScene::to_json, "The scene as JSON text that from_json reads back exactly.")
      .def("save", &PyScene::save, py::arg("path"), "Writes the scene as JSON (path: str or os.PathLike), atomically.")
      .def_property_readonly("width", [](const PyScene& s) { return s.scene().width; })
      .def_property_readonly("height", [](const PyScene& s) { return s.scene().height; })
      .def_property_readonly("shape", [](const PyScene& s) { return py::make_tuple(s.scene().height, s.scene().width, 3); },
                             "(height, width, 3): the shape of its rendered array.")
      .def_property_readonly("view", [](const PyScene& s) {
        const par2d::View& v = s.scene().view;
        return py::make_tuple(v.x0, v.y0, v.x1, v.y1);
      })
      .def_property_readonly("ambient", [](const PyScene& s) { return rgb_tuple(s.scene().ambient); },
                             "(r, g, b) added to every pixel.")
      .def_property_readonly("directional_lights", [](const PyScene& s) { return directional_dicts(s.scene().directional_lights); },
                             "List of dicts: angles, color, intensity, mask, elevation.")
      .def_property_readonly("normal", [](const PyScene& s) { return normal_tuple(s.scene().normal); },
                             "(nx, ny, nz) for every pixel, or None.")
      .def_property_readonly("normal_map", [](const PyScene& s) { return normal_map_array(s.scene().normal_map); },
                             "The normal map as a new float32 array (height, width, 3) in image axes (y up), or None.")
      .def_property_readonly("normal_map_path",
                             [](const PyScene& s) -> py::object {
                               if (!s.scene().normal_map) return py::none();
                               return py::str(s.scene().normal_map->path);
                             },
                             "The normal map's path as written in the scene, or None.")
      .def_property_readonly("light_count", [](const PyScene& s) { return s.scene().lights.size(); })
      .def_property_readonly("occluder_count", [](const PyScene& s) { return s.scene().occluders.size(); })
      .def("__repr__", [](const PyScene& s) {
        return "<par2d.Scene " + std::to_string(s.scene().width) + "x" + std::to_string(s.scene().height) + ", " +
               std::to_string(s.scene().lights.size()) + " lights, " + std::to_string(s.scene().occluders.size()) +
               " occluders>";
      });

  m.def("load_scene", &PyScene::load, py::arg("path"), "Scene from a JSON file (same as Scene.load).");

  m.def(
      "render",
      [](const py::object& scene_or_dict, const py::object& backend, const py::object& threads, const py::object& spp,
         const py::object& rays, const py::object& isa, const py::object& culling, const py::object& out,
         const py::object& shaded) {
        par2d::RenderOptions options = make_options(backend, threads, spp, to_int(rays, "rays"), isa, culling);
        options.shaded = to_bool(shaded, "shaded");
        std::optional<PyScene> holder;
        const PyScene& scene = as_scene(scene_or_dict, holder);
        py::array image;
        if (out.is_none()) {
          image = FloatArray({scene.scene().height, scene.scene().width, 3});
          render_into(scene.scene(), options, image, image);
        } else {
          render_into(scene.scene(), options, out, image);
        }
        return image;
      },
      py::arg("scene"), py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0, py::arg("spp") = 1,
      py::arg("rays") = 1024, py::arg("isa") = py::none(), py::arg("culling") = true, py::arg("out") = py::none(),
      py::arg("shaded") = true,
      "Linear irradiance of `scene` (a Scene or a dict) as a float32 array of shape (height, width, 3),\n"
      "row 0 at the top. backend: auto|simd|scalar|raycast; threads: 0 = all; spp: samples per pixel;\n"
      "rays: directions per sample for raycast; isa: cap the SIMD level (scalar|sse4|avx2|avx512);\n"
      "out: an existing array to fill instead of a new one; shaded=False: the plain irradiance of a scene\n"
      "with a normal source (no normal-map shading). The GIL is released while rendering.");

  py::class_<PyRenderer>(m, "Renderer",
                         "A persistent world of lights and occluders, changed through integer handles and\n"
                         "rendered frame after frame (par2d::Renderer, docs/api.md). Moving or recoloring a light\n"
                         "never rebuilds the occluder index. Lights and occluders are dicts shaped like one entry\n"
                         "of the scene file's lists. A refused update raises par2d.Error and changes nothing.")
      .def(py::init<const py::object&, const py::object&, const py::object&, const py::object&, const py::object&,
                    const py::object&>(),
           py::arg("scene") = py::none(), py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0,
           py::arg("isa") = py::none(), py::arg("spp") = 1, py::arg("culling") = true,
           "A renderer holding `scene` (a Scene or a dict), or an empty world (then call set_frame).\n"
           "backend: auto|simd|scalar (raycast is refused); threads: 0 = all.")
      .def("set_options", &PyRenderer::set_options, py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0,
           py::arg("isa") = py::none(), py::arg("spp") = 1, py::arg("culling") = true,
           "Backend, threads, isa cap, samples per pixel and culling for the next frames.")
      .def("set_scene", &PyRenderer::set_scene, py::arg("scene"),
           "Replaces the whole world (frame included); returns (light handles, occluder handles) in the scene's order.")
      .def("set_frame", &PyRenderer::set_frame, py::arg("width"), py::arg("height"), py::arg("view") = py::none(),
           "Lightmap size and the world rectangle (x0, y0, x1, y1) it shows (default (0, 0, width, height)).")
      .def("add_light", &PyRenderer::add_light, py::arg("light"), "Adds a light (dict); returns its handle.")
      .def("update_light", &PyRenderer::update_light, py::arg("handle"), py::arg("light"),
           "Replaces the light's shape, color and intensity.")
      .def("set_light_emission", &PyRenderer::set_light_emission, py::arg("handle"), py::arg("color"),
           py::arg("intensity"), "Changes only the color and intensity.")
      .def("remove_light", &PyRenderer::remove_light, py::arg("handle"))
      .def("add_occluder", &PyRenderer::add_occluder, py::arg("occluder"), "Adds an occluder (dict); returns its handle.")
      .def("update_occluder", &PyRenderer::update_occluder, py::arg("handle"), py::arg("occluder"))
      .def("remove_occluder", &PyRenderer::remove_occluder, py::arg("handle"))
      .def("render", &PyRenderer::render, py::kw_only(), py::arg("out") = py::none(), py::arg("region") = py::none(),
           "Linear irradiance as float32 (height, width, 3), or of region (x0, y0, x1, y1) only: then shape\n"
           "(y1 - y0, x1 - x0, 3), bit-identical to those pixels of the whole frame. out: an existing array\n"
           "to fill. The GIL is released while rendering.")
      .def("render_rgba8", &PyRenderer::render_rgba8, py::arg("exposure") = 1.0, py::kw_only(),
           py::arg("out") = py::none(), py::arg("region") = py::none(),
           "The frame as uint8 (height, width, 4): round(255 * srgb(clamp(exposure * E, 0, 1))), alpha 255 -\n"
           "the bytes write_png stores, written by the tiles directly.")
      .def("set_ambient", &PyRenderer::set_ambient, py::arg("rgb"), "Ambient (r, g, b), each >= 0, added to every pixel.")
      .def("set_directional_lights", &PyRenderer::set_directional_lights, py::arg("lights"),
           "Replaces the directional lights: a list of dicts like the scene file's directional_lights.")
      .def("set_normal", &PyRenderer::set_normal, py::arg("normal"),
           "One normal (nx, ny, nz) for every pixel, world axes; replaces a normal map.")
      .def("set_normal_map", &PyRenderer::set_normal_map, py::arg("normal_map"),
           "A PNG path or an array (height, width, 3) of normals in image axes (y up), exactly the frame's size.")
      .def("clear_normal_source", &PyRenderer::clear_normal_source, "No normal source: plain irradiance.")
      .def("snapshot", &PyRenderer::snapshot, "The world as a Scene; par2d.render of it gives the same image.")
      .def_property_readonly("stats", &PyRenderer::stats,
                             "dict: frames, index_builds, index_updates, reach_computations, full_prepares.")
      .def_property_readonly("lights", &PyRenderer::lights, "Handles of the lights, in the order they were added.")
      .def_property_readonly("occluders", &PyRenderer::occluders, "Handles of the occluders, in the order they were added.")
      .def_property_readonly("width", [](const PyRenderer& r) { return r.summary().width; })
      .def_property_readonly("height", [](const PyRenderer& r) { return r.summary().height; })
      .def_property_readonly("shape", [](const PyRenderer& r) {
        const PyRenderer::Summary s = r.summary();
        return py::make_tuple(s.height, s.width, 3);
      })
      .def_property_readonly("view", [](const PyRenderer& r) {
        const par2d::View v = r.summary().view;
        return py::make_tuple(v.x0, v.y0, v.x1, v.y1);
      })
      .def_property_readonly("threads", [](const PyRenderer& r) { return r.summary().threads; })
      .def("__repr__", [](const PyRenderer& r) {
        const PyRenderer::Summary s = r.summary();
        return "<par2d.Renderer " + std::to_string(s.width) + "x" + std::to_string(s.height) + ", " +
               std::to_string(s.light_count) + " lights, " + std::to_string(s.occluder_count) + " occluders>";
      });

  m.def(
      "write_png",
      [](const py::object& path_arg, const py::object& image_arg, const py::object& exposure_arg) {
        const std::string path = to_path(path_arg, "path");
        const FloatArray image = FloatArray::ensure(image_arg);
        if (!image || image.ndim() != 3 || image.shape(2) != 3)
          bad_argument("image", "needs a float32 array of shape (height, width, 3), got " + describe(image_arg));
        const double exposure = to_double(exposure_arg, "exposure");
        // ImageView takes a mutable pointer but write_png only reads; the array is C-contiguous.
        par2d::ImageView view{const_cast<float*>(image.data()), static_cast<int>(image.shape(1)),
                              static_cast<int>(image.shape(0)), static_cast<std::ptrdiff_t>(3 * image.shape(1))};
        check(par2d::write_png(path, view, exposure));
      },
      py::arg("path"), py::arg("image"), py::arg("exposure") = 1.0,
      "Writes clamp(exposure * image, 0, 1) as an 8-bit sRGB PNG (path: str or os.PathLike), atomically\n"
      "(as `par2d render -o`).");

  m.def("detect_isa", [] { return std::string(par2d::isa_name(par2d::detect_isa())); },
        "The best SIMD level this CPU supports: scalar, sse4, avx2 or avx512.");
  m.def("default_isa", [] { return std::string(par2d::isa_name(par2d::default_isa())); },
        "The level rendering uses by default: detect_isa() capped by the PAR2D_ISA environment variable.");
}
