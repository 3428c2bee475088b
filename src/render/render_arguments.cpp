// The argument checks every entry shares, and how options resolve to an ISA and a worker count.
#include "render/render_arguments.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

#include "par2d/isa.hpp"
#include "parallel/concurrency.hpp"

namespace par2d {
namespace {

constexpr int kMaxSpp = 256;
constexpr int kMaxRays = 1 << 20;

}  // namespace

namespace detail {

int worker_threads(int requested) noexcept {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (requested == 0) return calling_concurrency();
  return std::min(requested, hardware);  // more only adds scheduling overhead
}

Status check_options(const RenderOptions& options, const char* who) {
  auto bad = [who](std::string message) {
    return Status(StatusCode::invalid_argument, std::string(who) + ": " + std::move(message));
  };
  if (options.threads < 0) return bad("threads must be >= 0 (0 = all hardware threads)");
  if (options.spp < 1 || options.spp > kMaxSpp) return bad("spp must be in 1.." + std::to_string(kMaxSpp));
  if (options.isa && (static_cast<int>(*options.isa) < static_cast<int>(Isa::scalar) ||
                      static_cast<int>(*options.isa) > static_cast<int>(Isa::neon64)))
    return bad("unknown isa " + std::to_string(static_cast<int>(*options.isa)));
  if (static_cast<int>(options.backend) < static_cast<int>(Backend::automatic) ||
      static_cast<int>(options.backend) > static_cast<int>(Backend::scalar))
    return bad("unknown backend " + std::to_string(static_cast<int>(options.backend)));
  if (options.threading != Threading::own_pool && options.threading != Threading::caller_arena)
    return bad("unknown threading " + std::to_string(static_cast<int>(options.threading)));
  if (options.threading == Threading::caller_arena && !kCallerArena)
    return bad("threading caller_arena needs par2d built with TBB (this build schedules on std::threads)");
  if (options.bounce != BounceTerm::included && options.bounce != BounceTerm::excluded &&
      options.bounce != BounceTerm::only)
    return bad("unknown bounce term " + std::to_string(static_cast<int>(options.bounce)));
  if (!(std::isfinite(options.work_limit) && options.work_limit >= 0.0))
    return bad("work_limit must be finite and >= 0 (0 = no limit)");
  return {};
}

// The options the ray caster reads, checked: all of a renderer's, and the rays.
Status check_raycast_options(const RenderOptions& options, const char* who) {
  if (Status s = check_options(options, who); !s.ok()) return s;
  if (options.rays < 1 || options.rays > kMaxRays)
    return Status(StatusCode::invalid_argument, std::string(who) + ": rays must be in 1.." + std::to_string(kMaxRays));
  return {};
}

Status check_image_view(const ImageView& image, int width, int height, const char* who, const char* what) {
  auto bad = [who](std::string message) {
    return Status(StatusCode::invalid_argument, std::string(who) + ": " + std::move(message));
  };
  if (image.data == nullptr) return bad("image data is null");
  if (image.width != width || image.height != height)
    return bad("image is " + std::to_string(image.width) + "x" + std::to_string(image.height) + " but the " + what +
               " is " + std::to_string(width) + "x" + std::to_string(height));
  if (image.row_stride < 3 * static_cast<std::ptrdiff_t>(image.width))
    return bad("row_stride " + std::to_string(image.row_stride) + " is less than 3 * width");
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

Isa resolved_isa(const RenderOptions& options) noexcept {
  if (options.backend == Backend::scalar) return Isa::scalar;
  if (!options.isa) return default_isa();
  return capped_isa(*options.isa);
}

int resolved_threads(const RenderOptions& options) noexcept {
  if (options.threading == Threading::caller_arena) return detail::calling_concurrency();
  return detail::worker_threads(std::max(0, options.threads));
}

}  // namespace par2d
