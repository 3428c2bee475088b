// par2d.occluders_from_alpha: polygons_from_alpha on a NumPy alpha plane or RGBA image, as the scene's occluder dicts.
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace par2d::python {
namespace {

using ByteArray = py::array_t<std::uint8_t, py::array::c_style>;

// A number, or (x, y) numbers: `place` names it in errors.
par2d::Vec2 to_pair(const py::handle& obj, const char* place) {
  if (const std::optional<double> d = as_number(obj)) return {*d, *d};
  if (py::isinstance<py::sequence>(obj) && !py::isinstance<py::str>(obj) && py::len(obj) == 2) {
    const auto items = py::reinterpret_borrow<py::sequence>(obj);
    const std::optional<double> x = as_number(items[0]), y = as_number(items[1]);
    if (x && y) return {*x, *y};
  }
  bad_argument(place, "needs a number or (x, y) numbers, got " + describe(obj));
}

py::list occluders_from_alpha(const py::object& alpha_arg, const py::object& threshold, const py::object& tolerance,
                              const py::object& max_vertices, const py::object& scale, const py::object& offset) {
  // uint8 only: a float image's alpha (0 .. 1) would silently threshold wrongly if cast.
  if (!py::isinstance<py::array>(alpha_arg) ||
      !py::reinterpret_borrow<py::array>(alpha_arg).dtype().is(py::dtype::of<std::uint8_t>()))
    bad_argument("alpha",
                 "needs a uint8 array of shape (height, width) or (height, width, 4), got " + describe(alpha_arg));
  const ByteArray alpha = ByteArray::ensure(alpha_arg);
  if (!alpha || !(alpha.ndim() == 2 || (alpha.ndim() == 3 && alpha.shape(2) == 4)))
    bad_argument("alpha",
                 "needs a uint8 array of shape (height, width) or (height, width, 4), got " + describe(alpha_arg));
  const bool rgba = alpha.ndim() == 3;
  const py::ssize_t height = alpha.shape(0), width = alpha.shape(1);
  if (width < 1 || height < 1 || width > par2d::kMaxImageSide || height > par2d::kMaxImageSide)
    bad_argument("alpha", "needs 1 .. " + std::to_string(par2d::kMaxImageSide) + " pixels per side, got " +
                              std::to_string(height) + "x" + std::to_string(width));
  par2d::AlphaOutlineOptions options;
  options.threshold = to_int(threshold, "threshold");
  options.tolerance = to_double(tolerance, "tolerance");
  options.max_vertices = to_size(max_vertices, "max_vertices");
  options.scale = to_pair(scale, "scale");
  options.offset = to_pair(offset, "offset");
  const int pixel = rgba ? 4 : 1;
  const par2d::AlphaMask mask{alpha.data() + (rgba ? 3 : 0), static_cast<int>(width), static_cast<int>(height),
                              static_cast<std::ptrdiff_t>(width) * pixel, pixel};
  std::vector<par2d::Polygon> polygons;
  par2d::Status status;
  {
    py::gil_scoped_release release;
    status = par2d::polygons_from_alpha(mask, options, polygons);
  }
  check(status);
  // The scene file's own occluder entries: written and read back by the scene JSON code.
  par2d::Scene scene;
  scene.width = static_cast<int>(width);
  scene.height = static_cast<int>(height);
  for (par2d::Polygon& polygon : polygons) {
    par2d::Occluder occluder;
    occluder.shape = std::move(polygon);
    scene.occluders.push_back(std::move(occluder));
  }
  return PyScene(std::move(scene)).to_dict()["occluders"];
}

}  // namespace

void bind_alpha_outline(py::module_& m) {
  m.def("occluders_from_alpha", &occluders_from_alpha, py::arg("alpha"), py::kw_only(), py::arg("threshold") = 128,
        py::arg("tolerance") = 1.0, py::arg("max_vertices") = par2d::kMaxOutlineVertices, py::arg("scale") = 1.0,
        py::arg("offset") = py::make_tuple(0.0, 0.0),
        "Occluders traced from an image's alpha, as a list of the scene's occluder dicts ({\"polygon\": ...,\n"
        "\"holes\": ...}): alpha a uint8 array (height, width) or RGBA (height, width, 4), row 0 at the top;\n"
        "pixels with alpha >= threshold are solid, one polygon per 8-connected group, within `tolerance`\n"
        "pixels of the pixels' boundary, never crossing or touching, each valid as an occluder, at most\n"
        "max_vertices each. Pixel (i, j) covers [i, i+1] x [j, j+1], placed at offset + scale * p (scale:\n"
        "a number or (sx, sy)). The GIL is released while tracing.");
}

}  // namespace par2d::python
