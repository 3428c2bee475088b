// SDL2 + OpenGL example: par2d lights a sprite layer on the GPU. Each frame the torches move
// or flicker, par2d renders the lightmap into the host's pixel buffer (incremental frames: only
// the blocks whose inputs changed), only the rectangles it changed are uploaded with
// glTexSubImage2D, and a fragment shader composites the light over the sprites:
//   multiply: sprite (sRGB bytes) x lightmap (PixelFormat::rgba8_srgb, exposure applied by par2d)
//   hdr:      linear sprite x exposure x E (PixelFormat::rgba_f32 as a float texture),
//             Reinhard tone curve x / (1 + x), sRGB-encoded by the shader
// With --scroll the camera pans across a level wider and taller than the screen at a speed of
// no whole number of pixels. The lightmap is one pixel larger than the screen and sits on the
// world's pixel grid (Renderer::set_view_offset at the camera's whole pixels): each frame
// computes only the bands the pan uncovers (and what the torches changed). Buffer and texture
// are a ring on that grid (BufferLayout::ring; GL_REPEAT: grid pixel g at g modulo the size),
// so no pixel ever moves: the rectangles par2d wrote are uploaded where they are, and the
// shader samples the ring bilinearly at the camera's sub-pixel remainder, which keeps the
// light as smooth as the sprites under it.
// Build (installed par2d): see CMakeLists.txt here. Run: par2d_lightmap_gl [--mode multiply|hdr]
// [--scroll] [--frames N] [--exposure E] [--screenshot OUT.ppm] [--sprites OUT.ppm]
// [--scene OUT.json] [--lightmap OUT.json]
// With --frames it stops after N frames; --screenshot, --sprites and --scene then save the
// last frame as shown, the sprite layer as shown and the world as a scene file (with --scroll,
// --lightmap saves the camera: the last frame's view offset and sub-pixel remainder; the
// scene's view is then the lightmap's). tests/examples checks that the screenshot equals
// `par2d render` of that scene composited the same way.
#define GL_GLEXT_PROTOTYPES 1
#include <SDL.h>
#include <SDL_opengl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <par2d/par2d.hpp>
#include <par2d/scene_write.hpp>

namespace {

constexpr int kWidth = 640, kHeight = 360;

// The level with --scroll: the camera pans over it (world units are pixels).
constexpr int kLevelWidth = 1600, kLevelHeight = 900;
// The sprite tiles repeat every kSpriteWidth x kSpriteHeight world pixels (whole 32-px tiles).
constexpr int kSpriteWidth = 640, kSpriteHeight = 384;

// `world` is the screen pixel's world position (its corner); the sprite texture repeats over
// the world, the light texture is the lightmap's ring (see the top of this file; without
// --scroll its size is the screen's and the camera stays at 0).
const char* kVertexShader = R"(#version 120
attribute vec2 corner;
uniform vec2 camera;  // the screen's top-left corner in world pixels
uniform vec2 screen;
varying vec2 world;
void main() {
  // Screen row 0 (the top) is world row camera.y, drawn at the top of the window.
  world = camera + screen * vec2(0.5 * (corner.x + 1.0), 0.5 * (1.0 - corner.y));
  gl_Position = vec4(corner, 0.0, 1.0);
})";

const char* kFragmentShader = R"(#version 120
uniform sampler2D sprites;
uniform sampler2D light;
uniform vec2 sprite_size;
uniform vec2 ring_size;  // the light texture's size: texel = grid pixel modulo it
uniform int hdr;
uniform float exposure;
varying vec2 world;
float to_linear(float c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }
float to_srgb(float c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055; }
void main() {
  vec3 s = texture2D(sprites, world / sprite_size).rgb;
  // Grid pixel g's center is at world g + 0.5, texel g's at (g + 0.5) / ring_size: the same
  // world / ring_size, sampled bilinearly between the four nearest grid pixels.
  vec3 e = texture2D(light, world / ring_size).rgb;
  if (hdr == 0) {
    gl_FragColor = vec4(s * e, 1.0);
  } else {
    vec3 x = vec3(to_linear(s.r), to_linear(s.g), to_linear(s.b)) * e * exposure;
    x = x / (1.0 + x);
    gl_FragColor = vec4(to_srgb(x.r), to_srgb(x.g), to_srgb(x.b), 1.0);
  }
})";

int fail(const std::string& message) {
  std::fprintf(stderr, "par2d_lightmap_gl: %s\n", message.c_str());
  return 1;
}

GLuint compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    std::fprintf(stderr, "par2d_lightmap_gl: shader: %s\n", log);
    std::exit(1);
  }
  return shader;
}

// Binary PPM (P6), top row first: readable by every image tool, no library needed.
bool write_ppm(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  std::fprintf(f, "P6\n%d %d\n255\n", width, height);
  const bool ok = std::fwrite(rgb.data(), 1, rgb.size(), f) == rgb.size();
  return std::fclose(f) == 0 && ok;
}

// The sprite layer: stone floor tiles with mortar lines and a tint per tile (sRGB bytes).
std::vector<unsigned char> make_sprites() {
  std::vector<unsigned char> rgba(static_cast<std::size_t>(kSpriteWidth) * kSpriteHeight * 4);
  for (int y = 0; y < kSpriteHeight; ++y) {
    for (int x = 0; x < kSpriteWidth; ++x) {
      const int tx = x / 32, ty = y / 32;
      const bool mortar = x % 32 == 0 || y % 32 == 0;
      const int tint = (tx * 37 + ty * 91) % 40;
      unsigned char* p = &rgba[(static_cast<std::size_t>(y) * kSpriteWidth + x) * 4];
      p[0] = static_cast<unsigned char>(mortar ? 90 : 170 + tint);
      p[1] = static_cast<unsigned char>(mortar ? 85 : 160 + tint / 2);
      p[2] = static_cast<unsigned char>(mortar ? 80 : 140);
      p[3] = 255;
    }
  }
  return rgba;
}

}  // namespace

int main(int argc, char** argv) {
  bool hdr = false, scroll = false;
  int frames = -1;  // -1: until the window is closed
  double exposure = 1.0;
  std::string screenshot, sprites_out, scene_out, lightmap_out;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--mode" && has_value) {
      const std::string mode = argv[++i];
      if (mode != "multiply" && mode != "hdr") return fail("--mode must be multiply or hdr");
      hdr = mode == "hdr";
    } else if (arg == "--scroll") {
      scroll = true;
    } else if (arg == "--lightmap" && has_value) {
      lightmap_out = argv[++i];
    } else if (arg == "--frames" && has_value) {
      frames = std::atoi(argv[++i]);
    } else if (arg == "--exposure" && has_value) {
      exposure = std::atof(argv[++i]);
    } else if (arg == "--screenshot" && has_value) {
      screenshot = argv[++i];
    } else if (arg == "--sprites" && has_value) {
      sprites_out = argv[++i];
    } else if (arg == "--scene" && has_value) {
      scene_out = argv[++i];
    } else {
      return fail("unknown argument " + arg + " (see the comment at the top of lightmap_gl.cpp)");
    }
  }

  // --- The lighting world: walls, a pillar, two moving torches and a flickering brazier.
  // Incremental frames: each frame computes only the blocks whose inputs changed and reports
  // them as rectangles, which are all the GPU needs re-uploaded.
  // The lightmap: the screen, or with --scroll one pixel more each way (the bilinear sample at
  // the camera's sub-pixel remainder reads the next pixel), on the world's pixel grid.
  const int light_width = kWidth + (scroll ? 1 : 0), light_height = kHeight + (scroll ? 1 : 0);
  const int level_width = scroll ? kLevelWidth : kWidth, level_height = scroll ? kLevelHeight : kHeight;
  par2d::Renderer renderer;
  if (par2d::Status s = renderer.set_frame(light_width, light_height); !s) return fail(s.message());
  if (par2d::Status s = renderer.set_incremental(true); !s) return fail(s.message());
  if (par2d::Status s = renderer.set_buffer_layout(scroll ? par2d::BufferLayout::ring : par2d::BufferLayout::image); !s)
    return fail(s.message());
  auto wall = [&](double x0, double y0, double x1, double y1) {
    par2d::OccluderHandle h;
    return renderer.add_occluder({par2d::Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}}, &h);
  };
  const double lw = level_width, lh = level_height;
  for (const par2d::Status& s : {wall(0, 0, lw, 16), wall(0, lh - 16, lw, lh), wall(0, 0, 16, lh), wall(lw - 16, 0, lw, lh),
                                 wall(300, 16, 332, 140), wall(300, 220, 332, 344)})
    if (!s) return fail(s.message());
  if (scroll) {  // more rooms to pan over
    for (const par2d::Status& s : {wall(16, 344, 240, 376), wall(400, 344, 900, 376), wall(900, 200, 932, 700),
                                   wall(1100, 16, 1132, 500), wall(1100, 600, 1132, 884), wall(600, 560, 632, 884)})
      if (!s) return fail(s.message());
  }
  par2d::OccluderHandle pillar;
  if (par2d::Status s = renderer.add_occluder({par2d::Circle{{470, 180}, 18}}, &pillar); !s) return fail(s.message());
  par2d::LightHandle torch_a, torch_b, brazier;
  const par2d::Rgb warm{1.0, 0.75, 0.45}, cool{0.55, 0.7, 1.0}, fire{1.0, 0.55, 0.25};
  // Game torches have a range: light fades to nothing at `range` units from the shape, so a
  // torch that moves changes only the blocks within its range (old and new place).
  auto torch = [](double x, double y, double radius, const par2d::Rgb& color, double intensity, double range) {
    par2d::Light light;
    light.shape = par2d::Circle{{x, y}, radius};
    light.color = color;
    light.intensity = intensity;
    light.range = range;
    return light;
  };
  if (par2d::Status s = renderer.add_light(torch(150, 120, 5, warm, 4.0, 130), &torch_a); !s) return fail(s.message());
  if (par2d::Status s = renderer.add_light(torch(520, 260, 4, cool, 3.5, 150), &torch_b); !s) return fail(s.message());
  if (par2d::Status s = renderer.add_light(torch(160, 300, 8, fire, 2.5, 90), &brazier); !s) return fail(s.message());
  if (scroll) {
    par2d::LightHandle h;
    for (const par2d::Light& l : {torch(1000, 120, 5, cool, 4.0, 220), torch(780, 640, 6, warm, 4.0, 200),
                                  torch(1350, 700, 5, fire, 3.0, 260), torch(300, 600, 5, warm, 3.5, 200)})
      if (par2d::Status s = renderer.add_light(l, &h); !s) return fail(s.message());
  }

  // The host's light buffer, tightly packed rows, in the format the shader reads.
  const par2d::PixelFormat format = hdr ? par2d::PixelFormat::rgba_f32 : par2d::PixelFormat::rgba8_srgb;
  const int pixel = par2d::bytes_per_pixel(format);
  std::vector<unsigned char> light(static_cast<std::size_t>(light_width) * light_height * pixel);
  const par2d::FrameBuffer buffer{light.data(), format, static_cast<std::ptrdiff_t>(light_width) * pixel, hdr ? 1.0 : exposure};

  // --- The window and the GL objects.
  if (SDL_Init(SDL_INIT_VIDEO) != 0) return fail(std::string("SDL_Init: ") + SDL_GetError());
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 2);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 1);
  SDL_Window* window = SDL_CreateWindow("par2d lightmap over sprites", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                        kWidth, kHeight, SDL_WINDOW_OPENGL);
  if (!window) return fail(std::string("SDL_CreateWindow: ") + SDL_GetError());
  SDL_GLContext context = SDL_GL_CreateContext(window);
  if (!context) return fail(std::string("SDL_GL_CreateContext: ") + SDL_GetError());

  const GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER, kVertexShader));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER, kFragmentShader));
  glBindAttribLocation(program, 0, "corner");
  glLinkProgram(program);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "sprites"), 0);
  glUniform1i(glGetUniformLocation(program, "light"), 1);
  glUniform1i(glGetUniformLocation(program, "hdr"), hdr ? 1 : 0);
  glUniform1f(glGetUniformLocation(program, "exposure"), static_cast<float>(exposure));
  glUniform2f(glGetUniformLocation(program, "screen"), kWidth, kHeight);
  glUniform2f(glGetUniformLocation(program, "sprite_size"), kSpriteWidth, kSpriteHeight);
  glUniform2f(glGetUniformLocation(program, "ring_size"), static_cast<float>(light_width), static_cast<float>(light_height));
  const GLint camera_uniform = glGetUniformLocation(program, "camera");

  // Both textures repeat: the sprites over the world, the light as the ring on its grid.
  // Without --scroll one texel is one screen pixel (nearest); with it, the light is sampled
  // bilinearly at the camera's sub-pixel remainder.
  auto make_texture = [](GLenum unit, GLint internal, GLenum type, int width, int height, GLint filter, const void* data) {
    GLuint texture = 0;
    glActiveTexture(unit);
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, width, height, 0, GL_RGBA, type, data);
    return texture;
  };
  const std::vector<unsigned char> sprites = make_sprites();
  make_texture(GL_TEXTURE0, GL_RGBA8, GL_UNSIGNED_BYTE, kSpriteWidth, kSpriteHeight, GL_NEAREST, sprites.data());
  make_texture(GL_TEXTURE1, hdr ? GL_RGBA32F : GL_RGBA8, hdr ? GL_FLOAT : GL_UNSIGNED_BYTE, light_width, light_height,
               scroll ? GL_LINEAR : GL_NEAREST, nullptr);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, light_width);  // rectangles are read out of the whole buffer

  const GLfloat corners[] = {-1, -1, 1, -1, -1, 1, 1, 1};
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, corners);

  // --- The loop.
  bool running = true;
  long long uploaded = 0;  // texels sent to the GPU
  // The camera's top-left corner in world pixels: a back-and-forth diagonal pan at 1.3 and 0.7
  // pixels a frame (no whole number), within the level.
  auto pan = [](double distance, double span) { return span - std::abs(span - std::fmod(distance, 2.0 * span)); };
  double camera_x = 0.0, camera_y = 0.0;
  std::int64_t offset_x = 0, offset_y = 0;
  for (int frame = 0; running && (frames < 0 || frame < frames); ++frame) {
    SDL_Event event;
    while (SDL_PollEvent(&event))
      if (event.type == SDL_QUIT) running = false;
    const double t = frame / 60.0;
    // Torch A walks a circle, torch B stays put, the brazier only flickers (emission alone).
    par2d::Status s = renderer.update_light(torch_a, torch(150 + 60 * std::cos(t), 150 + 60 * std::sin(t), 5, warm, 4.0, 130));
    if (s) s = renderer.set_light_emission(brazier, fire, 2.5 * (0.85 + 0.15 * std::sin(13.0 * t)));
    if (scroll) {
      // The lightmap follows the camera's whole pixels; the shader takes the remainder.
      camera_x = 20.0 + pan(1.3 * frame, kLevelWidth - kWidth - 40.0);
      camera_y = 10.0 + pan(0.7 * frame, kLevelHeight - kHeight - 20.0);
      offset_x = static_cast<std::int64_t>(std::floor(camera_x));
      offset_y = static_cast<std::int64_t>(std::floor(camera_y));
      if (s) s = renderer.set_view_offset(offset_x, offset_y);
    }
    if (s) s = renderer.render(buffer);
    if (!s) return fail(s.message());

    // Upload only what changed (the first frame: all of it; a frame where nothing moved:
    // nothing). With --scroll the buffer is the ring the texture is: the rectangles are in its
    // coordinates, and the pixels a pan kept are already where the texture has them.
    glActiveTexture(GL_TEXTURE1);
    for (const par2d::PixelRect& r : renderer.dirty_rects()) {
      uploaded += static_cast<long long>(r.x1 - r.x0) * (r.y1 - r.y0);
      glPixelStorei(GL_UNPACK_SKIP_PIXELS, r.x0);
      glPixelStorei(GL_UNPACK_SKIP_ROWS, r.y0);
      glTexSubImage2D(GL_TEXTURE_2D, 0, r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_RGBA,
                      hdr ? GL_FLOAT : GL_UNSIGNED_BYTE, light.data());
    }
    glUniform2f(camera_uniform, static_cast<float>(camera_x), static_cast<float>(camera_y));
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    if (frames >= 0 && frame == frames - 1 && !screenshot.empty()) {
      std::vector<unsigned char> shown(static_cast<std::size_t>(kWidth) * kHeight * 3), row(kWidth * 3);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, kWidth, kHeight, GL_RGB, GL_UNSIGNED_BYTE, shown.data());
      for (int y = 0; y < kHeight / 2; ++y) {  // GL's row 0 is the bottom one
        unsigned char* a = &shown[static_cast<std::size_t>(y) * kWidth * 3];
        unsigned char* b = &shown[static_cast<std::size_t>(kHeight - 1 - y) * kWidth * 3];
        std::memcpy(row.data(), a, row.size());
        std::memcpy(a, b, row.size());
        std::memcpy(b, row.data(), row.size());
      }
      if (!write_ppm(screenshot, kWidth, kHeight, shown)) return fail("cannot write " + screenshot);
    }
    SDL_GL_SwapWindow(window);
  }
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) return fail("GL error " + std::to_string(error));
  if (frames > 0)
    std::printf("par2d_lightmap_gl: %d frames, %.1f %% of their texels uploaded\n", frames,
                100.0 * static_cast<double>(uploaded) / (static_cast<double>(frames) * light_width * light_height));

  if (!sprites_out.empty()) {  // as the last frame showed them: texel floor(world) of each pixel's center
    std::vector<unsigned char> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        const auto tx = static_cast<std::int64_t>(std::floor(camera_x + x + 0.5)) % kSpriteWidth;
        const auto ty = static_cast<std::int64_t>(std::floor(camera_y + y + 0.5)) % kSpriteHeight;
        std::memcpy(&rgb[(static_cast<std::size_t>(y) * kWidth + x) * 3],
                    &sprites[(static_cast<std::size_t>(ty) * kSpriteWidth + static_cast<std::size_t>(tx)) * 4], 3);
      }
    }
    if (!write_ppm(sprites_out, kWidth, kHeight, rgb)) return fail("cannot write " + sprites_out);
  }
  if (!lightmap_out.empty()) {  // the camera: the lightmap's grid offset and the shader's remainder
    FILE* f = std::fopen(lightmap_out.c_str(), "w");
    if (!f) return fail("cannot write " + lightmap_out);
    std::fprintf(f, "{\"offset\": [%lld, %lld], \"remainder\": [%.17g, %.17g]}\n", static_cast<long long>(offset_x),
                 static_cast<long long>(offset_y), camera_x - static_cast<double>(offset_x), camera_y - static_cast<double>(offset_y));
    if (std::fclose(f) != 0) return fail("cannot write " + lightmap_out);
  }
  if (!scene_out.empty())
    if (par2d::Status s = par2d::save_scene_file(scene_out, renderer.snapshot()); !s) return fail(s.message());
  SDL_GL_DeleteContext(context);
  SDL_DestroyWindow(window);
  SDL_Quit();
  return 0;
}
