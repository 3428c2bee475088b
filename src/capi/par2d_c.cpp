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

#include "capi/c_api_support.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene_write.hpp"
#include "par2d/version.hpp"

namespace par2d::capi {
thread_local std::string g_last_error;
}  // namespace par2d::capi

using namespace par2d::capi;

// The SONAME is the version's major.minor (src/CMakeLists.txt); par2d.h names that ABI.
static_assert(PAR2D_ABI_MAJOR == PAR2D_VERSION_MAJOR && PAR2D_ABI_MINOR == PAR2D_VERSION_MINOR,
              "par2d.h's PAR2D_ABI_* and version.hpp's major.minor differ");

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

par2d_status par2d_set_view_offset(par2d_renderer* r, int64_t x, int64_t y) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] { return to_c(fn, r->renderer.set_view_offset(x, y)); });
}

par2d_status par2d_set_buffer_layout(par2d_renderer* r, par2d_buffer_layout layout) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  const long long value = raw_enum(layout);  // never loaded as the enum (c_api_support.hpp)
  if (value != PAR2D_LAYOUT_IMAGE && value != PAR2D_LAYOUT_RING)
    return fail(fn, "layout " + std::to_string(value) + " is no par2d_buffer_layout");
  return to_c(fn, r->renderer.set_buffer_layout(value == PAR2D_LAYOUT_RING ? par2d::BufferLayout::ring
                                                                          : par2d::BufferLayout::image));
}

par2d_status par2d_get_view_offset(const par2d_renderer* r, int64_t* x, int64_t* y) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (x) *x = r->renderer.view_offset_x();
  if (y) *y = r->renderer.view_offset_y();
  return to_c(fn, par2d::Status());
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

namespace {

// par2d_add_light and par2d_update_light, with the shape placed by `transform` when given.
par2d_status add_light(const char* fn, par2d_renderer* r, const par2d_shape* shape, const par2d_transform* transform,
                       const double color[3], double intensity, par2d_light* out) {
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d_status s = fill_light(fn, r, shape, color, intensity); s != PAR2D_OK) return s;
    set_default_terms(r->light);
    r->lights.reserve(r->lights.size() + 1);  // so that the push_back below cannot fail
    par2d::LightHandle h;
    const par2d::Status s = transform ? r->renderer.add_light(r->light, to_transform(*transform), &h)
                                      : r->renderer.add_light(r->light, &h);
    if (!s.ok()) return to_c(fn, s);
    r->lights.push_back(h.id);
    *out = h.id;
    return PAR2D_OK;
  });
}

par2d_status update_light(const char* fn, par2d_renderer* r, par2d_light light, const par2d_shape* shape,
                          const par2d_transform* transform, const double color[3], double intensity) {
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    // The light keeps its terms (range, cone, mask, elevation): start from it as it is.
    if (!r->renderer.light(par2d::LightHandle{light}, &r->light).ok()) set_default_terms(r->light);
    if (par2d_status s = fill_light(fn, r, shape, color, intensity); s != PAR2D_OK) return s;
    const par2d::LightHandle h{light};
    return to_c(fn, transform ? r->renderer.update_light(h, r->light, to_transform(*transform))
                              : r->renderer.update_light(h, r->light));
  });
}

par2d_status add_occluder(const char* fn, par2d_renderer* r, const par2d_shape* shape, const par2d_transform* transform,
                          par2d_occluder* out) {
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    if (par2d_status s = convert_shape(fn, shape, r->occluder.shape); s != PAR2D_OK) return s;
    set_default_terms(r->occluder);
    r->occluders.reserve(r->occluders.size() + 1);
    par2d::OccluderHandle h;
    const par2d::Status s = transform ? r->renderer.add_occluder(r->occluder, to_transform(*transform), &h)
                                      : r->renderer.add_occluder(r->occluder, &h);
    if (!s.ok()) return to_c(fn, s);
    r->occluders.push_back(h.id);
    *out = h.id;
    return PAR2D_OK;
  });
}

par2d_status update_occluder(const char* fn, par2d_renderer* r, par2d_occluder occluder, const par2d_shape* shape,
                             const par2d_transform* transform) {
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    // The occluder keeps its terms (transmittance, mask, interior).
    if (!r->renderer.occluder(par2d::OccluderHandle{occluder}, &r->occluder).ok()) set_default_terms(r->occluder);
    if (par2d_status s = convert_shape(fn, shape, r->occluder.shape); s != PAR2D_OK) return s;
    const par2d::OccluderHandle h{occluder};
    return to_c(fn, transform ? r->renderer.update_occluder(h, r->occluder, to_transform(*transform))
                              : r->renderer.update_occluder(h, r->occluder));
  });
}

}  // namespace

par2d_status par2d_add_light(par2d_renderer* r, const par2d_shape* shape, const double color[3], double intensity,
                             par2d_light* out) {
  return add_light(__func__, r, shape, nullptr, color, intensity, out);
}

par2d_status par2d_update_light(par2d_renderer* r, par2d_light light, const par2d_shape* shape, const double color[3],
                                double intensity) {
  return update_light(__func__, r, light, shape, nullptr, color, intensity);
}

void par2d_transform_identity(par2d_transform* t) {
  if (t == nullptr) return;
  *t = par2d_transform{{0.0, 0.0}, 0.0, {1.0, 1.0}};
}

par2d_status par2d_add_light_transformed(par2d_renderer* r, const par2d_shape* local, const par2d_transform* transform,
                                         const double color[3], double intensity, par2d_light* out) {
  if (r != nullptr && transform == nullptr) return fail(__func__, "transform is null");
  return add_light(__func__, r, local, transform, color, intensity, out);
}

par2d_status par2d_update_light_transformed(par2d_renderer* r, par2d_light light, const par2d_shape* local,
                                            const par2d_transform* transform, const double color[3], double intensity) {
  if (r != nullptr && transform == nullptr) return fail(__func__, "transform is null");
  return update_light(__func__, r, light, local, transform, color, intensity);
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
  return add_occluder(__func__, r, shape, nullptr, out);
}

par2d_status par2d_update_occluder(par2d_renderer* r, par2d_occluder occluder, const par2d_shape* shape) {
  return update_occluder(__func__, r, occluder, shape, nullptr);
}

par2d_status par2d_add_occluder_transformed(par2d_renderer* r, const par2d_shape* local,
                                            const par2d_transform* transform, par2d_occluder* out) {
  if (r != nullptr && transform == nullptr) return fail(__func__, "transform is null");
  return add_occluder(__func__, r, local, transform, out);
}

par2d_status par2d_update_occluder_transformed(par2d_renderer* r, par2d_occluder occluder, const par2d_shape* local,
                                               const par2d_transform* transform) {
  if (r != nullptr && transform == nullptr) return fail(__func__, "transform is null");
  return update_occluder(__func__, r, occluder, local, transform);
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
    const par2d::PixelFormat* known = pixel_format_of(format);
    if (known == nullptr)
      return fail(fn, "pixel format " + std::to_string(raw_enum(format)) + " is not a par2d_pixel_format (0 .. 6)");
    buffer.format = *known;
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

par2d_status par2d_set_light_layer_budget(par2d_renderer* r, size_t bytes) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return to_c(fn, r->renderer.set_light_layer_budget(bytes));
}

size_t par2d_light_layer_budget(const par2d_renderer* r) { return r ? r->renderer.light_layer_budget() : 0; }
size_t par2d_light_layer_bytes(const par2d_renderer* r) { return r ? r->renderer.light_layer_bytes() : 0; }

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

par2d_status par2d_frame_shift(const par2d_renderer* r, int* dx, int* dy) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  const par2d::PixelShift shift = r->renderer.frame_shift();
  if (dx) *dx = shift.dx;
  if (dy) *dy = shift.dy;
  return to_c(fn, par2d::Status());
}

void par2d_light_terms_default(par2d_light_terms* terms) {
  if (terms == nullptr) return;
  *terms = par2d_light_terms{};
  terms->cone_half_angle = 180.0;
  terms->mask = par2d::kAllMaskBits;
  terms->falloff = 2.0;
  terms->shadow_strength = 1.0;
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
    out->falloff = r->light.falloff;
    out->normalize = r->light.normalize ? *r->light.normalize : 0.0;
    out->has_cone = r->light.cone ? 1 : 0;
    if (r->light.cone) {
      out->cone_direction = r->light.cone->direction;
      out->cone_half_angle = r->light.cone->half_angle;
      out->cone_fade = r->light.cone->fade;
    }
    out->mask = r->light.mask;
    out->elevation = r->light.elevation;
    out->shadow_strength = r->light.shadow.strength;
    for (int c = 0; c < 3; ++c) out->shadow_color[c] = r->light.shadow.color[static_cast<std::size_t>(c)];
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
    r->light.falloff = terms->falloff;
    // 0 means none, as for range.
    if (terms->normalize == 0.0) r->light.normalize.reset();
    else r->light.normalize = terms->normalize;
    if (terms->has_cone) r->light.cone = par2d::Cone{terms->cone_direction, terms->cone_half_angle, terms->cone_fade};
    else r->light.cone.reset();
    r->light.mask = terms->mask;
    r->light.elevation = terms->elevation;
    r->light.shadow = par2d::Shadow{terms->shadow_strength,
                                    {terms->shadow_color[0], terms->shadow_color[1], terms->shadow_color[2]}};
    return to_c(fn, r->renderer.update_light(par2d::LightHandle{light}, r->light));
  });
}

par2d_status par2d_set_light_cookie(par2d_renderer* r, par2d_light light, double rotation, const double* directions,
                                    const double* weights, size_t count) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (count != 0 && (directions == nullptr || weights == nullptr))
    return fail(fn, std::string(directions == nullptr ? "directions" : "weights") + " is null with count " +
                        std::to_string(count));
  // Far more knots than any cookie may have: refused by validation below without copying them.
  if (count > static_cast<size_t>(par2d::kMaxCookieKnots))
    return fail(fn, "count must be at most " + std::to_string(par2d::kMaxCookieKnots) + ", got " + std::to_string(count));
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.light(par2d::LightHandle{light}, &r->light); !s.ok()) return to_c(fn, s);
    if (count == 0) {
      r->light.cookie.reset();
    } else {
      if (!r->light.cookie) r->light.cookie.emplace();
      r->light.cookie->rotation = rotation;
      r->light.cookie->knots.resize(count);
      for (size_t k = 0; k < count; ++k) r->light.cookie->knots[k] = par2d::CookieKnot{directions[k], weights[k]};
    }
    return to_c(fn, r->renderer.update_light(par2d::LightHandle{light}, r->light));
  });
}

par2d_status par2d_get_light_cookie(par2d_renderer* r, par2d_light light, double* rotation, double* directions,
                                    double* weights, size_t capacity, size_t* count) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (count == nullptr) return fail(fn, "count is null");
  if (capacity != 0 && (directions == nullptr || weights == nullptr))
    return fail(fn, std::string(directions == nullptr ? "directions" : "weights") + " is null with capacity " +
                        std::to_string(capacity));
  return guarded(fn, [&] {
    if (par2d::Status s = r->renderer.light(par2d::LightHandle{light}, &r->light); !s.ok()) return to_c(fn, s);
    const std::vector<par2d::CookieKnot>* knots = r->light.cookie ? &r->light.cookie->knots : nullptr;
    *count = knots ? knots->size() : 0;
    if (rotation != nullptr) *rotation = r->light.cookie ? r->light.cookie->rotation : 0.0;
    for (size_t k = 0; knots && k < knots->size() && k < capacity; ++k) {
      directions[k] = (*knots)[k].direction;
      weights[k] = (*knots)[k].weight;
    }
    return PAR2D_OK;
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
    for (int c = 0; c < 3; ++c) out->albedo[c] = r->occluder.albedo[static_cast<std::size_t>(c)];
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
    r->occluder.albedo = {terms->albedo[0], terms->albedo[1], terms->albedo[2]};
    return to_c(fn, r->renderer.update_occluder(par2d::OccluderHandle{occluder}, r->occluder));
  });
}

par2d_status par2d_set_bounce(par2d_renderer* r, double piece) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    par2d::Bounce bounce = r->renderer.bounce();
    bounce.piece = piece;
    return to_c(fn, r->renderer.set_bounce(bounce));
  });
}

par2d_status par2d_set_bounce_step(par2d_renderer* r, int step) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    par2d::Bounce bounce = r->renderer.bounce();
    bounce.step = step;
    return to_c(fn, r->renderer.set_bounce(bounce));
  });
}

par2d_status par2d_get_bounce_step(const par2d_renderer* r, int* step) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (step == nullptr) return fail(fn, "step is null");
  *step = r->renderer.bounce().step;
  return PAR2D_OK;
}

par2d_status par2d_get_bounce(const par2d_renderer* r, double* piece) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (piece == nullptr) return fail(fn, "piece is null");
  *piece = r->renderer.bounce().piece;
  return PAR2D_OK;
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

}  // extern "C"
