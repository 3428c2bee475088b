// The game-loop level: walls and pillars on a 32-unit grid, eight rooms, one torch per room.
#include "game_level.hpp"

#include <cmath>

namespace par2d::bench {
namespace {

constexpr int kColumns = 40, kRows = 22;
constexpr double kCell = 32.0;

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

bool wall_cell(int cx, int cy) {
  if (cx == 0 || cy == 0 || cx == kColumns - 1 || cy == kRows - 1) return true;
  // Room walls every 10 columns and at row 11, each with door gaps.
  if (cx % 10 == 0) return !(cy == 5 || cy == 6 || cy == 16 || cy == 17);
  if (cy == 11) return !(cx % 10 == 4 || cx % 10 == 5);
  return false;
}

// The open cell each room's torch circles: room r = (column block r % 4, row block r / 4).
void torch_cell(int torch, int& cx, int& cy) {
  cx = (torch % 4) * 10 + 5;
  cy = (torch / 4) * 11 + 6;
}

}  // namespace

Scene game_level(int width, int height) {
  Scene scene;
  scene.width = width;
  scene.height = height;
  scene.view = {0.0, 0.0, kLevelWidth, kLevelHeight};
  for (int cy = 0; cy < kRows; ++cy) {
    for (int cx = 0; cx < kColumns; ++cx) {
      if (wall_cell(cx, cy)) {
        scene.occluders.push_back({box(cx * kCell, cy * kCell, (cx + 1) * kCell, (cy + 1) * kCell)});
        continue;
      }
      // Pillars on a 3-cell lattice inside rooms, away from the torch cells and doors.
      if (cx % 10 < 2 || cx % 10 > 8 || cy % 11 < 2 || cy % 11 > 9) continue;
      if ((cx + cy) % 3 != 0 || (cx * 7 + cy * 5) % 4 == 0) continue;
      int tx = 0, ty = 0;
      torch_cell((cx / 10) + 4 * (cy / 11), tx, ty);
      if (std::abs(cx - tx) <= 1 && std::abs(cy - ty) <= 1) continue;
      const double x = (cx + 0.5) * kCell, y = (cy + 0.5) * kCell;
      if ((cx + 2 * cy) % 2 == 0) {
        scene.occluders.push_back({Circle{{x, y}, 6.0}});
      } else {
        scene.occluders.push_back({box(x - 5.0, y - 5.0, x + 5.0, y + 5.0)});
      }
    }
  }
  for (int t = 0; t < kTorches; ++t) scene.lights.push_back(torch_at(t, 0));
  return scene;
}

Light torch_at(int torch, int frame) {
  int cx = 0, cy = 0;
  torch_cell(torch, cx, cy);
  const double phase = 0.07 * frame + 0.8 * torch;
  Light light;
  light.shape = Circle{{(cx + 0.5) * kCell + 8.0 * std::cos(phase), (cy + 0.5) * kCell + 8.0 * std::sin(phase)}, 3.0};
  const double colors[4][3] = {{1.0, 0.75, 0.45}, {1.0, 0.6, 0.3}, {0.9, 0.8, 0.6}, {1.0, 0.7, 0.5}};
  light.color = {colors[torch % 4][0], colors[torch % 4][1], colors[torch % 4][2]};
  light.intensity = 3.0 * (0.85 + 0.1 * std::sin(1.7 * frame + torch) + 0.05 * std::sin(4.1 * frame + 2.0 * torch));
  return light;
}

}  // namespace par2d::bench
