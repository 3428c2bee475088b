// The torch hall: 8 x 4 rooms of 160 x 180 units with doorways, two torches per room, crates.
#include "torch_hall.hpp"

#include <cmath>
#include <cstdint>

namespace par2d::bench {
namespace {

constexpr double kWidth = 1280.0, kHeight = 720.0;
constexpr int kRoomColumns = 8, kRoomRows = 4;
constexpr double kRoomW = kWidth / kRoomColumns, kRoomH = kHeight / kRoomRows;
constexpr double kWall = 6.0, kGap = 36.0;
constexpr int kCrates = 191;  // 300 occluders in all

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// The spot torch t circles: two per room, at a third and two thirds of its diagonal.
void torch_spot(int torch, double& x, double& y) {
  const int room = torch / 2;
  const double fx = torch % 2 == 0 ? 0.3 : 0.7, fy = torch % 2 == 0 ? 0.35 : 0.65;
  x = (room % kRoomColumns + fx) * kRoomW;
  y = (room / kRoomColumns + fy) * kRoomH;
}

}  // namespace

std::size_t hall_door_index() { return 0; }

Occluder hall_door(int frame) {
  // In the doorway of the wall between rooms 2 and 3 (x = 480), sliding up and down its gap.
  const double y = 0.5 * kRoomH - 0.5 * kGap + 18.0 * std::sin(0.3 * frame);
  const double x = 3 * kRoomW - 0.5 * kWall;
  return Occluder{box(x, y, x + kWall, y + kGap)};
}

Scene torch_hall(int width, int height) {
  Scene scene;
  scene.width = width;
  scene.height = height;
  scene.view = {0.0, 0.0, kWidth, kHeight};
  scene.occluders.push_back(hall_door(0));
  // Border.
  scene.occluders.push_back({box(0, 0, kWidth, kWall)});
  scene.occluders.push_back({box(0, kHeight - kWall, kWidth, kHeight)});
  scene.occluders.push_back({box(0, kWall, kWall, kHeight - kWall)});
  scene.occluders.push_back({box(kWidth - kWall, kWall, kWidth, kHeight - kWall)});
  // Inner walls, each with a doorway in its middle: two pieces per wall.
  for (int c = 1; c < kRoomColumns; ++c) {
    const double x = c * kRoomW - 0.5 * kWall;
    for (int r = 0; r < kRoomRows; ++r) {
      const double y0 = r * kRoomH, y1 = (r + 1) * kRoomH, mid = 0.5 * (y0 + y1);
      scene.occluders.push_back({box(x, y0 + (r == 0 ? kWall : 0.0), x + kWall, mid - 0.5 * kGap)});
      scene.occluders.push_back({box(x, mid + 0.5 * kGap, x + kWall, y1 - (r == kRoomRows - 1 ? kWall : 0.0))});
    }
  }
  for (int r = 1; r < kRoomRows; ++r) {
    const double y = r * kRoomH - 0.5 * kWall;
    for (int c = 0; c < kRoomColumns; ++c) {
      const double x0 = c * kRoomW + 0.5 * kWall, x1 = (c + 1) * kRoomW - 0.5 * kWall, mid = 0.5 * (x0 + x1);
      scene.occluders.push_back({box(x0 + (c == 0 ? 0.5 * kWall : 0.0), y, mid - 0.5 * kGap, y + kWall)});
      scene.occluders.push_back({box(mid + 0.5 * kGap, y, x1 - (c == kRoomColumns - 1 ? 0.5 * kWall : 0.0), y + kWall)});
    }
  }
  // Crates and pillars at deterministic places, clear of the torches' circles and doorways.
  std::uint32_t state = 12345u;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / 16777216.0;
  };
  int placed = 0;
  while (placed < kCrates) {
    const int room = placed % (kRoomColumns * kRoomRows);
    const double x = (room % kRoomColumns + 0.12 + 0.76 * next()) * kRoomW;
    const double y = (room / kRoomColumns + 0.12 + 0.76 * next()) * kRoomH;
    bool clear = true;
    for (int t = 2 * room; t < 2 * room + 2; ++t) {
      double tx = 0.0, ty = 0.0;
      torch_spot(t, tx, ty);
      clear = clear && std::hypot(x - tx, y - ty) > 26.0;
    }
    if (!clear) continue;
    const double s = 3.0 + 4.0 * next();
    if (placed % 3 == 0) {
      scene.occluders.push_back({Circle{{x, y}, s}});
    } else {
      scene.occluders.push_back({box(x - s, y - s, x + s, y + 0.6 * s)});
    }
    ++placed;
  }
  for (int t = 0; t < kHallTorches; ++t) scene.lights.push_back(hall_torch(t, 0));
  return scene;
}

Light hall_torch(int torch, int frame, bool flicker) {
  double x = 0.0, y = 0.0;
  torch_spot(torch, x, y);
  const double phase = 0.09 * frame + 0.7 * torch;
  Light light;
  light.shape = Circle{{x + 10.0 * std::cos(phase), y + 10.0 * std::sin(phase)}, 3.0};
  light.color = {1.0, 0.6 + 0.1 * (torch % 4), 0.35 + 0.05 * (torch % 3)};
  const int f = flicker ? frame : 0;
  light.intensity = 3.0 * (0.85 + 0.1 * std::sin(1.7 * f + torch) + 0.05 * std::sin(4.1 * f + 2.0 * torch));
  light.range = 64.0;
  return light;
}

}  // namespace par2d::bench
