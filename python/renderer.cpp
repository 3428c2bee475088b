// Python module: par2d.Renderer, par2d::Renderer behind a lock so that a Python object may be
// shared between threads; a persistent world changed through integer handles, rendered into
// float32, float16 or sRGB uint8 arrays.
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"

namespace par2d::python {
namespace {

// par2d::Renderer for Python: a persistent world changed through integer handles.
//
// The C++ class is one-thread-at-a-time, so every entry point below first converts its
// arguments (which may run Python code: __index__, __float__, __fspath__), then takes the
// world's lock, and only then reads or changes any state: a frame is rendered at the size
// and view of the moment it holds the lock, never a size read before. Errors are raised
// after the lock is let go. The lock is taken with the GIL released when it is busy, and
// the GIL is taken again while holding it (never the other order), so a render that holds
// the lock with the GIL released does not stall other Python threads, and nothing deadlocks.
class PyRenderer {
 public:
  PyRenderer(const py::object& scene, const py::object& backend, const py::object& threads, const py::object& isa,
             const py::object& spp, const py::object& culling, const py::object& shaded,
             const py::object& sample_needs, const py::object& bounce) {
    set_options(backend, threads, isa, spp, culling, shaded, sample_needs, bounce);
    if (!scene.is_none()) set_scene(scene);
  }

  void set_options(const py::object& backend, const py::object& threads, const py::object& isa, const py::object& spp,
                   const py::object& culling, const py::object& shaded, const py::object& sample_needs,
                   const py::object& bounce) {
    par2d::RenderOptions options = make_options(backend, threads, spp, 1024, isa, culling);
    options.shaded = to_bool(shaded, "shaded");
    options.sample_needs = to_bool(sample_needs, "sample_needs");
    options.bounce = to_bounce_term(bounce);
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_options(options);
    }
    check(status);
  }

  py::tuple set_scene(const py::object& scene_or_dict) {
    std::optional<PyScene> holder;
    const PyScene& scene = as_scene(scene_or_dict, holder);
    std::vector<par2d::LightHandle> lights;
    std::vector<par2d::OccluderHandle> occluders;
    std::vector<std::uint64_t> light_ids, occluder_ids;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_scene(scene.scene(), &lights, &occluders);
      if (status.ok()) {
        lights_.clear();
        occluders_.clear();
        for (const auto& h : lights) lights_.push_back(h.id);
        for (const auto& h : occluders) occluders_.push_back(h.id);
        light_ids = lights_;
        occluder_ids = occluders_;
      }
    }
    check(status);
    return py::make_tuple(light_ids, occluder_ids);
  }

  void set_frame(const py::object& width_arg, const py::object& height_arg, const py::object& view_arg) {
    const int width = to_int(width_arg, "width"), height = to_int(height_arg, "height");
    const std::optional<par2d::View> view = to_view(view_arg);
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = view ? renderer_.set_frame(width, height, *view) : renderer_.set_frame(width, height);
    }
    check(status);
  }

  void set_view_offset(const py::object& x_arg, const py::object& y_arg) {
    const auto offset = [](const py::object& arg, const char* place) -> std::int64_t {
      const std::optional<long long> value = as_integer(arg);
      if (!value) bad_argument(place, "must be an integer, not " + type_name(arg));
      return *value;
    };
    const std::int64_t x = offset(x_arg, "x"), y = offset(y_arg, "y");
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_view_offset(x, y);
    }
    check(status);
  }
  void set_buffer_layout(const py::object& value) {
    const std::string name = py::isinstance<py::str>(value) ? value.cast<std::string>() : std::string();
    if (name != "image" && name != "ring") bad_argument("buffer_layout", "must be \"image\" or \"ring\", got " + describe(value));
    WorldLock lock(mutex_);
    check(renderer_.set_buffer_layout(name == "ring" ? par2d::BufferLayout::ring : par2d::BufferLayout::image));
  }
  std::string buffer_layout() const {
    WorldLock lock(mutex_);
    return renderer_.buffer_layout() == par2d::BufferLayout::ring ? "ring" : "image";
  }
  py::tuple view_offset() const {
    WorldLock lock(mutex_);
    return py::make_tuple(renderer_.view_offset_x(), renderer_.view_offset_y());
  }
  py::tuple frame_shift() const {
    par2d::PixelShift shift;
    {
      WorldLock lock(mutex_);
      shift = renderer_.frame_shift();
    }
    return py::make_tuple(shift.dx, shift.dy);
  }

  std::uint64_t add_light(const py::object& dict, const py::object& transform_arg) {
    const par2d::Light light = parse_light(dict, "add_light");
    const std::optional<par2d::Transform> transform = to_transform(transform_arg);
    par2d::LightHandle handle;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = transform ? renderer_.add_light(light, *transform, &handle) : renderer_.add_light(light, &handle);
      if (status.ok()) lights_.push_back(handle.id);
    }
    check(status);
    return handle.id;
  }
  void update_light(const py::object& handle, const py::object& dict, const py::object& transform_arg) {
    const std::uint64_t id = handle_id(handle, "light");
    const par2d::Light light = parse_light(dict, "light " + std::to_string(id));
    const std::optional<par2d::Transform> transform = to_transform(transform_arg);
    locked_check([&] {
      const par2d::LightHandle h{id};
      return transform ? renderer_.update_light(h, light, *transform) : renderer_.update_light(h, light);
    });
  }
  void set_light_emission(const py::object& handle, const py::object& color_arg, const py::object& intensity_arg) {
    const std::uint64_t id = handle_id(handle, "light");
    const std::array<double, 3> color = to_three(color_arg, "color", "(r, g, b)");
    const double intensity = to_double(intensity_arg, "intensity");
    locked_check([&] {
      return renderer_.set_light_emission(par2d::LightHandle{id}, par2d::Rgb{color[0], color[1], color[2]}, intensity);
    });
  }
  void remove_light(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "light");
    locked_check([&] {
      par2d::Status status = renderer_.remove_light(par2d::LightHandle{id});
      if (status.ok()) lights_.erase(std::remove(lights_.begin(), lights_.end(), id), lights_.end());
      return status;
    });
  }

  std::uint64_t add_occluder(const py::object& dict, const py::object& transform_arg) {
    const par2d::Occluder occluder = parse_occluder(dict, "add_occluder");
    const std::optional<par2d::Transform> transform = to_transform(transform_arg);
    par2d::OccluderHandle handle;
    locked_check([&] {
      par2d::Status status =
          transform ? renderer_.add_occluder(occluder, *transform, &handle) : renderer_.add_occluder(occluder, &handle);
      if (status.ok()) occluders_.push_back(handle.id);
      return status;
    });
    return handle.id;
  }
  void update_occluder(const py::object& handle, const py::object& dict, const py::object& transform_arg) {
    const std::uint64_t id = handle_id(handle, "occluder");
    const par2d::Occluder occluder = parse_occluder(dict, "occluder " + std::to_string(id));
    const std::optional<par2d::Transform> transform = to_transform(transform_arg);
    locked_check([&] {
      const par2d::OccluderHandle h{id};
      return transform ? renderer_.update_occluder(h, occluder, *transform) : renderer_.update_occluder(h, occluder);
    });
  }
  void remove_occluder(const py::object& handle) {
    const std::uint64_t id = handle_id(handle, "occluder");
    locked_check([&] {
      par2d::Status status = renderer_.remove_occluder(par2d::OccluderHandle{id});
      if (status.ok()) occluders_.erase(std::remove(occluders_.begin(), occluders_.end(), id), occluders_.end());
      return status;
    });
  }

  // Float RGB frame (or region) into `out` or a new (h, w, 3) float32 array.
  py::array render(const py::object& out, const py::object& region, const py::object& progress) {
    return render_format(par2d::PixelFormat::rgb_f32, 1.0, out, region, progress);
  }
  py::array render_rgba(const py::object& out, const py::object& region, const py::object& progress) {
    return render_format(par2d::PixelFormat::rgba_f32, 1.0, out, region, progress);
  }
  py::array render_rgba8(const py::object& exposure, const py::object& dither, const py::object& out,
                         const py::object& region, const py::object& progress) {
    const double e = to_double(exposure, "exposure");
    const bool dithered = to_bool(dither, "dither");
    return render_format(dithered ? par2d::PixelFormat::rgba8_srgb_dithered : par2d::PixelFormat::rgba8_srgb, e, out,
                         region, progress);
  }
  py::array render_bgra8(const py::object& exposure, const py::object& dither, const py::object& out,
                         const py::object& region, const py::object& progress) {
    const double e = to_double(exposure, "exposure");
    const bool dithered = to_bool(dither, "dither");
    return render_format(dithered ? par2d::PixelFormat::bgra8_srgb_dithered : par2d::PixelFormat::bgra8_srgb, e, out,
                         region, progress);
  }
  // IEEE halves as NumPy float16 (native byte order, as the library writes them).
  py::array render_rgba16f(const py::object& out, const py::object& region, const py::object& progress) {
    return render_format(par2d::PixelFormat::rgba16f, 1.0, out, region, progress);
  }

  // Long renders (docs/python.md): the work estimate of the whole frame or a region, and the limit.
  py::dict estimate_work(const py::object& region_arg) {
    const std::optional<std::array<long long, 4>> region = to_region(region_arg);
    par2d::WorkEstimate estimate;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      if (region) {
        const auto& r = *region;
        const bool fits = r[0] >= 0 && r[1] >= 0 && r[2] <= renderer_.width() && r[3] <= renderer_.height();
        status = fits ? renderer_.estimate_work(par2d::PixelRect{static_cast<int>(r[0]), static_cast<int>(r[1]),
                                                                 static_cast<int>(r[2]), static_cast<int>(r[3])},
                                                estimate)
                      : par2d::Status(par2d::StatusCode::invalid_argument,
                                      "region: (" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
                                          std::to_string(r[2]) + ", " + std::to_string(r[3]) +
                                          ") is not inside the " + std::to_string(renderer_.width()) + "x" +
                                          std::to_string(renderer_.height()) + " frame");
      } else {
        status = renderer_.estimate_work(estimate);
      }
    }
    check(status);
    return estimate_dict(estimate);
  }
  double work_limit() const {
    WorldLock lock(mutex_);
    return renderer_.options().work_limit;
  }
  void set_work_limit(const py::object& limit_arg) {
    const double limit = to_work_limit(limit_arg);
    locked_check([&] {
      par2d::RenderOptions options = renderer_.options();
      options.work_limit = limit;
      return renderer_.set_options(options);
    });
  }

  py::dict stats() const {
    par2d::RendererStats s;
    {
      WorldLock lock(mutex_);
      s = renderer_.stats();
    }
    py::dict d;
    d["frames"] = s.frames;
    d["index_builds"] = s.index_builds;
    d["index_updates"] = s.index_updates;
    d["reach_computations"] = s.reach_computations;
    d["full_prepares"] = s.full_prepares;
    return d;
  }

  void set_incremental(const py::object& on_arg) {
    const bool on = to_bool(on_arg, "incremental");
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_incremental(on);
    }
    check(status);
  }
  bool incremental() const {
    WorldLock lock(mutex_);
    return renderer_.incremental();
  }
  void set_light_layer_budget(const py::object& bytes_arg) {
    const std::size_t bytes = to_size(bytes_arg, "light_layer_budget");
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.set_light_layer_budget(bytes);
    }
    check(status);
  }
  std::size_t light_layer_budget() const {
    WorldLock lock(mutex_);
    return renderer_.light_layer_budget();
  }
  std::size_t light_layer_bytes() const {
    WorldLock lock(mutex_);
    return renderer_.light_layer_bytes();
  }
  void force_full_frame() {
    WorldLock lock(mutex_);
    renderer_.force_full_frame();
  }
  py::list dirty_rects() const {
    std::vector<par2d::PixelRect> rects;
    {
      WorldLock lock(mutex_);
      rects = renderer_.dirty_rects();
    }
    py::list out;
    for (const par2d::PixelRect& r : rects) out.append(py::make_tuple(r.x0, r.y0, r.x1, r.y1));
    return out;
  }

  // What the last successful render computed (all zero before one), and what its culling and
  // kernel did.
  py::dict frame_stats() const {
    par2d::FrameStats s;
    {
      WorldLock lock(mutex_);
      s = renderer_.frame_stats();
    }
    py::dict d;
#define PAR2D_FRAME_STAT(name) d[#name] = s.name;
    PAR2D_FRAME_STAT(pixels) PAR2D_FRAME_STAT(tiles) PAR2D_FRAME_STAT(layer_tiles_reused)
    PAR2D_FRAME_STAT(layer_tiles_filled) PAR2D_FRAME_STAT(bounce_pieces) PAR2D_FRAME_STAT(bounce_lit_sources)
#undef PAR2D_FRAME_STAT
    return d;
  }
  py::dict frame_diagnostics() const {
    par2d::FrameDiagnostics s;
    {
      WorldLock lock(mutex_);
      s = renderer_.frame_diagnostics();
    }
    py::dict d;
#define PAR2D_FRAME_STAT(name) d[#name] = s.name;
    PAR2D_FRAME_STAT(samples) PAR2D_FRAME_STAT(blocks) PAR2D_FRAME_STAT(block_lights)
    PAR2D_FRAME_STAT(block_lights_out_of_reach) PAR2D_FRAME_STAT(block_candidates) PAR2D_FRAME_STAT(block_proofs_tried)
    PAR2D_FRAME_STAT(block_proofs_succeeded) PAR2D_FRAME_STAT(block_proofs_skipped)
    PAR2D_FRAME_STAT(tile_lights) PAR2D_FRAME_STAT(tile_pairs) PAR2D_FRAME_STAT(tile_general_pairs)
    PAR2D_FRAME_STAT(tile_proofs_tried) PAR2D_FRAME_STAT(tile_proofs_succeeded) PAR2D_FRAME_STAT(tile_proofs_skipped)
    PAR2D_FRAME_STAT(umbra_tests) PAR2D_FRAME_STAT(umbra_hits) PAR2D_FRAME_STAT(tile_pairs_outside_hull)
    PAR2D_FRAME_STAT(light_samples) PAR2D_FRAME_STAT(pair_samples) PAR2D_FRAME_STAT(scalar_tiles)
    PAR2D_FRAME_STAT(sampled_pixels) PAR2D_FRAME_STAT(sampled_visible_lights) PAR2D_FRAME_STAT(sampled_blocking_pairs)
    PAR2D_FRAME_STAT(bounce_tile_sources) PAR2D_FRAME_STAT(bounce_tile_sources_hidden)
    PAR2D_FRAME_STAT(bounce_source_walks) PAR2D_FRAME_STAT(bounce_depth_tests)
#undef PAR2D_FRAME_STAT
    return d;
  }

  // What a handle names, as last given, as a dict shaped like an entry of the scene file's
  // lists (written by the scene writer, so add_light(r.light(h)) adds the same light).
  py::object light(const py::object& handle) const {
    const std::uint64_t id = handle_id(handle, "light");
    par2d::Scene one;
    one.width = one.height = 1;
    one.lights.emplace_back();
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.light(par2d::LightHandle{id}, &one.lights[0]);
    }
    check(status);
    return entry_dict(one, "lights");
  }
  py::object occluder(const py::object& handle) const {
    const std::uint64_t id = handle_id(handle, "occluder");
    par2d::Scene one;
    one.width = one.height = 1;
    one.occluders.emplace_back();
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = renderer_.occluder(par2d::OccluderHandle{id}, &one.occluders[0]);
    }
    check(status);
    return entry_dict(one, "occluders");
  }

  // The options in use: what isa and threads resolve to on this CPU, and the rest as set.
  py::dict options() const {
    par2d::RenderOptions o;
    int threads = 0;
    {
      WorldLock lock(mutex_);
      o = renderer_.options();
      threads = renderer_.threads();
    }
    py::dict d;
    d["backend"] = par2d::backend_name(o.backend);
    d["threads"] = threads;
    d["isa"] = par2d::isa_name(par2d::resolved_isa(o));
    d["spp"] = o.spp;
    d["culling"] = o.culling;
    d["shaded"] = o.shaded;
    d["sample_needs"] = o.sample_needs;
    d["bounce"] = par2d::bounce_term_name(o.bounce);
    return d;
  }

  // The scene-wide lighting-model terms (docs/contract.md section 6).
  void set_bounce(const py::object& piece_arg, const py::object& step_arg) {
    // Either may be None: that value is kept. Converted before the lock (they may raise).
    const std::optional<double> piece = piece_arg.is_none() ? std::nullopt : std::optional(to_double(piece_arg, "piece"));
    const std::optional<int> step = step_arg.is_none() ? std::nullopt : std::optional(to_int(step_arg, "step"));
    locked_check([&] {
      par2d::Bounce bounce = renderer_.bounce();
      if (piece) bounce.piece = *piece;
      if (step) bounce.step = *step;
      return renderer_.set_bounce(bounce);
    });
  }
  int bounce_step() const {
    WorldLock lock(mutex_);
    return renderer_.bounce().step;
  }
  double bounce_piece() const {
    WorldLock lock(mutex_);
    return renderer_.bounce().piece;
  }
  void set_ambient(const py::object& rgb_arg) {
    const std::array<double, 3> rgb = to_three(rgb_arg, "rgb", "(r, g, b)");
    locked_check([&] { return renderer_.set_ambient({rgb[0], rgb[1], rgb[2]}); });
  }
  // A list of dicts shaped like the scene file's "directional_lights", checked by its loader.
  void set_directional_lights(const py::object& list) {
    const std::string name = "set_directional_lights";
    const std::string text =
        "{\"width\": 1, \"height\": 1, \"directional_lights\": " + json_text(list, name, "directional_lights") + "}";
    par2d::Scene scene;
    check(par2d::parse_scene(text, name, scene));
    locked_check([&] { return renderer_.set_directional_lights(scene.directional_lights); });
  }
  void set_normal(const py::object& normal) {
    const std::array<double, 3> n = to_three(normal, "normal", "(nx, ny, nz)");
    locked_check([&] { return renderer_.set_normal({n[0], n[1], n[2]}); });
  }
  // A PNG is checked against the frame's size (read under the lock) from its header, then
  // decoded outside the lock, so a large map does not hold up other threads' frames; a
  // set_frame in between is caught by set_normal_map, under the lock.
  void set_normal_map(const py::object& source_arg) {
    NormalMapSource source = to_normal_map_source(source_arg);
    if (source.png_path) {
      int width = 0, height = 0;
      {
        WorldLock lock(mutex_);
        width = renderer_.width();
        height = renderer_.height();
      }
      source.map = load_normal_map(*source.png_path, width, height);
    }
    locked_check([&] { return renderer_.set_normal_map(source.map); });
  }
  void clear_normal_source() {
    locked_check([&] { return renderer_.clear_normal_source(); });
  }

  PyScene snapshot() const {
    WorldLock lock(mutex_);
    return PyScene(renderer_.snapshot());
  }

  // The frame and the handles as one consistent reading.
  struct Summary {
    int width = 0, height = 0, threads = 0;
    par2d::View view{};
    std::size_t light_count = 0, occluder_count = 0;
  };
  Summary summary() const {
    WorldLock lock(mutex_);
    return Summary{renderer_.width(),      renderer_.height(),      renderer_.threads(), renderer_.view(),
                   renderer_.light_count(), renderer_.occluder_count()};
  }
  std::vector<std::uint64_t> lights() const {
    WorldLock lock(mutex_);
    return lights_;
  }
  std::vector<std::uint64_t> occluders() const {
    WorldLock lock(mutex_);
    return occluders_;
  }

 private:
  // Holds the world's mutex; waits for it with the GIL released.
  class WorldLock {
   public:
    explicit WorldLock(std::mutex& mutex) : mutex_(mutex) {
      if (!mutex_.try_lock()) {
        py::gil_scoped_release release;
        mutex_.lock();
      }
    }
    ~WorldLock() { mutex_.unlock(); }
    WorldLock(const WorldLock&) = delete;
    WorldLock& operator=(const WorldLock&) = delete;

   private:
    std::mutex& mutex_;
  };

  // Runs fn (which returns a Status) under the lock; raises its error after letting go.
  template <class Fn>
  void locked_check(Fn&& fn) {
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      status = fn();
    }
    check(status);
  }

  // The NumPy array a pixel format fills: its element type and channels per pixel.
  struct ArrayLayout {
    const char* dtype;
    py::ssize_t channels;
  };
  static ArrayLayout layout_of(par2d::PixelFormat format) {
    switch (format) {
      case par2d::PixelFormat::rgb_f32: return {"float32", 3};
      case par2d::PixelFormat::rgba_f32: return {"float32", 4};
      case par2d::PixelFormat::rgba16f: return {"float16", 4};
      case par2d::PixelFormat::rgba8_srgb:
      case par2d::PixelFormat::bgra8_srgb:
      case par2d::PixelFormat::rgba8_srgb_dithered:
      case par2d::PixelFormat::bgra8_srgb_dithered: break;
    }
    return {"uint8", 4};
  }

  py::array render_format(par2d::PixelFormat format, double exposure, const py::object& out_arg,
                          const py::object& region_arg, const py::object& progress_arg) {
    const std::optional<std::array<long long, 4>> region = to_region(region_arg);
    PyProgress progress(to_progress(progress_arg));
    const bool out_given = !out_arg.is_none();
    const ArrayLayout layout = layout_of(format);
    const py::dtype dtype(layout.dtype);
    const py::ssize_t channels = layout.channels, item = dtype.itemsize();
    py::array image;
    par2d::Status status;
    {
      WorldLock lock(mutex_);
      const int width = renderer_.width(), height = renderer_.height();
      par2d::PixelRect rect{0, 0, width, height};
      if (region) {
        const auto& r = *region;
        if (r[0] < 0 || r[1] < 0 || r[2] > width || r[3] > height || r[0] >= r[2] || r[1] >= r[3]) {
          status = par2d::Status(par2d::StatusCode::invalid_argument,
                                 "region: (" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
                                     std::to_string(r[2]) + ", " + std::to_string(r[3]) +
                                     ") is not a non-empty rectangle inside the " + std::to_string(width) + "x" +
                                     std::to_string(height) + " frame");
        } else {
          rect = {static_cast<int>(r[0]), static_cast<int>(r[1]), static_cast<int>(r[2]), static_cast<int>(r[3])};
        }
      }
      const py::ssize_t w = rect.x1 - rect.x0, h = rect.y1 - rect.y0;
      if (status.ok() && out_given) {
        bool fits = py::isinstance<py::array>(out_arg);
        if (fits) {
          image = py::reinterpret_borrow<py::array>(out_arg);
          const bool dtype_ok = image.dtype().equal(dtype);
          fits = dtype_ok && image.ndim() == 3 && image.shape(0) == h && image.shape(1) == w &&
                 image.shape(2) == channels && image.strides(2) == item && image.strides(1) == channels * item &&
                 image.strides(0) >= w * channels * item && image.writeable();
        }
        if (!fits)
          status = par2d::Status(par2d::StatusCode::invalid_argument,
                                 std::string("out: needs a writable ") + layout.dtype +
                                     " array of shape (" + std::to_string(h) + ", " + std::to_string(w) + ", " +
                                     std::to_string(channels) + ") with packed pixels (rows may be padded)");
      } else if (status.ok()) {
        try {
          image = py::array(dtype, std::vector<py::ssize_t>{h, w, channels});
        } catch (py::error_already_set&) {
          PyErr_Clear();
          status = par2d::Status(par2d::StatusCode::out_of_memory,
                                 "out: no memory for a (" + std::to_string(h) + ", " + std::to_string(w) + ", " +
                                     std::to_string(channels) + ") array");
        }
      }
      if (status.ok()) {
        par2d::FrameBuffer buffer;
        buffer.data = image.mutable_data();
        buffer.format = format;
        buffer.row_stride = static_cast<std::ptrdiff_t>(image.strides(0));
        buffer.exposure = exposure;
        // A new array holds no earlier frame (even at an earlier array's address).
        if (!out_given) renderer_.force_full_frame();
        // Ctrl-C is looked for during frames that are computed aside anyway (estimated work);
        // a callback makes every frame one (docs/python.md, "Long renders").
        par2d::WorkEstimate estimate;
        if (progress.has_callback() || (renderer_.estimate_work(rect, estimate).ok() && estimate.total > 0.0))
          renderer_.set_progress(progress.function());
        {
          py::gil_scoped_release release;
          status = region ? renderer_.render(buffer, rect) : renderer_.render(buffer);
        }
        renderer_.set_progress(nullptr);
      }
    }
    progress.finish(status);
    return image;
  }

  static py::object entry_dict(const par2d::Scene& one, const char* list) {
    return py::module_::import("json").attr("loads")(par2d::scene_to_json(one))[list][py::int_(0)];
  }

  mutable std::mutex mutex_;
  par2d::Renderer renderer_;
  std::vector<std::uint64_t> lights_, occluders_;
};

}  // namespace

void bind_renderer(py::module_& m) {
  py::class_<PyRenderer>(m, "Renderer",
                         "A persistent world of lights and occluders, changed through integer handles and\n"
                         "rendered frame after frame (par2d::Renderer, docs/api.md). Moving or recoloring a light\n"
                         "never rebuilds the occluder index. Lights and occluders are dicts shaped like one entry\n"
                         "of the scene file's lists. A refused update raises par2d.Error and changes nothing.")
      .def(py::init<const py::object&, const py::object&, const py::object&, const py::object&, const py::object&,
                    const py::object&, const py::object&, const py::object&, const py::object&>(),
           py::arg("scene") = py::none(), py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0,
           py::arg("isa") = py::none(), py::arg("spp") = 1, py::arg("culling") = true, py::arg("shaded") = true,
           py::arg("sample_needs") = false, py::arg("bounce") = "included",
           "A renderer holding `scene` (a Scene or a dict), or an empty world (then call set_frame).\n"
           "backend: auto|simd|scalar (raycast is par2d.render's alone); threads: 0 = all; shaded=False: the plain\n"
           "irradiance even with a normal source; sample_needs=True: frame_diagnostics' sampled_* counts too;\n"
           "bounce: included|excluded|only, which terms of one bounce a frame outputs.")
      .def("set_options", &PyRenderer::set_options, py::kw_only(), py::arg("backend") = "auto", py::arg("threads") = 0,
           py::arg("isa") = py::none(), py::arg("spp") = 1, py::arg("culling") = true, py::arg("shaded") = true,
           py::arg("sample_needs") = false, py::arg("bounce") = "included",
           "Backend, threads, isa cap, samples per pixel, culling, shading, sampled needs and the bounce\n"
           "terms (included|excluded|only) for the next frames.")
      .def_property_readonly("options", &PyRenderer::options,
                             "dict: backend, threads (workers used), isa (the level used on this CPU), spp, culling, shaded,\n"
                             "sample_needs, bounce.")
      .def("light", &PyRenderer::light, py::arg("handle"),
           "The light a handle names, as a dict like an entry of the scene file's lights (color and intensity\n"
           "always; the lighting-model terms where not default).")
      .def("occluder", &PyRenderer::occluder, py::arg("handle"), "The occluder a handle names, as a dict.")
      .def("set_scene", &PyRenderer::set_scene, py::arg("scene"),
           "Replaces the whole world (frame included); returns (light handles, occluder handles) in the scene's order.")
      .def("set_frame", &PyRenderer::set_frame, py::arg("width"), py::arg("height"), py::arg("view") = py::none(),
           "Lightmap size and the world rectangle (x0, y0, x1, y1) it shows (default (0, 0, width, height));\n"
           "the view offset starts again at (0, 0).")
      .def("set_view_offset", &PyRenderer::set_view_offset, py::arg("x"), py::arg("y"),
           "Scrolling: pixel (i, j) shows pixel (x + i, y + j) of set_frame's view extended past its edges.\n"
           "With incremental frames, a move by whole pixels shifts the kept pixels (frame_shift) and computes\n"
           "only the uncovered bands and what changed, byte for byte a renderer's at that offset. |x|, |y| <= 2**40.")
      .def_property_readonly("view_offset", &PyRenderer::view_offset, "(x, y): the view offset on set_frame's pixel grid.")
      .def_property("buffer_layout", &PyRenderer::buffer_layout, &PyRenderer::set_buffer_layout,
                    "\"image\" (default) or \"ring\": whole frames into out= with pixel (i, j) at ((x + i) % width,\n"
                    "(y + j) % height), (x, y) the view offset, so a scroll moves no pixel (frame_shift stays (0, 0);\n"
                    "dirty_rects in the array's coordinates). Region renders need \"image\".")
      .def_property_readonly("frame_shift", &PyRenderer::frame_shift,
                             "(dx, dy): how far the last render moved the buffer's pixels before writing dirty_rects:\n"
                             "pixel (i, j) now holds what pixel (i + dx, j + dy) held ((0, 0) unless a scroll kept pixels).")
      .def("add_light", &PyRenderer::add_light, py::arg("light"), py::kw_only(), py::arg("transform") = py::none(),
           "Adds a light (dict); returns its handle. transform: {\"position\": (x, y), \"rotation\": degrees,\n"
           "\"scale\": s or (sx, sy)} places a shape given in its own local frame (a sprite's).")
      .def("update_light", &PyRenderer::update_light, py::arg("handle"), py::arg("light"), py::kw_only(),
           py::arg("transform") = py::none(), "Replaces the light (dict), placed by transform when given.")
      .def("set_light_emission", &PyRenderer::set_light_emission, py::arg("handle"), py::arg("color"),
           py::arg("intensity"), "Changes only the color and intensity.")
      .def("remove_light", &PyRenderer::remove_light, py::arg("handle"))
      .def("add_occluder", &PyRenderer::add_occluder, py::arg("occluder"), py::kw_only(),
           py::arg("transform") = py::none(), "Adds an occluder (dict), placed by transform when given; returns its handle.")
      .def("update_occluder", &PyRenderer::update_occluder, py::arg("handle"), py::arg("occluder"), py::kw_only(),
           py::arg("transform") = py::none(), "Replaces the occluder (dict), placed by transform when given.")
      .def("remove_occluder", &PyRenderer::remove_occluder, py::arg("handle"))
      .def("render", &PyRenderer::render, py::kw_only(), py::arg("out") = py::none(), py::arg("region") = py::none(),
           py::arg("progress") = py::none(),
           "Linear irradiance as float32 (height, width, 3), or of region (x0, y0, x1, y1) only: then shape\n"
           "(y1 - y0, x1 - x0, 3), bit-identical to those pixels of the whole frame. out: an existing array\n"
           "to fill. progress: called as progress(tiles_done, tiles) on this thread as tiles finish; returning\n"
           "False cancels (par2d.CancelledError), as does Ctrl-C (KeyboardInterrupt), `out` then untouched.\n"
           "A frame past work_limit raises par2d.WorkLimitError. The GIL is released while rendering.")
      .def("render_rgba", &PyRenderer::render_rgba, py::kw_only(), py::arg("out") = py::none(),
           py::arg("region") = py::none(), py::arg("progress") = py::none(),
           "The frame as float32 (height, width, 4): render's values and alpha 1. out, region, progress: as for\n"
           "render.")
      .def("render_rgba8", &PyRenderer::render_rgba8, py::arg("exposure") = 1.0, py::kw_only(),
           py::arg("dither") = false, py::arg("out") = py::none(), py::arg("region") = py::none(),
           py::arg("progress") = py::none(),
           "The frame as uint8 (height, width, 4): round(255 * srgb(clamp(exposure * E, 0, 1))), alpha 255 -\n"
           "the bytes write_png stores, written by the tiles directly. dither=True: floor(255 * srgb(...) + t)\n"
           "with t from the 8x8 Bayer matrix at the frame pixel, so dark gradients do not band (docs/api.md,\n"
           "\"Pixel formats\"). out, region, progress: as for render.")
      .def("render_bgra8", &PyRenderer::render_bgra8, py::arg("exposure") = 1.0, py::kw_only(),
           py::arg("dither") = false, py::arg("out") = py::none(), py::arg("region") = py::none(),
           py::arg("progress") = py::none(),
           "render_rgba8's bytes in B, G, R, A order (the layout many GPUs and window systems prefer).")
      .def("render_rgba16f", &PyRenderer::render_rgba16f, py::kw_only(), py::arg("out") = py::none(),
           py::arg("region") = py::none(), py::arg("progress") = py::none(),
           "The frame as float16 (height, width, 4): render's values rounded to the nearest half (ties to even),\n"
           "those past 65504 (the largest finite half) saturating to it, alpha 1; what engines upload as\n"
           "RGBA16F. out, region, progress: as for render.")
      .def("estimate_work", &PyRenderer::estimate_work, py::arg("region") = py::none(),
           "The estimated work of the whole frame (or region (x0, y0, x1, y1)) with the options and world of\n"
           "now, as a dict: samples, bounce, scalar, raycast, total (docs/python.md, \"Long renders\").")
      .def_property("work_limit", &PyRenderer::work_limit, &PyRenderer::set_work_limit,
                    "float: the most estimated work (estimate_work()['total']) a frame may have, past which render\n"
                    "raises par2d.WorkLimitError before computing a pixel; 0: none. Default 1e11.")
      .def("set_ambient", &PyRenderer::set_ambient, py::arg("rgb"), "Ambient (r, g, b), each >= 0, added to every pixel.")
      .def("set_bounce", &PyRenderer::set_bounce, py::arg("piece") = py::none(), py::arg("step") = py::none(),
           "One bounce's piece length in world units (> 0) and coarse step in pixels (1 .. 64, 1: every pixel\n"
           "exact); None keeps a value (docs/contract.md section 7).")
      .def_property_readonly("bounce_piece", &PyRenderer::bounce_piece, "One bounce's piece length.")
      .def_property_readonly("bounce_step", &PyRenderer::bounce_step, "The coarse bounce's step in pixels.")
      .def("set_directional_lights", &PyRenderer::set_directional_lights, py::arg("lights"),
           "Replaces the directional lights: a list of dicts like the scene file's directional_lights.")
      .def("set_normal", &PyRenderer::set_normal, py::arg("normal"),
           "One normal (nx, ny, nz) for every pixel, world axes; replaces a normal map.")
      .def("set_normal_map", &PyRenderer::set_normal_map, py::arg("normal_map"),
           "A PNG path or an array (height, width, 3) of normals in image axes (y up), exactly the frame's size\n"
           "(a PNG's size is checked from its header before a pixel is decoded; before the first set_frame, any\n"
           "size up to 16384 per side).")
      .def("clear_normal_source", &PyRenderer::clear_normal_source, "No normal source: plain irradiance.")
      .def("snapshot", &PyRenderer::snapshot, "The world as a Scene; par2d.render of it gives the same image (at a view offset other than\n"
           "(0, 0): within the contract's accuracy bound, its tiles placed on its own frame).")
      .def_property_readonly("stats", &PyRenderer::stats,
                             "dict: frames, index_builds, index_updates, reach_computations, full_prepares.")
      .def_property("incremental", &PyRenderer::incremental, &PyRenderer::set_incremental,
                    "bool (default False): a whole-frame render into out= computes only the 64x64 blocks whose\n"
                    "inputs changed since the last whole frame into that array and leaves its other pixels as they\n"
                    "are; byte-identical to a full render. A render without out= computes every pixel.")
      .def("force_full_frame", &PyRenderer::force_full_frame, "The next whole-frame render computes every pixel.")
      .def_property("light_layer_budget", &PyRenderer::light_layer_budget, &PyRenderer::set_light_layer_budget,
                    "int bytes (default 0: off): the light-layer cache of incremental frames. Per 64x64 block and\n"
                    "light, the light's share before its emission, so blocks where lights only flicker or change\n"
                    "colour are recombined; pixels within 1e-6 x the brightest emission of a full render.")
      .def_property_readonly("light_layer_bytes", &PyRenderer::light_layer_bytes,
                             "int: bytes the light-layer cache holds after the last render (at most the budget).")
      .def_property_readonly("dirty_rects", &PyRenderer::dirty_rects,
                             "list of (x0, y0, x1, y1): the pixels the last render wrote (merged 64x64 blocks, then a\n"
                             "scroll's uncovered bands), after frame_shift; empty when an incremental frame changed nothing.")
      .def_property_readonly("frame_stats", &PyRenderer::frame_stats,
                             "dict: what the last render computed: pixels, tiles, the light-layer cache's reused\n"
                             "and filled shares, the bounce's pieces and lit sources (docs/api.md, FrameStats).")
      .def_property_readonly("frame_diagnostics", &PyRenderer::frame_diagnostics,
                             "dict: what the last render's culling and kernel did (docs/api.md, FrameDiagnostics).")
      .def_property_readonly("lights", &PyRenderer::lights, "Handles of the lights, in the order they were added.")
      .def_property_readonly("occluders", &PyRenderer::occluders, "Handles of the occluders, in the order they were added.")
      .def_property_readonly("width", [](const PyRenderer& r) { return r.summary().width; })
      .def_property_readonly("height", [](const PyRenderer& r) { return r.summary().height; })
      .def_property_readonly("shape", [](const PyRenderer& r) {
        const PyRenderer::Summary s = r.summary();
        return py::make_tuple(s.height, s.width, 3);
      })
      .def_property_readonly("view", [](const PyRenderer& r) {
        const par2d::View v = r.summary().view;
        return py::make_tuple(v.x0, v.y0, v.x1, v.y1);
      })
      .def_property_readonly("threads", [](const PyRenderer& r) { return r.summary().threads; })
      .def("__repr__", [](const PyRenderer& r) {
        const PyRenderer::Summary s = r.summary();
        return "<par2d.Renderer " + std::to_string(s.width) + "x" + std::to_string(s.height) + ", " +
               std::to_string(s.light_count) + " lights, " + std::to_string(s.occluder_count) + " occluders>";
      });
}

}  // namespace par2d::python
