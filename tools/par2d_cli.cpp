// The par2d command-line tool: render a JSON scene to PNG/PFM, benchmark it, report the build (docs/contract.md §4).
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "outline_command.hpp"
#include "par2d/par2d.hpp"
#ifdef PAR2D_HAVE_VIEWER
#include "viewer/viewer.hpp"
#endif

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// Every failure is exactly one line on stderr, so scripts can show it verbatim.
int fail(const std::string& message, int code = kExitFailure) {
  std::string line = message;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  while (!line.empty() && line.back() == ' ') line.pop_back();
  std::fprintf(stderr, "par2d: %s\n", line.c_str());
  return code;
}

// User text echoed in a message, cut so that a megabyte argument stays a short line.
std::string shortened(const std::string& text) {
  constexpr std::size_t kKeep = 32;
  if (text.size() <= kKeep + 8) return text;
  return text.substr(0, kKeep) + "... (" + std::to_string(text.size()) + " characters)";
}

// Whether two output paths name one file: by identity when it exists ("a.png", "./a.png",
// a link to it), by resolved directory and name when it does not yet.
bool same_output(const std::string& a, const std::string& b) {
  if (a == "-" || b == "-") return a == b;
  std::error_code ea, eb;
  if (std::filesystem::equivalent(a, b, ea)) return true;
  const auto ca = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ea), ea);
  const auto cb = std::filesystem::weakly_canonical(std::filesystem::absolute(b, eb), eb);
  return !ea && !eb && ca == cb;
}

// Whether standard output was closed when the process started (main() then put /dev/null
// there): "-" must not write into whatever file would otherwise get descriptor 1.
bool g_stdout_was_closed = false;

// Makes descriptors 0, 1 and 2 valid before anything opens a file: a closed one gets
// /dev/null (opened only to hold the number), so that no output or input file can become
// standard output or standard error. False when even that is impossible.
bool claim_standard_descriptors() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    if (fd == STDOUT_FILENO) g_stdout_was_closed = true;
    // open() returns the lowest free descriptor: this one, since those below it are open.
    const int opened = ::open("/dev/null", O_RDWR | O_NOCTTY);
    if (opened != fd) {
      if (opened >= 0) ::close(opened);
      return false;
    }
  }
  return true;
}

// An input the outputs must not replace: what it is, and the path it was read from.
struct InputFile {
  const char* what;
  std::string path;
};

// The first output that is one of the inputs (the same file by identity, following symbolic
// links: a link to it or a hard link counts), as a message; empty when there is none.
// Checked before anything is written.
std::string output_replacing_input(const std::pair<const char*, const std::string*>* outputs, std::size_t count,
                                   const std::vector<InputFile>& inputs) {
  for (const InputFile& input : inputs) {
    struct stat in {};
    if (::stat(input.path.c_str(), &in) != 0) continue;
    for (std::size_t k = 0; k < count; ++k) {
      const std::string& path = *outputs[k].second;
      if (path.empty()) continue;
      struct stat out {};
      const int got = path == "-" ? (g_stdout_was_closed ? -1 : ::fstat(STDOUT_FILENO, &out))
                                  : ::stat(path.c_str(), &out);
      if (got != 0 || out.st_dev != in.st_dev || out.st_ino != in.st_ino) continue;
      return std::string("render: ") + outputs[k].first + " '" + (path == "-" ? "-' (standard output)" : path + "'") +
             " is the " + input.what + " '" + input.path + "': an output may not replace an input";
    }
  }
  return {};
}

// SIGINT/SIGTERM/SIGHUP/SIGPIPE mid-write: delete the temporaries, then die of the signal as usual.
extern "C" void on_fatal_signal(int sig) {
  par2d::remove_pending_outputs();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Options shared by `render` and `bench`, as typed on the command line.
struct CommonArgs {
  std::string scene_path;
  std::string backend = "auto";
  std::string isa;  // empty: PAR2D_ISA or the best the CPU has
  int threads = 0;
  int spp = 1;
  int rays = 1024;
  std::string bounce = "included";  // RenderOptions::bounce
  bool allow_any_path = false;  // normal_map paths outside the scene's folder
  double work_limit = par2d::kDefaultWorkLimit;  // RenderOptions::work_limit
};

// Loads the scene under the path policy the command line chose.
par2d::Status load_scene(const CommonArgs& args, par2d::Scene& scene) {
  par2d::LoadOptions options;
  options.allow_any_path = args.allow_any_path;
  return par2d::load_scene_file(args.scene_path, scene, options);
}

struct RenderArgs {
  std::string png_path;
  std::string pfm_path;
  // The plain irradiance (no normal-map shading) as well; the same image as the main output
  // when the scene has no normal source.
  std::string plain_png_path;
  std::string plain_pfm_path;
  double exposure = 1.0;
  bool dither = false;  // PNG outputs with the ordered dither
  std::string progress = "auto";  // the progress bar: auto (a terminal, past a second), always, never
};

struct BenchArgs {
  int frames = 10;
  int width = 0;   // 0: the scene's
  int height = 0;  // 0: the scene's
  bool json = false;
  bool stats = false;
};

const CLI::Validator kBackendName(
    [](std::string& value) -> std::string {
      if (value == "raycast" || par2d::parse_backend(value.c_str())) return {};
      return "unknown backend '" + value + "' (expected auto, simd, scalar or raycast)";
    },
    "auto|simd|scalar|raycast", "backend name");

const CLI::Validator kBounceTermName(
    [](std::string& value) -> std::string {
      if (par2d::parse_bounce_term(value.c_str())) return {};
      return "unknown bounce term '" + value + "' (expected included, excluded or only)";
    },
    "included|excluded|only", "bounce term");

const CLI::Validator kIsaName(
    [](std::string& value) -> std::string {
      if (par2d::parse_isa(value)) return {};
      return "unknown ISA '" + value + "' (expected scalar, sse4, avx2, avx512 or neon64)";
    },
    "scalar|sse4|avx2|avx512|neon64", "ISA name");

// CLI::NonNegativeNumber prints DBL_MAX in full when it fails; this says it plainly.
const CLI::Validator kNonNegative(
    [](std::string& value) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || *end != '\0' || !std::isfinite(v) || v < 0.0)
        return "must be a finite number >= 0, got '" + shortened(value) + "'";
      return {};
    },
    "NUMBER >= 0", "non-negative");

void add_common_options(CLI::App& cmd, CommonArgs& args) {
  cmd.add_option("scene", args.scene_path, "Scene file (JSON, see README)")->required();
  cmd.add_option("--backend", args.backend,
                 "Rendering path. auto (default) picks the fastest path this CPU supports "
                 "(the SIMD path where available); simd: vectorized tiles; scalar: the "
                 "double-precision reference; raycast: brute-force baseline")
      ->check(kBackendName);
  cmd.add_option("--threads", args.threads,
                 "Worker threads; 0 = all hardware threads. Default: 0")
      ->check(CLI::Range(0, 1 << 20));
  cmd.add_option("--spp", args.spp,
                 "Samples per pixel in a fixed stratified pattern, 1..256. Default: 1")
      ->check(CLI::Range(1, 256));
  cmd.add_option("--rays", args.rays,
                 "Directions per sample for --backend raycast, 1..1048576. Default: 1024")
      ->check(CLI::Range(1, 1 << 20));
  cmd.add_option("--isa", args.isa,
                 "Force the SIMD instruction set (capped at what the CPU supports). "
                 "Default: $PAR2D_ISA if set, else the best the CPU has")
      ->check(kIsaName);
  cmd.add_option("--bounce", args.bounce,
                 "With reflecting occluders (one bounce): included (default) outputs direct light plus "
                 "bounce; excluded the direct light alone; only the bounce term alone")
      ->check(kBounceTermName);
  cmd.add_option("--work-limit", args.work_limit,
                 "Refuse a frame whose estimated work (bounce pieces, scalar-reference and ray-caster samples "
                 "times the shapes they look at; docs/cli.md) is past this many units; 0 = no limit. Default: 1e11")
      ->check(kNonNegative);
  cmd.add_flag("--allow-any-path", args.allow_any_path,
               "Let the scene's normal_map name any file (absolute, or outside the scene's folder); by "
               "default it must stay inside the scene file's folder. For trusted scenes only");
}

// What the rendering options ask for: a renderer's options, or with --backend raycast the
// ray-casting baseline (par2d::render_raycast, which is no renderer backend) with them.
struct RenderChoice {
  par2d::RenderOptions options;
  bool raycast = false;

  par2d::Status render(const par2d::Scene& scene, const par2d::ImageView& image,
                       const par2d::RenderControl& control = {}) const {
    return raycast ? par2d::render_raycast(scene, options, image, control) : par2d::render(scene, options, image, control);
  }
  const char* backend_name() const { return raycast ? "raycast" : par2d::backend_name(options.backend); }
  // The ISA the choice runs at (the ray caster is scalar code).
  par2d::Isa isa() const { return raycast ? par2d::Isa::scalar : par2d::resolved_isa(options); }
};

RenderChoice make_choice(const CommonArgs& args) {
  RenderChoice choice;
  par2d::RenderOptions& options = choice.options;
  choice.raycast = args.backend == "raycast";
  if (!choice.raycast) options.backend = *par2d::parse_backend(args.backend.c_str());  // validated by kBackendName
  options.threads = args.threads;
  options.spp = args.spp;
  options.rays = args.rays;
  options.bounce = *par2d::parse_bounce_term(args.bounce.c_str());  // validated by kBounceTermName
  if (!args.isa.empty()) options.isa = par2d::parse_isa(args.isa);
  options.work_limit = args.work_limit;
  return choice;
}

// A refused or failed render as one line; a frame past the work limit names the option that
// raises it.
int render_failed(const CommonArgs& args, const par2d::Status& s) {
  if (s.code() != par2d::StatusCode::work_limit) return fail(s.message());
  std::string what = s.message();
  for (const char* who : {"render: ", "render_raycast: "})
    if (what.rfind(who, 0) == 0) what.erase(0, std::string(who).size());
  return fail("render: " + args.scene_path + ": " + what + "; --work-limit raises the limit (0: none)");
}

// The progress bar on standard error: `always`, or `auto` on a terminal once a render has run
// for a second; redrawn at most ten times a second, ended by a newline once drawn.
class ProgressBar {
 public:
  ProgressBar(const std::string& mode, const char* label)
      : label_(label), always_(mode == "always"), start_(Clock::now()) {}
  ~ProgressBar() {
    if (drawn_) std::fputc('\n', stderr);
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Whether a bar may be drawn at all in this mode (`auto` needs a terminal).
  static bool wanted(const std::string& mode) { return mode == "always" || (mode == "auto" && ::isatty(STDERR_FILENO)); }

  bool operator()(const par2d::Progress& p) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    if (!always_ && elapsed < 1.0) return true;
    const bool last = p.tiles_done == p.tiles;
    if (drawn_ && !last && elapsed - drawn_at_ < 0.1) return true;
    drawn_ = true;
    drawn_at_ = elapsed;
    constexpr int kWidth = 30;
    const double fraction = p.tiles == 0 ? 1.0 : static_cast<double>(p.tiles_done) / static_cast<double>(p.tiles);
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\rpar2d: %s [%s%s] %3d%% %llu/%llu tiles, %.1f s", label_,
                 std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(kWidth - filled), ' ').c_str(),
                 static_cast<int>(fraction * 100.0), static_cast<unsigned long long>(p.tiles_done),
                 static_cast<unsigned long long>(p.tiles), elapsed);
    std::fflush(stderr);
    return true;
  }

 private:
  using Clock = std::chrono::steady_clock;
  const char* label_;
  bool always_;
  Clock::time_point start_;
  bool drawn_ = false;
  double drawn_at_ = 0.0;
};

// The choice's render with the progress bar `mode` asks for.
par2d::Status render_with_progress(const par2d::Scene& scene, const RenderChoice& choice,
                                   const par2d::ImageView& image, const std::string& mode, const char* label) {
  if (!ProgressBar::wanted(mode)) return choice.render(scene, image);
  ProgressBar bar(mode, label);
  par2d::RenderControl control;
  control.progress = [&bar](const par2d::Progress& p) { return bar(p); };
  return choice.render(scene, image, control);
}

// What the library resolves the thread count to (capped at the hardware), so that what is
// reported is what ran.
int resolved_threads(int requested) {
  par2d::RenderOptions options;
  options.threads = requested;
  return par2d::resolved_threads(options);
}

// The storage behind an ImageView: left uninitialized, since a render writes every pixel
// of its view before anything reads it (zero-filling a 1920x1080 image first cost as many
// instructions as 3 % of a paper frame).
using ImageStorage = std::unique_ptr<float[]>;

// Allocates the caller-owned float RGB buffer the library renders into, starting on a
// 64-byte boundary: whole tile rows then start on a vector-register boundary wherever the
// row stride allows, and large frames take the library's non-temporal stores there.
bool allocate_image(int width, int height, ImageStorage& storage, par2d::ImageView& view, std::string& error) {
  constexpr std::size_t kAlignFloats = 64 / sizeof(float);
  try {
    storage.reset(new float[static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3 + kAlignFloats]);
  } catch (const std::bad_alloc&) {
    error = "out of memory allocating a " + std::to_string(width) + "x" + std::to_string(height) +
            " image";
    return false;
  }
  const std::size_t misaligned = reinterpret_cast<std::uintptr_t>(storage.get()) / sizeof(float) % kAlignFloats;
  view.data = storage.get() + (kAlignFloats - misaligned) % kAlignFloats;
  view.width = width;
  view.height = height;
  view.row_stride = static_cast<std::ptrdiff_t>(width) * 3;
  return true;
}

int run_render(const CommonArgs& common, const RenderArgs& args) {
  if (args.png_path.empty() && args.pfm_path.empty() && args.plain_png_path.empty() && args.plain_pfm_path.empty())
    return fail("render: give -o OUT.png and/or --pfm OUT.pfm", kExitUsage);
  const std::pair<const char*, const std::string*> named[] = {{"-o", &args.png_path},
                                                              {"--pfm", &args.pfm_path},
                                                              {"--plain-png", &args.plain_png_path},
                                                              {"--plain-pfm", &args.plain_pfm_path}};
  for (std::size_t a = 0; a < 4; ++a) {
    for (std::size_t b = a + 1; b < 4; ++b) {
      if (named[a].second->empty() || named[b].second->empty()) continue;
      if (same_output(*named[a].second, *named[b].second))
        return fail(std::string("render: ") + named[a].first + " '" + *named[a].second + "' and " + named[b].first +
                        " '" + *named[b].second + "' name the same file",
                    kExitUsage);
    }
  }

  for (const auto& [option, path] : named) {
    if (*path == "-" && g_stdout_was_closed)
      return fail(std::string("render: ") + option + " -: standard output is closed", kExitUsage);
  }

  par2d::Scene scene;
  if (par2d::Status s = load_scene(common, scene); !s)
    return fail(s.message());

  // No output may replace what was read: the scene file or its normal map.
  std::vector<InputFile> inputs{{"scene file", common.scene_path}};
  if (scene.normal_map)
    inputs.push_back({"scene's normal map", par2d::scene_relative_path(common.scene_path, scene.normal_map->path)});
  if (std::string clash = output_replacing_input(named, 4, inputs); !clash.empty()) return fail(clash, kExitUsage);

  ImageStorage storage;
  par2d::ImageView image;
  std::string error;
  if (!allocate_image(scene.width, scene.height, storage, image, error)) return fail(error);

  // The whole image exists before any file is touched: a failed render writes nothing.
  RenderChoice choice = make_choice(common);
  if (par2d::Status s = render_with_progress(scene, choice, image, args.progress, "rendering"); !s)
    return render_failed(common, s);

  // The plain irradiance differs only where a normal source shades the scene; then it is a
  // second render, finished (like the first) before any file is touched.
  const bool wants_plain = !args.plain_png_path.empty() || !args.plain_pfm_path.empty();
  const bool shaded = scene.normal.has_value() || scene.normal_map.has_value();
  ImageStorage plain_storage;
  par2d::ImageView plain = image;
  if (wants_plain && shaded) {
    if (!allocate_image(scene.width, scene.height, plain_storage, plain, error)) return fail(error);
    choice.options.shaded = false;
    if (par2d::Status s = render_with_progress(scene, choice, plain, args.progress, "rendering the plain image"); !s)
      return render_failed(common, s);
  }

  // All or nothing: every file is complete before any replaces what was there.
  std::vector<par2d::ImageOutput> outputs;
  if (!args.png_path.empty())
    outputs.push_back({args.png_path, par2d::ImageOutput::Format::png, args.exposure});
  if (!args.pfm_path.empty()) outputs.push_back({args.pfm_path, par2d::ImageOutput::Format::pfm, 1.0});
  if (!args.plain_png_path.empty())
    outputs.push_back({args.plain_png_path, par2d::ImageOutput::Format::png, args.exposure, &plain});
  if (!args.plain_pfm_path.empty())
    outputs.push_back({args.plain_pfm_path, par2d::ImageOutput::Format::pfm, 1.0, &plain});
  for (par2d::ImageOutput& output : outputs) output.dither = args.dither && output.format == par2d::ImageOutput::Format::png;
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) std::signal(sig, on_fatal_signal);
  if (par2d::Status s = par2d::write_images(outputs, image); !s) return fail(s.message());
  return 0;
}

// A frame's FrameStats and FrameDiagnostics, as `par2d bench --stats` reports them.
struct FrameReport {
  par2d::FrameStats stats;
  par2d::FrameDiagnostics diagnostics;
};

// The report as a JSON object of its counts.
std::string stats_json(const FrameReport& report) {
  const par2d::FrameStats& f = report.stats;
  const par2d::FrameDiagnostics& s = report.diagnostics;
  const std::pair<const char*, std::uint64_t> fields[] = {
      {"pixels", f.pixels},
      {"samples", s.samples},
      {"blocks", s.blocks},
      {"block_lights", s.block_lights},
      {"block_lights_out_of_reach", s.block_lights_out_of_reach},
      {"block_candidates", s.block_candidates},
      {"block_proofs_tried", s.block_proofs_tried},
      {"block_proofs_succeeded", s.block_proofs_succeeded},
      {"block_proofs_skipped", s.block_proofs_skipped},
      {"tiles", f.tiles},
      {"tile_lights", s.tile_lights},
      {"tile_pairs", s.tile_pairs},
      {"tile_general_pairs", s.tile_general_pairs},
      {"tile_proofs_tried", s.tile_proofs_tried},
      {"tile_proofs_succeeded", s.tile_proofs_succeeded},
      {"tile_proofs_skipped", s.tile_proofs_skipped},
      {"umbra_tests", s.umbra_tests},
      {"umbra_hits", s.umbra_hits},
      {"tile_pairs_outside_hull", s.tile_pairs_outside_hull},
      {"light_samples", s.light_samples},
      {"pair_samples", s.pair_samples},
      {"scalar_tiles", s.scalar_tiles},
      {"sampled_pixels", s.sampled_pixels},
      {"sampled_visible_lights", s.sampled_visible_lights},
      {"sampled_blocking_pairs", s.sampled_blocking_pairs},
      {"bounce_pieces", f.bounce_pieces},
      {"bounce_lit_sources", f.bounce_lit_sources},
      {"bounce_tile_sources", s.bounce_tile_sources},
      {"bounce_tile_sources_hidden", s.bounce_tile_sources_hidden},
      {"bounce_source_walks", s.bounce_source_walks},
      {"bounce_depth_tests", s.bounce_depth_tests},
  };
  std::string out = "{";
  for (const auto& [name, value] : fields) {
    if (out.size() > 1) out += ", ";
    out += std::string("\"") + name + "\": " + std::to_string(value);
  }
  return out + "}";
}

// `part` / `whole`, 0 when `whole` is 0.
double ratio(std::uint64_t part, std::uint64_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

// The report as a few readable lines: where a frame's work goes, from blocks down to samples.
void print_stats(const FrameReport& report) {
  const par2d::FrameStats& f = report.stats;
  const par2d::FrameDiagnostics& s = report.diagnostics;
  std::printf("stats per frame: %llu pixels, %llu tiles (16x16), %llu blocks (64x64)\n",
              static_cast<unsigned long long>(f.pixels), static_cast<unsigned long long>(f.tiles),
              static_cast<unsigned long long>(s.blocks));
  std::printf(
      "  blocks x lights: %llu, %.1f %% out of reach; %.1f occluders per (block, light) from the index; "
      "proofs %llu tried, %llu hid the light (%.1f %%), %llu skipped by the adaptive rule\n",
      static_cast<unsigned long long>(s.block_lights), 100.0 * ratio(s.block_lights_out_of_reach, s.block_lights),
      ratio(s.block_candidates, s.block_lights - s.block_lights_out_of_reach),
      static_cast<unsigned long long>(s.block_proofs_tried), static_cast<unsigned long long>(s.block_proofs_succeeded),
      100.0 * ratio(s.block_proofs_succeeded, s.block_proofs_tried),
      static_cast<unsigned long long>(s.block_proofs_skipped));
  std::printf(
      "  per tile: %.2f lights, %.2f pairs (%.3f overlapping or touching); proofs %llu tried, %llu hid the light, "
      "%llu skipped by the adaptive rule; umbra tests %llu, %llu hit; %.2f pairs dropped outside the tile-light hull\n",
      ratio(s.tile_lights, f.tiles), ratio(s.tile_pairs, f.tiles), ratio(s.tile_general_pairs, f.tiles),
      static_cast<unsigned long long>(s.tile_proofs_tried), static_cast<unsigned long long>(s.tile_proofs_succeeded),
      static_cast<unsigned long long>(s.tile_proofs_skipped), static_cast<unsigned long long>(s.umbra_tests), static_cast<unsigned long long>(s.umbra_hits),
      ratio(s.tile_pairs_outside_hull, f.tiles));
  std::printf("  per sample (kernel): %.2f light arcs, %.2f pairs; %.2f samples per pixel (tile padding included)\n",
              ratio(s.light_samples, s.samples), ratio(s.pair_samples, s.samples), ratio(s.samples, f.pixels));
  std::printf("  per pixel (exact, at %llu sampled pixels): %.2f lights visible, %.2f occluders cutting into their arcs",
              static_cast<unsigned long long>(s.sampled_pixels), ratio(s.sampled_visible_lights, s.sampled_pixels),
              ratio(s.sampled_blocking_pairs, s.sampled_pixels));
  // The kernel's pairs per sample over the pairs a pixel needs: the work culling left over.
  if (s.sampled_blocking_pairs > 0 && s.samples > 0)
    std::printf("; the kernel takes %.1fx those pairs",
                ratio(s.pair_samples, s.samples) / ratio(s.sampled_blocking_pairs, s.sampled_pixels));
  std::printf("\n");
  std::printf("  tiles computed by the scalar reference: %llu\n", static_cast<unsigned long long>(s.scalar_tiles));
  if (f.bounce_pieces == 0) return;
  std::printf(
      "  one bounce: %llu pieces, %llu reflecting occluders lit; per tile %.2f lit reflectors, %.1f %% hidden by "
      "proofs; per pixel %.2f reflectors walked, %.2f occluders depth-tested (exact, no clustering)\n",
      static_cast<unsigned long long>(f.bounce_pieces), static_cast<unsigned long long>(f.bounce_lit_sources),
      ratio(s.bounce_tile_sources, f.tiles), 100.0 * ratio(s.bounce_tile_sources_hidden, s.bounce_tile_sources),
      ratio(s.bounce_source_walks, f.pixels), ratio(s.bounce_depth_tests, f.pixels));
}

// The choice's render as one frame of a Renderer that also measures what pixels need,
// reporting its counts (all zero for the ray caster, which counts nothing).
par2d::Status render_with_report(const par2d::Scene& scene, const RenderChoice& choice, const par2d::ImageView& image,
                                 FrameReport& report) {
  report = FrameReport{};
  if (choice.raycast) return choice.render(scene, image);
  par2d::RenderOptions measured = choice.options;
  measured.sample_needs = true;
  par2d::Renderer renderer;
  if (par2d::Status s = renderer.set_options(measured); !s) return s;
  if (par2d::Status s = renderer.set_scene(scene); !s) return s;
  if (par2d::Status s = renderer.render(image); !s) return s;
  report.stats = renderer.frame_stats();
  report.diagnostics = renderer.frame_diagnostics();
  return {};
}

int run_bench(const CommonArgs& common, const BenchArgs& args) {
  par2d::Scene scene;
  if (par2d::Status s = load_scene(common, scene); !s)
    return fail(s.message());
  // The view stays as loaded (explicit or [0, 0, W, H]), so a new size rescales the same world.
  if (args.width > 0) scene.width = args.width;
  if (args.height > 0) scene.height = args.height;
  // A normal map holds one normal per pixel of the scene's own size; say so naming the file
  // and the options, rather than letting the renderer refuse a nameless "scene".
  if (scene.normal_map && (scene.normal_map->width != scene.width || scene.normal_map->height != scene.height))
    return fail(common.scene_path + ": normal_map: " + scene.normal_map->path + " is " +
                    std::to_string(scene.normal_map->width) + "x" + std::to_string(scene.normal_map->height) +
                    " but --width/--height make the image " + std::to_string(scene.width) + "x" +
                    std::to_string(scene.height) + " (a normal-mapped scene keeps its size)",
                kExitUsage);
  // Anything else a new size breaks is reported under the scene file's name too.
  if (args.width > 0 || args.height > 0) {
    if (par2d::Status s = par2d::validate_scene(scene, common.scene_path); !s) return fail(s.message());
  }

  ImageStorage storage;
  par2d::ImageView image;
  std::string error;
  if (!allocate_image(scene.width, scene.height, storage, image, error)) return fail(error);

  const RenderChoice choice = make_choice(common);
  // One untimed frame first: it pays for thread-pool start-up and first-touch page faults.
  // With --stats its work counts are those of every frame (the scene does not change); only
  // then does it sample each tile's exact needs, which a timed frame never does.
  FrameReport report;
  const par2d::Status warm_up = args.stats ? render_with_report(scene, choice, image, report)
                                           : choice.render(scene, image);
  if (!warm_up) return render_failed(common, warm_up);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  for (int k = 0; k < args.frames; ++k) {
    if (par2d::Status s = choice.render(scene, image); !s) return fail(s.message());
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  const double ms_per_frame = 1e3 * seconds / args.frames;
  const double frames_per_s = seconds > 0.0 ? args.frames / seconds : INFINITY;
  const double mpixel_per_s =
      frames_per_s * static_cast<double>(scene.width) * static_cast<double>(scene.height) / 1e6;
  const char* backend = choice.backend_name();
  const char* isa = par2d::isa_name(choice.isa());
  const int threads = resolved_threads(choice.options.threads);

  if (args.json) {
    std::printf(
        "{\"ms_per_frame\": %.6g, \"frames_per_s\": %.6g, \"mpixel_per_s\": %.6g, "
        "\"backend\": \"%s\", \"isa\": \"%s\", \"threads\": %d, \"width\": %d, "
        "\"height\": %d, \"frames\": %d, \"spp\": %d, \"lights\": %zu, \"occluders\": %zu%s}\n",
        ms_per_frame, std::isfinite(frames_per_s) ? frames_per_s : 0.0,
        std::isfinite(mpixel_per_s) ? mpixel_per_s : 0.0, backend, isa, threads, scene.width,
        scene.height, args.frames, choice.options.spp, scene.lights.size(), scene.occluders.size(),
        args.stats ? (", \"stats\": " + stats_json(report)).c_str() : "");
  } else {
    std::printf("ms/frame=%.3f frames/s=%.2f Mpixel/s=%.2f backend=%s isa=%s threads=%d size=%dx%d\n",
                ms_per_frame, frames_per_s, mpixel_per_s, backend, isa, threads, scene.width,
                scene.height);
    if (args.stats) print_stats(report);
  }
  return 0;
}

void print_info() {
  std::printf("par2d %s\n", par2d::kVersion);
  std::printf("detected isa: %s\n", par2d::isa_name(par2d::detect_isa()));
  const char* env = std::getenv("PAR2D_ISA");
  std::printf("selected isa: %s%s%s%s\n", par2d::isa_name(par2d::default_isa()),
              env ? " (PAR2D_ISA=" : "", env ? env : "", env ? ")" : "");
  std::printf("hardware threads: %d\n", resolved_threads(0));
}

}  // namespace

namespace {

int run_cli(int argc, char** argv) {
  CLI::App app{"par2d: exact 2D soft shadows (Probabilistic Angular Radiance), no noise.", "par2d"};
  app.require_subcommand(0, 1);
  app.footer(
      "Backends (--backend): auto (default) picks the fastest path this CPU supports, the SIMD "
      "path where available; simd, scalar (double-precision reference), raycast (brute force).\n"
      "Run 'par2d render --help', 'par2d bench --help' or 'par2d outline --help' for their options.\n");
  bool show_version = false;
  app.add_flag("--version", show_version, "Print the version and the detected/selected ISA");

  CommonArgs render_common;
  RenderArgs render_args;
  CLI::App* render = app.add_subcommand("render", "Render a scene to an sRGB PNG and/or a linear PFM");
  add_common_options(*render, render_common);
  render->add_option("-o,--output", render_args.png_path, "Output PNG (8-bit sRGB); - for standard output");
  render->add_option("--pfm", render_args.pfm_path, "Output PFM (linear float32 RGB); - for standard output");
  render->add_option("--plain-png", render_args.plain_png_path,
                     "Also write the plain irradiance (no normal-map shading) as an 8-bit sRGB PNG; the same "
                     "image as -o when the scene has no normal or normal_map");
  render->add_option("--plain-pfm", render_args.plain_pfm_path,
                     "Also write the plain irradiance as a linear PFM (see --plain-png)");
  render->add_option("--exposure", render_args.exposure,
                     "PNG shows clamp(exposure * E, 0, 1), sRGB-encoded. Default: 1")
      ->check(kNonNegative);
  render->add_flag("--dither", render_args.dither,
                   "PNG outputs with an 8x8 ordered dither (floor(255 srgb + t), t from the Bayer matrix) instead "
                   "of rounding, so that dark gradients do not band; the codes of the library's dithered formats");
  render->add_option("--progress", render_args.progress,
                     "Progress bar on standard error: auto (default) on a terminal for renders past a second; "
                     "always; never")
      ->check(CLI::IsMember({"auto", "always", "never"}));

  CommonArgs bench_common;
  BenchArgs bench_args;
  CLI::App* bench = app.add_subcommand(
      "bench", "Render a scene repeatedly in memory (one warm-up frame) and report the speed");
  add_common_options(*bench, bench_common);
  bench->add_option("--frames", bench_args.frames, "Timed frames. Default: 10")
      ->check(CLI::Range(1, 1000000));
  bench->add_option("--width", bench_args.width, "Override the image width, keeping the view")
      ->check(CLI::Range(1, par2d::kMaxImageSide));
  bench->add_option("--height", bench_args.height, "Override the image height, keeping the view")
      ->check(CLI::Range(1, par2d::kMaxImageSide));
  bench->add_flag("--json", bench_args.json, "Print one JSON object instead of a line");
  bench->add_flag("--stats", bench_args.stats,
                  "Also print what a frame's culling and kernel did: lights and pairs per tile and per pixel, "
                  "proofs tried and succeeded, scalar fallbacks");

  CLI::App* info = app.add_subcommand("info", "Print the version, detected and selected ISA");
  par2d::cli::OutlineArgs outline_args;
  CLI::App* outline = par2d::cli::add_outline_command(app, outline_args);
#ifdef PAR2D_HAVE_VIEWER
  par2d::viewer::ViewArgs view_args;
  CLI::App* view = par2d::viewer::add_view_command(app, view_args);
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(std::string(e.what()) + " (run 'par2d --help' for usage)", kExitUsage);
  }

  try {
    if (show_version || info->parsed()) {
      print_info();
      return 0;
    }
    if (render->parsed()) return run_render(render_common, render_args);
    if (bench->parsed()) return run_bench(bench_common, bench_args);
    if (outline->parsed()) {
      const par2d::Status s = par2d::cli::run_outline(outline_args, g_stdout_was_closed);
      return s ? 0 : fail(s.message());
    }
#ifdef PAR2D_HAVE_VIEWER
    if (view->parsed()) {
      // An empty DISPLAY or WAYLAND_DISPLAY names no display: treated as unset, the viewer
      // says so in one line instead of letting SDL probe (and libwayland print its own line).
      for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"}) {
        const char* value = std::getenv(name);
        if (value != nullptr && *value == '\0') ::unsetenv(name);
      }
      return par2d::viewer::run_view(view_args);
    }
#endif
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    // The library reports through Status; this only guards against the unexpected.
    return fail(std::string("internal error: ") + e.what());
  }
  return fail("no command given: use render, bench, outline or info (run 'par2d --help' for usage)",
              kExitUsage);
}

}  // namespace

int main(int argc, char** argv) {
  if (!claim_standard_descriptors())
    return fail("standard input, output or error is closed and /dev/null cannot be opened in its place");
  // Setting up the options allocates too: out of memory there (a tight ulimit -v) is the same
  // one-line failure as anywhere else, not an abort.
  try {
    return run_cli(argc, argv);
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  }
}
