// The C API (include/par2d/par2d.h) over par2d::Renderer: shapes converted into reused
// buffers (no allocation per update), errors kept per thread.
#include "par2d/par2d.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include "par2d/renderer.hpp"
#include "par2d/scene_write.hpp"
#include "par2d/version.hpp"

struct par2d_renderer {
  par2d::Renderer renderer;
  par2d::Light light;        // conversion buffers, reused from call to call
  par2d::Occluder occluder;
  // The world's handles in the order par2d_get_*_handles reports them: the C++ Renderer
  // returns a scene's handles only from set_scene, so the C side keeps the list.
  std::vector<par2d_light> lights;
  std::vector<par2d_occluder> occluders;
  std::vector<double> vertices_out;  // par2d_get_light/_occluder's polygon vertices
};

namespace {

thread_local std::string g_last_error;

// The message with the C function's name in front (`par2d_add_light: shape is null`). A
// library message that already starts with the C++ call's name (`set_ambient: ...` from
// par2d_set_ambient) gets the C name in its place rather than a second name.
std::string named(const char* function, const std::string& message) {
  const char* stem = function + std::strlen("par2d_");
  const std::size_t n = std::strlen(stem);
  if (std::strncmp(function, "par2d_", 6) == 0 && message.size() > n + 2 && message.compare(0, n, stem) == 0 &&
      message.compare(n, 2, ": ") == 0)
    return "par2d_" + message;
  return std::string(function) + ": " + message;
}

par2d_status to_c(const char* function, const par2d::Status& s) {
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
  }
  return PAR2D_INVALID_ARGUMENT;
}

par2d_status fail(const char* function, const std::string& message) {
  return to_c(function, par2d::Status(par2d::StatusCode::invalid_argument, message));
}

// Runs fn, turning exceptions into statuses (nothing may unwind into C). Counts and sizes are
// checked before anything is allocated, so these are real failures, not misuse.
template <class Fn>
par2d_status guarded(const char* function, Fn&& fn) noexcept {
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

// Converts into `out`, reusing a polygon's vertex buffer when the shape stays a polygon.
// Everything about the C struct is checked before its vertices are read or copied.
par2d_status convert_shape(const char* function, const par2d_shape* in, par2d::Shape& out) {
  if (in == nullptr) return fail(function, "shape is null");
  switch (raw_enum(in->kind)) {
    case PAR2D_SHAPE_POLYGON: {
      if (in->vertex_count > PAR2D_MAX_POLYGON_VERTICES)
        return fail(function, "shape vertex_count " + std::to_string(in->vertex_count) + " is more than " +
                                  std::to_string(PAR2D_MAX_POLYGON_VERTICES));
      if (in->vertices == nullptr && in->vertex_count > 0) return fail(function, "shape vertices are null");
      if (!std::holds_alternative<par2d::Polygon>(out)) out = par2d::Polygon{};
      auto& v = std::get<par2d::Polygon>(out).vertices;
      v.resize(in->vertex_count);
      for (std::size_t i = 0; i < in->vertex_count; ++i) v[i] = {in->vertices[2 * i], in->vertices[2 * i + 1]};
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

par2d_status fill_light(const char* function, par2d_renderer* r, const par2d_shape* shape, const double color[3],
                        double intensity) {
  if (color == nullptr) return fail(function, "color is null");
  if (par2d_status s = convert_shape(function, shape, r->light.shape); s != PAR2D_OK) return s;
  r->light.color = {color[0], color[1], color[2]};
  r->light.intensity = intensity;
  return PAR2D_OK;
}

void set_default_terms(par2d::Light& light) {
  light.range.reset();
  light.cone.reset();
  light.mask = par2d::kAllMaskBits;
  light.elevation = 0.0;
}

void set_default_terms(par2d::Occluder& occluder) {
  occluder.transmittance = {0.0, 0.0, 0.0};
  occluder.mask = par2d::kAllMaskBits;
  occluder.interior = par2d::Interior::dark;
}

par2d::DirectionalLight from_c(const par2d_directional_light& in) {
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
par2d_status apply_options(const char* fn, const par2d_options& in, par2d::RenderOptions& o) {
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
void to_c_shape(const par2d::Shape& in, std::vector<double>& vertices, par2d_shape& out) {
  if (const auto* p = std::get_if<par2d::Polygon>(&in)) {
    vertices.clear();
    for (const par2d::Vec2& v : p->vertices) {
      vertices.push_back(v.x);
      vertices.push_back(v.y);
    }
  }
  out = par2d_shape{};
  if (const auto* p = std::get_if<par2d::Polygon>(&in)) {
    out.kind = PAR2D_SHAPE_POLYGON;
    out.vertices = vertices.data();
    out.vertex_count = p->vertices.size();
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
par2d_status copy_ids(const char* fn, const std::vector<Id>& ids, Id* out, size_t capacity, size_t* count) {
  if (count == nullptr) return fail(fn, "count is null");
  if (out == nullptr && capacity > 0) return fail(fn, "out is null but capacity is " + std::to_string(capacity));
  std::copy_n(ids.begin(), std::min(capacity, ids.size()), out);
  *count = ids.size();
  return PAR2D_OK;
}

}  // namespace

extern "C" {

const char* par2d_version(void) { return par2d::kVersion; }

void par2d_version_numbers(int* major, int* minor, int* patch) {
  if (major) *major = PAR2D_VERSION_MAJOR;
  if (minor) *minor = PAR2D_VERSION_MINOR;
  if (patch) *patch = PAR2D_VERSION_PATCH;
}

const char* par2d_last_error(void) { return g_last_error.c_str(); }

void par2d_options_default(par2d_options* options) {
  if (options == nullptr) return;
  options->backend = PAR2D_BACKEND_AUTO;
  options->threads = 0;
  options->spp = 1;
  options->culling = 1;
}

// Each function below names itself (fn = __func__) in every message it leaves.

par2d_status par2d_renderer_create(const par2d_options* options, par2d_renderer** out) {
  const char* const fn = __func__;
  if (out == nullptr) return fail(fn, "out is null");
  *out = nullptr;
  return guarded(fn, [&] {
    par2d::RenderOptions o;
    if (options)
      if (par2d_status s = apply_options(fn, *options, o); s != PAR2D_OK) return s;
    auto r = std::make_unique<par2d_renderer>();
    if (par2d::Status s = r->renderer.set_options(o); !s.ok()) return to_c(fn, s);
    *out = r.release();
    return PAR2D_OK;
  });
}

void par2d_renderer_destroy(par2d_renderer* renderer) { delete renderer; }

int par2d_renderer_threads(const par2d_renderer* renderer) { return renderer ? renderer->renderer.threads() : 0; }

par2d_status par2d_set_frame(par2d_renderer* r, int width, int height, const double* view) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (view == nullptr) return to_c(fn, r->renderer.set_frame(width, height));
    return to_c(fn, r->renderer.set_frame(width, height, par2d::View{view[0], view[1], view[2], view[3]}));
  });
}

namespace {

par2d_status load_scene(const char* fn, par2d_renderer* r, const char* path, unsigned flags) {
  if (r == nullptr) return fail(fn, "renderer is null");
  if (path == nullptr) return fail(fn, "path is null");
  if ((flags & ~static_cast<unsigned>(PAR2D_LOAD_ALLOW_ANY_PATH)) != 0) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%X", flags);
    return fail(fn, std::string("flags ") + hex + " has bits other than PAR2D_LOAD_ALLOW_ANY_PATH");
  }
  return guarded(fn, [&] {
    par2d::LoadOptions options;
    options.allow_any_path = (flags & PAR2D_LOAD_ALLOW_ANY_PATH) != 0;
    par2d::Scene scene;
    if (par2d::Status s = par2d::load_scene_file(path, scene, options); !s.ok()) return to_c(fn, s);
    // The handle lists are sized before the world changes, so that nothing can fail after.
    std::vector<par2d::LightHandle> lights;
    std::vector<par2d::OccluderHandle> occluders;
    std::vector<par2d_light> light_ids(scene.lights.size());
    std::vector<par2d_occluder> occluder_ids(scene.occluders.size());
    if (par2d::Status s = r->renderer.set_scene(scene, &lights, &occluders); !s.ok()) return to_c(fn, s);
    for (std::size_t i = 0; i < lights.size() && i < light_ids.size(); ++i) light_ids[i] = lights[i].id;
    for (std::size_t i = 0; i < occluders.size() && i < occluder_ids.size(); ++i) occluder_ids[i] = occluders[i].id;
    r->lights.swap(light_ids);
    r->occluders.swap(occluder_ids);
    return PAR2D_OK;
  });
}

}  // namespace

par2d_status par2d_load_scene(par2d_renderer* r, const char* path) { return load_scene(__func__, r, path, 0); }

par2d_status par2d_load_scene_ex(par2d_renderer* r, const char* path, unsigned flags) {
  return load_scene(__func__, r, path, flags);
}

par2d_status par2d_add_light(par2d_renderer* r, const par2d_shape* shape, const double color[3], double intensity,
                             par2d_light* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d_status s = fill_light(fn, r, shape, color, intensity); s != PAR2D_OK) return s;
    set_default_terms(r->light);
    r->lights.reserve(r->lights.size() + 1);  // so that the push_back below cannot fail
    par2d::LightHandle h;
    if (par2d::Status s = r->renderer.add_light(r->light, &h); !s.ok()) return to_c(fn, s);
    r->lights.push_back(h.id);
    *out = h.id;
    return PAR2D_OK;
  });
}

par2d_status par2d_update_light(par2d_renderer* r, par2d_light light, const par2d_shape* shape, const double color[3],
                                double intensity) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    // The light keeps its terms (range, cone, mask, elevation): start from it as it is.
    if (!r->renderer.light(par2d::LightHandle{light}, &r->light).ok()) set_default_terms(r->light);
    if (par2d_status s = fill_light(fn, r, shape, color, intensity); s != PAR2D_OK) return s;
    return to_c(fn, r->renderer.update_light(par2d::LightHandle{light}, r->light));
  });
}

par2d_status par2d_set_light_emission(par2d_renderer* r, par2d_light light, const double color[3], double intensity) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (color == nullptr) return fail(fn, "color is null");
  return guarded(fn, [&] {
    return to_c(fn, r->renderer.set_light_emission(par2d::LightHandle{light}, {color[0], color[1], color[2]}, intensity));
  });
}

par2d_status par2d_remove_light(par2d_renderer* r, par2d_light light) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.remove_light(par2d::LightHandle{light}); !s.ok()) return to_c(fn, s);
    r->lights.erase(std::remove(r->lights.begin(), r->lights.end(), light), r->lights.end());
    return PAR2D_OK;
  });
}

par2d_status par2d_add_occluder(par2d_renderer* r, const par2d_shape* shape, par2d_occluder* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d_status s = convert_shape(fn, shape, r->occluder.shape); s != PAR2D_OK) return s;
    set_default_terms(r->occluder);
    r->occluders.reserve(r->occluders.size() + 1);
    par2d::OccluderHandle h;
    if (par2d::Status s = r->renderer.add_occluder(r->occluder, &h); !s.ok()) return to_c(fn, s);
    r->occluders.push_back(h.id);
    *out = h.id;
    return PAR2D_OK;
  });
}

par2d_status par2d_update_occluder(par2d_renderer* r, par2d_occluder occluder, const par2d_shape* shape) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    // The occluder keeps its terms (transmittance, mask, interior).
    if (!r->renderer.occluder(par2d::OccluderHandle{occluder}, &r->occluder).ok()) set_default_terms(r->occluder);
    if (par2d_status s = convert_shape(fn, shape, r->occluder.shape); s != PAR2D_OK) return s;
    return to_c(fn, r->renderer.update_occluder(par2d::OccluderHandle{occluder}, r->occluder));
  });
}

par2d_status par2d_remove_occluder(par2d_renderer* r, par2d_occluder occluder) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.remove_occluder(par2d::OccluderHandle{occluder}); !s.ok()) return to_c(fn, s);
    r->occluders.erase(std::remove(r->occluders.begin(), r->occluders.end(), occluder), r->occluders.end());
    return PAR2D_OK;
  });
}

par2d_status par2d_render(par2d_renderer* r, void* pixels, par2d_pixel_format format, ptrdiff_t row_stride,
                          double exposure, const int* region) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    par2d::FrameBuffer buffer;
    buffer.data = pixels;
    switch (raw_enum(format)) {
      case PAR2D_RGB_F32: buffer.format = par2d::PixelFormat::rgb_f32; break;
      case PAR2D_RGBA_F32: buffer.format = par2d::PixelFormat::rgba_f32; break;
      case PAR2D_RGBA8_SRGB: buffer.format = par2d::PixelFormat::rgba8_srgb; break;
      default:
        return fail(fn, "pixel format " + std::to_string(raw_enum(format)) +
                            " is not PAR2D_RGB_F32, PAR2D_RGBA_F32 or PAR2D_RGBA8_SRGB");
    }
    buffer.row_stride = row_stride;
    buffer.exposure = exposure;
    if (region == nullptr) return to_c(fn, r->renderer.render(buffer));
    return to_c(fn, r->renderer.render(buffer, par2d::PixelRect{region[0], region[1], region[2], region[3]}));
  });
}

par2d_status par2d_set_incremental(par2d_renderer* r, int on) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return to_c(fn, r->renderer.set_incremental(on != 0));
}

par2d_status par2d_force_full_frame(par2d_renderer* r) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  r->renderer.force_full_frame();
  return to_c(fn, par2d::Status());
}

par2d_status par2d_dirty_rects(const par2d_renderer* r, par2d_rect* out, size_t capacity, size_t* count) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (count == nullptr) return fail(fn, "count is null");
  if (out == nullptr && capacity != 0) return fail(fn, "out is null with capacity " + std::to_string(capacity));
  const std::vector<par2d::PixelRect>& rects = r->renderer.dirty_rects();
  for (std::size_t i = 0; i < rects.size() && i < capacity; ++i)
    out[i] = par2d_rect{rects[i].x0, rects[i].y0, rects[i].x1, rects[i].y1};
  *count = rects.size();
  return to_c(fn, par2d::Status());
}

void par2d_light_terms_default(par2d_light_terms* terms) {
  if (terms == nullptr) return;
  *terms = par2d_light_terms{};
  terms->cone_half_angle = 180.0;
  terms->mask = par2d::kAllMaskBits;
}

void par2d_occluder_terms_default(par2d_occluder_terms* terms) {
  if (terms == nullptr) return;
  *terms = par2d_occluder_terms{};
  terms->mask = par2d::kAllMaskBits;
  terms->interior = PAR2D_INTERIOR_DARK;
}

void par2d_directional_light_default(par2d_directional_light* light) {
  if (light == nullptr) return;
  *light = par2d_directional_light{};
  light->color[0] = light->color[1] = light->color[2] = 1.0;
  light->intensity = 1.0;
  light->mask = par2d::kAllMaskBits;
}

par2d_status par2d_get_light_terms(par2d_renderer* r, par2d_light light, par2d_light_terms* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.light(par2d::LightHandle{light}, &r->light); !s.ok()) return to_c(fn, s);
    par2d_light_terms_default(out);
    out->range = r->light.range ? *r->light.range : 0.0;
    out->has_cone = r->light.cone ? 1 : 0;
    if (r->light.cone) {
      out->cone_direction = r->light.cone->direction;
      out->cone_half_angle = r->light.cone->half_angle;
      out->cone_fade = r->light.cone->fade;
    }
    out->mask = r->light.mask;
    out->elevation = r->light.elevation;
    return PAR2D_OK;
  });
}

par2d_status par2d_set_light_terms(par2d_renderer* r, par2d_light light, const par2d_light_terms* terms) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (terms == nullptr) return fail(fn, "terms is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.light(par2d::LightHandle{light}, &r->light); !s.ok()) return to_c(fn, s);
    // 0 means no range; anything else (negative, NaN) goes to validation and is refused there.
    if (terms->range == 0.0) r->light.range.reset();
    else r->light.range = terms->range;
    if (terms->has_cone) r->light.cone = par2d::Cone{terms->cone_direction, terms->cone_half_angle, terms->cone_fade};
    else r->light.cone.reset();
    r->light.mask = terms->mask;
    r->light.elevation = terms->elevation;
    return to_c(fn, r->renderer.update_light(par2d::LightHandle{light}, r->light));
  });
}

par2d_status par2d_get_occluder_terms(par2d_renderer* r, par2d_occluder occluder, par2d_occluder_terms* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.occluder(par2d::OccluderHandle{occluder}, &r->occluder); !s.ok())
      return to_c(fn, s);
    for (int c = 0; c < 3; ++c) out->transmittance[c] = r->occluder.transmittance[static_cast<std::size_t>(c)];
    out->mask = r->occluder.mask;
    out->interior = r->occluder.interior == par2d::Interior::lit ? PAR2D_INTERIOR_LIT : PAR2D_INTERIOR_DARK;
    return PAR2D_OK;
  });
}

par2d_status par2d_set_occluder_terms(par2d_renderer* r, par2d_occluder occluder, const par2d_occluder_terms* terms) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (terms == nullptr) return fail(fn, "terms is null");
  if (raw_enum(terms->interior) != PAR2D_INTERIOR_DARK && raw_enum(terms->interior) != PAR2D_INTERIOR_LIT)
    return fail(fn, "interior " + std::to_string(raw_enum(terms->interior)) +
                        " is not PAR2D_INTERIOR_DARK or PAR2D_INTERIOR_LIT");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.occluder(par2d::OccluderHandle{occluder}, &r->occluder); !s.ok())
      return to_c(fn, s);
    r->occluder.transmittance = {terms->transmittance[0], terms->transmittance[1], terms->transmittance[2]};
    r->occluder.mask = terms->mask;
    r->occluder.interior = terms->interior == PAR2D_INTERIOR_LIT ? par2d::Interior::lit : par2d::Interior::dark;
    return to_c(fn, r->renderer.update_occluder(par2d::OccluderHandle{occluder}, r->occluder));
  });
}

par2d_status par2d_set_ambient(par2d_renderer* r, const double ambient[3]) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (ambient == nullptr) return fail(fn, "ambient is null");
  return guarded(fn, [&] { return to_c(fn, r->renderer.set_ambient({ambient[0], ambient[1], ambient[2]})); });
}

par2d_status par2d_set_directional_lights(par2d_renderer* r, const par2d_directional_light* lights, size_t count) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (count > PAR2D_MAX_DIRECTIONAL_LIGHTS)
    return fail(fn, "count " + std::to_string(count) + " is more than " + std::to_string(PAR2D_MAX_DIRECTIONAL_LIGHTS));
  if (lights == nullptr && count > 0) return fail(fn, "lights is null");
  return guarded(fn, [&] {
    std::vector<par2d::DirectionalLight> converted;
    converted.reserve(count);
    for (size_t i = 0; i < count; ++i) converted.push_back(from_c(lights[i]));
    return to_c(fn, r->renderer.set_directional_lights(converted));
  });
}

par2d_status par2d_set_normal(par2d_renderer* r, const double normal[3]) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (normal == nullptr) return fail(fn, "normal is null");
  return guarded(fn, [&] { return to_c(fn, r->renderer.set_normal({normal[0], normal[1], normal[2]})); });
}

par2d_status par2d_set_normal_map(par2d_renderer* r, const float* normals, int width, int height) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (normals == nullptr) return fail(fn, "normals is null");
  if (width < 1 || height < 1 || width > par2d::kMaxImageSide || height > par2d::kMaxImageSide)
    return fail(fn, "width and height must be from 1 to " + std::to_string(par2d::kMaxImageSide) + ", got " +
                        std::to_string(width) + "x" + std::to_string(height));
  return guarded(fn, [&] {
    par2d::NormalMap map;
    map.width = width;
    map.height = height;
    map.normals.assign(normals, normals + 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    return to_c(fn, r->renderer.set_normal_map(map));
  });
}

par2d_status par2d_load_normal_map(par2d_renderer* r, const char* png_path) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (png_path == nullptr) return fail(fn, "png_path is null");
  return guarded(fn, [&] {
    // Checked against the frame from the PNG header, before a pixel is decoded: a small file
    // may declare any size. Before the first set_frame any size up to kMaxImageSide goes.
    const int width = r->renderer.width(), height = r->renderer.height();
    par2d::NormalMap map;
    const par2d::Status s = width > 0 && height > 0 ? par2d::load_normal_map_png(png_path, map, width, height)
                                                    : par2d::load_normal_map_png(png_path, map);
    if (!s.ok()) return to_c(fn, s);
    return to_c(fn, r->renderer.set_normal_map(map));
  });
}

par2d_status par2d_clear_normal_source(par2d_renderer* r) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] { return to_c(fn, r->renderer.clear_normal_source()); });
}

// ---- Options beyond par2d_options, the frame, the world's contents and what was done ----

par2d_status par2d_get_options(const par2d_renderer* r, par2d_options* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  const par2d::RenderOptions& o = r->renderer.options();
  out->backend = o.backend == par2d::Backend::simd     ? PAR2D_BACKEND_SIMD
                 : o.backend == par2d::Backend::scalar ? PAR2D_BACKEND_SCALAR
                                                       : PAR2D_BACKEND_AUTO;
  out->threads = o.threads;
  out->spp = o.spp;
  out->culling = o.culling ? 1 : 0;
  return PAR2D_OK;
}

par2d_status par2d_set_options(par2d_renderer* r, const par2d_options* options) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (options == nullptr) return fail(fn, "options is null");
  return guarded(fn, [&] {
    par2d::RenderOptions o = r->renderer.options();
    if (par2d_status s = apply_options(fn, *options, o); s != PAR2D_OK) return s;
    return to_c(fn, r->renderer.set_options(o));
  });
}

void par2d_advanced_options_default(par2d_advanced_options* options) {
  if (options == nullptr) return;
  options->isa = PAR2D_ISA_DEFAULT;
  options->threading = PAR2D_THREADING_OWN_POOL;
  options->shaded = 1;
}

par2d_status par2d_get_advanced_options(const par2d_renderer* r, par2d_advanced_options* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  const par2d::RenderOptions& o = r->renderer.options();
  // par2d_isa's values are par2d::Isa's (checked at the end of this file).
  out->isa = o.isa ? static_cast<par2d_isa>(static_cast<int>(*o.isa)) : PAR2D_ISA_DEFAULT;
  out->threading = o.threading == par2d::Threading::caller_arena ? PAR2D_THREADING_CALLER_ARENA
                                                                 : PAR2D_THREADING_OWN_POOL;
  out->shaded = o.shaded ? 1 : 0;
  return PAR2D_OK;
}

par2d_status par2d_set_advanced_options(par2d_renderer* r, const par2d_advanced_options* options) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (options == nullptr) return fail(fn, "options is null");
  const long long isa = raw_enum(options->isa), threading = raw_enum(options->threading);
  if (isa < PAR2D_ISA_DEFAULT || isa > PAR2D_ISA_NEON64)
    return fail(fn, "isa " + std::to_string(isa) + " is not PAR2D_ISA_DEFAULT or a PAR2D_ISA_* level");
  if (threading != PAR2D_THREADING_OWN_POOL && threading != PAR2D_THREADING_CALLER_ARENA)
    return fail(fn, "threading " + std::to_string(threading) +
                        " is not PAR2D_THREADING_OWN_POOL or PAR2D_THREADING_CALLER_ARENA");
  return guarded(fn, [&] {
    par2d::RenderOptions o = r->renderer.options();
    if (isa == PAR2D_ISA_DEFAULT) o.isa.reset();
    else o.isa = static_cast<par2d::Isa>(isa);
    o.threading = threading == PAR2D_THREADING_CALLER_ARENA ? par2d::Threading::caller_arena
                                                            : par2d::Threading::own_pool;
    o.shaded = options->shaded != 0;
    return to_c(fn, r->renderer.set_options(o));
  });
}

par2d_isa par2d_renderer_isa(const par2d_renderer* r) {
  if (r == nullptr) return PAR2D_ISA_SCALAR;
  return static_cast<par2d_isa>(static_cast<int>(par2d::resolved_isa(r->renderer.options())));
}

par2d_isa par2d_detect_isa(void) { return static_cast<par2d_isa>(static_cast<int>(par2d::detect_isa())); }

const char* par2d_isa_name(par2d_isa isa) {
  const long long value = raw_enum(isa);
  if (value < PAR2D_ISA_SCALAR || value > PAR2D_ISA_NEON64) return "";
  return par2d::isa_name(static_cast<par2d::Isa>(value));
}

int par2d_bytes_per_pixel(par2d_pixel_format format) {
  switch (raw_enum(format)) {
    case PAR2D_RGB_F32: return par2d::bytes_per_pixel(par2d::PixelFormat::rgb_f32);
    case PAR2D_RGBA_F32: return par2d::bytes_per_pixel(par2d::PixelFormat::rgba_f32);
    case PAR2D_RGBA8_SRGB: return par2d::bytes_per_pixel(par2d::PixelFormat::rgba8_srgb);
    default: return 0;
  }
}

par2d_status par2d_get_frame(const par2d_renderer* r, int* width, int* height, double view[4]) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (width) *width = r->renderer.width();
  if (height) *height = r->renderer.height();
  if (view) {
    const par2d::View& v = r->renderer.view();
    view[0] = v.x0;
    view[1] = v.y0;
    view[2] = v.x1;
    view[3] = v.y1;
  }
  return PAR2D_OK;
}

size_t par2d_light_count(const par2d_renderer* r) { return r ? r->renderer.light_count() : 0; }
size_t par2d_occluder_count(const par2d_renderer* r) { return r ? r->renderer.occluder_count() : 0; }

par2d_status par2d_get_light_handles(const par2d_renderer* r, par2d_light* out, size_t capacity, size_t* count) {
  if (r == nullptr) return fail(__func__, "renderer is null");
  return copy_ids(__func__, r->lights, out, capacity, count);
}

par2d_status par2d_get_occluder_handles(const par2d_renderer* r, par2d_occluder* out, size_t capacity,
                                        size_t* count) {
  if (r == nullptr) return fail(__func__, "renderer is null");
  return copy_ids(__func__, r->occluders, out, capacity, count);
}

par2d_status par2d_get_light(par2d_renderer* r, par2d_light light, par2d_shape* shape, double color[3],
                             double* intensity) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.light(par2d::LightHandle{light}, &r->light); !s.ok()) return to_c(fn, s);
    if (shape) to_c_shape(r->light.shape, r->vertices_out, *shape);
    if (color) std::copy(r->light.color.begin(), r->light.color.end(), color);
    if (intensity) *intensity = r->light.intensity;
    return PAR2D_OK;
  });
}

par2d_status par2d_get_occluder(par2d_renderer* r, par2d_occluder occluder, par2d_shape* shape) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.occluder(par2d::OccluderHandle{occluder}, &r->occluder); !s.ok())
      return to_c(fn, s);
    if (shape) to_c_shape(r->occluder.shape, r->vertices_out, *shape);
    return PAR2D_OK;
  });
}

par2d_status par2d_get_ambient(const par2d_renderer* r, double ambient[3]) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (ambient == nullptr) return fail(fn, "ambient is null");
  const par2d::Rgb& a = r->renderer.model_terms().ambient;
  std::copy(a.begin(), a.end(), ambient);
  return PAR2D_OK;
}

par2d_status par2d_get_directional_lights(const par2d_renderer* r, par2d_directional_light* out, size_t capacity,
                                          size_t* count) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (count == nullptr) return fail(fn, "count is null");
  if (out == nullptr && capacity > 0) return fail(fn, "out is null but capacity is " + std::to_string(capacity));
  const std::vector<par2d::DirectionalLight>& lights = r->renderer.model_terms().directional_lights;
  for (std::size_t i = 0; i < lights.size() && i < capacity; ++i) {
    const par2d::DirectionalLight& d = lights[i];
    out[i] = par2d_directional_light{{d.angle0, d.angle1}, {d.color[0], d.color[1], d.color[2]}, d.intensity, d.mask,
                                     d.elevation};
  }
  *count = lights.size();
  return PAR2D_OK;
}

par2d_status par2d_get_normal_source(const par2d_renderer* r, par2d_normal_source* kind, double normal[3]) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (kind == nullptr) return fail(fn, "kind is null");
  const par2d::Scene& terms = r->renderer.model_terms();
  *kind = terms.normal ? PAR2D_NORMAL_CONSTANT : terms.normal_map ? PAR2D_NORMAL_MAP : PAR2D_NORMAL_NONE;
  if (terms.normal && normal) {
    normal[0] = terms.normal->x;
    normal[1] = terms.normal->y;
    normal[2] = terms.normal->z;
  }
  return PAR2D_OK;
}

par2d_status par2d_save_scene(const par2d_renderer* r, const char* path) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (path == nullptr) return fail(fn, "path is null");
  return guarded(fn, [&] { return to_c(fn, par2d::save_scene_file(path, r->renderer.snapshot())); });
}

par2d_status par2d_snapshot_json(const par2d_renderer* r, char* out, size_t capacity, size_t* length) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (length == nullptr) return fail(fn, "length is null");
  if (out == nullptr && capacity > 0) return fail(fn, "out is null but capacity is " + std::to_string(capacity));
  return guarded(fn, [&] {
    const std::string text = par2d::scene_to_json(r->renderer.snapshot());
    *length = text.size();
    if (capacity == 0) return PAR2D_OK;  // a size query
    if (text.size() >= capacity)
      return fail(fn, "capacity " + std::to_string(capacity) + " is too small for " + std::to_string(text.size() + 1) +
                          " bytes (text and NUL)");
    std::memcpy(out, text.c_str(), text.size() + 1);
    return PAR2D_OK;
  });
}

par2d_status par2d_get_stats(const par2d_renderer* r, par2d_stats* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  const par2d::RendererStats s = r->renderer.stats();
  *out = par2d_stats{s.frames, s.index_builds, s.index_updates, s.reach_computations, s.full_prepares};
  return PAR2D_OK;
}

par2d_status par2d_get_frame_stats(const par2d_renderer* r, par2d_frame_stats* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  const par2d::FrameStats s = r->renderer.frame_stats();
  *out = par2d_frame_stats{s.pixels,
                           s.samples,
                           s.blocks,
                           s.block_lights,
                           s.block_lights_out_of_reach,
                           s.block_candidates,
                           s.block_proofs_tried,
                           s.block_proofs_succeeded,
                           s.block_proofs_skipped,
                           s.tiles,
                           s.tile_lights,
                           s.tile_pairs,
                           s.tile_general_pairs,
                           s.tile_proofs_tried,
                           s.tile_proofs_succeeded,
                           s.tile_proofs_skipped,
                           s.umbra_tests,
                           s.umbra_hits,
                           s.tile_pairs_outside_hull,
                           s.light_samples,
                           s.pair_samples,
                           s.scalar_tiles};
  return PAR2D_OK;
}

}  // extern "C"

// The C enum mirrors par2d::Isa value for value (the conversions above cast between them).
static_assert(PAR2D_ISA_SCALAR == static_cast<int>(par2d::Isa::scalar) &&
                  PAR2D_ISA_SSE4_2 == static_cast<int>(par2d::Isa::sse4_2) &&
                  PAR2D_ISA_AVX2 == static_cast<int>(par2d::Isa::avx2) &&
                  PAR2D_ISA_AVX512 == static_cast<int>(par2d::Isa::avx512) &&
                  PAR2D_ISA_NEON64 == static_cast<int>(par2d::Isa::neon64),
              "par2d_isa and par2d::Isa differ");
