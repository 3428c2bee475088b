// The C API's read-backs (include/par2d/par2d.h): options, the ISA, the frame, the world's
// contents and what the renderer has done, each as plain C data.
#include "par2d/par2d.h"

#include <cstring>
#include <string>
#include <vector>

#include "capi/c_api_support.hpp"
#include "par2d/isa.hpp"
#include "par2d/scene_write.hpp"

using namespace par2d::capi;

extern "C" {

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
  options->sample_needs = 0;
  options->bounce = PAR2D_BOUNCE_INCLUDED;
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
  out->sample_needs = o.sample_needs ? 1 : 0;
  out->bounce = static_cast<par2d_bounce_term>(static_cast<int>(o.bounce));
  return PAR2D_OK;
}

par2d_status par2d_set_advanced_options(par2d_renderer* r, const par2d_advanced_options* options) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (options == nullptr) return fail(fn, "options is null");
  const long long isa = raw_enum(options->isa), threading = raw_enum(options->threading);
  const long long bounce = raw_enum(options->bounce);
  if (bounce < PAR2D_BOUNCE_INCLUDED || bounce > PAR2D_BOUNCE_ONLY)
    return fail(fn, "bounce " + std::to_string(bounce) +
                        " is not PAR2D_BOUNCE_INCLUDED, PAR2D_BOUNCE_EXCLUDED or PAR2D_BOUNCE_ONLY");
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
    o.sample_needs = options->sample_needs != 0;
    o.bounce = static_cast<par2d::BounceTerm>(bounce);
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
  const par2d::PixelFormat* known = pixel_format_of(format);
  return known ? par2d::bytes_per_pixel(*known) : 0;
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
    if (shape) to_c_shape(r->light.shape, r->vertices_out, r->holes_out, *shape);
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
    if (shape) to_c_shape(r->occluder.shape, r->vertices_out, r->holes_out, *shape);
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
  *out = par2d_frame_stats{s.pixels,        s.tiles,         s.layer_tiles_reused, s.layer_tiles_filled,
                           s.bounce_pieces, s.bounce_lit_sources};
  return PAR2D_OK;
}

par2d_status par2d_get_frame_diagnostics(const par2d_renderer* r, par2d_frame_diagnostics* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  const par2d::FrameDiagnostics d = r->renderer.frame_diagnostics();
  *out = par2d_frame_diagnostics{d.samples,
                                 d.blocks,
                                 d.block_lights,
                                 d.block_lights_out_of_reach,
                                 d.block_candidates,
                                 d.block_proofs_tried,
                                 d.block_proofs_succeeded,
                                 d.block_proofs_skipped,
                                 d.tile_lights,
                                 d.tile_pairs,
                                 d.tile_general_pairs,
                                 d.tile_proofs_tried,
                                 d.tile_proofs_succeeded,
                                 d.tile_proofs_skipped,
                                 d.umbra_tests,
                                 d.umbra_hits,
                                 d.tile_pairs_outside_hull,
                                 d.light_samples,
                                 d.pair_samples,
                                 d.scalar_tiles,
                                 d.sampled_pixels,
                                 d.sampled_visible_lights,
                                 d.sampled_blocking_pairs,
                                 d.bounce_tile_sources,
                                 d.bounce_tile_sources_hidden,
                                 d.bounce_source_walks,
                                 d.bounce_depth_tests};
  return PAR2D_OK;
}

}  // extern "C"

// The C reports hold the C++ ones field for field (the conversions above list every field).
static_assert(sizeof(par2d_frame_stats) == sizeof(par2d::FrameStats) &&
                  sizeof(par2d_frame_diagnostics) == sizeof(par2d::FrameDiagnostics),
              "par2d_frame_stats and par2d_frame_diagnostics mirror FrameStats and FrameDiagnostics");

// The C enum mirrors par2d::Isa value for value (the conversions above cast between them).
static_assert(PAR2D_ISA_SCALAR == static_cast<int>(par2d::Isa::scalar) &&
                  PAR2D_ISA_SSE4_2 == static_cast<int>(par2d::Isa::sse4_2) &&
                  PAR2D_ISA_AVX2 == static_cast<int>(par2d::Isa::avx2) &&
                  PAR2D_ISA_AVX512 == static_cast<int>(par2d::Isa::avx512) &&
                  PAR2D_ISA_NEON64 == static_cast<int>(par2d::Isa::neon64),
              "par2d_isa and par2d::Isa differ");
// par2d_bounce_term mirrors par2d::BounceTerm (cast in the advanced options above).
static_assert(PAR2D_BOUNCE_INCLUDED == static_cast<int>(par2d::BounceTerm::included) &&
                  PAR2D_BOUNCE_EXCLUDED == static_cast<int>(par2d::BounceTerm::excluded) &&
                  PAR2D_BOUNCE_ONLY == static_cast<int>(par2d::BounceTerm::only),
              "par2d_bounce_term and par2d::BounceTerm differ");
