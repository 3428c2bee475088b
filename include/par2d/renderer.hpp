// Persistent renderer for a game loop: a world of lights and occluders kept prepared across
// frames, changed through stable handles, rendered into the host's own pixel buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "par2d/status.hpp"
#include "par2d/types.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// One frame of `scene` in any pixel format: render() for a FrameBuffer (whole frame, the
// scene's width x height).
Status render(const Scene& scene, const RenderOptions& options, const FrameBuffer& buffer);

// A persistent world and renderer. Not thread-safe: one thread at a time calls its methods
// (render itself runs on many threads). Every update is validated when it is made; a refused
// update returns a Status naming the handle and the problem and leaves the world unchanged.
//
// Cost model: changing a light (shape, position, color, intensity) never touches the occluder
// index; changing an occluder updates the index in place and re-proves the reach of the lights
// whose earlier proofs looked at its old or new place. A frame creates no threads. Buffers are
// reserved by the scene's counts (lights, occluders, the most vertices of a shape) when those
// grow, so moving, resizing or recolouring existing convex lights anywhere allocates nothing,
// in update_light or in render, once a frame of the scene has rendered; reservations are
// capped for levels of thousands of occluders (docs/api.md, "Cost model").
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Backend, spp, isa, culling, threading, shading, sample_needs, bounce and work_limit
  // (rays is render_raycast's alone).
  // Creates the renderer's thread pool here (never per frame) unless
  // options.threading == Threading::caller_arena.
  Status set_options(const RenderOptions& options);
  const RenderOptions& options() const noexcept;
  // The worker count render uses: resolved_threads(options()), or in caller_arena mode the
  // concurrency of the arena render was last called from.
  int threads() const noexcept;

  // The lightmap: width x height pixels showing the world rectangle `view`
  // (docs/contract.md section 2). Independent of the host's screen. Default view: [0, 0, width, height].
  Status set_frame(int width, int height);
  Status set_frame(int width, int height, const View& view);
  int width() const noexcept;
  int height() const noexcept;
  // The world rectangle the frame shows now (set_frame's view moved by the view offset).
  const View& view() const noexcept;

  // Scrolling (docs/api.md, "Scrolling"). The frame becomes a window on the pixel grid of
  // set_frame's view (that image extended past its edges in every direction): pixel (i, j)
  // shows the grid's pixel (x + i, y + j), sampled exactly where that pixel of the grid is.
  // A camera that moves by whole pixels sets this; with incremental frames on, the next
  // whole frame shifts the buffer's pixels that stay in view (frame_shift says how far) and
  // computes only the uncovered bands and what changed in the world, byte for byte what a
  // Renderer at that offset renders (tiles and blocks are placed on the grid). set_frame
  // starts again at (0, 0). |x|, |y| <= 2^40 (kMaxViewOffset) and the moved view must be
  // valid (docs/contract.md section 3); a refused offset keeps the old one.
  Status set_view_offset(std::int64_t x, std::int64_t y);
  std::int64_t view_offset_x() const noexcept;
  std::int64_t view_offset_y() const noexcept;
  // Where whole frames go in the host's buffer (BufferLayout; default image). ring: pixel
  // (i, j) at ((x + i) mod width, (y + j) mod height), (x, y) the view offset, so a scroll
  // moves no byte (frame_shift stays 0, 0) and dirty_rects are in the buffer's coordinates,
  // split where the ring wraps. Region renders need the image layout. A change of layout
  // makes the next frame whole.
  Status set_buffer_layout(BufferLayout layout);
  BufferLayout buffer_layout() const noexcept;

  // Replaces the whole world (frame included) with a validated scene; `lights` and
  // `occluders`, when given, receive the handles in the scene's order.
  Status set_scene(const Scene& scene, std::vector<LightHandle>* lights = nullptr,
                   std::vector<OccluderHandle>* occluders = nullptr);

  Status add_light(const Light& light, LightHandle* handle);
  Status update_light(LightHandle handle, const Light& light);
  // Color and intensity only: the light's shape and everything derived from it stay.
  Status set_light_emission(LightHandle handle, const Rgb& color, double intensity);
  Status remove_light(LightHandle handle);

  Status add_occluder(const Occluder& occluder, OccluderHandle* handle);
  Status update_occluder(OccluderHandle handle, const Occluder& occluder);
  // The same with the shape given in its own local frame and placed by `transform` (a sprite's
  // position, rotation and scale; see Transform). The placement reuses one buffer per kind, so
  // moving an existing light or occluder by its transform allocates nothing once its shape
  // has been placed at that vertex count.
  Status add_light(const Light& light, const Transform& transform, LightHandle* handle);
  Status update_light(LightHandle handle, const Light& light, const Transform& transform);
  Status add_occluder(const Occluder& occluder, const Transform& transform, OccluderHandle* handle);
  Status update_occluder(OccluderHandle handle, const Occluder& occluder, const Transform& transform);
  Status remove_occluder(OccluderHandle handle);

  // The scene-wide lighting-model terms (docs/contract.md section 6), validated like a scene's;
  // a refused value returns a Status and keeps the previous one. Lights and occluders carry
  // their own terms (range, cone, mask, elevation; transmittance, mask, interior).
  Status set_ambient(const Rgb& ambient);
  // One bounce's piece length (docs/contract.md section 7); refused, keeping the old one, where
  // it is not > 0 or would cut the reflecting occluders into more than kMaxBouncePieces pieces
  // (adding or reshaping a reflecting occluder past that limit is refused the same way).
  Status set_bounce(const Bounce& bounce);
  const Bounce& bounce() const noexcept;
  Status set_directional_lights(const std::vector<DirectionalLight>& lights);
  // One normal for every pixel (world axes, any non-zero length); replaces a normal map.
  Status set_normal(const Vec3& normal);
  // A normal per pixel, exactly the frame's width x height (before the first set_frame: any
  // size, and set_frame then refuses another); replaces a constant normal.
  Status set_normal_map(const NormalMap& map);
  // No normal source: plain irradiance again (fails only when out of memory).
  Status clear_normal_source();
  // The terms as last set (ambient, directional_lights, normal, normal_map; no shapes).
  const Scene& model_terms() const noexcept;

  // Copies the light or occluder `handle` names, as last given, into `out` (reusing its
  // buffers); an unknown handle is refused and `out` is left as it was.
  Status light(LightHandle handle, Light* out) const;
  Status occluder(OccluderHandle handle, Occluder* out) const;

  std::size_t light_count() const noexcept;
  std::size_t occluder_count() const noexcept;

  // Renders the whole frame into `buffer` (width x height pixels).
  Status render(const FrameBuffer& buffer);
  // Renders only `region` (inside the frame); its pixels are bit-identical to the same
  // pixels of a whole frame. `buffer` holds just the region.
  Status render(const FrameBuffer& buffer, const PixelRect& region);
  // The whole frame as float RGB into an ImageView of the frame's size.
  Status render(const ImageView& image);

  // Long frames (docs/api.md, "Long renders"). The estimated work of a whole frame (or of
  // `region`) with the options and world of now, as render checks it against
  // options().work_limit (an incremental frame is checked with only the blocks it computes).
  Status estimate_work(WorkEstimate& estimate);
  Status estimate_work(const PixelRect& region, WorkEstimate& estimate);
  // Called during each frame from the thread that called render, after tiles finish (see
  // ProgressFunction; returning false cancels the frame). Empty (the default): none.
  void set_progress(ProgressFunction progress);
  // Cancels the frame rendering now, or else the next one: it returns StatusCode::cancelled
  // with the buffer untouched, and the request is used up. May be called from any thread at
  // any time (the one exception to "one thread at a time"). A frame stops midway (before its
  // next tile) when it renders into the renderer's own buffer and is copied into the host's
  // once complete: when a progress function is set or the frame has estimated work (a bounce,
  // the scalar reference). Other frames (the SIMD path's direct light alone, written straight
  // into the host's buffer) see the request only before they start.
  void cancel() noexcept;

  // Frames that cost what changed (docs/api.md, "Incremental frames"). Off by default: every
  // whole-frame render computes every pixel. On: a whole-frame render computes only the
  // 64x64 blocks whose inputs changed since the last whole frame and leaves the buffer's
  // other pixels as they are, so the buffer must hold that last frame (same data pointer,
  // format, row stride and exposure, or the frame is computed whole). The pixels equal a full
  // render's byte for byte. Region renders compute their region whole and change nothing here.
  Status set_incremental(bool on);
  bool incremental() const noexcept;
  // The next whole-frame render computes every pixel (after the host changed its buffer).
  void force_full_frame() noexcept;
  // Cached light layers for incremental frames (docs/api.md, "Light-layer cache"). With a
  // budget above 0 bytes, an incremental frame keeps, per 64x64 block and light, the light's
  // share of the block before its emission is applied, so a frame in which lights only change
  // intensity or colour recombines their blocks instead of computing visibility again. At most
  // `bytes` are held; blocks beyond the budget are computed as without the cache. Pixels are
  // then within 1e-6 x the brightest emission of a full render's (float rounding of the
  // recombination), no longer byte-identical; 0 (the default) turns the cache off and frees
  // it. The next whole frame is computed whole either way. Needs incremental frames, culling
  // and a SIMD ISA; scenes with one bounce do without.
  Status set_light_layer_budget(std::size_t bytes);
  std::size_t light_layer_budget() const noexcept;
  // Bytes the layers hold after the last frame (at most the budget).
  std::size_t light_layer_bytes() const noexcept;
  // The rectangles the last successful render wrote (merged block runs, in row order, then
  // a scroll's uncovered bands; empty when an incremental frame changed nothing): the parts
  // of the buffer to upload, after the shift below.
  const std::vector<PixelRect>& dirty_rects() const noexcept;
  // How far the last successful render moved the buffer's pixels before writing dirty_rects
  // (0, 0 but for an incremental frame whose view offset moved by less than the frame): a
  // host whose texture holds the last frame moves its pixels the same way (or uploads the
  // whole buffer), then uploads dirty_rects.
  PixelShift frame_shift() const noexcept;

  // The world as a Scene: lights that emit (in the renderer's internal order), then dark
  // ones, then occluders. Rendering it with par2d::render gives the same image.
  // At a view offset other than (0, 0) the snapshot's view is the one shown (view()); a
  // render of it places its tiles on its own frame, not on this renderer's grid, so it agrees
  // within docs/contract.md section 5 rather than bit for bit.
  Scene snapshot() const;

  RendererStats stats() const noexcept;
  // What the last successful render call computed (all zero before one), and what its culling
  // and kernel did (the sampled needs only when options().sample_needs is set).
  FrameStats frame_stats() const noexcept;
  FrameDiagnostics frame_diagnostics() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace par2d
#pragma GCC visibility pop
