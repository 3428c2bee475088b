// Python module: par2d.Error and argument conversion. Every argument arrives as a plain object
// and is converted here, so that a wrong one raises par2d.Error naming it (`region: needs (x0,
// y0, x1, y1) integers, got (0.5, 0, 4, 4)`), never pybind11's TypeError or cast error; numbers
// and handles are anything integer-like (__index__) or real, NumPy scalars included.
#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"

namespace par2d::python {
namespace {

// StatusCode as a Python identifier (status_code_name gives words meant for messages).
const char* code_identifier(par2d::StatusCode code) {
  switch (code) {
    case par2d::StatusCode::ok: return "ok";
    case par2d::StatusCode::invalid_argument: return "invalid_argument";
    case par2d::StatusCode::invalid_scene: return "invalid_scene";
    case par2d::StatusCode::io_error: return "io_error";
    case par2d::StatusCode::out_of_memory: return "out_of_memory";
    case par2d::StatusCode::unsupported: return "unsupported";
    case par2d::StatusCode::work_limit: return "work_limit";
    case par2d::StatusCode::cancelled: return "cancelled";
  }
  return "unknown";
}

bool is_text(const py::handle& obj) { return PyUnicode_Check(obj.ptr()) || PyBytes_Check(obj.ptr()); }

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

}  // namespace

PyObject* g_error_type = nullptr;
std::array<PyObject*, kStatusCodes> g_error_types{};

PyObject* error_type(par2d::StatusCode code) {
  const auto index = static_cast<std::size_t>(code);
  PyObject* type = index < g_error_types.size() ? g_error_types[index] : nullptr;
  return type != nullptr ? type : g_error_type;
}

void set_error(par2d::StatusCode code, const std::string& message) {
  PyObject* type = error_type(code);
  py::object error = py::reinterpret_borrow<py::object>(type)(message);
  error.attr("code") = code_identifier(code);
  PyErr_SetObject(type, error.ptr());
}

// Raises the par2d.Error subclass of the status code, `code` set to the code's name.
[[noreturn]] void raise(const par2d::Status& status) {
  set_error(status.code(), status.message());
  throw py::error_already_set();
}

[[noreturn]] void raise(par2d::StatusCode code, std::string message) { raise(par2d::Status(code, std::move(message))); }

void check(const par2d::Status& status) {
  if (!status.ok()) raise(status);
}

// ---- Arguments ---------------------------------------------------------------------------

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

// A 0-d NumPy array as the scalar it holds (numpy.array(3) is the number 3); anything else as is.
py::object unwrapped(const py::handle& obj) {
  if (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() == 0) {
    PyObject* item = PyObject_CallMethod(obj.ptr(), "item", nullptr);
    if (item != nullptr) return py::reinterpret_steal<py::object>(item);
    PyErr_Clear();
  }
  return py::reinterpret_borrow<py::object>(obj);
}

// An integer-like object (int, numpy.int64, a 0-d integer array, anything with __index__; not
// bool) as a long long.
std::optional<long long> as_integer(const py::handle& arg) {
  const py::object obj = unwrapped(arg);
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

// A real number (int, float, NumPy scalars and 0-d arrays, anything with __float__ or
// __index__; not bool or text).
std::optional<double> as_number(const py::handle& arg) {
  const py::object obj = unwrapped(arg);
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
    // Integer-like but not a long long: too large (a 0-d float array is index-like as a type,
    // not as a value, so it is judged by what it holds).
    const py::object held = unwrapped(obj);
    if (!PyBool_Check(held.ptr()) && PyIndex_Check(held.ptr())) bad_argument(place, describe(obj) + " is out of range");
    bad_argument(place, "must be an integer, not " + type_name(obj));
  }
  if (*value < std::numeric_limits<int>::min() || *value > std::numeric_limits<int>::max())
    bad_argument(place, std::to_string(*value) + " is out of range");
  return static_cast<int>(*value);
}

// A count or a byte size: an integer-like object from 0 to SIZE_MAX.
std::size_t to_size(const py::handle& arg, const char* place) {
  const py::object obj = unwrapped(arg);
  if (PyBool_Check(obj.ptr()) || !PyIndex_Check(obj.ptr()))
    bad_argument(place, "must be a non-negative integer, not " + type_name(arg));
  PyObject* index = PyNumber_Index(obj.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    bad_argument(place, "must be a non-negative integer, not " + type_name(arg));
  }
  const py::object value = py::reinterpret_steal<py::object>(index);
  const int negative = PyObject_RichCompareBool(value.ptr(), py::int_(0).ptr(), Py_LT);
  if (negative != 0) {
    PyErr_Clear();
    bad_argument(place, "must be >= 0, got " + describe(value));
  }
  const unsigned long long bytes = PyLong_AsUnsignedLongLong(value.ptr());
  if ((bytes == static_cast<unsigned long long>(-1) && PyErr_Occurred()) ||
      bytes > std::numeric_limits<std::size_t>::max()) {
    PyErr_Clear();
    bad_argument(place, describe(value) + " is out of range");
  }
  return static_cast<std::size_t>(bytes);
}

double to_double(const py::handle& obj, const char* place) {
  const std::optional<double> value = as_number(obj);
  if (!value) bad_argument(place, "must be a number, not " + type_name(obj));
  return *value;
}

bool to_bool(const py::handle& arg, const char* place) {
  const py::object obj = unwrapped(arg);
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

std::optional<par2d::Transform> to_transform(const py::handle& obj) {
  if (obj.is_none()) return std::nullopt;
  if (!PyDict_Check(obj.ptr()))
    bad_argument("transform", "needs a dict with position, rotation, scale, got " + describe(obj));
  par2d::Transform t;
  for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(obj)) {
    const std::string name = is_text(key) ? py::str(key).cast<std::string>() : std::string();
    if (name == "position" || (name == "scale" && !as_number(value))) {
      const auto items = as_items(value, 2);
      const std::optional<double> x = items ? as_number((*items)[0]) : std::nullopt;
      const std::optional<double> y = items ? as_number((*items)[1]) : std::nullopt;
      if (!x || !y)
        bad_argument("transform." + name, std::string(name == "position" ? "needs (x, y)" : "needs a number or (sx, sy)") +
                                              " numbers, got " + describe(value));
      (name == "position" ? t.position : t.scale) = par2d::Vec2{*x, *y};
    } else if (name == "scale") {
      t.scale = par2d::Vec2{*as_number(value), *as_number(value)};
    } else if (name == "rotation") {
      t.rotation = to_double(value, "transform.rotation");
    } else {
      bad_argument("transform", "unknown key " + describe(key) + " (expected position, rotation, scale)");
    }
  }
  return t;
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

par2d::RenderOptions make_options(const py::object& backend_arg, const py::object& threads, const py::object& spp,
                                  int rays, const py::object& isa_arg, const py::object& culling, bool* raycast) {
  par2d::RenderOptions options;
  const std::string backend = to_text(backend_arg, "backend");
  if (raycast) *raycast = backend == "raycast";
  if (backend == "raycast" && !raycast)
    raise(par2d::StatusCode::invalid_argument,
          "backend: \"raycast\" is the baseline of par2d.render, not a Renderer backend (auto, simd, scalar)");
  const auto parsed_backend = par2d::parse_backend(backend.c_str());
  if (!parsed_backend && !(raycast && *raycast))
    raise(par2d::StatusCode::invalid_argument, "backend: unknown name \"" + backend + "\" (auto, simd, scalar" +
                                                   (raycast ? ", raycast)" : ")"));
  if (parsed_backend) options.backend = *parsed_backend;
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

par2d::BounceTerm to_bounce_term(const py::object& obj) {
  const std::string name = to_text(obj, "bounce");
  const auto term = par2d::parse_bounce_term(name.c_str());
  if (!term) raise(par2d::StatusCode::invalid_argument, "bounce: unknown name \"" + name + "\" (included, excluded, only)");
  return *term;
}

}  // namespace par2d::python
