// Python module: scenes. Dicts cross into C++ as JSON text, so a dict is checked by the same
// loader as a file and its errors read the same (`<dict>: lights[2].polygon: edges 1 and 3
// cross`, docs/contract.md section 3); par2d.Scene wraps a validated par2d::Scene; normal
// maps, lights and occluders given to a Renderer are converted here too.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "bindings.hpp"

namespace par2d::python {

// ---- Dicts as JSON ------------------------------------------------------------------------
// Dicts cross into C++ as JSON text for the scene loader. JSON has no NaN or infinity, and
// json.dumps would write them as bare tokens that the loader can only place by column; so
// the dict is walked first and such a value is reported at its path, in the loader's words
// (`lights[0].intensity: not a finite number (nan)`), as is anything JSON cannot hold.

namespace {

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

// `obj` as plain JSON values (dict, list, str, int, float, bool, None) in `out`, or the first
// value on the way that JSON cannot hold. NumPy arrays become (nested) lists and NumPy scalars
// and 0-d arrays the Python numbers they hold, so a dict built with NumPy reads exactly as the
// same dict built with lists; other numbers (anything with __index__ or __float__) become the
// int or float they stand for.
std::optional<JsonProblem> to_plain(const py::handle& obj, const std::string& place, int depth, py::object& out) {
  if (depth > kMaxJsonDepth) return JsonProblem{place, "nested too deeply (more than 64 levels)"};
  PyObject* p = obj.ptr();
  out = py::reinterpret_borrow<py::object>(obj);
  if (p == Py_None || PyBool_Check(p) || PyUnicode_Check(p) || PyLong_Check(p)) return std::nullopt;
  if (PyFloat_Check(p)) {
    const double v = PyFloat_AS_DOUBLE(p);
    if (!std::isfinite(v)) return JsonProblem{place, "not a finite number (" + format_number(v) + ")"};
    out = py::float_(v);  // numpy.float64 is a float subclass: written as a plain float
    return std::nullopt;
  }
  if (PyDict_Check(p)) {
    py::dict plain;
    for (auto item : py::reinterpret_borrow<py::dict>(obj)) {
      if (!PyUnicode_Check(item.first.ptr()))
        return JsonProblem{place, "a key must be a string, not " + type_name(item.first)};
      py::object value;
      if (auto problem = to_plain(item.second, member_place(place, item.first), depth + 1, value)) return problem;
      plain[item.first] = value;
    }
    out = std::move(plain);
    return std::nullopt;
  }
  if (PyList_Check(p) || PyTuple_Check(p)) {
    const py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
    py::list plain(seq.size());
    for (std::size_t i = 0; i < seq.size(); ++i) {
      py::object value;
      if (auto problem = to_plain(seq[i], place + "[" + std::to_string(i) + "]", depth + 1, value)) return problem;
      PyList_SET_ITEM(plain.ptr(), static_cast<Py_ssize_t>(i), value.release().ptr());
    }
    out = std::move(plain);
    return std::nullopt;
  }
  if (py::isinstance<py::array>(obj)) {
    // tolist() gives Python numbers (a 0-d array: the one it holds), checked like any others.
    PyObject* list = PyObject_CallMethod(p, "tolist", nullptr);
    if (list == nullptr) {
      PyErr_Clear();
      return JsonProblem{place, a_type(obj) + " is not a JSON value"};
    }
    return to_plain(py::reinterpret_steal<py::object>(list), place, depth, out);
  }
  if (py::isinstance(obj, py::module_::import("numpy").attr("bool_"))) {
    out = py::bool_(PyObject_IsTrue(p) == 1);
    return std::nullopt;
  }
  if (PyIndex_Check(p)) {
    PyObject* index = PyNumber_Index(p);
    if (index != nullptr) {
      out = py::reinterpret_steal<py::object>(index);
      return std::nullopt;
    }
    PyErr_Clear();
  }
  if (const std::optional<double> v = as_number(obj)) {
    if (!std::isfinite(*v)) return JsonProblem{place, "not a finite number (" + format_number(*v) + ")"};
    out = py::float_(*v);
    return std::nullopt;
  }
  return JsonProblem{place, a_type(obj) + " is not a JSON value"};
}

}  // namespace

// JSON text of a dict or list, converted to plain JSON values first (see to_plain).
std::string json_text(const py::handle& obj, const std::string& name, const std::string& root) {
  py::object plain;
  if (auto problem = to_plain(obj, root, 0, plain))
    raise(par2d::StatusCode::invalid_scene,
          name + ": " + (problem->place.empty() ? "" : problem->place + ": ") + problem->what);
  try {
    return py::module_::import("json").attr("dumps")(plain).cast<std::string>();
  } catch (py::error_already_set& e) {
    raise(par2d::StatusCode::invalid_scene, name + ": " + one_line(e));
  }
}

// ---- Scenes ---------------------------------------------------------------------------------

namespace {

par2d::LoadOptions to_load_options(const py::object& allow_any_path) {
  par2d::LoadOptions options;
  options.allow_any_path = to_bool(allow_any_path, "allow_any_path");
  return options;
}

}  // namespace

PyScene PyScene::from_json_text(const std::string& text, const std::string& name, const par2d::LoadOptions& options) {
  par2d::Scene scene;
  check(par2d::parse_scene(text, name, scene, options));
  return PyScene(std::move(scene));
}

PyScene PyScene::from_json(const py::object& text, const py::object& name, const py::object& allow_any_path) {
  const std::string n = to_text(name, "name");
  const par2d::LoadOptions options = to_load_options(allow_any_path);
  return from_json_text(to_text(text, "text"), n, options);
}

PyScene PyScene::from_dict_named(const py::object& dict, const std::string& name, const par2d::LoadOptions& options) {
  if (!py::isinstance<py::dict>(dict))
    raise(par2d::StatusCode::invalid_scene, name + ": a scene must be a dict, not " + type_name(dict));
  return from_json_text(json_text(dict, name, ""), name, options);
}

PyScene PyScene::from_dict(const py::object& dict, const py::object& name, const py::object& allow_any_path) {
  const std::string n = to_text(name, "name");
  return from_dict_named(dict, n, to_load_options(allow_any_path));
}

PyScene PyScene::load(const py::object& path, const py::object& allow_any_path) {
  const std::string p = to_path(path, "path");
  const par2d::LoadOptions options = to_load_options(allow_any_path);
  par2d::Scene scene;
  check(par2d::load_scene_file(p, scene, options));
  return PyScene(std::move(scene));
}

std::string PyScene::to_json() const { return par2d::scene_to_json(scene_); }
py::object PyScene::to_dict() const { return py::module_::import("json").attr("loads")(to_json()); }
void PyScene::save(const py::object& path) const { check(par2d::save_scene_file(to_path(path, "path"), scene_)); }

// The `scene` argument: a Scene, or a dict checked by the loader under the name "<dict>".
const PyScene& as_scene(const py::object& scene, std::optional<PyScene>& holder) {
  if (py::isinstance<PyScene>(scene)) return scene.cast<const PyScene&>();
  if (!py::isinstance<py::dict>(scene)) bad_argument("scene", "must be a par2d.Scene or a dict, not " + type_name(scene));
  holder = PyScene::from_dict_named(scene, "<dict>", par2d::LoadOptions{});
  return *holder;
}

namespace {

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

}  // namespace

NormalMapSource to_normal_map_source(const py::object& source) {
  NormalMapSource out;
  if (PyUnicode_Check(source.ptr()) || PyObject_HasAttrString(source.ptr(), "__fspath__")) {
    out.png_path = to_path(source, "normal_map");
    return out;
  }
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(source);
  if (!a || a.ndim() != 3 || a.shape(2) != 3)
    bad_argument("normal_map", "needs a PNG path or an array of shape (height, width, 3), got " + describe(source));
  out.map.height = static_cast<int>(a.shape(0));
  out.map.width = static_cast<int>(a.shape(1));
  out.map.normals.assign(a.data(), a.data() + a.size());
  return out;
}

par2d::NormalMap load_normal_map(const std::string& path, int width, int height) {
  par2d::NormalMap map;
  par2d::Status status;
  {
    py::gil_scoped_release release;
    status = width > 0 && height > 0 ? par2d::load_normal_map_png(path, map, width, height)
                                     : par2d::load_normal_map_png(path, map);
  }
  check(status);
  return map;
}

par2d::Light parse_light(const py::object& dict, const std::string& name) {
  return parse_entry<par2d::Light>(dict, "lights", name);
}

par2d::Occluder parse_occluder(const py::object& dict, const std::string& name) {
  return parse_entry<par2d::Occluder>(dict, "occluders", name);
}

void bind_scene(py::module_& m) {
  // docs/contract.md section 6's folder rule, as every loader's docstring states it.
  const std::string policy =
      "A scene's normal_map must be a relative path that stays inside the scene's folder; an absolute\n"
      "path or one that leaves it is refused before anything is opened. allow_any_path=True accepts any\n"
      "path (trusted scenes only).";
  py::class_<PyScene>(m, "Scene",
                      "A validated scene (docs/contract.md section 3). Build one with Scene.from_dict, "
                      "Scene.from_json or Scene.load; edit a copy of to_dict() and build again to change it.")
      .def_static("from_dict", &PyScene::from_dict, py::arg("scene"), py::arg("name") = "<dict>", py::kw_only(),
                  py::arg("allow_any_path") = false,
                  ("Scene from a dict shaped like the JSON file; `name` prefixes error messages. A relative\n"
                   "normal_map path is read relative to the directory part of `name` (none: the current one).\n" +
                   policy)
                      .c_str())
      .def_static("from_json", &PyScene::from_json, py::arg("text"), py::arg("name") = "<json>", py::kw_only(),
                  py::arg("allow_any_path") = false,
                  ("Scene from JSON text; `name` prefixes error messages and its directory part is the scene's\n"
                   "folder (none: the current one).\n" +
                   policy)
                      .c_str())
      .def_static("load", &PyScene::load, py::arg("path"), py::kw_only(), py::arg("allow_any_path") = false,
                  ("Scene from a JSON file (path: str or os.PathLike).\n" + policy).c_str())
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

  m.def("load_scene", &PyScene::load, py::arg("path"), py::kw_only(), py::arg("allow_any_path") = false,
        "Scene from a JSON file (same as Scene.load).");
}

}  // namespace par2d::python
