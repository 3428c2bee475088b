// Game-loop example: keep a par2d world alive, move a torch and a door every frame, and
// render into an RGBA8 texture buffer ready to upload (no conversion pass).
#include <cmath>
#include <cstdio>
#include <vector>

#include <par2d/par2d.hpp>

int main() {
  // The lightmap: 320 x 180 texels showing the world rectangle [0, 0, 640, 360]. The host
  // draws it stretched over its screen (a texel covers 2 x 2 world units).
  par2d::Renderer renderer;
  par2d::RenderOptions options;  // automatic backend, own thread pool with every hardware thread
  if (par2d::Status s = renderer.set_options(options); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
  if (par2d::Status s = renderer.set_frame(320, 180, par2d::View{0, 0, 640, 360}); !s)
    return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;

  // Walls once; keep the handles of what moves.
  par2d::OccluderHandle wall, door;
  renderer.add_occluder({par2d::Polygon{{{300, 0}, {320, 0}, {320, 150}, {300, 150}}}}, &wall);
  renderer.add_occluder({par2d::Polygon{{{300, 210}, {320, 210}, {320, 360}, {300, 360}}}}, &wall);
  par2d::Occluder door_shape{par2d::Polygon{{{300, 150}, {320, 150}, {320, 210}, {300, 210}}}};
  renderer.add_occluder(door_shape, &door);
  par2d::LightHandle torch;
  renderer.add_light({par2d::Circle{{150, 180}, 6}, {1.0, 0.7, 0.4}, 4.0}, &torch);

  std::vector<unsigned char> texture(320 * 180 * 4);  // RGBA8, tightly packed rows
  par2d::FrameBuffer buffer{texture.data(), par2d::PixelFormat::rgba8_srgb, 320 * 4, /*exposure=*/1.5};

  for (int frame = 0; frame < 60; ++frame) {
    const double t = frame / 60.0;
    // The torch circles and flickers: changing a light never touches the occluder index.
    par2d::Light light{par2d::Circle{{150 + 40 * std::cos(6.28 * t), 180 + 40 * std::sin(6.28 * t)}, 6},
                       {1.0, 0.7, 0.4}, 4.0 * (0.9 + 0.1 * std::sin(40 * t))};
    if (par2d::Status s = renderer.update_light(torch, light); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
    // The door slides up (an occluder update refits the index in place).
    auto& v = std::get<par2d::Polygon>(door_shape.shape).vertices;
    const double open = 60.0 * t;
    v = {{300, 150 - open}, {320, 150 - open}, {320, 210 - open}, {300, 210 - open}};
    if (par2d::Status s = renderer.update_occluder(door, door_shape); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
    if (par2d::Status s = renderer.render(buffer); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
    // ... upload `texture` (e.g. glTexSubImage2D(..., GL_RGBA, GL_UNSIGNED_BYTE, texture.data())).
  }

  // With the door open, light reaches the right room through the doorway.
  const unsigned char* right_room = &texture[(90 * 320 + 200) * 4];
  std::printf("frames: %llu, index builds: %llu, texel in the right room: %d %d %d\n",
              static_cast<unsigned long long>(renderer.stats().frames),
              static_cast<unsigned long long>(renderer.stats().index_builds), right_room[0], right_room[1],
              right_room[2]);
  return right_room[0] > 0 ? 0 : 1;
}
