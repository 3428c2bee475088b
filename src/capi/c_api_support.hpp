// What the C API's files share (src/capi/): the renderer handle's C++ side, the per-thread
// last error, and the conversions and the one exception-to-status wrapper at the C boundary.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include "par2d/par2d.h"
#include "par2d/renderer.hpp"

struct par2d_renderer {
  par2d::Renderer renderer;
  par2d::Light light;        // conversion buffers, reused from call to call
  par2d::Occluder occluder;
  // The world's handles in the order par2d_get_*_handles reports them: the C++ Renderer
  // returns a scene's handles only from set_scene, so the C side keeps the list.
  std::vector<par2d_light> lights;
  std::vector<par2d_occluder> occluders;
  std::vector<double> vertices_out;      // par2d_get_light/_occluder's polygon vertices
  std::vector<std::size_t> holes_out;    // ... and its holes' vertex counts
};

namespace par2d::capi {

// The calling thread's last error message (par2d_last_error). Defined once in par2d_c.cpp: an
// inline thread_local with a constructor gets its TLS init function defined in every object
// that uses it under MinGW's emulated TLS, which the linker then refuses as duplicates.
extern thread_local std::string g_last_error;

// The message with the C function's name in front (`par2d_add_light: shape is null`). A
// library message that already starts with the C++ call's name (`set_ambient: ...` from
// par2d_set_ambient) gets the C name in its place rather than a second name.
inline std::string named(const char* function, const std::string& message) {
  const char* stem = function + std::strlen("par2d_");
  const std::size_t n = std::strlen(stem);
  if (std::strncmp(function, "par2d_", 6) == 0 && message.size() > n + 2 && message.compare(0, n, stem) == 0 &&
      message.compare(n, 2, ": ") == 0)
    return "par2d_" + message;
  return std::string(function) + ": " + message;
}

inline par2d_status to_c(const char* function, const par2d::Status& s) {
  if (s.ok()) return PAR2D_OK;
  try {
    g_last_error = named(function, s.message());
  } catch (...) {
    g_last_error.clear();
  }
  switch (s.code()) {
    case par2d::StatusCode::ok: return PAR2D_OK;
    case par2d::StatusCode::invalid_argument: return PAR2D_INVALID_ARGUMENT;
    case par2d::StatusCode::invalid_scene: return PAR2D_INVALID_SCENE;
    case par2d::StatusCode::io_error: return PAR2D_IO_ERROR;
    case par2d::StatusCode::out_of_memory: return PAR2D_OUT_OF_MEMORY;
    case par2d::StatusCode::unsupported: return PAR2D_UNSUPPORTED;
    case par2d::StatusCode::work_limit: return PAR2D_WORK_LIMIT;
    case par2d::StatusCode::cancelled: return PAR2D_CANCELLED;
  }
  return PAR2D_INVALID_ARGUMENT;
}

inline par2d_status fail(const char* function, const std::string& message) {
  return to_c(function, par2d::Status(par2d::StatusCode::invalid_argument, message));
}

// Runs fn, turning exceptions into statuses (nothing may unwind into C). Counts and sizes are
// checked before anything is allocated, so these are real failures, not misuse.
template <class Fn>
inline par2d_status guarded(const char* function, Fn&& fn) noexcept {
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    return to_c(function, par2d::Status(par2d::StatusCode::out_of_memory, "out of memory"));
  } catch (const std::exception& e) {
    return fail(function, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(function, "internal error");
  }
}

// The value a C caller stored in an enum field or parameter, read as its bytes. A C caller may
// store any int there; in C++, loading an enum object whose value lies outside its
// enumerators' range is undefined (UBSan's enum check stops on it), so the value is checked
// as an integer before it is ever read as the enum.
template <class E>
long long raw_enum(const E& field) noexcept {
  std::underlying_type_t<E> value;
  std::memcpy(&value, &field, sizeof value);
  return static_cast<long long>(value);
}

// The PixelFormat a par2d_pixel_format names (the two enums list the formats in one order),
// or null for a value outside it. Taken by reference and read as an integer (raw_enum): a C
// caller's out-of-range value must never be loaded as the enum.
inline const par2d::PixelFormat* pixel_format_of(const par2d_pixel_format& format) noexcept {
  static constexpr par2d::PixelFormat kFormats[] = {
      par2d::PixelFormat::rgb_f32,    par2d::PixelFormat::rgba_f32,           par2d::PixelFormat::rgba8_srgb,
      par2d::PixelFormat::bgra8_srgb, par2d::PixelFormat::rgba16f,            par2d::PixelFormat::rgba8_srgb_dithered,
      par2d::PixelFormat::bgra8_srgb_dithered};
  static_assert(PAR2D_RGB_F32 == 0 && PAR2D_RGBA_F32 == 1 && PAR2D_RGBA8_SRGB == 2 && PAR2D_BGRA8_SRGB == 3 &&
                    PAR2D_RGBA16F == 4 && PAR2D_RGBA8_SRGB_DITHERED == 5 && PAR2D_BGRA8_SRGB_DITHERED == 6,
                "kFormats follows par2d_pixel_format");
  const long long value = raw_enum(format);
  return value >= 0 && value < 7 ? &kFormats[value] : nullptr;
}

// Converts into `out`, reusing a polygon's vertex buffer when the shape stays a polygon.
// Everything about the C struct is checked before its vertices are read or copied.
inline par2d_status convert_shape(const char* function, const par2d_shape* in, par2d::Shape& out) {
  if (in == nullptr) return fail(function, "shape is null");
  switch (raw_enum(in->kind)) {
    case PAR2D_SHAPE_POLYGON: {
      if (in->vertex_count > PAR2D_MAX_POLYGON_VERTICES)
        return fail(function, "shape vertex_count " + std::to_string(in->vertex_count) + " is more than " +
                                  std::to_string(PAR2D_MAX_POLYGON_VERTICES));
      // Every count is bounded before the array it sizes is read: a hole_count past the limit
      // (a garbage field in a struct that was not zeroed) would walk off hole_vertex_counts.
      if (in->hole_count > PAR2D_MAX_POLYGON_HOLES)
        return fail(function, "shape hole_count " + std::to_string(in->hole_count) + " is more than " +
                                  std::to_string(PAR2D_MAX_POLYGON_HOLES));
      if (in->hole_count > 0 && in->hole_vertex_counts == nullptr)
        return fail(function, "shape hole_vertex_counts are null");
      std::size_t total = in->vertex_count;
      for (std::size_t k = 0; k < in->hole_count; ++k) {
        if (in->hole_vertex_counts[k] > PAR2D_MAX_POLYGON_VERTICES - total)  // total <= the limit: no wrap
          return fail(function, "shape vertex_count and hole_vertex_counts add up to more than " +
                                    std::to_string(PAR2D_MAX_POLYGON_VERTICES));
        total += in->hole_vertex_counts[k];
      }
      if (in->vertices == nullptr && total > 0) return fail(function, "shape vertices are null");
      if (!std::holds_alternative<par2d::Polygon>(out)) out = par2d::Polygon{};
      auto& polygon = std::get<par2d::Polygon>(out);
      auto& v = polygon.vertices;
      v.resize(in->vertex_count);
      for (std::size_t i = 0; i < in->vertex_count; ++i) v[i] = {in->vertices[2 * i], in->vertices[2 * i + 1]};
      polygon.holes.clear();
      const double* next = in->vertices + 2 * in->vertex_count;
      for (std::size_t k = 0; k < in->hole_count; ++k) {
        std::vector<par2d::Vec2> ring(in->hole_vertex_counts[k]);
        for (par2d::Vec2& p : ring) {
          p = {next[0], next[1]};
          next += 2;
        }
        polygon.holes.push_back(std::move(ring));
      }
      return PAR2D_OK;
    }
    case PAR2D_SHAPE_CIRCLE:
      out = par2d::Circle{{in->circle[0], in->circle[1]}, in->circle[2]};
      return PAR2D_OK;
    case PAR2D_SHAPE_SEGMENT:
      out = par2d::Segment{{in->segment[0], in->segment[1]}, {in->segment[2], in->segment[3]}};
      return PAR2D_OK;
  }
  return fail(function, "shape kind " + std::to_string(raw_enum(in->kind)) +
                            " is not PAR2D_SHAPE_POLYGON, _CIRCLE or _SEGMENT");
}

inline par2d_status fill_light(const char* function, par2d_renderer* r, const par2d_shape* shape, const double color[3],
                        double intensity) {
  if (color == nullptr) return fail(function, "color is null");
  if (par2d_status s = convert_shape(function, shape, r->light.shape); s != PAR2D_OK) return s;
  r->light.color = {color[0], color[1], color[2]};
  r->light.intensity = intensity;
  return PAR2D_OK;
}

inline void set_default_terms(par2d::Light& light) {
  light.range.reset();
  light.falloff = 2.0;
  light.normalize.reset();
  light.cone.reset();
  light.cookie.reset();
  light.mask = par2d::kAllMaskBits;
  light.elevation = 0.0;
  light.shadow = par2d::Shadow{};
}

inline void set_default_terms(par2d::Occluder& occluder) {
  occluder.transmittance = {0.0, 0.0, 0.0};
  occluder.mask = par2d::kAllMaskBits;
  occluder.interior = par2d::Interior::dark;
  occluder.albedo = {0.0, 0.0, 0.0};
}

// The C transform as the C++ one.
inline par2d::Transform to_transform(const par2d_transform& t) {
  return par2d::Transform{{t.position[0], t.position[1]}, t.rotation, {t.scale[0], t.scale[1]}};
}

inline par2d::DirectionalLight from_c(const par2d_directional_light& in) {
  par2d::DirectionalLight out;
  out.angle0 = in.angles[0];
  out.angle1 = in.angles[1];
  out.color = {in.color[0], in.color[1], in.color[2]};
  out.intensity = in.intensity;
  out.mask = in.mask;
  out.elevation = in.elevation;
  return out;
}


// The par2d_options fields into `o` (its other fields stay), the backend checked as an integer.
inline par2d_status apply_options(const char* fn, const par2d_options& in, par2d::RenderOptions& o) {
  switch (raw_enum(in.backend)) {
    case PAR2D_BACKEND_AUTO: o.backend = par2d::Backend::automatic; break;
    case PAR2D_BACKEND_SIMD: o.backend = par2d::Backend::simd; break;
    case PAR2D_BACKEND_SCALAR: o.backend = par2d::Backend::scalar; break;
    default:
      return fail(fn, "backend " + std::to_string(raw_enum(in.backend)) + " is not PAR2D_BACKEND_AUTO, _SIMD or _SCALAR");
  }
  o.threads = in.threads;
  o.spp = in.spp;
  o.culling = in.culling != 0;
  return PAR2D_OK;
}

// `out` is written only once the vertices are copied, so a failed copy leaves it as it was.
inline void to_c_shape(const par2d::Shape& in, std::vector<double>& vertices, std::vector<std::size_t>& holes,
                       par2d_shape& out) {
  if (const auto* p = std::get_if<par2d::Polygon>(&in)) {
    vertices.clear();
    holes.clear();
    const auto put = [&vertices](const std::vector<par2d::Vec2>& ring) {
      for (const par2d::Vec2& v : ring) {
        vertices.push_back(v.x);
        vertices.push_back(v.y);
      }
    };
    put(p->vertices);
    for (const std::vector<par2d::Vec2>& hole : p->holes) {
      put(hole);
      holes.push_back(hole.size());
    }
  }
  out = par2d_shape{};
  if (const auto* p = std::get_if<par2d::Polygon>(&in)) {
    out.kind = PAR2D_SHAPE_POLYGON;
    out.vertices = vertices.data();
    out.vertex_count = p->vertices.size();
    out.hole_vertex_counts = holes.empty() ? nullptr : holes.data();
    out.hole_count = holes.size();
  } else if (const auto* c = std::get_if<par2d::Circle>(&in)) {
    out.kind = PAR2D_SHAPE_CIRCLE;
    out.circle[0] = c->center.x;
    out.circle[1] = c->center.y;
    out.circle[2] = c->radius;
  } else if (const auto* g = std::get_if<par2d::Segment>(&in)) {
    out.kind = PAR2D_SHAPE_SEGMENT;
    out.segment[0] = g->a.x;
    out.segment[1] = g->a.y;
    out.segment[2] = g->b.x;
    out.segment[3] = g->b.y;
  }
}

// Writes the first min(capacity, list size) ids and the total; NULL `out` only with capacity 0.
template <class Id>
inline par2d_status copy_ids(const char* fn, const std::vector<Id>& ids, Id* out, size_t capacity, size_t* count) {
  if (count == nullptr) return fail(fn, "count is null");
  if (out == nullptr && capacity > 0) return fail(fn, "out is null but capacity is " + std::to_string(capacity));
  std::copy_n(ids.begin(), std::min(capacity, ids.size()), out);
  *count = ids.size();
  return PAR2D_OK;
}

}  // namespace par2d::capi
