// Python bindings (`import par2d`): scenes from dicts, JSON text or files, rendered into NumPy
// float32 arrays. This file defines the module: par2d.Error, the one-shot functions (render,
// write_png, the ISA queries) and the module's other files' bindings: arguments.cpp (errors and
// argument conversion), scene.cpp (par2d.Scene and dict conversion), renderer.cpp
// (par2d.Renderer). Only the public C++ API (include/par2d/) is used.
//
// Rendering goes through render_into(), the one place that touches a one-shot output array
// and releases the GIL.
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace par2d::python {
namespace {

// Renders into `out`, an (H, W, 3) float32 array whose pixels and channels are packed (rows
// may be padded), with the GIL released so other Python threads run meanwhile; `raycast`: by
// the ray-casting baseline.
void render_into(const par2d::Scene& scene, const par2d::RenderOptions& options, bool raycast,
                 const py::object& out_arg, py::array& out, PyProgress& progress) {
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
  par2d::RenderControl control;
  control.progress = progress.function();  // the callback, and Ctrl-C
  par2d::Status status;
  {
    py::gil_scoped_release release;
    status = raycast ? par2d::render_raycast(scene, options, view, control) : par2d::render(scene, options, view, control);
  }
  progress.finish(status);
}

// par2d.Error and one subclass per status code that also derives from the built-in exception
// Python code catches for that kind of failure, so `except ValueError` or `except OSError`
// works on par2d calls as on any other library's, and `except par2d.Error` catches them all.
void define_errors(py::module_& m) {
  struct Kind {
    par2d::StatusCode code;
    const char* name;
    PyObject* builtin;
    const char* doc;
  };
  const Kind kinds[] = {
      {par2d::StatusCode::invalid_argument, "InvalidArgumentError", PyExc_ValueError,
       "A bad argument (type, value, size, handle): a par2d.Error and a ValueError; code 'invalid_argument'."},
      {par2d::StatusCode::invalid_scene, "InvalidSceneError", PyExc_ValueError,
       "A scene, light or occluder that breaks docs/contract.md section 3: a par2d.Error and a ValueError; code "
       "'invalid_scene'."},
      {par2d::StatusCode::io_error, "FileError", PyExc_OSError,
       "A file that could not be read or written: a par2d.Error and an OSError; code 'io_error'."},
      {par2d::StatusCode::out_of_memory, "OutOfMemoryError", PyExc_MemoryError,
       "An allocation that failed: a par2d.Error and a MemoryError; code 'out_of_memory'."},
      {par2d::StatusCode::unsupported, "UnsupportedError", PyExc_NotImplementedError,
       "Something this build or CPU lacks: a par2d.Error and a NotImplementedError; code 'unsupported'."},
      {par2d::StatusCode::work_limit, "WorkLimitError", PyExc_RuntimeError,
       "A frame whose estimated work is past work_limit, refused before any pixel is computed: a par2d.Error\n"
       "and a RuntimeError; code 'work_limit'."},
      {par2d::StatusCode::cancelled, "CancelledError", PyExc_RuntimeError,
       "A frame its progress callback cancelled (by returning False), its output untouched: a par2d.Error and a\n"
       "RuntimeError; code 'cancelled'."},
  };
  // The module keeps the classes alive; the pointers below are borrowed for its lifetime.
  py::object base = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "par2d.Error",
      "A failed par2d call. str(e) is par2d's one-line message (`FILE: PLACE: what is wrong`); e.code names the\n"
      "kind: invalid_scene, invalid_argument, io_error, out_of_memory, unsupported, work_limit, cancelled. Each\n"
      "kind has its subclass (InvalidArgumentError, InvalidSceneError, FileError, OutOfMemoryError,\n"
      "UnsupportedError, WorkLimitError, CancelledError), which is also the built-in exception of that kind\n"
      "(ValueError, ValueError, OSError, MemoryError, NotImplementedError, RuntimeError, RuntimeError).",
      PyExc_Exception, nullptr));
  if (!base) throw py::error_already_set();
  m.attr("Error") = base;
  g_error_type = base.ptr();
  for (const Kind& kind : kinds) {
    const std::string qualified = std::string("par2d.") + kind.name;
    py::object bases = py::make_tuple(base, py::handle(kind.builtin));
    py::object type = py::reinterpret_steal<py::object>(
        PyErr_NewExceptionWithDoc(qualified.c_str(), kind.doc, bases.ptr(), nullptr));
    if (!type) throw py::error_already_set();
    m.attr(kind.name) = type;
    g_error_types[static_cast<std::size_t>(kind.code)] = type.ptr();
  }
}

// A uint8 array of shape (H, W, 4) or (H, W, 3): sRGB bytes such as render_rgba8 returns.
bool is_srgb8_image(const py::object& image) {
  if (!py::isinstance<py::array_t<std::uint8_t>>(image)) return false;
  const auto a = py::reinterpret_borrow<py::array>(image);
  return a.ndim() == 3 && (a.shape(2) == 3 || a.shape(2) == 4);
}

// The bytes' RGB as linear floats that par2d::write_png encodes back to the same bytes: code k
// decodes to the exact inverse transfer function at k / 255, the middle of the interval of
// values that round to k (write_png's thresholds lie at (k +- 0.5) / 255), far wider than a
// float's rounding. Alpha is dropped (the PNG is RGB).
std::vector<float> decoded_srgb8(const py::array& image) {
  std::array<float, 256> table{};
  for (int k = 0; k < 256; ++k) {
    const double s = k / 255.0;
    table[static_cast<std::size_t>(k)] =
        static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
  }
  const auto bytes = image.unchecked<std::uint8_t, 3>();  // any strides
  const py::ssize_t h = image.shape(0), w = image.shape(1);
  std::vector<float> out(static_cast<std::size_t>(h) * static_cast<std::size_t>(w) * 3);
  std::size_t i = 0;
  for (py::ssize_t y = 0; y < h; ++y)
    for (py::ssize_t x = 0; x < w; ++x)
      for (py::ssize_t c = 0; c < 3; ++c) out[i++] = table[bytes(y, x, c)];
  return out;
}

// The module's contents; PYBIND11_MODULE (at the end) calls it.
void define_module(py::module_& m) {
  m.doc() = "Exact 2D soft shadows (Probabilistic Angular Radiance): scenes in, float32 RGB irradiance out.";
  m.attr("__version__") = par2d::kVersion;

  define_errors(m);

  // pybind11 (2.10) sets up its NumPy API table on first use in a function-local static whose
  // initialization imports NumPy; two threads using an array for the first time at once can
  // deadlock there (one waits on the static holding the GIL, the other on the GIL inside it).
  // Using it once here, on the importing thread, settles it before any other thread can.
  FloatArray({py::ssize_t{1}, py::ssize_t{1}, py::ssize_t{3}});
  py::array_t<std::uint8_t, py::array::c_style>({py::ssize_t{1}, py::ssize_t{1}, py::ssize_t{4}});

  // A C++ allocation failure inside any call is par2d.OutOfMemoryError (a par2d.Error and a
  // MemoryError) with code "out_of_memory".
  py::register_local_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::bad_alloc&) {
      set_error(par2d::StatusCode::out_of_memory, "out of memory");
    }
  });

  bind_scene(m);

  m.def(
      "render",
      [](const py::object& scene_or_dict, const py::object& backend, const py::object& threads, const py::object& spp,
         const py::object& rays, const py::object& isa, const py::object& culling, const py::object& out,
         const py::object& shaded, const py::object& bounce, const py::object& work_limit,
         const py::object& progress_arg) {
        bool raycast = false;
        par2d::RenderOptions options =
            make_options(backend, threads, spp, to_int(rays, "rays"), isa, culling, &raycast);
        options.shaded = to_bool(shaded, "shaded");
        options.bounce = to_bounce_term(bounce);
        options.work_limit = to_work_limit(work_limit);
        PyProgress progress(to_progress(progress_arg));
        std::optional<PyScene> holder;
        const PyScene& scene = as_scene(scene_or_dict, holder);
        py::array image;
        if (out.is_none()) {
          image = FloatArray({scene.scene().height, scene.scene().width, 3});
          render_into(scene.scene(), options, raycast, image, image, progress);
        } else {
          render_into(scene.scene(), options, raycast, out, image, progress);
        }
        return image;
      },
      py::arg("scene"), py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0, py::arg("spp") = 1,
      py::arg("rays") = 1024, py::arg("isa") = py::none(), py::arg("culling") = true, py::arg("out") = py::none(),
      py::arg("shaded") = true, py::arg("bounce") = "included", py::arg("work_limit") = par2d::kDefaultWorkLimit,
      py::arg("progress") = py::none(),
      "Linear irradiance of `scene` (a Scene or a dict) as a float32 array of shape (height, width, 3),\n"
      "row 0 at the top. backend: auto|simd|scalar|raycast; threads: 0 = all; spp: samples per pixel;\n"
      "rays: directions per sample for raycast; isa: cap the SIMD level (scalar|sse4|avx2|avx512);\n"
      "out: an existing array to fill instead of a new one; shaded=False: the plain irradiance of a scene\n"
      "with a normal source (no normal-map shading); bounce: with reflecting occluders, included (direct\n"
      "plus one bounce), excluded (the direct light alone) or only (the bounce term alone). work_limit: the\n"
      "most estimated work a frame may have (estimate_work; default 1e11, 0: none), past which\n"
      "par2d.WorkLimitError is raised before rendering. progress: called as progress(tiles_done, tiles) on\n"
      "this thread as tiles finish; returning False cancels (par2d.CancelledError), and so does Ctrl-C\n"
      "(KeyboardInterrupt), `out` then untouched. The GIL is released while rendering.");

  m.def(
      "estimate_work",
      [](const py::object& scene_or_dict, const py::object& backend, const py::object& spp, const py::object& rays,
         const py::object& isa, const py::object& bounce) {
        bool raycast = false;
        par2d::RenderOptions options =
            make_options(backend, py::int_(0), spp, to_int(rays, "rays"), isa, py::bool_(true), &raycast);
        options.bounce = to_bounce_term(bounce);
        std::optional<PyScene> holder;
        const PyScene& scene = as_scene(scene_or_dict, holder);
        par2d::WorkEstimate estimate;
        check(raycast ? par2d::estimate_raycast_work(scene.scene(), options, estimate)
                      : par2d::estimate_work(scene.scene(), options, estimate));
        return estimate_dict(estimate);
      },
      py::arg("scene"), py::kw_only(), py::arg("backend") = "auto", py::arg("spp") = 1, py::arg("rays") = 1024,
      py::arg("isa") = py::none(), py::arg("bounce") = "included",
      "The estimated work of render(scene, ...) with these options, as a dict: samples, bounce, scalar,\n"
      "raycast and total (docs/python.md, \"Long renders\"), total being what work_limit bounds.");

  bind_renderer(m);
  bind_alpha_outline(m);

  m.def(
      "write_png",
      [](const py::object& path_arg, const py::object& image_arg, const py::object& exposure_arg,
         const py::object& dither_arg) {
        const std::string path = to_path(path_arg, "path");
        const double exposure = to_double(exposure_arg, "exposure");
        const bool dither = to_bool(dither_arg, "dither");
        if (is_srgb8_image(image_arg)) {
          // Already encoded (render_rgba8's bytes): an exposure or dither would have to have been given there.
          if (exposure != 1.0)
            bad_argument("exposure", "applies to float images; a uint8 image is stored as it is (give the exposure "
                                     "to render_rgba8)");
          if (dither)
            bad_argument("dither", "applies to float images; a uint8 image is stored as it is (give dither=True "
                                   "to render_rgba8)");
          const std::vector<float> linear = decoded_srgb8(py::reinterpret_borrow<py::array>(image_arg));
          const auto a = py::reinterpret_borrow<py::array>(image_arg);
          par2d::ImageView view{const_cast<float*>(linear.data()), static_cast<int>(a.shape(1)),
                                static_cast<int>(a.shape(0)), static_cast<std::ptrdiff_t>(3 * a.shape(1))};
          check(par2d::write_png(path, view, 1.0));
          return;
        }
        const FloatArray image = FloatArray::ensure(image_arg);
        if (!image || image.ndim() != 3 || image.shape(2) != 3)
          bad_argument("image", "needs a float32 array of shape (height, width, 3) or a uint8 array of shape "
                                "(height, width, 4) or (height, width, 3), got " + describe(image_arg));
        // ImageView takes a mutable pointer but write_png only reads; the array is C-contiguous.
        par2d::ImageView view{const_cast<float*>(image.data()), static_cast<int>(image.shape(1)),
                              static_cast<int>(image.shape(0)), static_cast<std::ptrdiff_t>(3 * image.shape(1))};
        check(par2d::write_png(path, view, exposure, dither));
      },
      py::arg("path"), py::arg("image"), py::arg("exposure") = 1.0, py::kw_only(), py::arg("dither") = false,
      "Writes an image as an 8-bit sRGB PNG (path: str or os.PathLike), atomically (as `par2d render -o`):\n"
      "a float array (height, width, 3) of linear values as clamp(exposure * image, 0, 1), rounded or with\n"
      "dither=True the ordered dither of render_rgba8(dither=True) (`par2d render --dither`), or the uint8\n"
      "array render_rgba8 returns, (height, width, 4) or (height, width, 3), byte for byte (the PNG is RGB:\n"
      "alpha is not stored; exposure must stay 1 and dither False).");

  m.def("detect_isa", [] { return std::string(par2d::isa_name(par2d::detect_isa())); },
        "The best SIMD level this CPU supports: scalar, sse4, avx2 or avx512.");
  m.def("default_isa", [] { return std::string(par2d::isa_name(par2d::default_isa())); },
        "The level rendering uses by default: detect_isa() capped by the PAR2D_ISA environment variable.");
}

}  // namespace
}  // namespace par2d::python

PYBIND11_MODULE(par2d, m) { par2d::python::define_module(m); }
