// What the Python module's files share (internal to the module): par2d.Error, argument
// conversion, scene conversion and the Scene class, and each file's binding function.
//
// Every argument arrives as a plain object and is converted by the functions below, so that a
// wrong one raises par2d.Error naming it (`region: needs (x0, y0, x1, y1) integers, got (0.5,
// 0, 4, 4)`), never pybind11's TypeError or cast error. Every failed par2d call raises
// par2d.Error with the library's one-line message.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "par2d/par2d.hpp"

namespace par2d::python {

namespace py = pybind11;

using FloatArray = py::array_t<float, py::array::c_style>;

// ---- Errors (arguments.cpp) -------------------------------------------------------------------

// par2d.Error and its subclass per status code, created in PYBIND11_MODULE (par2d_module.cpp);
// every failed par2d call raises the subclass of its code, which is also the built-in exception
// a Python user expects (an invalid argument is a ValueError, an I/O failure an OSError).
inline constexpr std::size_t kStatusCodes = 8;  // StatusCode's values, ok included
extern PyObject* g_error_type;
extern std::array<PyObject*, kStatusCodes> g_error_types;  // by StatusCode value; ok: nullptr
PyObject* error_type(par2d::StatusCode code);  // the subclass (par2d.Error when none)

// Sets (without throwing) the Python error of `code`: its class, `message`, `e.code`.
void set_error(par2d::StatusCode code, const std::string& message);
// Raise the par2d.Error subclass of the status code with `code` set to the code's name
// ("invalid_scene", ...).
[[noreturn]] void raise(const par2d::Status& status);
[[noreturn]] void raise(par2d::StatusCode code, std::string message);
void check(const par2d::Status& status);

// ---- Arguments (arguments.cpp) ----------------------------------------------------------------
// Each converter names the argument (`place`) in its error, one line, code invalid_argument.
// Numbers and handles are anything integer-like (__index__) or real, NumPy scalars included.

[[noreturn]] void bad_argument(const std::string& place, const std::string& what);
std::string type_name(const py::handle& obj);
std::string a_type(const py::handle& obj);   // "a set", "an ndarray"
std::string describe(const py::handle& obj);  // a short repr, or a_type when that is long or odd
std::string one_line(const py::error_already_set& e);
std::optional<long long> as_integer(const py::handle& obj);
std::optional<double> as_number(const py::handle& obj);

int to_int(const py::handle& obj, const char* place);
std::size_t to_size(const py::handle& obj, const char* place);
double to_double(const py::handle& obj, const char* place);
bool to_bool(const py::handle& obj, const char* place);
std::string to_text(const py::handle& obj, const char* place);
std::optional<std::string> to_optional_text(const py::handle& obj, const char* place);
std::string to_path(const py::handle& obj, const char* place);  // str or os.PathLike
std::array<double, 3> to_three(const py::handle& obj, const char* place, const char* form);
// (x0, y0, x1, y1) pixels, unchecked against the frame (that needs the world, under its lock).
std::optional<std::array<long long, 4>> to_region(const py::handle& obj);
std::optional<par2d::View> to_view(const py::handle& obj);
// A sprite transform: None, or a dict with any of "position" (x, y), "rotation" (degrees) and
// "scale" (one number, or (sx, sy)); missing keys keep the identity's.
std::optional<par2d::Transform> to_transform(const py::handle& obj);
std::uint64_t handle_id(const py::handle& handle, const char* kind);  // kind: "light", "occluder"

// The options of a backend name: "auto", "simd", "scalar", and where `raycast` is given also
// "raycast" (the one-shot calls' ray-casting baseline, par2d::render_raycast), which sets it.
par2d::RenderOptions make_options(const py::object& backend, const py::object& threads, const py::object& spp,
                                  int rays, const py::object& isa, const py::object& culling,
                                  bool* raycast = nullptr);
// "included", "excluded" or "only" (RenderOptions::bounce).
par2d::BounceTerm to_bounce_term(const py::object& obj);

// ---- Long renders (progress.cpp) ------------------------------------------------------------

// A render's progress function for Python (docs/python.md, "Long renders"): calls `callback`
// (None: none) with (tiles_done, tiles) on the rendering thread, the GIL taken for the call, and
// looks for Ctrl-C there (PyErr_CheckSignals: KeyboardInterrupt), at least every 50 ms without a
// callback. The callback returning False, raising, or a signal cancels the frame; finish()
// then raises that exception (par2d.CancelledError for False), or the render's status.
// Made, finished and destroyed with the GIL held.
class PyProgress {
 public:
  explicit PyProgress(py::object callback);
  ~PyProgress();
  PyProgress(const PyProgress&) = delete;
  PyProgress& operator=(const PyProgress&) = delete;
  bool has_callback() const { return !callback_.is_none(); }
  // The function to hand par2d (it refers to this object).
  par2d::ProgressFunction function();
  void finish(const par2d::Status& status);

 private:
  bool call(const par2d::Progress& progress);
  py::object callback_;
  PyObject *type_ = nullptr, *value_ = nullptr, *traceback_ = nullptr;  // the exception that stopped it
  double last_check_ = 0.0;  // seconds, steady clock
};

// The `progress` argument: None or a callable, else par2d.Error naming it.
py::object to_progress(const py::object& obj);

// A work estimate as a dict (samples, bounce, scalar, raycast, total).
py::dict estimate_dict(const par2d::WorkEstimate& estimate);

// The `work_limit` argument: a finite number >= 0 (0: none).
double to_work_limit(const py::object& obj);

// ---- Scenes (scene.cpp) -----------------------------------------------------------------------

// JSON text of a dict or list (`root`: its place in messages), every value checked first so
// that a NaN or anything JSON cannot hold is reported at its path under `name`.
std::string json_text(const py::handle& obj, const std::string& name, const std::string& root);

// A validated scene. Immutable from Python: edit its dict and build a new one, so a Scene
// object is always one that renders.
class PyScene {
 public:
  explicit PyScene(par2d::Scene scene) : scene_(std::move(scene)) {}

  // `allow_any_path` (a bool): LoadOptions::allow_any_path; by default a scene's normal_map
  // must be relative and stay inside the scene's folder (docs/contract.md section 6).
  static PyScene from_json_text(const std::string& text, const std::string& name, const par2d::LoadOptions& options);
  static PyScene from_json(const py::object& text, const py::object& name, const py::object& allow_any_path);
  static PyScene from_dict_named(const py::object& dict, const std::string& name, const par2d::LoadOptions& options);
  static PyScene from_dict(const py::object& dict, const py::object& name, const py::object& allow_any_path);
  static PyScene load(const py::object& path, const py::object& allow_any_path);

  const par2d::Scene& scene() const { return scene_; }
  std::string to_json() const;
  py::object to_dict() const;
  void save(const py::object& path) const;

 private:
  par2d::Scene scene_;
};

// The `scene` argument: a Scene, or a dict checked by the loader under the name "<dict>"
// (default LoadOptions: its normal_map confined to the current directory).
const PyScene& as_scene(const py::object& scene, std::optional<PyScene>& holder);

// The `normal_map` argument: a PNG path (str or os.PathLike), to be loaded once the frame's
// size is known, or an (H, W, 3) array of numbers, converted to float32 into `map`.
struct NormalMapSource {
  std::optional<std::string> png_path;
  par2d::NormalMap map;
};
NormalMapSource to_normal_map_source(const py::object& source);

// Loads a PNG normal map with the GIL released. width, height > 0: the PNG must declare
// exactly that size, checked from its header before a pixel is decoded (a tiny file may
// declare 16000x16000); 0 x 0 (no frame yet): at most kMaxImageSide per side.
par2d::NormalMap load_normal_map(const std::string& path, int width, int height);

// One light or occluder from a dict shaped like an entry of the scene file's lists, checked by
// the scene loader; `name` prefixes its messages.
par2d::Light parse_light(const py::object& dict, const std::string& name);
par2d::Occluder parse_occluder(const py::object& dict, const std::string& name);

// ---- Bindings: each file defines its classes and functions on the module ---------------------

void bind_scene(py::module_& m);     // scene.cpp: par2d.Scene, par2d.load_scene
void bind_renderer(py::module_& m);  // renderer.cpp: par2d.Renderer
void bind_alpha_outline(py::module_& m);  // alpha_outline.cpp: par2d.occluders_from_alpha

}  // namespace par2d::python
