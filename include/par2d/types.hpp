// Basic types every part of par2d shares: the threading mode, the bounce terms, the host's image
// and frame-buffer descriptors, the sample pattern, the Renderer's handles and its counts.
// The front doors (render.hpp, renderer.hpp, par2d.hpp) include it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// Where render's parallel work runs.
enum class Threading {
  // par2d's own pool of `threads` workers: a one-shot render makes one per call; a Renderer
  // makes one in set_options and keeps it.
  own_pool,
  // The TBB arena render is called from: the host calls render inside its own
  // tbb::task_arena::execute, and `threads` is ignored. A par2d built without TBB
  // (docs/platforms.md) refuses it with invalid_argument.
  caller_arena,
};

// Which terms of a scene with one bounce (docs/contract.md section 7) a render outputs, so
// that a host can composite or inspect the direct and the indirect light apart. A scene with
// no reflecting occluder has no bounce term: `only` renders it black, the others the same.
enum class BounceTerm {
  included,  // direct light plus the bounce (the contract's value)
  excluded,  // the direct light alone (section 6), as if every albedo were zero
  only,      // the bounce term alone: what `included` adds to `excluded`
};

// "included", "excluded", "only".
const char* bounce_term_name(BounceTerm term) noexcept;
std::optional<BounceTerm> parse_bounce_term(const char* name) noexcept;

// A float RGB image owned by the caller. Pixel (i, j) channel c lives at
// data[j * row_stride + 3 * i + c]; row 0 is the top row. `row_stride` counts
// floats and must be at least 3 * width. Any alignment works; an image of 16 MiB or more
// whose data starts on a 64-byte boundary (with a row stride in floats divisible by 16) is
// written with non-temporal stores, which bypass the cache.
struct ImageView {
  float* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t row_stride = 0;
};

// Offset inside the pixel, in [0, 1)^2 pixel units, of sample k of `spp` (a
// stratified rank-1 lattice; spp = 1 gives the center (0.5, 0.5)).
void sample_offset(int k, int spp, double& dx, double& dy) noexcept;

// Pixel layouts a frame can be written in. Every format is written by the tiles directly,
// and every ISA writes the same bytes.
enum class PixelFormat {
  rgb_f32,     // 3 floats per pixel: linear irradiance E (docs/contract.md section 1)
  rgba_f32,    // 4 floats: E and alpha 1
  rgba8_srgb,  // 4 bytes: round(255 * srgb(clamp(exposure * E, 0, 1))) per channel, alpha 255
  bgra8_srgb,  // the same bytes in B, G, R, A order (the layout many GPUs and window systems prefer)
  // 4 IEEE half floats (8 bytes, native byte order): E rounded to nearest even, values past the
  // largest finite half (65504) saturating to it, alpha 1: what engines upload as RGBA16F.
  rgba16f,
  // rgba8_srgb and bgra8_srgb with an ordered dither: floor(255 * srgb(clamp(exposure * E, 0,
  // 1)) + t) per channel, t = (B(x mod 8, y mod 8) + 0.5) / 64 with B the 8x8 Bayer matrix and
  // (x, y) the pixel in the frame, so that dark gradients do not band; a region or an
  // incremental frame writes the bytes a whole frame has there (docs/api.md, "Pixel formats").
  rgba8_srgb_dithered,
  bgra8_srgb_dithered,
};

// Bytes one pixel of `format` takes (12, 16, 4, 4, 8, 4, 4).
int bytes_per_pixel(PixelFormat format) noexcept;

// Pixel columns [x0, x1) and rows [y0, y1) of the lightmap.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// How whole frames sit in the host's buffer (Renderer::set_buffer_layout).
enum class BufferLayout : std::uint8_t {
  image,  // pixel (i, j) of the frame at (i, j): a plain image
  // Pixel (i, j) at ((x + i) mod width, (y + j) mod height), (x, y) the view offset: each
  // pixel of the view's grid has one place, so a scrolled frame moves no pixel (a texture
  // sampled with wrapping at the offset shows the frame).
  ring,
};

// How far an incremental frame moved the buffer's pixels (Renderer::frame_shift): pixel
// (i, j) now holds what pixel (i + dx, j + dy) held before the frame.
struct PixelShift {
  int dx = 0, dy = 0;
};

// The host's buffer for a frame or a region of it: the region's top-left pixel is at `data`,
// row r of the region starts `r * row_stride` bytes after it. Any alignment works; float
// regions of 16 MiB or more are written with non-temporal stores (bypassing the cache) on
// the rows that start on a 64-byte boundary (16 bytes for SSE4.2 kernels, 32 for AVX2).
struct FrameBuffer {
  void* data = nullptr;
  PixelFormat format = PixelFormat::rgb_f32;
  // Bytes between the starts of consecutive rows; at least region width * bytes_per_pixel.
  std::ptrdiff_t row_stride = 0;
  // Multiplies E before sRGB encoding (the 8-bit formats only); finite, >= 0. Default: 1.
  double exposure = 1.0;
};

// Names a light of one Renderer for as long as it exists; a removed light's handle is never
// valid again (handles carry a generation). id 0 never names anything.
struct LightHandle {
  std::uint64_t id = 0;
};
struct OccluderHandle {
  std::uint64_t id = 0;
};

// What the renderer has done so far (for tests and profiling).
struct RendererStats {
  std::uint64_t frames = 0;             // successful render calls
  std::uint64_t index_builds = 0;       // occluder index (BVH) built from scratch
  std::uint64_t index_updates = 0;      // occluder index updated in place (refit, insert, remove)
  std::uint64_t reach_computations = 0; // per-light reach proofs run (lights changed or near changes)
  std::uint64_t full_prepares = 0;      // whole world re-prepared (frame or coordinate scale changed)
};

}  // namespace par2d
#pragma GCC visibility pop
