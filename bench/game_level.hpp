// A game-like level for the game-loop benchmark and the Renderer tests: a tilemap of wall
// boxes and pillars in rooms, with torches that move and flicker every frame.
#pragma once

#include <cstdint>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::bench {

// The level's world is kLevelWidth x kLevelHeight units (40 x 22 cells of 32 units): border
// walls, walls between 8 rooms with door gaps, and pillars (boxes and circles) in the rooms,
// about 300 occluders. `width` x `height` is the lightmap size; the view is the whole level
// whatever the size. Lights: kTorches torches, one per room.
inline constexpr double kLevelWidth = 1280.0;
inline constexpr double kLevelHeight = 704.0;
inline constexpr int kTorches = 8;
Scene game_level(int width, int height);

// Torch `torch` at frame `frame`: a small circle circling its room's open cell (it never
// touches a wall or pillar), its intensity flickering. Deterministic.
Light torch_at(int torch, int frame);

}  // namespace par2d::bench
