// Python bindings (`import par2d`): scenes from dicts, JSON text or files, rendered into NumPy float32 arrays.
//
// Only the public C++ API (include/par2d/) is used. Scenes cross into C++ as JSON text, so a
// dict is checked by the same loader as a file and its errors read the same
// (`<dict>: lights[2].polygon: not convex at vertex 3`, docs/contract.md section 3).
// Rendering goes through render_into(), the one place that touches the output array and
// releases the GIL: a persistent Renderer class can reuse it unchanged.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <utility>

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

const PyScene& as_scene(const py::object& scene, std::optional<PyScene>& holder) {
  if (py::isinstance<PyScene>(scene)) return scene.cast<const PyScene&>();
  holder = PyScene::from_dict(scene, "<dict>");
  return *holder;
}

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
                  "Scene from a dict shaped like the JSON file; `name` prefixes error messages.")
      .def_static("from_json", &PyScene::from_json, py::arg("text"), py::arg("name") = "<json>",
                  "Scene from JSON text; `name` prefixes error messages.")
      .def_static("load", &PyScene::load, py::arg("path"), "Scene from a JSON file.")
      .def("to_dict", &PyScene::to_dict, "The scene as a new dict (every default written out).")
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
         const std::optional<std::string>& isa, bool culling, std::optional<py::array> out) {
        std::optional<PyScene> holder;
        const PyScene& scene = as_scene(scene_or_dict, holder);
        const par2d::RenderOptions options = make_options(backend, threads, spp, rays, isa, culling);
        py::array image = out ? *out : py::array(FloatArray({scene.scene().height, scene.scene().width, 3}));
        render_into(scene.scene(), options, image);
        return image;
      },
      py::arg("scene"), py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0, py::arg("spp") = 1,
      py::arg("rays") = 1024, py::arg("isa") = py::none(), py::arg("culling") = true, py::arg("out") = py::none(),
      "Linear irradiance of `scene` (a Scene or a dict) as a float32 array of shape (height, width, 3),\n"
      "row 0 at the top. backend: auto|simd|scalar|raycast; threads: 0 = all; spp: samples per pixel;\n"
      "rays: directions per sample for raycast; isa: cap the SIMD level (scalar|sse4|avx2|avx512);\n"
      "out: an existing array to fill instead of a new one. The GIL is released while rendering.");

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
