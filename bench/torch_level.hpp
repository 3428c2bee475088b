// A game level with wall-mounted torches, for the overlap benchmark: the same rooms with the
// torches poking into their walls or standing just off them.
#pragma once

#include "par2d/scene.hpp"

namespace par2d::bench {

// A 1280 x 720 level: outer and inner walls (boxes) with doorways, pillars and crates, and
// 8 circle torches of radius 5 against wall faces. `wall_offset` is the gap between each
// torch and its wall: -1 makes every torch overlap its wall by 1 px, 2 keeps it 2 px off.
Scene torch_level(double wall_offset);

}  // namespace par2d::bench
