// par2d::Renderer: options and threading, the persistent world, and frames into host buffers.
#include "par2d/renderer.hpp"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>
#include <optional>
#include <string>

#include "culling/reach_cache.hpp"
#include "render/change_tracker.hpp"
#include "parallel/scheduler.hpp"
#include "render/frame_counters.hpp"
#include "render/frame_driver.hpp"
#include "render/frame_output.hpp"
#include "render/frame_plan.hpp"
#include "render/block_culling.hpp"
#include "render/kernel_shapes.hpp"
#include "render/light_layers.hpp"
#include "render/render_arguments.hpp"
#include "render/work_estimate.hpp"
#include "scene/same_values.hpp"
#include "status_guard.hpp"
#include "world/world.hpp"

namespace par2d {

struct Renderer::Impl {
  Impl() {
    tracker.forward_to(&reach);
    tracker.set_layers(&layers);
    world.observe(&tracker);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  RenderOptions options;
  // resolved_isa(options), resolved at the first frame after set_options: a Renderer that
  // never renders never probes the CPU or reads PAR2D_ISA.
  std::optional<Isa> isa;
  detail::Scheduler scheduler;
  detail::ReachCache reach;  // follows `world`'s changes (declared first: the world points at it)
  detail::ChangeTracker tracker;  // observes `world` and passes every event on to `reach`
  detail::LightLayerCache layers;  // kept by `tracker`'s plans (budget 0: off)
  bool incremental = false;
  BufferLayout layout = BufferLayout::image;
  std::vector<PixelRect> dirty_rects;  // the last successful render's
  PixelShift shift;                    // the last successful render's
  detail::World world;
  detail::FramePlan plan;  // this frame's (its storage kept from frame to frame)
  detail::FrameEngine engine;
  detail::FrameCounters frame_counts;  // the last successful render's (FrameStats, FrameDiagnostics)
  // Shapes placed by a Transform before they go to the world (kept: their storage is reused).
  Light placed_light;
  Occluder placed_occluder;
  // Long frames (docs/api.md, "Long renders"): the host's progress function, its cancel
  // request, and the buffer a watched frame is computed into before it is copied out whole
  // (kept and grown, 64-byte aligned at `scratch_data`).
  ProgressFunction progress;
  std::atomic<bool> cancel{false};
  std::unique_ptr<unsigned char[]> scratch;
  std::size_t scratch_bytes = 0;
  unsigned char* scratch_data = nullptr;

  // The estimated work of `pixels` pixels with the options and world of now.
  WorkEstimate estimate(const detail::PreparedScene& scene, double pixels, Isa frame_isa) const {
    return detail::estimate_work(
        detail::work_counts(scene, pixels, options.spp, frame_isa == Isa::scalar, options.bounce));
  }
  // At least `bytes` of scratch, 64-byte aligned.
  unsigned char* scratch_of(std::size_t bytes) {
    if (bytes > scratch_bytes) {
      scratch.reset();
      scratch_bytes = 0;
      scratch.reset(new unsigned char[bytes + 64]);
      scratch_bytes = bytes;
      const auto address = reinterpret_cast<std::uintptr_t>(scratch.get());
      scratch_data = scratch.get() + (64 - address % 64) % 64;
    }
    return scratch_data;
  }
};

namespace {

Status bad(std::string message) { return Status(StatusCode::invalid_argument, std::move(message)); }

using detail::guarded;

}  // namespace

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Status Renderer::set_options(const RenderOptions& options) {
  return guarded("set_options", [&]() -> Status {
    if (Status s = detail::check_options(options, "set_options"); !s.ok()) return s;
    impl_->scheduler.configure(resolved_threads(options), options.threading);
    impl_->options = options;
    impl_->isa.reset();  // resolved at the next frame
    return {};
  });
}

const RenderOptions& Renderer::options() const noexcept { return impl_->options; }

int Renderer::threads() const noexcept {
  return impl_->scheduler.configured() ? impl_->scheduler.workers() : resolved_threads(impl_->options);
}

Status Renderer::set_frame(int width, int height) { return set_frame(width, height, View{0.0, 0.0, double(width), double(height)}); }

Status Renderer::set_frame(int width, int height, const View& view) {
  return guarded("set_frame", [&] { return impl_->world.set_frame(width, height, view); });
}

int Renderer::width() const noexcept { return impl_->world.prepared().width; }
int Renderer::height() const noexcept { return impl_->world.prepared().height; }
const View& Renderer::view() const noexcept { return impl_->world.view(); }

Status Renderer::set_view_offset(std::int64_t x, std::int64_t y) {
  return guarded("set_view_offset", [&] { return impl_->world.set_view_offset(x, y); });
}
Status Renderer::set_buffer_layout(BufferLayout layout) {
  if (layout != BufferLayout::image && layout != BufferLayout::ring)
    return bad("set_buffer_layout: " + std::to_string(static_cast<int>(layout)) + " is no BufferLayout");
  if (layout != impl_->layout) impl_->tracker.force_full();  // every pixel has another place
  impl_->layout = layout;
  return {};
}
BufferLayout Renderer::buffer_layout() const noexcept { return impl_->layout; }
std::int64_t Renderer::view_offset_x() const noexcept { return impl_->world.view_offset_x(); }
std::int64_t Renderer::view_offset_y() const noexcept { return impl_->world.view_offset_y(); }

Status Renderer::set_scene(const Scene& scene, std::vector<LightHandle>* lights, std::vector<OccluderHandle>* occluders) {
  return guarded("set_scene", [&] { return impl_->world.set_scene(scene, lights, occluders); });
}

Status Renderer::add_light(const Light& light, LightHandle* handle) {
  return guarded("add_light", [&] { return impl_->world.add_light(light, handle); });
}
Status Renderer::update_light(LightHandle handle, const Light& light) {
  return guarded("update_light", [&] { return impl_->world.update_light(handle, light); });
}
Status Renderer::set_light_emission(LightHandle handle, const Rgb& color, double intensity) {
  return guarded("set_light_emission", [&] { return impl_->world.set_light_emission(handle, color, intensity); });
}
Status Renderer::remove_light(LightHandle handle) {
  return guarded("remove_light", [&] { return impl_->world.remove_light(handle); });
}
Status Renderer::add_occluder(const Occluder& occluder, OccluderHandle* handle) {
  return guarded("add_occluder", [&] { return impl_->world.add_occluder(occluder, handle); });
}
Status Renderer::update_occluder(OccluderHandle handle, const Occluder& occluder) {
  return guarded("update_occluder", [&] { return impl_->world.update_occluder(handle, occluder); });
}
namespace {

// `item` with its shape placed by `transform` into `placed`; a refused transform is named
// `who` (an addition) or `kind id` (an update), the name built only then: a frame's moves
// allocate nothing.
template <class Item>
Status place(const Item& item, const Transform& transform, Item& placed, const char* who,
             const std::uint64_t* id = nullptr) {
  placed = item;  // copy-assignment keeps the polygon storage `placed` already has
  Status s = transform_shape(item.shape, transform, placed.shape);
  if (s.ok()) return s;
  return Status(s.code(), (id ? std::string(who) + " " + std::to_string(*id) : std::string(who)) + ": " + s.message());
}

}  // namespace

Status Renderer::add_light(const Light& light, const Transform& transform, LightHandle* handle) {
  return guarded("add_light", [&] {
    if (Status s = place(light, transform, impl_->placed_light, "add_light"); !s.ok()) return s;
    return impl_->world.add_light(impl_->placed_light, handle);
  });
}
Status Renderer::update_light(LightHandle handle, const Light& light, const Transform& transform) {
  return guarded("update_light", [&] {
    if (Status s = place(light, transform, impl_->placed_light, "light", &handle.id); !s.ok()) return s;
    return impl_->world.update_light(handle, impl_->placed_light);
  });
}
Status Renderer::add_occluder(const Occluder& occluder, const Transform& transform, OccluderHandle* handle) {
  return guarded("add_occluder", [&] {
    if (Status s = place(occluder, transform, impl_->placed_occluder, "add_occluder"); !s.ok()) return s;
    return impl_->world.add_occluder(impl_->placed_occluder, handle);
  });
}
Status Renderer::update_occluder(OccluderHandle handle, const Occluder& occluder, const Transform& transform) {
  return guarded("update_occluder", [&] {
    if (Status s = place(occluder, transform, impl_->placed_occluder, "occluder", &handle.id); !s.ok()) return s;
    return impl_->world.update_occluder(handle, impl_->placed_occluder);
  });
}
Status Renderer::remove_occluder(OccluderHandle handle) {
  return guarded("remove_occluder", [&] { return impl_->world.remove_occluder(handle); });
}

Status Renderer::set_ambient(const Rgb& ambient) {
  return guarded("set_ambient", [&] {
    if (detail::same_rgb(impl_->world.model_terms().ambient, ambient)) return Status::success();  // unchanged: nothing marked
    Scene terms = impl_->world.model_terms();
    terms.ambient = ambient;
    return impl_->world.set_model_terms("set_ambient", terms);
  });
}
Status Renderer::set_bounce(const Bounce& bounce) {
  return guarded("set_bounce", [&] { return impl_->world.set_bounce(bounce); });
}
const Bounce& Renderer::bounce() const noexcept { return impl_->world.model_terms().bounce; }
Status Renderer::set_directional_lights(const std::vector<DirectionalLight>& lights) {
  return guarded("set_directional_lights", [&] {
    if (detail::same_directional_lights(impl_->world.model_terms().directional_lights, lights))
      return Status::success();  // unchanged: nothing marked
    Scene terms = impl_->world.model_terms();
    terms.directional_lights = lights;
    return impl_->world.set_model_terms("set_directional_lights", terms);
  });
}
Status Renderer::set_normal(const Vec3& normal) {
  return guarded("set_normal", [&] {
    Scene terms = impl_->world.model_terms();
    terms.normal = normal;
    terms.normal_map.reset();
    return impl_->world.set_model_terms("set_normal", terms);
  });
}
Status Renderer::set_normal_map(const NormalMap& map) {
  return guarded("set_normal_map", [&] {
    Scene terms = impl_->world.model_terms();
    terms.normal.reset();
    terms.normal_map = map;
    return impl_->world.set_model_terms("set_normal_map", terms);
  });
}
Status Renderer::clear_normal_source() {
  return guarded("clear_normal_source", [&] {
    Scene terms = impl_->world.model_terms();
    terms.normal.reset();
    terms.normal_map.reset();
    return impl_->world.set_model_terms("clear_normal_source", terms);
  });
}
const Scene& Renderer::model_terms() const noexcept { return impl_->world.model_terms(); }

Status Renderer::light(LightHandle handle, Light* out) const {
  if (out == nullptr) return bad("light: out is null");
  const Light* light = impl_->world.find_light(handle.id);
  if (light == nullptr) return bad("light: unknown handle " + std::to_string(handle.id));
  return guarded("light", [&] {
    *out = *light;
    return Status::success();
  });
}
Status Renderer::occluder(OccluderHandle handle, Occluder* out) const {
  if (out == nullptr) return bad("occluder: out is null");
  const Occluder* occluder = impl_->world.find_occluder(handle.id);
  if (occluder == nullptr) return bad("occluder: unknown handle " + std::to_string(handle.id));
  return guarded("occluder", [&] {
    *out = *occluder;
    return Status::success();
  });
}

std::size_t Renderer::light_count() const noexcept { return impl_->world.light_count(); }
std::size_t Renderer::occluder_count() const noexcept { return impl_->world.occluder_count(); }

Status Renderer::render(const FrameBuffer& buffer) {
  return render(buffer, PixelRect{0, 0, width(), height()});
}

Status Renderer::render(const ImageView& image) {
  if (Status s = detail::check_image_view(image, width(), height(), "render", "frame"); !s.ok()) return s;
  return render(detail::frame_buffer_of(image));
}

Status Renderer::render(const FrameBuffer& buffer, const PixelRect& region) {
  Impl& impl = *impl_;
  if (!impl.world.has_frame()) return bad("render: no frame size (call set_frame or set_scene first)");
  if (Status s = detail::check_frame_buffer(buffer, region, width(), height(), "render"); !s.ok()) return s;
  const bool ring = impl.layout == BufferLayout::ring;
  if (ring && !(region.x0 == 0 && region.y0 == 0 && region.x1 == width() && region.y1 == height()))
    return bad("render: a region render needs BufferLayout::image (the ring layout holds whole frames)");
  // A cancel request is used up by the frame it reaches, whether or not the frame stops for it.
  struct RequestUsedUp {
    std::atomic<bool>& cancel;
    ~RequestUsedUp() { cancel.store(false); }
  } used_up{impl.cancel};
  if (impl.cancel.load()) return Status(StatusCode::cancelled, "render: cancelled");
  return guarded("render", [&]() -> Status {
    if (!impl.scheduler.configured()) impl.scheduler.configure(resolved_threads(impl.options), impl.options.threading);
    if (!impl.isa) impl.isa = resolved_isa(impl.options);
    const Isa isa = *impl.isa;
    const bool culling = impl.options.culling && isa != Isa::scalar;
    const detail::PreparedScene& scene = impl.world.commit();
    if (culling) impl.world.stats().reach_computations += impl.reach.update(scene, impl.scheduler);
    detail::FrameTarget target;
    target.data = static_cast<unsigned char*>(buffer.data);
    target.format = buffer.format;
    target.row_stride = buffer.row_stride;
    target.exposure = buffer.exposure;
    target.region = {region.x0, region.y0, region.x1, region.y1};
    target.dither_x = static_cast<int>(scene.grid_x & 7);  // two's complement: the grid's place mod 8
    target.dither_y = static_cast<int>(scene.grid_y & 7);
    if (ring) {
      target.ring = true;
      target.ring_x = static_cast<int>(((scene.grid_x % scene.width) + scene.width) % scene.width);
      target.ring_y = static_cast<int>(((scene.grid_y % scene.height) + scene.height) % scene.height);
    }
    const detail::FrameSettings settings{impl.options.spp, culling, isa, impl.options.shaded,
                                         impl.options.sample_needs, impl.options.bounce};
    const std::vector<detail::LightReach>* reach = culling ? &impl.reach.reach() : nullptr;
    const bool whole = region.x0 == 0 && region.y0 == 0 && region.x1 == width() && region.y1 == height();
    const std::vector<std::uint8_t>* dirty = nullptr;
    detail::LightLayerCache* layers = nullptr;
    PixelShift shift;       // a scroll: the buffer's pixels move first (image layout)
    bool scrolled = false;  // a scroll keeps pixels: only its uncovered bands are planned
    if (impl.incremental && whole) {
      // Only the blocks whose inputs changed since the last whole frame into this buffer.
      detail::FrameKey key;
      key.width = scene.width;
      key.height = scene.height;
      key.view = scene.view;
      key.grid_x = scene.grid_x;
      key.grid_y = scene.grid_y;
      key.scale = scene.scale;
      key.far = detail::tile_frame(scene, Vec2{}).far;
      key.trusted = detail::culling_trusted(scene);
      key.extent = scene.directionals.empty() ? 0.0 : scene.extent;
      key.model = scene.model;
      key.bounce = scene.bounce;
      // Pixels a moved view keeps depend on the grid alone, but for the bounce stage (over the
      // whole scene each frame), directional lights (their sweep follows the extent) and a
      // normal map (one normal per frame pixel).
      key.scrolls = !scene.bounce && scene.directionals.empty() && scene.normal_source != detail::NormalSource::map;
      key.ring = ring;
      key.data = buffer.data;
      key.format = buffer.format;
      key.row_stride = buffer.row_stride;
      key.exposure = buffer.exposure;
      key.settings = settings;
      dirty = impl.tracker.plan(scene, reach, key, impl.dirty_rects);
      if (impl.tracker.layered()) layers = &impl.layers;
      shift = PixelShift{impl.tracker.shift_x(), impl.tracker.shift_y()};
      if (ring) shift = PixelShift{};  // the kept pixels are where they were
      scrolled = impl.tracker.shift_x() != 0 || impl.tracker.shift_y() != 0;
    } else {
      impl.dirty_rects.assign(1, region);
    }
    impl.shift = PixelShift{};  // set again once the frame is complete
    // The work bound, on the pixels this frame computes (an incremental frame's changed blocks).
    double pixels = static_cast<double>(region.x1 - region.x0) * static_cast<double>(region.y1 - region.y0);
    if (dirty) {
      pixels = 0.0;
      for (const PixelRect& r : impl.dirty_rects)
        pixels += static_cast<double>(r.x1 - r.x0) * static_cast<double>(r.y1 - r.y0);
    }
    const WorkEstimate estimate = impl.estimate(scene, pixels, isa);
    if (Status s = detail::check_work(estimate, impl.options.work_limit, "render"); !s.ok()) {
      impl.tracker.force_full();  // the plan counted on this frame
      return s;
    }
    // A watched frame (a progress function, or work worth stopping midway) is computed into
    // the scratch and copied out only once complete, so a cancelled one leaves the buffer as
    // it was; the others are written in place and see a cancel request only before they start.
    const bool watched = static_cast<bool>(impl.progress) || estimate.total > 0.0;
    const int pixel_bytes = bytes_per_pixel(buffer.format);
    const std::ptrdiff_t scratch_stride = static_cast<std::ptrdiff_t>(region.x1 - region.x0) * pixel_bytes;
    if (watched) {
      target.data = impl.scratch_of(static_cast<std::size_t>(scratch_stride) * static_cast<std::size_t>(region.y1 - region.y0));
      target.row_stride = scratch_stride;
      target.ring = false;  // the scratch holds the frame as an image; the copy places it
    }
    const detail::FrameControl control{&impl.progress, &impl.cancel};
    const bool shifts = shift.dx != 0 || shift.dy != 0;
    detail::FrameTarget host = target;
    host.data = static_cast<unsigned char*>(buffer.data);
    host.row_stride = buffer.row_stride;
    host.ring = ring;
    bool complete = false;
    try {
      // In place, the kept pixels move before the new ones are written; a watched frame moves
      // them once it is complete (a cancelled one leaves the buffer as it was).
      if (shifts && !watched) detail::shift_pixels(host, shift.dx, shift.dy);
      detail::plan_frame(scene, settings, target.region, reach, dirty, layers, impl.plan,
                         scrolled ? &impl.tracker.uncovered() : nullptr);
      complete = impl.engine.run(impl.plan, scene, impl.scheduler, target, &impl.frame_counts, watched ? &control : nullptr);
    } catch (...) {
      impl.tracker.force_full();  // the buffer may hold part of a frame (the plan drops the layers)
      throw;
    }
    if (!complete) {
      impl.tracker.force_full();  // the blocks planned were not computed
      return Status(StatusCode::cancelled, "render: cancelled");
    }
    if (watched) {
      if (shifts) detail::shift_pixels(host, shift.dx, shift.dy);
      auto* out = static_cast<unsigned char*>(buffer.data);
      // A rectangle's rows from the scratch (frame layout) to the buffer, `dx`, `dy` pixels on.
      const auto copy = [&](const detail::TileRect& r, int dx, int dy) {
        const std::size_t row_bytes = static_cast<std::size_t>(r.x1 - r.x0) * static_cast<std::size_t>(pixel_bytes);
        for (int y = r.y0; y < r.y1; ++y) {
          const std::ptrdiff_t x = static_cast<std::ptrdiff_t>(r.x0 - region.x0) * pixel_bytes;
          std::memcpy(out + (y + dy - region.y0) * buffer.row_stride + x + static_cast<std::ptrdiff_t>(dx) * pixel_bytes,
                      target.data + (y - region.y0) * scratch_stride + x, row_bytes);
        }
      };
      for (const PixelRect& r : impl.dirty_rects) {  // in the frame, within the region
        const detail::TileRect rect{r.x0, r.y0, r.x1, r.y1};
        if (ring) {
          detail::for_each_ring_piece(host, rect, copy);
        } else {
          copy(rect, 0, 0);
        }
      }
    }
    if (ring) {
      // The rectangles in the buffer's coordinates: the pieces that stay whole on the ring; a
      // rectangle as wide (tall) as the frame covers every column (row) of the ring.
      std::vector<PixelRect>& rects = impl.dirty_rects;
      const std::size_t count = rects.size();
      for (std::size_t i = 0; i < count; ++i) {
        const PixelRect r = rects[i];
        const bool wide = r.x0 == 0 && r.x1 == width(), tall = r.y0 == 0 && r.y1 == height();
        bool first = true;
        detail::for_each_ring_piece(host, detail::TileRect{r.x0, r.y0, r.x1, r.y1},
                                    [&](const detail::TileRect& piece, int dx, int dy) {
          PixelRect placed{piece.x0 + dx, piece.y0 + dy, piece.x1 + dx, piece.y1 + dy};
          if (wide) placed.x0 = 0, placed.x1 = width();
          if (tall) placed.y0 = 0, placed.y1 = height();
          if ((wide && piece.x0 != r.x0) || (tall && piece.y0 != r.y0)) return;  // the same span again
          if (first) {
            rects[i] = placed;
            first = false;
          } else {
            rects.push_back(placed);
          }
        });
      }
    }
    impl.shift = shift;
    ++impl.world.stats().frames;
    return {};
  });
}

Status Renderer::estimate_work(WorkEstimate& estimate) {
  return estimate_work(PixelRect{0, 0, width(), height()}, estimate);
}

Status Renderer::estimate_work(const PixelRect& region, WorkEstimate& estimate) {
  Impl& impl = *impl_;
  if (!impl.world.has_frame()) return bad("estimate_work: no frame size (call set_frame or set_scene first)");
  if (!(0 <= region.x0 && region.x0 < region.x1 && region.x1 <= width() && 0 <= region.y0 && region.y0 < region.y1 &&
        region.y1 <= height()))
    return bad("estimate_work: region [" + std::to_string(region.x0) + ", " + std::to_string(region.y0) + ", " +
               std::to_string(region.x1) + ", " + std::to_string(region.y1) + ") is empty or outside the " +
               std::to_string(width()) + "x" + std::to_string(height()) + " frame");
  return guarded("estimate_work", [&]() -> Status {
    const detail::PreparedScene& scene = impl.world.commit();
    const Isa isa = impl.isa ? *impl.isa : resolved_isa(impl.options);
    estimate = impl.estimate(scene, static_cast<double>(region.x1 - region.x0) * (region.y1 - region.y0), isa);
    return {};
  });
}

void Renderer::set_progress(ProgressFunction progress) { impl_->progress = std::move(progress); }

void Renderer::cancel() noexcept { impl_->cancel.store(true); }

Status Renderer::set_incremental(bool on) {
  impl_->incremental = on;
  impl_->tracker.force_full();
  impl_->layers.clear();  // kept again from the next incremental frame
  return {};
}
bool Renderer::incremental() const noexcept { return impl_->incremental; }
Status Renderer::set_light_layer_budget(std::size_t bytes) {
  return guarded("set_light_layer_budget", [&] {
    impl_->layers.set_budget(bytes);
    impl_->tracker.force_full();  // no pixel of the buffer mixes the two ways
    return Status::success();
  });
}
std::size_t Renderer::light_layer_budget() const noexcept { return impl_->layers.budget(); }
std::size_t Renderer::light_layer_bytes() const noexcept { return impl_->layers.bytes(); }
void Renderer::force_full_frame() noexcept { impl_->tracker.force_full(); }
const std::vector<PixelRect>& Renderer::dirty_rects() const noexcept { return impl_->dirty_rects; }
PixelShift Renderer::frame_shift() const noexcept { return impl_->shift; }

Scene Renderer::snapshot() const { return impl_->world.snapshot(); }

RendererStats Renderer::stats() const noexcept { return impl_->world.stats(); }

FrameStats Renderer::frame_stats() const noexcept {
  FrameStats stats;
  FrameDiagnostics diagnostics;
  detail::to_frame_report(impl_->frame_counts, stats, diagnostics);
  return stats;
}

FrameDiagnostics Renderer::frame_diagnostics() const noexcept {
  FrameStats stats;
  FrameDiagnostics diagnostics;
  detail::to_frame_report(impl_->frame_counts, stats, diagnostics);
  return diagnostics;
}

}  // namespace par2d
