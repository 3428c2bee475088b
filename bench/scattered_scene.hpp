// Synthetic levels of many small scattered occluders and lights (deterministic per seed).
#pragma once

#include <cstdint>

#include "par2d/scene.hpp"

namespace par2d::bench {

// Sizes of a scattered level's shapes, in pixels across (a circle's diameter, a polygon's
// circumscribed diameter or a rectangle's long side), each drawn uniformly from [min, max].
// The defaults are the scaling benchmark's original level.
struct ScatteredSizes {
  double occluder_min = 4.0, occluder_max = 12.0;
  double light_min = 6.0, light_max = 12.0;
};

// `occluders` small convex shapes (quads, triangles, circles) and `lights` small lights
// (circles or small polygons), all placed uniformly over the view [0, 0, width, height].
// Every light keeps a margin from every occluder where the level leaves room, so the scene is
// in the regime where PAR's per-pair depth test is exact (docs/contract.md section 1); in a
// level so dense that no spot is clear, a light goes where it overlaps least after a bounded
// number of tries (the renderer handles overlap exactly either way).
// Deterministic for a given seed on every platform: only std::mt19937's specified output is
// used, with our own mapping to doubles (std::uniform_real_distribution is not portable).
Scene scattered_scene(int lights, int occluders, uint32_t seed, int width = 1920, int height = 1080,
                      const ScatteredSizes& sizes = {});

}  // namespace par2d::bench
