// The C API's occluders from an alpha mask: polygons_from_alpha behind an opaque result handle.
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "capi/c_api_support.hpp"
#include "par2d/alpha_outline.hpp"
#include "par2d/par2d.h"

// Each polygon's vertices flat (outline, then each hole) with its holes' vertex counts, as
// par2d_shape points at them.
struct par2d_outline {
  struct Flat {
    std::vector<double> vertices;
    std::size_t outline_count = 0;
    std::vector<std::size_t> hole_counts;
  };
  std::vector<Flat> polygons;
};

using par2d::capi::fail;
using par2d::capi::guarded;
using par2d::capi::to_c;

extern "C" {

par2d_status par2d_outline_alpha(const uint8_t* alpha, int width, int height, ptrdiff_t row_stride, int pixel_stride,
                                 int threshold, double tolerance, size_t max_vertices, const double* placement,
                                 par2d_outline** out) {
  const char* const fn = __func__;
  if (out == nullptr) return fail(fn, "out is null");
  *out = nullptr;
  return guarded(fn, [&]() -> par2d_status {
    par2d::AlphaOutlineOptions options;
    options.threshold = threshold;
    options.tolerance = tolerance;
    options.max_vertices = max_vertices;
    if (placement != nullptr) {
      options.scale = {placement[0], placement[1]};
      options.offset = {placement[2], placement[3]};
    }
    std::vector<par2d::Polygon> polygons;
    const par2d::AlphaMask mask{alpha, width, height, row_stride, pixel_stride};
    if (par2d::Status s = par2d::polygons_from_alpha(mask, options, polygons); !s) return to_c(fn, s);
    auto result = std::make_unique<par2d_outline>();
    result->polygons.resize(polygons.size());
    for (std::size_t k = 0; k < polygons.size(); ++k) {
      par2d_outline::Flat& flat = result->polygons[k];
      auto append = [&flat](const std::vector<par2d::Vec2>& ring) {
        for (const par2d::Vec2& v : ring) flat.vertices.insert(flat.vertices.end(), {v.x, v.y});
      };
      append(polygons[k].vertices);
      flat.outline_count = polygons[k].vertices.size();
      for (const auto& hole : polygons[k].holes) {
        append(hole);
        flat.hole_counts.push_back(hole.size());
      }
    }
    *out = result.release();
    return PAR2D_OK;
  });
}

size_t par2d_outline_polygon_count(const par2d_outline* outline) { return outline ? outline->polygons.size() : 0; }

par2d_status par2d_outline_polygon(const par2d_outline* outline, size_t index, par2d_shape* shape) {
  const char* const fn = __func__;
  if (outline == nullptr) return fail(fn, "outline is null");
  if (shape == nullptr) return fail(fn, "shape is null");
  if (index >= outline->polygons.size())
    return fail(fn, "index " + std::to_string(index) + " is past the " + std::to_string(outline->polygons.size()) +
                        " polygons");
  const par2d_outline::Flat& flat = outline->polygons[index];
  *shape = par2d_shape{};
  shape->kind = PAR2D_SHAPE_POLYGON;
  shape->vertices = flat.vertices.data();
  shape->vertex_count = flat.outline_count;
  shape->hole_vertex_counts = flat.hole_counts.empty() ? nullptr : flat.hole_counts.data();
  shape->hole_count = flat.hole_counts.size();
  return to_c(fn, par2d::Status());
}

void par2d_outline_destroy(par2d_outline* outline) { delete outline; }

}  // extern "C"
