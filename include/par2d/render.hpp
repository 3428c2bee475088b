// Rendering entry point: irradiance of a scene into a caller-provided float RGB image.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>

#include "par2d/isa.hpp"
#include "par2d/scene.hpp"
#include "par2d/status.hpp"
#include "par2d/types.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

enum class Backend {
  automatic,  // the fastest path this CPU supports (the SIMD path where there is one)
  simd,       // the vectorized tiled path at RenderOptions::isa (or the default ISA)
  scalar,     // the reference: double precision, exact trigonometry, one pixel at a time
  raycast,    // the brute-force baseline (render() calls render_raycast; a Renderer refuses it)
};

// "auto", "simd", "scalar", "raycast".
const char* backend_name(Backend backend) noexcept;
std::optional<Backend> parse_backend(const char* name) noexcept;

// The estimated work (WorkEstimate::total) past which a frame is refused by default: 1e11 units,
// a quarter of an hour to two and a half hours of one core (docs/api.md, "Long renders").
inline constexpr double kDefaultWorkLimit = 1e11;

struct RenderOptions {
  // Which path computes the image. Default: automatic.
  Backend backend = Backend::automatic;
  // Worker threads; 0 means all hardware threads. Values above the hardware
  // thread count are capped there. Negative is an error. Default: 0.
  int threads = 0;
  // Samples per pixel in a fixed stratified pattern (see sample_offset); 1 is the
  // pixel center. 1 .. 256. Default: 1.
  int spp = 1;
  // Directions per sample for Backend::raycast. 1 .. 1<<20. Default: 1024.
  int rays = 1024;
  // Forces the SIMD instruction set (see capped_isa: a level the CPU lacks falls back to
  // the best it has). Empty: the
  // PAR2D_ISA environment variable if set, else the best the CPU has. Default: empty.
  std::optional<Isa> isa;
  // Per-tile culling of lights and occluders that cannot matter (what makes large scenes cheap).
  // Only switch off to measure what culling saves; the image is the same. Default: true.
  bool culling = true;
  // See Threading. Default: own_pool.
  Threading threading = Threading::own_pool;
  // false: the plain irradiance even when the scene has a normal source (docs/contract.md
  // section 6), e.g. to output both. Default: true (the shaded value when there is a source).
  bool shaded = true;
  // Also measure what pixels really need (FrameStats' sampled_* counts: one exact pixel per
  // 16x16 tile, about a scalar pixel's cost per tile). render()'s FrameStats overload sets it;
  // a Renderer fills them in frame_stats() when it is set. Default: false.
  bool sample_needs = false;
  // With reflecting occluders: the direct light and the bounce together, or one of them (see
  // BounceTerm; the ambient term belongs to the direct light). Default: included.
  BounceTerm bounce = BounceTerm::included;
  // The most estimated work (WorkEstimate::total) a frame may have: a frame past it is refused
  // with StatusCode::work_limit before any pixel is computed. Finite and >= 0; 0: no limit.
  // Default: kDefaultWorkLimit (1e11).
  double work_limit = kDefaultWorkLimit;
};

// The worker count a render with these options uses from the calling thread: `threads`
// capped at the hardware thread count, 0 meaning all of them (TBB's concurrency limit from
// here); in caller_arena mode the calling arena's concurrency. What a benchmark should report.
int resolved_threads(const RenderOptions& options) noexcept;

// Renders the linear irradiance E of `scene` (docs/contract.md section 1) into `image`,
// whose size must equal the scene's width and height. Validates the scene and the
// arguments first; on failure the image content is unspecified and a status says why.
// One frame of a Renderer made for the call (Backend::raycast: render_raycast).
Status render(const Scene& scene, const RenderOptions& options, const ImageView& image);

// The brute-force baseline, sharing nothing with the renderers but the scene types and the
// parallel loop: per sample (options.spp), options.rays stratified directions, each taking
// the emission of the first light it meets through the transmittances of the occluders before
// it (docs/contract.md sections 1 and 6). Converges to render()'s image as rays grow; for
// tests and for measuring what the analytic renderers save. Reads spp, rays, threads and
// shaded; the other options are checked and ignored.
Status render_raycast(const Scene& scene, const RenderOptions& options, const ImageView& image);

// What one frame's culling and kernel did: the numbers that say why a level costs what it
// costs (`par2d bench --stats` prints them). Counts are totals over the frame; divide by
// `tiles` or `pixels` for averages. The SIMD path works in blocks of 64x64 pixels (one
// spatial-index query and proof attempt per block and light) split into tiles of 16x16
// (the kernel's unit: per tile, the lights that may reach it and, per light, the occluders
// that may stand in front of it somewhere in the tile, the "pairs"). Zero for the raycast
// backend; the scalar backend counts only pixels, tiles and scalar_tiles.
struct FrameStats {
  std::uint64_t pixels = 0;   // pixels rendered
  std::uint64_t samples = 0;  // samples the kernel computed, tile padding included (pixels x spp when tiles fit)
  std::uint64_t blocks = 0;
  std::uint64_t block_lights = 0;               // (block, light) combinations looked at: blocks x lights
  std::uint64_t block_lights_out_of_reach = 0;  // skipped without a query: light reach or range proves the block unlit
  std::uint64_t block_candidates = 0;           // occluders the index queries returned, over (block, light)
  std::uint64_t block_proofs_tried = 0;         // occlusion proofs over a whole block and light
  std::uint64_t block_proofs_succeeded = 0;     // ... that proved the light hidden from the block
  std::uint64_t block_proofs_skipped = 0;       // proofs not tried: the block's earlier proofs mostly failed
  std::uint64_t tiles = 0;
  std::uint64_t tile_lights = 0;          // lights handed to the kernel, summed over tiles
  std::uint64_t tile_pairs = 0;           // (light, occluder) pairs handed to the kernel, summed over tiles
  std::uint64_t tile_general_pairs = 0;   // of those, overlapping or touching pairs (a depth test per piece)
  std::uint64_t tile_proofs_tried = 0;    // occlusion proofs over a tile and one of its lights
  std::uint64_t tile_proofs_succeeded = 0;
  std::uint64_t tile_proofs_skipped = 0;  // proofs not tried: the light's earlier tile proofs in the block mostly failed
  std::uint64_t umbra_tests = 0;          // "is the tile in this one occluder's umbra" tests
  std::uint64_t umbra_hits = 0;
  std::uint64_t tile_pairs_outside_hull = 0;  // pairs dropped before the kernel: the occluder misses the hull of the tile and the light
  std::uint64_t light_samples = 0;        // light arcs the kernel evaluates: sum over tiles (or their cells) of lights x samples
  std::uint64_t pair_samples = 0;         // pairs likewise: sum over tiles (or their cells) of pairs x samples
  std::uint64_t scalar_tiles = 0;         // tiles computed by the scalar reference (only with Isa::scalar)
  // The light-layer cache (Renderer::set_light_layer_budget): (tile, light) shares added from
  // a stored layer instead of computed, and shares computed alone to be stored.
  std::uint64_t layer_tiles_reused = 0;
  std::uint64_t layer_tiles_filled = 0;
  // What pixels really need, by the exact double geometry at one pixel per tile (the tile's
  // middle pixel), for comparison with the kernel's work above: lights visible there (some
  // direction reaches the light with no occluder in front; the lighting model's cone, range
  // and transmittance aside) and, for those lights, the occluders in front of a part of the
  // light's arc. Directional lights are not counted. Filled by render()'s
  // FrameStats overload and by a Renderer whose options set sample_needs (it costs about a
  // scalar pixel per tile); zero otherwise.
  std::uint64_t sampled_pixels = 0;
  std::uint64_t sampled_visible_lights = 0;
  std::uint64_t sampled_blocking_pairs = 0;
  // One bounce (docs/contract.md section 7; zero without reflecting occluders or when
  // RenderOptions::bounce excludes it). The term is computed exactly, piece by piece: there
  // is no grouping of pieces, so no cluster or refinement counts.
  std::uint64_t bounce_pieces = 0;               // pieces the reflecting occluders are cut into
  std::uint64_t bounce_lit_sources = 0;          // reflecting occluders with a lit piece
  std::uint64_t bounce_tile_sources = 0;         // (tile, lit source) combinations looked at
  std::uint64_t bounce_tile_sources_hidden = 0;  // ... that occlusion proofs hid from the whole tile
  std::uint64_t bounce_source_walks = 0;         // (sample, source) walks over a source's pieces
  std::uint64_t bounce_depth_tests = 0;          // occluders depth-tested against a source at a sample
};

// What a frame will cost, estimated from counts before it runs (docs/api.md, "Long renders"), in
// units of one shape or bounce piece looked at for one sample (or ray): 10 to 100 nanoseconds
// of one core each. `samples` is the pixels the frame computes (an incremental
// frame's changed blocks only) times spp; `lights` counts the directional lights too. The SIMD
// path's direct light is not counted: its culling keeps it near what the pixels need
// (FrameStats), however many shapes the scene has. The bounce is counted before culling (which
// only lowers it).
struct WorkEstimate {
  double samples = 0.0;
  double bounce = 0.0;   // one bounce (SIMD or scalar path): pieces x (samples + lights x (occluders + 1))
  double scalar = 0.0;   // the scalar reference's direct light: samples x lights x (occluders + 1)
  double raycast = 0.0;  // Backend::raycast: rays x (samples + pieces) x (lights + occluders)
  double total = 0.0;    // bounce + scalar + raycast: what RenderOptions::work_limit bounds
};

// The estimated work of render(scene, options, ...) for the whole frame (the scene is validated).
Status estimate_work(const Scene& scene, const RenderOptions& options, WorkEstimate& estimate);

// How far a frame has got, in the 16x16-pixel tiles it computes (64x64 blocks for
// Backend::raycast, counted as their tiles).
struct Progress {
  std::uint64_t tiles_done = 0;
  std::uint64_t tiles = 0;  // the frame's total
};

// Called during a frame from the thread that called render (never from two threads at once),
// after tiles finish: tiles_done rises with each call, and a frame that completes ends with a
// call where tiles_done == tiles. Returning false cancels the frame. It must not throw.
using ProgressFunction = std::function<bool(const Progress&)>;

// Watching and stopping one render() call (docs/api.md, "Long renders"). A cancelled call
// returns StatusCode::cancelled with the image untouched; with either member set the frame is
// computed into a buffer of the library's and copied into the image only once it is complete.
struct RenderControl {
  ProgressFunction progress;                  // empty: none
  const std::atomic<bool>* cancel = nullptr;  // set (from any thread) to cancel before the next tile
};

// render() with progress and cancellation.
Status render(const Scene& scene, const RenderOptions& options, const ImageView& image, const RenderControl& control);

// render() that also reports the frame's work in `stats` (overwritten), including the sampled
// needs (slower than render() by about one scalar pixel per 16x16 tile).
Status render(const Scene& scene, const RenderOptions& options, const ImageView& image, FrameStats& stats);

// The ISA the SIMD path would use for these options on this CPU (scalar when the
// backend is scalar or raycast).
Isa resolved_isa(const RenderOptions& options) noexcept;

}  // namespace par2d
#pragma GCC visibility pop
