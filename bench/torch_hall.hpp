// The incremental-frame benchmark's level (issue 40): 1280 x 720, 32 rooms with doorways,
// 64 ranged torches and about 300 walls and crates; a door that slides in one doorway.
#pragma once

#include "par2d/scene.hpp"

namespace par2d::bench {

inline constexpr int kHallTorches = 64;

// The level at frame 0 (the door closed); the door is occluder hall_door_index().
Scene torch_hall(int width, int height);
// Torch `torch` at frame `frame`: a circle of radius 3, range 64, circling its spot (10 units)
// and flickering; `flicker` false keeps frame 0's emission.
Light hall_torch(int torch, int frame, bool flicker = true);
// The door at frame `frame`: a 6 x 36 box sliding along its doorway (never through a torch).
Occluder hall_door(int frame);
std::size_t hall_door_index();

}  // namespace par2d::bench
