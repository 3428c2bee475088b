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
#include "render/kernel_table.hpp"
#include "render/prepared_scene.hpp"
#include "render/scalar_tiles.hpp"
#include "render/tiling.hpp"

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
  if (options.threads < 0) return bad("render: threads must be >= 0 (0 = all hardware threads)");
  if (options.spp < 1 || options.spp > kMaxSpp) return bad("render: spp must be in 1.." + std::to_string(kMaxSpp));
  if (options.backend == Backend::raycast && (options.rays < 1 || options.rays > kMaxRays))
    return bad("render: rays must be in 1.." + std::to_string(kMaxRays));
  if (options.isa && (static_cast<int>(*options.isa) < static_cast<int>(Isa::scalar) ||
                      static_cast<int>(*options.isa) > static_cast<int>(Isa::neon64)))
    return bad("render: unknown isa " + std::to_string(static_cast<int>(*options.isa)));
  if (static_cast<int>(options.backend) < static_cast<int>(Backend::automatic) ||
      static_cast<int>(options.backend) > static_cast<int>(Backend::raycast))
    return bad("render: unknown backend " + std::to_string(static_cast<int>(options.backend)));
  return {};
}

int worker_threads(int requested) noexcept {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (requested == 0) return tbb::this_task_arena::max_concurrency();
  return std::min(requested, hardware);  // more only adds scheduling overhead
}

void render_scalar(const PreparedScene& scene, const RenderOptions& options, int threads, const ImageView& image) {
  std::vector<detail::ScalarScratch> scratches(static_cast<std::size_t>(threads));
  detail::for_each_block(scene.width, scene.height, threads, [&](const detail::TileRect& block, int worker) {
    detail::render_rect_scalar(scene, options.spp, block, scratches[static_cast<std::size_t>(worker)], image);
  });
}

void render_raycast(const Scene& scene, const RenderOptions& options, int threads, const ImageView& image) {
  const detail::RaycastRenderer caster(scene);
  detail::for_each_block(scene.width, scene.height, threads, [&](const detail::TileRect& block, int) {
    detail::render_rect_raycast(scene, caster, options.spp, options.rays, block, image);
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

Status render(const Scene& scene, const RenderOptions& options, const ImageView& image) {
  try {
    if (Status s = check_arguments(scene, options, image); !s.ok()) return s;
    if (Status s = validate_scene(scene); !s.ok()) return s;
    const int threads = worker_threads(options.threads);
    if (options.backend == Backend::raycast) {
      render_raycast(scene, options, threads, image);
      return {};
    }
    const PreparedScene prepared = detail::prepare_scene(scene);
    const Isa isa = resolved_isa(options);
    if (isa == Isa::scalar) {
      render_scalar(prepared, options, threads, image);
      return {};
    }
    detail::render_simd(prepared, options, isa, threads, image);
    return {};
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, "render: out of memory");
  } catch (const std::exception& e) {
    return Status(StatusCode::invalid_argument, std::string("render: ") + e.what());
  }
}

}  // namespace par2d
