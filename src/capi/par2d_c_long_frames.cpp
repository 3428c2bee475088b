// The C API's long-frame calls (include/par2d/par2d.h, "Long frames"): the work estimate and
// limit, the progress function and cancellation, over par2d::Renderer's.
#include <string>

#include "capi/c_api_support.hpp"
#include "par2d/par2d.h"
#include "par2d/renderer.hpp"

using namespace par2d::capi;

extern "C" {

par2d_status par2d_estimate_work(par2d_renderer* r, const int* region, par2d_work_estimate* out) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (out == nullptr) return fail(fn, "out is null");
  return guarded(fn, [&] {
    par2d::WorkEstimate e;
    const par2d::Status s = region == nullptr
                                ? r->renderer.estimate_work(e)
                                : r->renderer.estimate_work(par2d::PixelRect{region[0], region[1], region[2], region[3]}, e);
    if (!s.ok()) return to_c(fn, s);
    *out = par2d_work_estimate{e.samples, e.bounce, e.scalar, e.raycast, e.total};
    return PAR2D_OK;
  });
}

par2d_status par2d_set_work_limit(par2d_renderer* r, double limit) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    par2d::RenderOptions o = r->renderer.options();
    o.work_limit = limit;
    return to_c(fn, r->renderer.set_options(o));
  });
}

par2d_status par2d_get_work_limit(const par2d_renderer* r, double* limit) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  if (limit == nullptr) return fail(fn, "limit is null");
  *limit = r->renderer.options().work_limit;
  return PAR2D_OK;
}

par2d_status par2d_set_progress(par2d_renderer* r, par2d_progress_fn progress, void* user) {
  const char* const fn = __func__;
  if (r == nullptr) return fail(fn, "renderer is null");
  return guarded(fn, [&] {
    if (progress == nullptr) {
      r->renderer.set_progress(nullptr);
    } else {
      r->renderer.set_progress(
          [progress, user](const par2d::Progress& p) { return progress(user, p.tiles_done, p.tiles) != 0; });
    }
    return PAR2D_OK;
  });
}

void par2d_cancel(par2d_renderer* r) {
  if (r != nullptr) r->renderer.cancel();
}

}  // extern "C"
