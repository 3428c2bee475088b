// Runs the game loop of bench_game_loop.cpp for a fixed number of frames, for profiling with
// callgrind (instruction counts do not depend on machine load):
//   valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*timed_frames*'
//       par2d_game_loop_frames persistent|persistent_rgba8|one_shot FRAMES WIDTH HEIGHT
// persistent_rgba8 stores the 8-bit sRGB texture a game uploads (exposure 1.5), the others
// float RGB.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "game_level.hpp"
#include "par2d/par2d.hpp"

namespace {

// Frames [1, frames] after an untimed first frame (kept out of line so callgrind can
// collect exactly its calls).
__attribute__((noinline)) bool timed_frames_persistent(par2d::Renderer& r, const std::vector<par2d::LightHandle>& torches,
                                                       const par2d::FrameBuffer& buffer, int frames) {
  for (int f = 1; f <= frames; ++f) {
    for (int t = 0; t < par2d::bench::kTorches; ++t)
      if (!r.update_light(torches[static_cast<std::size_t>(t)], par2d::bench::torch_at(t, f)).ok()) return false;
    if (!r.render(buffer).ok()) return false;
  }
  return true;
}

__attribute__((noinline)) bool timed_frames_one_shot(par2d::Scene& scene, const par2d::ImageView& image, int frames) {
  par2d::RenderOptions options;
  options.threads = 1;
  for (int f = 1; f <= frames; ++f) {
    for (int t = 0; t < par2d::bench::kTorches; ++t) scene.lights[static_cast<std::size_t>(t)] = par2d::bench::torch_at(t, f);
    if (!par2d::render(scene, options, image).ok()) return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s persistent|persistent_rgba8|one_shot FRAMES WIDTH HEIGHT\n", argv[0]);
    return 2;
  }
  const int frames = std::atoi(argv[2]), width = std::atoi(argv[3]), height = std::atoi(argv[4]);
  par2d::Scene scene = par2d::bench::game_level(width, height);
  std::vector<float> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  const par2d::ImageView image{pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * 3};
  bool ok = false;
  const bool rgba8 = std::strcmp(argv[1], "persistent_rgba8") == 0;
  if (rgba8 || std::strcmp(argv[1], "persistent") == 0) {
    par2d::Renderer r;
    par2d::RenderOptions options;
    options.threads = 1;
    std::vector<par2d::LightHandle> torches;
    ok = r.set_options(options).ok() && r.set_scene(scene, &torches).ok() && r.render(image).ok();
    // The float image's storage holds the 4-byte pixels too.
    const par2d::FrameBuffer buffer =
        rgba8 ? par2d::FrameBuffer{pixels.data(), par2d::PixelFormat::rgba8_srgb, static_cast<std::ptrdiff_t>(width) * 4, 1.5}
              : par2d::FrameBuffer{pixels.data(), par2d::PixelFormat::rgb_f32, static_cast<std::ptrdiff_t>(width) * 12, 1.0};
    ok = ok && timed_frames_persistent(r, torches, buffer, frames);
  } else {
    par2d::RenderOptions options;
    options.threads = 1;
    ok = par2d::render(scene, options, image).ok() && timed_frames_one_shot(scene, image, frames);
  }
  std::printf("%s: %d frames %s\n", argv[1], frames, ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
