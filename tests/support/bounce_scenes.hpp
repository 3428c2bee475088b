// Scenes with one bounce (docs/contract.md section 7) that several test files render.
#pragma once

#include "par2d/scene.hpp"

namespace par2d::test {

// An occluder of `shape` reflecting `albedo`.
Occluder reflector(Shape shape, Rgb albedo);

// Two lights (a circle and a segment), a reflecting polygon with a collinear vertex, a
// reflecting circle and segment, a translucent disc and a dark triangle, in a 32 x 24 view of
// [-80, -60, 80, 60]; piece length 7.
Scene bounce_mixed_scene();

}  // namespace par2d::test
