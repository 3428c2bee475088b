// The one-shot front door (a Renderer made for one frame), the ray-casting baseline, and the
// names of the backends and bounce terms.
#include <atomic>
#include <cstring>
#include <memory>
#include <cstdint>
#include <optional>
#include <string_view>
#include <thread>

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "render/render_arguments.hpp"
#include "render/scalar_tiles.hpp"
#include "render/tiling.hpp"
#include "render/work_estimate.hpp"
#include "scene/scene_validate.hpp"
#include "status_guard.hpp"

namespace par2d {

using detail::worker_threads;

const char* backend_name(Backend backend) noexcept {
  switch (backend) {
    case Backend::automatic: return "auto";
    case Backend::simd: return "simd";
    case Backend::scalar: return "scalar";
    case Backend::raycast: return "raycast";
  }
  return "unknown";
}

std::optional<Backend> parse_backend(const char* name) noexcept {
  const std::string_view n = name ? name : "";
  if (n == "auto") return Backend::automatic;
  if (n == "simd") return Backend::simd;
  if (n == "scalar") return Backend::scalar;
  if (n == "raycast") return Backend::raycast;
  return std::nullopt;
}

const char* bounce_term_name(BounceTerm term) noexcept {
  switch (term) {
    case BounceTerm::included: return "included";
    case BounceTerm::excluded: return "excluded";
    case BounceTerm::only: return "only";
  }
  return "unknown";
}

std::optional<BounceTerm> parse_bounce_term(const char* name) noexcept {
  const std::string_view n = name ? name : "";
  if (n == "included") return BounceTerm::included;
  if (n == "excluded") return BounceTerm::excluded;
  if (n == "only") return BounceTerm::only;
  return std::nullopt;
}

namespace {

// One frame of `scene` by a Renderer made for it: the same path as a host's Renderer.
Status render_once(const Scene& scene, const RenderOptions& options, const FrameBuffer& buffer, FrameStats* stats,
                   const RenderControl* control = nullptr) {
  return detail::guarded("render", [&]() -> Status {
    Renderer renderer;
    RenderOptions once = options;
    once.sample_needs = options.sample_needs || stats != nullptr;
    if (Status s = renderer.set_options(once); !s.ok()) return s;
    if (Status s = renderer.set_scene(scene); !s.ok()) return s;
    if (control && (control->progress || control->cancel)) {
      if (control->cancel && control->cancel->load()) return Status(StatusCode::cancelled, "render: cancelled");
      // The host's flag is read after each of the calling thread's tiles; any progress
      // function makes the frame a watched one (computed aside, copied out when complete).
      renderer.set_progress([control](const Progress& p) {
        if (control->cancel && control->cancel->load()) return false;
        return !control->progress || control->progress(p);
      });
    }
    if (Status s = renderer.render(buffer); !s.ok()) return s;
    if (stats) *stats = renderer.frame_stats();
    return {};
  });
}

// The ray caster's estimated work on a validated scene.
WorkEstimate raycast_estimate(const Scene& scene, const RenderOptions& options) noexcept {
  detail::WorkCounts counts;
  counts.pixels = static_cast<double>(scene.width) * scene.height;
  counts.spp = options.spp;
  counts.lights = static_cast<double>(scene.lights.size() + scene.directional_lights.size());
  counts.occluders = static_cast<double>(scene.occluders.size());
  counts.pieces = options.bounce == BounceTerm::excluded ? 0.0 : detail::bounce_pieces(scene);
  counts.raycast = true;
  counts.rays = options.rays;
  return detail::estimate_work(counts);
}

// The ray caster over `image`'s blocks; with `control`, into an image of its own copied out
// once complete, reporting each block's tiles from the calling thread.
Status raycast_frame(const Scene& scene, const RenderOptions& options, const ImageView& image,
                     const RenderControl* control) {
  if (Status s = detail::check_image_view(image, scene.width, scene.height, "render_raycast", "scene"); !s.ok()) return s;
  RenderOptions checked = options;
  checked.backend = Backend::raycast;  // the rays' range is checked
  if (Status s = detail::check_options(checked, "render_raycast"); !s.ok()) return s;
  return detail::guarded("render_raycast", [&]() -> Status {
    if (Status s = validate_scene(scene); !s.ok()) return s;
    if (Status s = detail::check_work(raycast_estimate(scene, options), options.work_limit, "render_raycast"); !s.ok())
      return s;
    const bool watched = control && (control->progress || control->cancel);
    if (watched && control->cancel && control->cancel->load())
      return Status(StatusCode::cancelled, "render_raycast: cancelled");
    detail::RaycastRenderer caster(scene);
    caster.set_bounce_term(options.bounce);
    ImageView target = image;
    std::unique_ptr<float[]> aside;
    if (watched) {
      aside.reset(new float[static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3]);
      target = ImageView{aside.get(), scene.width, scene.height, static_cast<std::ptrdiff_t>(scene.width) * 3};
    }
    const auto tiles_of = [](const detail::TileRect& b) {
      return static_cast<std::uint64_t>((b.x1 - b.x0 + detail::kTileSize - 1) / detail::kTileSize) *
             static_cast<std::uint64_t>((b.y1 - b.y0 + detail::kTileSize - 1) / detail::kTileSize);
    };
    const std::uint64_t tiles = static_cast<std::uint64_t>((scene.width + detail::kTileSize - 1) / detail::kTileSize) *
                                static_cast<std::uint64_t>((scene.height + detail::kTileSize - 1) / detail::kTileSize);
    std::atomic<std::uint64_t> done{0};
    std::atomic<bool> stop{false};
    std::uint64_t reported = 0;
    const std::thread::id caller = std::this_thread::get_id();
    detail::for_each_block(scene.width, scene.height, worker_threads(options.threads),
                           [&](const detail::TileRect& block, int) {
                             if (watched && (stop.load() || (control->cancel && control->cancel->load()))) return;
                             detail::render_rect_raycast(scene, caster, options.spp, options.rays, block, target,
                                                         options.shaded);
                             if (!watched) return;
                             const std::uint64_t now = done.fetch_add(tiles_of(block)) + tiles_of(block);
                             if (!control->progress || std::this_thread::get_id() != caller) return;
                             reported = now;
                             if (!control->progress(Progress{now, tiles})) stop.store(true);
                           });
    if (!watched) return {};
    if (done.load() < tiles) return Status(StatusCode::cancelled, "render_raycast: cancelled");
    if (control->progress && reported < tiles) control->progress(Progress{tiles, tiles});
    for (int y = 0; y < scene.height; ++y)
      std::memcpy(image.data + y * image.row_stride, target.data + y * target.row_stride,
                  static_cast<std::size_t>(scene.width) * 3 * sizeof(float));
    return {};
  });
}

Status render_frame(const Scene& scene, const RenderOptions& options, const ImageView& image, FrameStats* stats) {
  if (Status s = detail::check_image_view(image, scene.width, scene.height, "render", "scene"); !s.ok()) return s;
  if (Status s = detail::check_options(options, "render"); !s.ok()) return s;
  if (options.backend == Backend::raycast) return raycast_frame(scene, options, image, nullptr);
  return render_once(scene, options, detail::frame_buffer_of(image), stats);
}

}  // namespace

Status render_raycast(const Scene& scene, const RenderOptions& options, const ImageView& image) {
  return raycast_frame(scene, options, image, nullptr);
}

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image) {
  return render_frame(scene, options, image, nullptr);
}

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image, const RenderControl& control) {
  if (Status s = detail::check_image_view(image, scene.width, scene.height, "render", "scene"); !s.ok()) return s;
  if (Status s = detail::check_options(options, "render"); !s.ok()) return s;
  if (options.backend == Backend::raycast) return raycast_frame(scene, options, image, &control);
  return render_once(scene, options, detail::frame_buffer_of(image), nullptr, &control);
}

Status estimate_work(const Scene& scene, const RenderOptions& options, WorkEstimate& estimate) {
  if (Status s = detail::check_options(options, "estimate_work"); !s.ok()) return s;
  return detail::guarded("estimate_work", [&]() -> Status {
    if (Status s = validate_scene(scene); !s.ok()) return s;
    if (options.backend == Backend::raycast) {
      estimate = raycast_estimate(scene, options);
      return {};
    }
    Renderer renderer;
    if (Status s = renderer.set_options(options); !s.ok()) return s;
    if (Status s = renderer.set_scene(scene); !s.ok()) return s;
    return renderer.estimate_work(estimate);
  });
}

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image, FrameStats& stats) {
  stats = FrameStats{};
  return render_frame(scene, options, image, &stats);
}

Status render(const Scene& scene, const RenderOptions& options, const FrameBuffer& buffer) {
  if (Status s = detail::check_options(options, "render"); !s.ok()) return s;
  if (options.backend == Backend::raycast)
    return Status(StatusCode::unsupported, "render: the raycast baseline writes float RGB (call render_raycast)");
  return render_once(scene, options, buffer, nullptr);
}

}  // namespace par2d
