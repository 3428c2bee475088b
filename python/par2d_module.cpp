// Python bindings (`import par2d`): scenes from dicts, JSON text or files, rendered into NumPy float32 arrays.
//
// Only the public C++ API (include/par2d/) is used. Scenes cross into C++ as JSON text, so a
// dict is checked by the same loader as a file and its errors read the same
// (`<dict>: lights[2].polygon: not convex at vertex 3`, docs/contract.md section 3).
// Rendering goes through render_into(), the one place that touches the output array and
// releases the GIL. par2d.Renderer wraps par2d::Renderer: a world kept across frames, changed
// through integer handles, rendered into float32 or sRGB uint8 arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
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

// A validated scene. Immutable from Python: edit its dict and build a new one, so a Scene
// object is always one that renders.
class PyScene {
 public:
  explicit PyScene(par2d::Scene scene) : scene_(std::move(scene)) {}

  static PyScene from_json(const std::string& text, const std::string& name) {
    par2d::Scene scene;
    check(par2d::parse_scene(text, name, scene));
    return PyScene(std::move(scene));
  }

  static PyScene from_dict(const py::object& dict, const std::string& name) {
    if (!py::isinstance<py::dict>(dict))
      raise(par2d::StatusCode::invalid_scene, name + ": a scene must be a dict, not " +
                                                  py::str(py::type::of(dict).attr("__name__")).cast<std::string>());
    // NaN and infinities become bare tokens that the loader refuses with their place.
    const py::object dumps = py::module_::import("json").attr("dumps");
    std::string text;
    try {
      text = dumps(dict).cast<std::string>();
    } catch (py::error_already_set& e) {
      // Not representable as JSON at all (a set, an object): say so in par2d's form.
      raise(par2d::StatusCode::invalid_scene, name + ": " + py::str(e.value()).cast<std::string>());
    }
    return from_json(text, name);
  }

  static PyScene load(const std::string& path) {
    par2d::Scene scene;
    check(par2d::load_scene_file(path, scene));
    return PyScene(std::move(scene));
  }

  const par2d::Scene& scene() const { return scene_; }
  std::string to_json() const { return par2d::scene_to_json(scene_); }
  py::object to_dict() const { return py::module_::import("json").attr("loads")(to_json()); }
  void save(const std::string& path) const { check(par2d::save_scene_file(path, scene_)); }

 private:
  par2d::Scene scene_;
};

par2d::RenderOptions make_options(const std::string& backend, int threads, int spp, int rays,
                                  const std::optional<std::string>& isa, bool culling) {
  par2d::RenderOptions options;
  const auto parsed_backend = par2d::parse_backend(backend.c_str());
  if (!parsed_backend)
    raise(par2d::StatusCode::invalid_argument, "backend: unknown name \"" + backend + "\" (auto, simd, scalar, raycast)");
  options.backend = *parsed_backend;
  if (isa) {
    options.isa = par2d::parse_isa(*isa);
    if (!options.isa) raise(par2d::StatusCode::invalid_argument, "isa: unknown name \"" + *isa + "\" (scalar, sse4, avx2, avx512)");
  }
  options.threads = threads;
  options.spp = spp;
  options.rays = rays;
  options.culling = culling;
  return options;
}

using FloatArray = py::array_t<float, py::array::c_style>;

// Renders into `out`, an (H, W, 3) float32 array whose pixels and channels are packed (rows
// may be padded), with the GIL released so other Python threads run meanwhile.
void render_into(const par2d::Scene& scene, const par2d::RenderOptions& options, py::array& out) {
  if (!py::isinstance<py::array_t<float>>(out) || out.ndim() != 3 || out.shape(2) != 3 ||
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
  if (py::isinstance<py::str>(source)) {
    check(par2d::load_normal_map_png(source.cast<std::string>(), map));
    return map;
  }
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(source);
  if (!a || a.ndim() != 3 || a.shape(2) != 3)
    raise(par2d::StatusCode::invalid_argument, "normal_map: needs a PNG path or an array of shape (height, width, 3)");
  map.height = static_cast<int>(a.shape(0));
  map.width = static_cast<int>(a.shape(1));
  map.normals.assign(a.data(), a.data() + a.size());
  return map;
}

const PyScene& as_scene(const py::object& scene, std::optional<PyScene>& holder) {
  if (py::isinstance<PyScene>(scene)) return scene.cast<const PyScene&>();
  holder = PyScene::from_dict(scene, "<dict>");
  return *holder;
}

// One light or occluder from a dict shaped like an entry of the scene file's "lights" or
// "occluders" list: parsed by the scene loader inside a one-entry scene, so it is checked by
// the same rules, and the loader's "lights[0]." prefix is dropped from its messages.
template <typename T>
T parse_entry(const py::object& dict, const char* list, const std::string& name) {
  if (!py::isinstance<py::dict>(dict))
    raise(par2d::StatusCode::invalid_scene, name + ": must be a dict, not " +
                                                py::str(py::type::of(dict).attr("__name__")).cast<std::string>());
  py::dict wrapper;
  wrapper["width"] = 1;
  wrapper["height"] = 1;
  wrapper[list] = py::make_tuple(dict);
  std::string text;
  try {
    text = py::module_::import("json").attr("dumps")(wrapper).cast<std::string>();
  } catch (py::error_already_set& e) {
    raise(par2d::StatusCode::invalid_scene, name + ": " + py::str(e.value()).cast<std::string>());
  }
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

// (x0, y0, x1, y1) pixels of the frame, or None for the whole frame.
par2d::PixelRect to_rect(const std::optional<py::tuple>& region, int width, int height) {
  if (!region) return {0, 0, width, height};
  if (region->size() != 4) raise(par2d::StatusCode::invalid_argument, "region: needs (x0, y0, x1, y1)");
  par2d::PixelRect rect;
  rect.x0 = (*region)[0].cast<int>();
  rect.y0 = (*region)[1].cast<int>();
  rect.x1 = (*region)[2].cast<int>();
  rect.y1 = (*region)[3].cast<int>();
  // The library checks the rectangle too; the array shape needs it sane first.
  if (rect.x0 < 0 || rect.y0 < 0 || rect.x1 > width || rect.y1 > height || rect.x0 >= rect.x1 || rect.y0 >= rect.y1)
    raise(par2d::StatusCode::invalid_argument,
          "region: (" + std::to_string(rect.x0) + ", " + std::to_string(rect.y0) + ", " + std::to_string(rect.x1) +
              ", " + std::to_string(rect.y1) + ") is not a non-empty rectangle inside the " + std::to_string(width) +
              "x" + std::to_string(height) + " frame");
  return rect;
}

// A handle from Python: any int; one that no 64-bit id can be (negative, too large, not an
// int) is refused as the library refuses unknown ids, not with pybind11's TypeError.
std::uint64_t handle_id(const py::object& handle, const char* kind) {
  if (PyLong_Check(handle.ptr()) && !PyBool_Check(handle.ptr())) {
    const unsigned long long value = PyLong_AsUnsignedLongLong(handle.ptr());
    if (!(value == static_cast<unsigned long long>(-1) && PyErr_Occurred())) return value;
    PyErr_Clear();  // negative or above 2**64 - 1
  }
  raise(par2d::StatusCode::invalid_argument,
        std::string("unknown ") + kind + " handle " + py::repr(handle).cast<std::string>());
}

// par2d::Renderer for Python: a persistent world changed through integer handles. Calls
// from several Python threads are serialized by a mutex (the C++ class is one-thread-at-a-time);
// render releases the GIL while it holds the mutex.
class PyRenderer {
 public:
  PyRenderer(const std::optional<py::object>& scene, const std::string& backend, int threads,
             const std::optional<std::string>& isa, int spp, bool culling) {
    set_options(backend, threads, isa, spp, culling);
    if (scene) set_scene(*scene);
  }

  void set_options(const std::string& backend, int threads, const std::optional<std::string>& isa, int spp,
                   bool culling) {
    const par2d::RenderOptions options = make_options(backend, threads, spp, 1024, isa, culling);
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_options(options));
  }

  py::tuple set_scene(const py::object& scene_or_dict) {
    std::optional<PyScene> holder;
    const PyScene& scene = as_scene(scene_or_dict, holder);
    std::vector<par2d::LightHandle> lights;
    std::vector<par2d::OccluderHandle> occluders;
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_scene(scene.scene(), &lights, &occluders));
    lights_.clear();
    occluders_.clear();
    for (const auto& h : lights) lights_.push_back(h.id);
    for (const auto& h : occluders) occluders_.push_back(h.id);
    return py::make_tuple(lights_, occluders_);
  }

  void set_frame(int width, int height, const std::optional<py::tuple>& view) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!view) {
      check(renderer_.set_frame(width, height));
      return;
    }
    if (view->size() != 4) raise(par2d::StatusCode::invalid_argument, "view: needs (x0, y0, x1, y1)");
    const par2d::View v{(*view)[0].cast<double>(), (*view)[1].cast<double>(), (*view)[2].cast<double>(),
                        (*view)[3].cast<double>()};
    check(renderer_.set_frame(width, height, v));
  }

  std::uint64_t add_light(const py::object& dict) {
    const par2d::Light light = parse_entry<par2d::Light>(dict, "lights", "add_light");
    std::lock_guard<std::mutex> lock(mutex_);
    par2d::LightHandle handle;
    check(renderer_.add_light(light, &handle));
    lights_.push_back(handle.id);
    return handle.id;
  }
  void update_light(const py::object& handle, const py::object& dict) {
    const std::uint64_t id = handle_id(handle, "light");
    const par2d::Light light = parse_entry<par2d::Light>(dict, "lights", "light " + std::to_string(id));
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.update_light(par2d::LightHandle{id}, light));
  }
  void set_light_emission(const py::object& handle, const std::vector<double>& color, double intensity) {
    const std::uint64_t id = handle_id(handle, "light");
    if (color.size() != 3) raise(par2d::StatusCode::invalid_argument, "light " + std::to_string(id) + ": color needs 3 numbers");
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_light_emission(par2d::LightHandle{id}, par2d::Rgb{color[0], color[1], color[2]}, intensity));
  }
  void remove_light(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "light");
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.remove_light(par2d::LightHandle{id}));
    lights_.erase(std::remove(lights_.begin(), lights_.end(), id), lights_.end());
  }

  std::uint64_t add_occluder(const py::object& dict) {
    const par2d::Occluder occluder = parse_entry<par2d::Occluder>(dict, "occluders", "add_occluder");
    std::lock_guard<std::mutex> lock(mutex_);
    par2d::OccluderHandle handle;
    check(renderer_.add_occluder(occluder, &handle));
    occluders_.push_back(handle.id);
    return handle.id;
  }
  void update_occluder(const py::object& handle, const py::object& dict) {
    const std::uint64_t id = handle_id(handle, "occluder");
    const par2d::Occluder occluder = parse_entry<par2d::Occluder>(dict, "occluders", "occluder " + std::to_string(id));
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.update_occluder(par2d::OccluderHandle{id}, occluder));
  }
  void remove_occluder(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "occluder");
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.remove_occluder(par2d::OccluderHandle{id}));
    occluders_.erase(std::remove(occluders_.begin(), occluders_.end(), id), occluders_.end());
  }

  // Float RGB frame (or region) into `out` or a new (h, w, 3) float32 array.
  py::array render(std::optional<py::array> out, const std::optional<py::tuple>& region) {
    return render_format(par2d::PixelFormat::rgb_f32, 1.0, std::move(out), region);
  }
  py::array render_rgba8(double exposure, std::optional<py::array> out, const std::optional<py::tuple>& region) {
    return render_format(par2d::PixelFormat::rgba8_srgb, exposure, std::move(out), region);
  }

  py::dict stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    const par2d::RendererStats s = renderer_.stats();
    py::dict d;
    d["frames"] = s.frames;
    d["index_builds"] = s.index_builds;
    d["index_updates"] = s.index_updates;
    d["reach_computations"] = s.reach_computations;
    d["full_prepares"] = s.full_prepares;
    return d;
  }

  // The scene-wide lighting-model terms (docs/contract.md section 6).
  void set_ambient(const std::vector<double>& rgb) {
    if (rgb.size() != 3) raise(par2d::StatusCode::invalid_argument, "set_ambient: needs 3 numbers (r, g, b)");
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_ambient({rgb[0], rgb[1], rgb[2]}));
  }
  // A list of dicts shaped like the scene file's "directional_lights", checked by its loader.
  void set_directional_lights(const py::object& list) {
    py::dict wrapper;
    wrapper["width"] = 1;
    wrapper["height"] = 1;
    wrapper["directional_lights"] = list;
    std::string text;
    try {
      text = py::module_::import("json").attr("dumps")(wrapper).cast<std::string>();
    } catch (py::error_already_set& e) {
      raise(par2d::StatusCode::invalid_scene, "set_directional_lights: " + py::str(e.value()).cast<std::string>());
    }
    par2d::Scene scene;
    check(par2d::parse_scene(text, "set_directional_lights", scene));
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_directional_lights(scene.directional_lights));
  }
  void set_normal(const std::vector<double>& n) {
    if (n.size() != 3) raise(par2d::StatusCode::invalid_argument, "set_normal: needs 3 numbers (nx, ny, nz)");
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_normal({n[0], n[1], n[2]}));
  }
  void set_normal_map(const py::object& source) {
    const par2d::NormalMap map = to_normal_map(source);
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.set_normal_map(map));
  }
  void clear_normal_source() {
    std::lock_guard<std::mutex> lock(mutex_);
    check(renderer_.clear_normal_source());
  }

  PyScene snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return PyScene(renderer_.snapshot());
  }
  const par2d::Renderer& renderer() const { return renderer_; }
  const std::vector<std::uint64_t>& lights() const { return lights_; }
  const std::vector<std::uint64_t>& occluders() const { return occluders_; }

 private:
  py::array render_format(par2d::PixelFormat format, double exposure, std::optional<py::array> out,
                          const std::optional<py::tuple>& region) {
    const int width = renderer_.width(), height = renderer_.height();
    const par2d::PixelRect rect = to_rect(region, width, height);
    const py::ssize_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
    const bool bytes = format == par2d::PixelFormat::rgba8_srgb;
    const py::ssize_t channels = bytes ? 4 : 3, item = bytes ? 1 : static_cast<py::ssize_t>(sizeof(float));
    py::array image;
    if (out) {
      image = *out;
      const bool dtype_ok = bytes ? py::isinstance<py::array_t<std::uint8_t>>(image) : py::isinstance<py::array_t<float>>(image);
      if (!dtype_ok || image.ndim() != 3 || image.shape(0) != h || image.shape(1) != w || image.shape(2) != channels ||
          image.strides(2) != item || image.strides(1) != channels * item || image.strides(0) < w * channels * item ||
          !image.writeable())
        raise(par2d::StatusCode::invalid_argument,
              std::string("out: needs a writable ") + (bytes ? "uint8" : "float32") + " array of shape (" +
                  std::to_string(h) + ", " + std::to_string(w) + ", " + std::to_string(channels) +
                  ") with packed pixels (rows may be padded)");
    } else if (bytes) {
      image = py::array_t<std::uint8_t, py::array::c_style>({h, w, channels});
    } else {
      image = FloatArray({h, w, channels});
    }
    par2d::FrameBuffer buffer;
    buffer.data = image.mutable_data();
    buffer.format = format;
    buffer.row_stride = static_cast<std::ptrdiff_t>(image.strides(0));
    buffer.exposure = exposure;
    par2d::Status status;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      status = renderer_.render(buffer, rect);
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
      .def_static("load", &PyScene::load, py::arg("path"), "Scene from a JSON file.")
      .def("to_dict", &PyScene::to_dict, "The scene as a new dict (color and intensity always written; the lighting-model terms only where they differ from their defaults).")
      .def("to_json", &PyScene::to_json, "The scene as JSON text that from_json reads back exactly.")
      .def("save", &PyScene::save, py::arg("path"), "Writes the scene as JSON, atomically.")
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
      [](const py::object& scene_or_dict, const std::string& backend, int threads, int spp, int rays,
         const std::optional<std::string>& isa, bool culling, std::optional<py::array> out, bool shaded) {
        std::optional<PyScene> holder;
        const PyScene& scene = as_scene(scene_or_dict, holder);
        par2d::RenderOptions options = make_options(backend, threads, spp, rays, isa, culling);
        options.shaded = shaded;
        py::array image = out ? *out : py::array(FloatArray({scene.scene().height, scene.scene().width, 3}));
        render_into(scene.scene(), options, image);
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
      .def(py::init<const std::optional<py::object>&, const std::string&, int, const std::optional<std::string>&, int,
                    bool>(),
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
      .def_property_readonly("width", [](const PyRenderer& r) { return r.renderer().width(); })
      .def_property_readonly("height", [](const PyRenderer& r) { return r.renderer().height(); })
      .def_property_readonly("shape", [](const PyRenderer& r) {
        return py::make_tuple(r.renderer().height(), r.renderer().width(), 3);
      })
      .def_property_readonly("view", [](const PyRenderer& r) {
        const par2d::View& v = r.renderer().view();
        return py::make_tuple(v.x0, v.y0, v.x1, v.y1);
      })
      .def_property_readonly("threads", [](const PyRenderer& r) { return r.renderer().threads(); })
      .def("__repr__", [](const PyRenderer& r) {
        return "<par2d.Renderer " + std::to_string(r.renderer().width()) + "x" + std::to_string(r.renderer().height()) +
               ", " + std::to_string(r.renderer().light_count()) + " lights, " +
               std::to_string(r.renderer().occluder_count()) + " occluders>";
      });

  m.def(
      "write_png",
      [](const std::string& path, const FloatArray& image, double exposure) {
        if (image.ndim() != 3 || image.shape(2) != 3)
          raise(par2d::StatusCode::invalid_argument, path + ": image must have shape (height, width, 3)");
        // ImageView takes a mutable pointer but write_png only reads; the array is C-contiguous.
        par2d::ImageView view{const_cast<float*>(image.data()), static_cast<int>(image.shape(1)),
                              static_cast<int>(image.shape(0)), static_cast<std::ptrdiff_t>(3 * image.shape(1))};
        check(par2d::write_png(path, view, exposure));
      },
      py::arg("path"), py::arg("image"), py::arg("exposure") = 1.0,
      "Writes clamp(exposure * image, 0, 1) as an 8-bit sRGB PNG, atomically (as `par2d render -o`).");

  m.def("detect_isa", [] { return std::string(par2d::isa_name(par2d::detect_isa())); },
        "The best SIMD level this CPU supports: scalar, sse4, avx2 or avx512.");
  m.def("default_isa", [] { return std::string(par2d::isa_name(par2d::default_isa())); },
        "The level rendering uses by default: detect_isa() capped by the PAR2D_ISA environment variable.");
}
