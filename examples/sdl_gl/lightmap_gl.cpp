// SDL2 + OpenGL example: par2d lights a sprite layer on the GPU. Each frame the torches move
// or flicker, par2d renders the lightmap into the host's pixel buffer (incremental frames: only
// the blocks whose inputs changed), only the rectangles it changed are uploaded with
// glTexSubImage2D, and a fragment shader composites the light over the sprites:
//   multiply: sprite (sRGB bytes) x lightmap (PixelFormat::rgba8_srgb, exposure applied by par2d)
//   hdr:      linear sprite x exposure x E (PixelFormat::rgba_f32 as a float texture),
//             Reinhard tone curve x / (1 + x), sRGB-encoded by the shader
// Build (installed par2d): see CMakeLists.txt here. Run: par2d_lightmap_gl [--mode multiply|hdr]
// [--frames N] [--exposure E] [--screenshot OUT.ppm] [--sprites OUT.ppm] [--scene OUT.json]
// With --frames it stops after N frames; --screenshot, --sprites and --scene then save the
// last frame as shown, the sprite layer and the world as a scene file (tests/examples checks
// that the screenshot equals `par2d render` of that scene composited the same way).
#define GL_GLEXT_PROTOTYPES 1
#include <SDL.h>
#include <SDL_opengl.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <par2d/par2d.hpp>
#include <par2d/scene_write.hpp>

namespace {

constexpr int kWidth = 640, kHeight = 360;

const char* kVertexShader = R"(#version 120
attribute vec2 corner;
varying vec2 uv;
void main() {
  // Texture row 0 is the lightmap's top row (par2d's row 0), drawn at the top of the screen.
  uv = vec2(0.5 * (corner.x + 1.0), 0.5 * (1.0 - corner.y));
  gl_Position = vec4(corner, 0.0, 1.0);
})";

const char* kFragmentShader = R"(#version 120
uniform sampler2D sprites;
uniform sampler2D light;
uniform int hdr;
uniform float exposure;
varying vec2 uv;
float to_linear(float c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }
float to_srgb(float c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055; }
void main() {
  vec3 s = texture2D(sprites, uv).rgb;
  vec3 e = texture2D(light, uv).rgb;
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
  std::vector<unsigned char> rgba(static_cast<std::size_t>(kWidth) * kHeight * 4);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const int tx = x / 32, ty = y / 32;
      const bool mortar = x % 32 == 0 || y % 32 == 0;
      const int tint = (tx * 37 + ty * 91) % 40;
      unsigned char* p = &rgba[(static_cast<std::size_t>(y) * kWidth + x) * 4];
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
  bool hdr = false;
  int frames = -1;  // -1: until the window is closed
  double exposure = 1.0;
  std::string screenshot, sprites_out, scene_out;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--mode" && has_value) {
      const std::string mode = argv[++i];
      if (mode != "multiply" && mode != "hdr") return fail("--mode must be multiply or hdr");
      hdr = mode == "hdr";
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
  par2d::Renderer renderer;
  if (par2d::Status s = renderer.set_frame(kWidth, kHeight); !s) return fail(s.message());
  if (par2d::Status s = renderer.set_incremental(true); !s) return fail(s.message());
  auto wall = [&](double x0, double y0, double x1, double y1) {
    par2d::OccluderHandle h;
    return renderer.add_occluder({par2d::Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}}, &h);
  };
  for (const par2d::Status& s : {wall(0, 0, 640, 16), wall(0, 344, 640, 360), wall(0, 0, 16, 360), wall(624, 0, 640, 360),
                                 wall(300, 16, 332, 140), wall(300, 220, 332, 344)})
    if (!s) return fail(s.message());
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

  // The host's light buffer, tightly packed rows, in the format the shader reads.
  const par2d::PixelFormat format = hdr ? par2d::PixelFormat::rgba_f32 : par2d::PixelFormat::rgba8_srgb;
  const int pixel = par2d::bytes_per_pixel(format);
  std::vector<unsigned char> light(static_cast<std::size_t>(kWidth) * kHeight * pixel);
  const par2d::FrameBuffer buffer{light.data(), format, static_cast<std::ptrdiff_t>(kWidth) * pixel, hdr ? 1.0 : exposure};

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

  auto make_texture = [](GLenum unit, GLint internal, GLenum type, const void* data) {
    GLuint texture = 0;
    glActiveTexture(unit);
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // one texel per pixel
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, kWidth, kHeight, 0, GL_RGBA, type, data);
    return texture;
  };
  const std::vector<unsigned char> sprites = make_sprites();
  make_texture(GL_TEXTURE0, GL_RGBA8, GL_UNSIGNED_BYTE, sprites.data());
  make_texture(GL_TEXTURE1, hdr ? GL_RGBA32F : GL_RGBA8, hdr ? GL_FLOAT : GL_UNSIGNED_BYTE, nullptr);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, kWidth);  // rectangles are read out of the whole buffer

  const GLfloat corners[] = {-1, -1, 1, -1, -1, 1, 1, 1};
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, corners);

  // --- The loop.
  bool running = true;
  long long uploaded = 0;  // texels sent to the GPU
  for (int frame = 0; running && (frames < 0 || frame < frames); ++frame) {
    SDL_Event event;
    while (SDL_PollEvent(&event))
      if (event.type == SDL_QUIT) running = false;
    const double t = frame / 60.0;
    // Torch A walks a circle, torch B stays put, the brazier only flickers (emission alone).
    par2d::Status s = renderer.update_light(torch_a, torch(150 + 60 * std::cos(t), 150 + 60 * std::sin(t), 5, warm, 4.0, 130));
    if (s) s = renderer.set_light_emission(brazier, fire, 2.5 * (0.85 + 0.15 * std::sin(13.0 * t)));
    if (s) s = renderer.render(buffer);
    if (!s) return fail(s.message());

    // Upload only what changed (the first frame: all of it; a frame where nothing moved: nothing).
    glActiveTexture(GL_TEXTURE1);
    for (const par2d::PixelRect& r : renderer.dirty_rects()) {
      uploaded += static_cast<long long>(r.x1 - r.x0) * (r.y1 - r.y0);
      glPixelStorei(GL_UNPACK_SKIP_PIXELS, r.x0);
      glPixelStorei(GL_UNPACK_SKIP_ROWS, r.y0);
      glTexSubImage2D(GL_TEXTURE_2D, 0, r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0, GL_RGBA,
                      hdr ? GL_FLOAT : GL_UNSIGNED_BYTE, light.data());
    }
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
                100.0 * static_cast<double>(uploaded) / (static_cast<double>(frames) * kWidth * kHeight));

  if (!sprites_out.empty()) {
    std::vector<unsigned char> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3);
    for (std::size_t i = 0; i < rgb.size() / 3; ++i) std::memcpy(&rgb[3 * i], &sprites[4 * i], 3);
    if (!write_ppm(sprites_out, kWidth, kHeight, rgb)) return fail("cannot write " + sprites_out);
  }
  if (!scene_out.empty())
    if (par2d::Status s = par2d::save_scene_file(scene_out, renderer.snapshot()); !s) return fail(s.message());
  SDL_GL_DeleteContext(context);
  SDL_DestroyWindow(window);
  SDL_Quit();
  return 0;
}
