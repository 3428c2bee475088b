// The render entry point: checks arguments, prepares the scene, and runs the chosen
// backend over image tiles on a TBB arena of the requested size.
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

#include "par2d/render.hpp"
#include "render/frame_output.hpp"
#include "render/frame_driver.hpp"
#include "render/render_arguments.hpp"
#include "parallel/scheduler.hpp"
#include "world/prepared_scene.hpp"
#include "render/scalar_tiles.hpp"
#include "render/tiling.hpp"
#include "world/world.hpp"

namespace par2d {
namespace {

using detail::PreparedScene;

constexpr int kMaxSpp = 256;
constexpr int kMaxRays = 1 << 20;

Status check_arguments(const Scene& scene, const RenderOptions& options, const ImageView& image) {
  auto bad = [](std::string message) { return Status(StatusCode::invalid_argument, std::move(message)); };
  if (image.data == nullptr) return bad("render: image data is null");
  if (image.width != scene.width || image.height != scene.height)
    return bad("render: image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
               " but the scene is " + std::to_string(scene.width) + "x" + std::to_string(scene.height));
  if (image.row_stride < 3 * static_cast<std::ptrdiff_t>(image.width))
    return bad("render: row_stride " + std::to_string(image.row_stride) + " is less than 3 * width");
  return detail::check_options(options, "render");
}

int worker_threads(int requested) noexcept {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (requested == 0) return tbb::this_task_arena::max_concurrency();
  return std::min(requested, hardware);  // more only adds scheduling overhead
}

void render_raycast(const Scene& scene, const RenderOptions& options, int threads, const ImageView& image) {
  const detail::RaycastRenderer caster(scene);
  detail::for_each_block(scene.width, scene.height, threads, [&](const detail::TileRect& block, int) {
    detail::render_rect_raycast(scene, caster, options.spp, options.rays, block, image, options.shaded);
  });
}

}  // namespace

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

void sample_offset(int k, int spp, double& dx, double& dy) noexcept {
  if (spp <= 1) {
    dx = dy = 0.5;
    return;
  }
  // Rank-1 lattice: one sample per column and per row of an spp x spp grid, rows visited
  // with a golden-ratio stride so the samples also spread in 2D.
  int stride = std::max(1, static_cast<int>(std::lround(spp * 0.6180339887498949)));
  while (std::gcd(stride, spp) != 1) ++stride;
  dx = (k + 0.5) / spp;
  dy = (static_cast<double>((static_cast<long long>(k) * stride) % spp) + 0.5) / spp;
}

Isa resolved_isa(const RenderOptions& options) noexcept {
  if (options.backend == Backend::scalar || options.backend == Backend::raycast) return Isa::scalar;
  if (!options.isa) return default_isa();
  return capped_isa(*options.isa);
}

int resolved_threads(const RenderOptions& options) noexcept {
  if (options.threading == Threading::caller_arena) return tbb::this_task_arena::max_concurrency();
  return worker_threads(std::max(0, options.threads));
}

namespace detail {

Status check_options(const RenderOptions& options, const char* who) {
  auto bad = [who](std::string message) {
    return Status(StatusCode::invalid_argument, std::string(who) + ": " + std::move(message));
  };
  if (options.threads < 0) return bad("threads must be >= 0 (0 = all hardware threads)");
  if (options.spp < 1 || options.spp > kMaxSpp) return bad("spp must be in 1.." + std::to_string(kMaxSpp));
  if (options.backend == Backend::raycast && (options.rays < 1 || options.rays > kMaxRays))
    return bad("rays must be in 1.." + std::to_string(kMaxRays));
  if (options.isa && (static_cast<int>(*options.isa) < static_cast<int>(Isa::scalar) ||
                      static_cast<int>(*options.isa) > static_cast<int>(Isa::neon64)))
    return bad("unknown isa " + std::to_string(static_cast<int>(*options.isa)));
  if (static_cast<int>(options.backend) < static_cast<int>(Backend::automatic) ||
      static_cast<int>(options.backend) > static_cast<int>(Backend::raycast))
    return bad("unknown backend " + std::to_string(static_cast<int>(options.backend)));
  if (options.threading != Threading::own_pool && options.threading != Threading::caller_arena)
    return bad("unknown threading " + std::to_string(static_cast<int>(options.threading)));
  return {};
}

Status check_frame_buffer(const FrameBuffer& buffer, const PixelRect& region, int width, int height, const char* who) {
  auto bad = [who](std::string message) {
    return Status(StatusCode::invalid_argument, std::string(who) + ": " + std::move(message));
  };
  if (buffer.data == nullptr) return bad("buffer data is null");
  const int pixel = bytes_per_pixel(buffer.format);
  if (pixel == 0) return bad("unknown pixel format " + std::to_string(static_cast<int>(buffer.format)));
  if (!(std::isfinite(buffer.exposure) && buffer.exposure >= 0.0)) return bad("exposure must be finite and >= 0");
  if (!(0 <= region.x0 && region.x0 < region.x1 && region.x1 <= width && 0 <= region.y0 && region.y0 < region.y1 &&
        region.y1 <= height))
    return bad("region [" + std::to_string(region.x0) + ", " + std::to_string(region.y0) + ", " +
               std::to_string(region.x1) + ", " + std::to_string(region.y1) + ") is empty or outside the " +
               std::to_string(width) + "x" + std::to_string(height) + " frame");
  const std::ptrdiff_t row_bytes = static_cast<std::ptrdiff_t>(region.x1 - region.x0) * pixel;
  if (buffer.row_stride < row_bytes)
    return bad("row_stride " + std::to_string(buffer.row_stride) + " bytes is less than a row of the region (" +
               std::to_string(row_bytes) + " bytes)");
  return {};
}

}  // namespace detail

namespace {

Status render_frame(const Scene& scene, const RenderOptions& options, const ImageView& image, FrameStats* stats) {
  try {
    if (Status s = check_arguments(scene, options, image); !s.ok()) return s;
    if (options.backend == Backend::raycast) {
      if (Status s = validate_scene(scene); !s.ok()) return s;
      render_raycast(scene, options, worker_threads(options.threads), image);
      return {};
    }
    // The same machinery as a persistent Renderer, for one frame.
    detail::World world;
    if (Status s = world.set_scene(scene, nullptr, nullptr); !s.ok()) return s;
    detail::Scheduler scheduler;
    scheduler.configure(resolved_threads(options), options.threading);
    const Isa isa = resolved_isa(options);
    const bool culling = options.culling && isa != Isa::scalar;
    const PreparedScene& prepared = world.commit(culling, scheduler);
    detail::FrameTarget target;
    target.data = reinterpret_cast<unsigned char*>(image.data);
    target.format = PixelFormat::rgb_f32;
    target.row_stride = image.row_stride * static_cast<std::ptrdiff_t>(sizeof(float));
    target.region = {0, 0, scene.width, scene.height};
    detail::FrameEngine engine;
    engine.render(prepared, culling ? &world.reach() : nullptr,
                  detail::FrameSettings{options.spp, culling, isa, options.shaded, stats != nullptr}, scheduler, target,
                  stats);
    return {};
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, "render: out of memory");
  } catch (const std::exception& e) {
    return Status(StatusCode::invalid_argument, std::string("render: ") + e.what());
  }
}

}  // namespace

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image) {
  return render_frame(scene, options, image, nullptr);
}

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image, FrameStats& stats) {
  stats = FrameStats{};
  return render_frame(scene, options, image, &stats);
}

}  // namespace par2d
