// The live viewer: SDL2 window, mouse and key handling, file watch, heads-up text (SDL2_ttf), screenshots.
//
// A thin layer over the library: the scene is a par2d::Scene edited by scene_edit.cpp, mirrored
// in one persistent par2d::Renderer (a lightmap at the window's size) that each edit updates
// through the light's handle; frames go straight into the window's texture as sRGB bytes.
// Every action is also logged on stdout as one line ("view: ..."), so scripted sessions
// (tests/viewer/) can follow what happened.
#include "viewer.hpp"

#include <stb_image_write.h>
#include <sys/stat.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "scene_edit.hpp"
#include "sdl_library.hpp"

namespace par2d::viewer {
namespace {

// Whether DISPLAY names a local X display (":N", "unix:N", with an optional ".screen") whose
// server socket /tmp/.X11-unix/XN exists neither as a file nor in Linux's abstract namespace
// (/proc/net/unix). Anything else (a remote display, no /proc) is left to SDL to try.
bool local_x_server_missing(const char* display, std::string& socket) {
  std::string d = display;
  if (d.rfind("unix:", 0) == 0) d.erase(0, 4);
  if (d.size() < 2 || d[0] != ':') return false;
  std::size_t end = 1;
  while (end < d.size() && d[end] >= '0' && d[end] <= '9') ++end;
  if (end == 1 || (end < d.size() && d[end] != '.')) return false;
  socket = "/tmp/.X11-unix/X" + d.substr(1, end - 1);
  struct stat st {};
  if (stat(socket.c_str(), &st) == 0) return false;
  std::FILE* sockets = std::fopen("/proc/net/unix", "r");
  if (!sockets) return false;
  char line[512];
  bool listed = false;
  const std::string abstract = "@" + socket;
  while (!listed && std::fgets(line, sizeof line, sockets)) {
    const char* at = std::strstr(line, abstract.c_str());
    listed = at != nullptr && (at[abstract.size()] == '\n' || at[abstract.size()] == ' ' || at[abstract.size()] == '\0');
  }
  std::fclose(sockets);
  return !listed;
}


using Clock = std::chrono::steady_clock;

constexpr double kPickRadiusPx = 8.0;      // how near (window pixels) a click must be to grab a light
constexpr double kWheelFactor = 1.1;       // size change per wheel notch
constexpr double kNewLightRadiusPx = 10.0; // radius of an added light, in window pixels
constexpr int kFontSize = 14;
constexpr auto kWatchInterval = std::chrono::milliseconds(200);

void log_line(const std::string& line) {
  std::printf("view: %s\n", line.c_str());
  std::fflush(stdout);
}

int fail(const std::string& message) {
  std::fprintf(stderr, "par2d: %s\n", message.c_str());
  return 1;
}

std::string format(const char* fmt, double a, double b = 0.0) {
  char buf[128];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

// Shortest text that reads back as the same double (as the saved JSON writes it).
std::string num(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

std::string point(Vec2 p) { return "(" + num(p.x) + ", " + num(p.y) + ")"; }

std::string describe(const Shape& shape) {
  if (const auto* c = std::get_if<Circle>(&shape)) return "circle at " + point(c->center) + " radius " + num(c->radius);
  if (const auto* s = std::get_if<Segment>(&shape)) return "segment from " + point(s->a) + " to " + point(s->b);
  const auto& v = std::get<Polygon>(shape).vertices;
  return "polygon of " + std::to_string(v.size()) + " vertices, first " + point(v[0]);
}

// What identifies a file's current content for the watch: editors that save through a
// rename change the inode, others the modification time or the size.
struct FileStamp {
  bool exists = false;
  ino_t inode = 0;
  off_t size = 0;
  long long mtime_ns = 0;
  bool operator==(const FileStamp& o) const {
    return exists == o.exists && inode == o.inode && size == o.size && mtime_ns == o.mtime_ns;
  }
  bool operator!=(const FileStamp& o) const { return !(*this == o); }
};

FileStamp stamp_of(const std::string& path) {
  struct stat st {};
  FileStamp s;
  if (::stat(path.c_str(), &st) != 0) return s;
  s.exists = true;
  s.inode = st.st_ino;
  s.size = st.st_size;
  s.mtime_ns = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  return s;
}

std::string default_screenshot_path(const std::string& scene_path) {
  std::string base = scene_path;
  const std::size_t slash = base.find_last_of('/');
  const std::size_t dot = base.find_last_of('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) base.erase(dot);
  return base + ".screenshot.png";
}

// Where S saves without --save-to: never the opened file (an edit session must not silently
// replace the scene it started from) but SCENE.edited.json next to it, or SCENE.edited-2.json,
// -3, ... when that exists: the first name that does not exist yet.
std::string fresh_save_path(const std::string& scene_path) {
  std::string base = scene_path;
  const std::size_t slash = base.find_last_of('/');
  const std::size_t dot = base.find_last_of('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) base.erase(dot);
  for (int n = 1;; ++n) {
    const std::string path = base + ".edited" + (n == 1 ? std::string() : "-" + std::to_string(n)) + ".json";
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return path;
  }
}

std::string window_capture_path(const std::string& screenshot_path) {
  std::string base = screenshot_path;
  if (base.size() > 4 && base.compare(base.size() - 4, 4, ".png") == 0) base.erase(base.size() - 4);
  return base + ".window.png";
}

// SDL2 and SDL2_ttf, loaded by open_window (see sdl_library.hpp).
SdlLibrary sdl_api;

struct Sdl {
  SDL_Window* window = nullptr;
  SDL_Renderer* renderer = nullptr;
  SDL_Texture* texture = nullptr;
  TTF_Font* font = nullptr;
  bool sdl = false, ttf = false;
  ~Sdl() {
    if (font) sdl_api.TTF_CloseFont(font);
    if (texture) sdl_api.SDL_DestroyTexture(texture);
    if (renderer) sdl_api.SDL_DestroyRenderer(renderer);
    if (window) sdl_api.SDL_DestroyWindow(window);
    if (ttf) sdl_api.TTF_Quit();
    if (sdl) sdl_api.SDL_Quit();
  }
};

class Viewer {
 public:
  Viewer(const ViewArgs& args, Scene scene) : args_(args), scene_(std::move(scene)) {
    save_path_ = args.save_path;  // empty: chosen by the first save (fresh_save_path)
    screenshot_path_ = args.screenshot_path.empty() ? default_screenshot_path(args.scene_path) : args.screenshot_path;
    options_.backend = *parse_backend(args.backend.c_str());
    if (!args.isa.empty()) options_.isa = parse_isa(args.isa);
    options_.threads = args.threads;
    exposure_ = args.exposure;
    stamp_ = stamp_of(args.scene_path);
  }

  int run() {
    if (int rc = open_window(); rc != 0) return rc;
    log_line("opened " + args_.scene_path + " in a " + std::to_string(win_w_) + "x" + std::to_string(win_h_) +
             " window (" + std::to_string(scene_.lights.size()) + " lights)");
    auto last_watch = Clock::now();
    while (running_) {
      SDL_Event event;
      // Idle: wait for input (and wake for the file watch); after an edit, redraw at once.
      if (sdl_api.SDL_WaitEventTimeout(&event, dirty_ ? 1 : 100)) {
        handle(event);
        while (sdl_api.SDL_PollEvent(&event)) handle(event);
      }
      if (Clock::now() - last_watch >= kWatchInterval) {
        last_watch = Clock::now();
        watch_file();
      }
      if (dirty_) render_frame();
      draw();
    }
    // The renderer's counters: how many edits went through handles instead of a rebuilt world.
    const RendererStats stats = renderer_.stats();
    log_line("closed (renderer: " + std::to_string(stats.frames) + " frames, " + std::to_string(stats.index_builds) +
             " index builds, " + std::to_string(stats.full_prepares) + " full prepares)");
    return 0;
  }

 private:
  int open_window() {
    // Without a display SDL falls back to its invisible "offscreen" driver (after libwayland
    // prints its own complaint): say so in one line instead, unless a driver was asked for.
    const bool driver_chosen = std::getenv("SDL_VIDEODRIVER") != nullptr;
    const char* x11_display = std::getenv("DISPLAY");
    const bool wayland = std::getenv("WAYLAND_DISPLAY") != nullptr;
    if (!driver_chosen && !x11_display && !wayland)
      return fail("cannot open a window: no display (DISPLAY and WAYLAND_DISPLAY are unset; "
                  "SDL_VIDEODRIVER picks another video driver)");
    // Only X11 can serve DISPLAY: without WAYLAND_DISPLAY, SDL's Wayland probe would add
    // libwayland's own line to ours when the X display cannot be opened.
    const bool only_x11 = !driver_chosen && !wayland;
    if (only_x11) {
      // A local display with no server is refused before SDL is loaded: its probe would only
      // add its drivers' complaints, and leave libdbus's allocations behind.
      if (std::string socket; local_x_server_missing(x11_display, socket))
        return fail(std::string("cannot open a window: no display (DISPLAY=") + x11_display +
                    " cannot be opened: no X server listens on " + socket + ")");
      setenv("SDL_VIDEODRIVER", "x11", 1);
    }
    if (std::string error; !load_sdl_library(sdl_api, error)) return fail("cannot open a window: " + error);
    if (sdl_api.SDL_Init(SDL_INIT_VIDEO) != 0) {
      const std::string why = sdl_api.SDL_GetError();
      sdl_api.SDL_Quit();  // safe after a failed SDL_Init; releases what the probe opened
      if (only_x11)
        return fail(std::string("cannot open a window: no display (DISPLAY=") + x11_display + " cannot be opened: " +
                    why + ")");
      return fail("cannot open a window: " + why);
    }
    sdl_.sdl = true;
    const std::string driver = sdl_api.SDL_GetCurrentVideoDriver();
    if (!driver_chosen && (driver == "offscreen" || driver == "dummy"))
      return fail("cannot open a window: no display (SDL found only its " + driver + " video driver)");
    if (sdl_api.TTF_Init() != 0) return fail(std::string("cannot start SDL_ttf: ") + sdl_api.SDL_GetError());
    sdl_.ttf = true;
    sdl_.font = sdl_api.TTF_OpenFont(PAR2D_VIEWER_FONT, kFontSize);
    if (!sdl_.font) return fail(std::string(PAR2D_VIEWER_FONT) + ": " + sdl_api.SDL_GetError());

    // The window shows the scene's view at its own size, scaled down to fit the screen.
    SDL_Rect bounds{0, 0, scene_.width, scene_.height};
    sdl_api.SDL_GetDisplayUsableBounds(0, &bounds);
    const double fit = std::min({1.0, 0.95 * bounds.w / scene_.width, 0.95 * bounds.h / scene_.height});
    win_w_ = std::max(1, static_cast<int>(std::lround(scene_.width * fit)));
    win_h_ = std::max(1, static_cast<int>(std::lround(scene_.height * fit)));
    sdl_.window = sdl_api.SDL_CreateWindow(("par2d view: " + args_.scene_path).c_str(), SDL_WINDOWPOS_CENTERED,
                                   SDL_WINDOWPOS_CENTERED, win_w_, win_h_, 0);
    if (!sdl_.window) return fail(std::string("cannot open a window: ") + sdl_api.SDL_GetError());
    sdl_.renderer = sdl_api.SDL_CreateRenderer(sdl_.window, -1, 0);
    if (!sdl_.renderer) return fail(std::string("cannot draw in the window: ") + sdl_api.SDL_GetError());
    sdl_api.SDL_SetRenderDrawBlendMode(sdl_.renderer, SDL_BLENDMODE_BLEND);
    // RGBA32: bytes R, G, B, A in memory, the layout of PixelFormat::rgba8_srgb.
    sdl_.texture = sdl_api.SDL_CreateTexture(sdl_.renderer, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, win_w_, win_h_);
    if (!sdl_.texture) return fail(std::string("cannot draw in the window: ") + sdl_api.SDL_GetError());
    sdl_api.SDL_SetTextureBlendMode(sdl_.texture, SDL_BLENDMODE_NONE);
    if (Status s = renderer_.set_options(options_); !s) return fail(s.message());
    if (Status s = load_world(); !s) return fail(s.message());
    return 0;
  }

  // Hands the whole scene to the renderer (at the window's size) and takes its light handles.
  Status load_world() {
    Scene sized = scene_;
    sized.width = win_w_;
    sized.height = win_h_;
    handles_.clear();
    return renderer_.set_scene(sized, &handles_);
  }

  // Takes the renderer's answer to a light edit already applied to scene_. A refusal (not
  // expected: scene_edit validated the scene) shows it and resynchronizes the whole world.
  void sync_light(const Status& status) {
    if (status) return;
    message(status.message(), true);
    if (Status s = load_world(); !s) message(s.message(), true);
  }

  Status apply_options() {
    frame_ms_.clear();  // the average describes one path
    dirty_ = true;
    return renderer_.set_options(options_);
  }

  WindowMapping mapping() const { return {scene_.view, win_w_, win_h_}; }
  // World point under the center of window pixel (x, y).
  Vec2 world_at(int x, int y) const { return mapping().to_world(x + 0.5, y + 0.5); }
  std::optional<std::size_t> light_at(int x, int y) const {
    return pick_light(scene_, world_at(x, y), kPickRadiusPx * mapping().pixel_size());
  }

  void handle(const SDL_Event& e) {
    switch (e.type) {
      case SDL_QUIT: running_ = false; break;
      case SDL_MOUSEBUTTONDOWN:
        mouse_x_ = e.button.x;
        mouse_y_ = e.button.y;
        if (e.button.button == SDL_BUTTON_LEFT) {
          dragging_ = light_at(e.button.x, e.button.y);
          drag_x_ = e.button.x;
          drag_y_ = e.button.y;
          if (dragging_) selected_ = dragging_;
        }
        break;
      case SDL_MOUSEMOTION:
        mouse_x_ = e.motion.x;
        mouse_y_ = e.motion.y;
        if (dragging_ && (e.motion.x != drag_x_ || e.motion.y != drag_y_)) {
          const Vec2 d = mapping().delta_to_world(e.motion.x - drag_x_, e.motion.y - drag_y_);
          if (move_light(scene_, *dragging_, d)) {
            sync_light(renderer_.update_light(handles_[*dragging_], scene_.lights[*dragging_]));
            drag_x_ = e.motion.x;
            drag_y_ = e.motion.y;
            dirty_ = true;
          }
        }
        break;
      case SDL_MOUSEBUTTONUP:
        if (e.button.button == SDL_BUTTON_LEFT && dragging_) {
          log_line("moved light " + std::to_string(*dragging_) + ": " + describe(scene_.lights[*dragging_].shape));
          dragging_.reset();
        }
        break;
      case SDL_MOUSEWHEEL: {
        const auto target = light_at(mouse_x_, mouse_y_);
        if (target && e.wheel.y != 0 && scale_light(scene_, *target, std::pow(kWheelFactor, e.wheel.y))) {
          sync_light(renderer_.update_light(handles_[*target], scene_.lights[*target]));
          selected_ = target;
          dirty_ = true;
          log_line("resized light " + std::to_string(*target) + ": " + describe(scene_.lights[*target].shape));
        }
        break;
      }
      case SDL_KEYDOWN: key(e.key.keysym); break;
      default: break;
    }
  }

  void key(const SDL_Keysym& k) {
    switch (k.sym) {
      case SDLK_q:
      case SDLK_ESCAPE: running_ = false; break;
      case SDLK_a: {
        const Light* like = selected_ && *selected_ < scene_.lights.size() ? &scene_.lights[*selected_] : nullptr;
        if (add_light(scene_, world_at(mouse_x_, mouse_y_), kNewLightRadiusPx * mapping().pixel_size(), like)) {
          selected_ = scene_.lights.size() - 1;
          LightHandle handle;
          const Status s = renderer_.add_light(scene_.lights.back(), &handle);
          if (s) handles_.push_back(handle);
          sync_light(s);
          dirty_ = true;
          log_line("added light " + std::to_string(*selected_) + ": " + describe(scene_.lights.back().shape));
        }
        break;
      }
      case SDLK_d:
      case SDLK_DELETE:
      case SDLK_BACKSPACE: {
        const auto target = light_at(mouse_x_, mouse_y_);
        if (target && delete_light(scene_, *target)) {
          const Status s = renderer_.remove_light(handles_[*target]);
          if (s) handles_.erase(handles_.begin() + static_cast<std::ptrdiff_t>(*target));
          sync_light(s);
          selected_.reset();
          dirty_ = true;
          log_line("deleted light " + std::to_string(*target) + " (" + std::to_string(scene_.lights.size()) + " left)");
        }
        break;
      }
      case SDLK_b:
        options_.backend = options_.backend == Backend::scalar ? Backend::simd : Backend::scalar;
        if (Status s = apply_options(); !s) message(s.message(), true);
        log_line(std::string("backend ") + backend_name(options_.backend));
        break;
      case SDLK_g:  // one bounce: both terms, the direct light alone, the bounce alone
        options_.bounce = options_.bounce == BounceTerm::included   ? BounceTerm::excluded
                          : options_.bounce == BounceTerm::excluded ? BounceTerm::only
                                                                    : BounceTerm::included;
        if (Status s = apply_options(); !s) message(s.message(), true);
        log_line(std::string("bounce ") + bounce_term_name(options_.bounce));
        break;
      case SDLK_i: next_isa(); break;
      case SDLK_s: save(); break;
      case SDLK_r: reload(); break;
      case SDLK_EQUALS:
      case SDLK_PLUS:
      case SDLK_KP_PLUS:
        exposure_ *= 1.25;
        dirty_ = true;
        break;
      case SDLK_MINUS:
      case SDLK_KP_MINUS:
        exposure_ /= 1.25;
        dirty_ = true;
        break;
      case SDLK_h: help_ = !help_; break;
      default: break;
    }
  }

  // The next SIMD level this CPU supports after the current one (wrapping), on the SIMD path.
  void next_isa() {
    const Isa current = resolved_isa(options_);
    std::vector<Isa> levels;
    for (Isa isa : par2d::kSimdIsas)
      if (isa_supported(isa)) levels.push_back(isa);
    if (levels.empty()) {
      message("this CPU has no SIMD level: the scalar path only", false);
      return;
    }
    Isa next = levels.front();
    for (std::size_t i = 0; i < levels.size(); ++i)
      if (levels[i] == current && options_.backend != Backend::scalar) next = levels[(i + 1) % levels.size()];
    options_.backend = Backend::simd;
    options_.isa = next;
    if (Status s = apply_options(); !s) message(s.message(), true);
    log_line(std::string("isa ") + isa_name(next));
  }

  void message(const std::string& text, bool error) {
    status_ = text;
    status_is_error_ = error;
    if (error)
      std::fprintf(stderr, "par2d: %s\n", text.c_str());
  }

  void watch_file() {
    const FileStamp now = stamp_of(args_.scene_path);
    if (now == stamp_) return;
    stamp_ = now;
    if (now.exists) reload();
  }

  // A file that fails to load keeps the last good scene on screen, its error in the window.
  void reload() {
    Scene fresh;
    const Status status = load_scene_file(args_.scene_path, fresh);
    if (!status) {
      message(status.message() + " (keeping the last good scene)", true);
      log_line("reload failed: " + status.message());
      return;
    }
    const bool same_size = fresh.width == scene_.width && fresh.height == scene_.height;
    scene_ = std::move(fresh);
    if (Status s = load_world(); !s) {  // not expected: the file was validated when loaded
      message(s.message(), true);
      return;
    }
    selected_.reset();
    dragging_.reset();
    dirty_ = true;
    message("reloaded " + args_.scene_path + (same_size ? "" : " (new size: the window keeps its own)"), false);
    log_line("reloaded " + args_.scene_path + " (" + std::to_string(scene_.lights.size()) + " lights)");
  }

  // The save key: the edited scene as JSON, the scene rendered at its own size as a PNG (the
  // bytes `par2d render -o` writes for the saved file with these options), and the window.
  void save() {
    // The first save of a session without --save-to picks a new file; later ones rewrite it.
    if (save_path_.empty()) save_path_ = fresh_save_path(args_.scene_path);
    if (Status s = save_scene_file(save_path_, scene_); !s) {
      message(s.message(), true);
      return;
    }
    if (save_path_ == args_.scene_path) stamp_ = stamp_of(save_path_);  // our own write is no edit
    std::vector<float> full;
    try {
      full.assign(static_cast<std::size_t>(scene_.width) * scene_.height * 3, 0.0f);
    } catch (const std::bad_alloc&) {
      message("out of memory for the screenshot", true);
      return;
    }
    const ImageView view{full.data(), scene_.width, scene_.height, static_cast<std::ptrdiff_t>(scene_.width) * 3};
    Status s = render(scene_, options_, view);
    if (s) s = write_png(screenshot_path_, view, exposure_);
    if (!s) {
      message(s.message(), true);
      return;
    }
    capture_window_ = true;  // after the next draw, so the capture shows this frame
    message("saved " + save_path_ + " and " + screenshot_path_, false);
    log_line("saved " + save_path_ + " and " + screenshot_path_ + " (backend " + backend_name(options_.backend) +
             ", isa " + isa_name(resolved_isa(options_)) + ", bounce " + bounce_term_name(options_.bounce) +
             format(", exposure %.6g)", exposure_));
  }

  // The renderer writes sRGB bytes (with the exposure) straight into the locked texture:
  // no float frame and no conversion pass.
  void render_frame() {
    dirty_ = false;
    void* texels = nullptr;
    int pitch = 0;
    if (sdl_api.SDL_LockTexture(sdl_.texture, nullptr, &texels, &pitch) != 0) {
      message(std::string("cannot draw in the window: ") + sdl_api.SDL_GetError(), true);
      return;
    }
    FrameBuffer buffer;
    buffer.data = texels;
    buffer.format = PixelFormat::rgba8_srgb;
    buffer.row_stride = pitch;
    buffer.exposure = exposure_;
    const auto start = Clock::now();
    const Status status = renderer_.render(buffer);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    sdl_api.SDL_UnlockTexture(sdl_.texture);
    if (!status) {
      message(status.message(), true);
      return;
    }
    frame_ms_.push_back(ms);
    if (frame_ms_.size() > 10) frame_ms_.pop_front();
  }

  // One line of heads-up text at (x, y); returns its height.
  int text(const std::string& line, int x, int y, SDL_Color color) {
    SDL_Surface* surface = sdl_api.TTF_RenderUTF8_Blended(sdl_.font, line.c_str(), color);
    if (!surface) return kFontSize + 4;
    SDL_Texture* t = sdl_api.SDL_CreateTextureFromSurface(sdl_.renderer, surface);
    const SDL_Rect box{x - 4, y - 1, surface->w + 8, surface->h + 2};
    sdl_api.SDL_SetRenderDrawColor(sdl_.renderer, 0, 0, 0, 170);
    sdl_api.SDL_RenderFillRect(sdl_.renderer, &box);
    const SDL_Rect dst{x, y, surface->w, surface->h};
    if (t) sdl_api.SDL_RenderCopy(sdl_.renderer, t, nullptr, &dst);
    const int h = surface->h + 2;
    if (t) sdl_api.SDL_DestroyTexture(t);
    sdl_api.SDL_FreeSurface(surface);
    return h;
  }

  // The selected light's outline, so one sees what the wheel and D will act on.
  void draw_selection() {
    if (!selected_ || *selected_ >= scene_.lights.size()) return;
    Shape shape = scene_.lights[*selected_].shape;
    // A circle light's edge is as bright as its inside: ring it 3 pixels out to be seen.
    if (auto* c = std::get_if<Circle>(&shape)) c->radius += 3.0 * mapping().pixel_size();
    std::vector<SDL_FPoint> points;
    for (const Vec2& p : outline(shape)) {
      const Vec2 w = mapping().to_window(p);
      points.push_back({static_cast<float>(w.x), static_cast<float>(w.y)});
    }
    sdl_api.SDL_SetRenderDrawColor(sdl_.renderer, 255, 190, 0, 255);
    sdl_api.SDL_RenderDrawLinesF(sdl_.renderer, points.data(), static_cast<int>(points.size()));
  }

  void draw() {
    sdl_api.SDL_RenderCopy(sdl_.renderer, sdl_.texture, nullptr, nullptr);
    draw_selection();
    const SDL_Color white{255, 255, 255, 255}, grey{190, 190, 190, 255}, red{255, 90, 80, 255};
    int y = 6;
    if (!frame_ms_.empty()) {
      double sum = 0;
      for (double ms : frame_ms_) sum += ms;
      const double ms = sum / static_cast<double>(frame_ms_.size());
      y += text(format("%.1f ms/frame  %.1f frames/s", ms, 1000.0 / ms) + "  (" + backend_name(options_.backend) +
                    ", " + isa_name(resolved_isa(options_)) + ", " + std::to_string(win_w_) + "x" +
                    std::to_string(win_h_) + format(", exposure %.3g)", exposure_),
                8, y, white);
    }
    y += text(std::to_string(scene_.lights.size()) + " lights, " + std::to_string(scene_.occluders.size()) +
                  " occluders" + (selected_ ? ", light " + std::to_string(*selected_) + " selected" : "") +
                  "   H: help",
              8, y, grey);
    if (help_) {
      for (const char* line :
           {"drag a light: move   wheel over it: resize",
            "A: add a light at the mouse   D/Del: delete the light under it",
            "B: SIMD/scalar   I: next ISA   +/-: exposure",
            "G: one bounce: with it, without it, the bounce alone",
            "S: save scene (never over the opened file) + screenshot",
            "R: reload the file now (edits lost)   Q: quit"})
        y += text(line, 8, y, grey);
    }
    if (!status_.empty()) text(status_, 8, y, status_is_error_ ? red : white);
    if (capture_window_) {
      capture_window_ = false;
      write_window_capture();
    }
    sdl_api.SDL_RenderPresent(sdl_.renderer);
  }

  void write_window_capture() {
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(win_w_) * win_h_ * 3);
    const std::string path = window_capture_path(screenshot_path_);
    const std::string temp = path + ".tmp.png";
    if (sdl_api.SDL_RenderReadPixels(sdl_.renderer, nullptr, SDL_PIXELFORMAT_RGB24, rgb.data(), win_w_ * 3) != 0 ||
        !stbi_write_png(temp.c_str(), win_w_, win_h_, 3, rgb.data(), win_w_ * 3) ||
        std::rename(temp.c_str(), path.c_str()) != 0) {
      std::remove(temp.c_str());
      message(path + ": cannot write the window capture", true);
      return;
    }
    log_line("captured the window in " + path);
  }

  const ViewArgs& args_;
  Scene scene_;
  std::string save_path_, screenshot_path_;
  RenderOptions options_;
  double exposure_ = 1.0;
  FileStamp stamp_;
  Sdl sdl_;
  Renderer renderer_;                // the scene at the window's size, kept prepared across edits
  std::vector<LightHandle> handles_;  // handles_[i] names scene_.lights[i] in renderer_
  int win_w_ = 0, win_h_ = 0;
  std::deque<double> frame_ms_;
  bool running_ = true, dirty_ = true, help_ = false, capture_window_ = false;
  std::optional<std::size_t> dragging_, selected_;
  int drag_x_ = 0, drag_y_ = 0, mouse_x_ = 0, mouse_y_ = 0;
  std::string status_;
  bool status_is_error_ = false;
};

}  // namespace

CLI::App* add_view_command(CLI::App& app, ViewArgs& args) {
  CLI::App* view = app.add_subcommand(
      "view",
      "Open a window on a scene: drag lights, wheel to resize, A/D add/delete, S saves, R reloads (H: help)");
  view->add_option("scene", args.scene_path, "Scene file (JSON); reloaded when it changes on disk")->required();
  view->add_option("--save-to", args.save_path,
                   "Where S writes the edited scene (may be the scene file itself). Default: SCENE.edited.json "
                   "next to it, or SCENE.edited-N.json for the first N that does not exist yet (never the scene file)");
  view->add_option("--screenshot", args.screenshot_path,
                   "Where S writes the rendered PNG (the window goes to *.window.png). Default: SCENE.screenshot.png");
  view->add_option("--backend", args.backend, "auto (default), simd or scalar; B toggles")
      ->check(CLI::IsMember({"auto", "simd", "scalar"}));
  view->add_option("--isa", args.isa, "Start with this SIMD level; I cycles")
      ->check(CLI::IsMember({"scalar", "sse4", "avx2", "avx512"}));
  view->add_option("--threads", args.threads, "Worker threads; 0 = all. Default: 0")->check(CLI::Range(0, 1 << 20));
  view->add_option("--exposure", args.exposure, "Display and screenshot exposure; +/- change it. Default: 1")
      ->check(CLI::PositiveNumber);
  return view;
}

int run_view(const ViewArgs& args) {
  Scene scene;
  if (Status s = load_scene_file(args.scene_path, scene); !s) return fail(s.message());
  Viewer viewer(args, std::move(scene));
  return viewer.run();
}

}  // namespace par2d::viewer
