// The overlap benchmark's level: rooms, pillars, crates and 8 torches against the walls.
#include "torch_level.hpp"

#include <array>

namespace par2d::bench {
namespace {

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

}  // namespace

Scene torch_level(double wall_offset) {
  Scene s;
  s.width = 1280;
  s.height = 720;
  s.view = View{0.0, 0.0, 1280.0, 720.0};
  constexpr double kT = 12.0;  // wall thickness
  // Outer walls.
  s.occluders.push_back(Occluder{box(0, 0, 1280, kT)});
  s.occluders.push_back(Occluder{box(0, 720 - kT, 1280, 720)});
  s.occluders.push_back(Occluder{box(0, kT, kT, 720 - kT)});
  s.occluders.push_back(Occluder{box(1280 - kT, kT, 1280, 720 - kT)});
  // Inner walls with doorways: two vertical, one horizontal in three pieces.
  s.occluders.push_back(Occluder{box(420, kT, 420 + kT, 300)});
  s.occluders.push_back(Occluder{box(420, 380, 420 + kT, 720 - kT)});
  s.occluders.push_back(Occluder{box(860, kT, 860 + kT, 200)});
  s.occluders.push_back(Occluder{box(860, 280, 860 + kT, 720 - kT)});
  s.occluders.push_back(Occluder{box(kT, 360, 300, 360 + kT)});
  s.occluders.push_back(Occluder{box(540, 360, 860, 360 + kT)});
  s.occluders.push_back(Occluder{box(960, 450, 1280 - kT, 450 + kT)});
  // Pillars and crates.
  for (const auto& c : std::array<std::array<double, 3>, 6>{
           {{200, 180, 14}, {640, 180, 16}, {640, 540, 16}, {1060, 150, 12}, {1100, 600, 14}, {220, 560, 12}}})
    s.occluders.push_back(Occluder{Circle{{c[0], c[1]}, c[2]}});
  for (const auto& b : std::array<std::array<double, 4>, 6>{{{300, 100, 330, 130},
                                                             {520, 260, 560, 290},
                                                             {740, 460, 770, 500},
                                                             {980, 320, 1020, 350},
                                                             {120, 440, 150, 470},
                                                             {1150, 250, 1180, 290}}})
    s.occluders.push_back(Occluder{box(b[0], b[1], b[2], b[3])});
  // Torches, radius 5, each against one wall face: (face coordinate, along, which side).
  constexpr double kR = 5.0;
  const double d = kR + wall_offset;  // center distance from the wall face
  const std::array<Vec2, 8> centers{{
      {200, kT + d},              // top outer wall, from below
      {640, 720 - kT - d},        // bottom outer wall, from above
      {kT + d, 200},              // left outer wall, from the right
      {1280 - kT - d, 560},       // right outer wall, from the left
      {420 - d, 120},             // first inner wall, from the left
      {860 + kT + d, 500},        // second inner wall, from the right
      {700, 360 + kT + d},        // horizontal wall, from below
      {1100, 450 - d},            // short wall, from above
  }};
  const std::array<Rgb, 4> colors{{{1.0, 0.75, 0.45}, {1.0, 0.6, 0.3}, {0.9, 0.8, 0.55}, {1.0, 0.7, 0.4}}};
  for (std::size_t i = 0; i < centers.size(); ++i) {
    Light l;
    l.shape = Circle{centers[i], kR};
    l.color = colors[i % colors.size()];
    l.intensity = 3.0;
    s.lights.push_back(l);
  }
  return s;
}

}  // namespace par2d::bench
