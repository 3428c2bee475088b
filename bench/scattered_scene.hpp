// Synthetic levels of many small scattered occluders and lights (deterministic per seed).
#pragma once

#include <cstdint>

#include "par2d/scene.hpp"

namespace par2d::bench {

// `occluders` small convex shapes (quads, triangles, circles, about 4-12 px across) and
// `lights` small lights (circles or small polygons, radius about 3-6 px), all placed uniformly
// over the view [0, 0, width, height]. Every light keeps a margin from every occluder, so the
// scene is in the regime where PAR's per-pair depth test is exact (docs/contract.md section 1).
// Deterministic for a given seed on every platform: only std::mt19937's specified output is
// used, with our own mapping to doubles (std::uniform_real_distribution is not portable).
Scene scattered_scene(int lights, int occluders, uint32_t seed, int width = 1920, int height = 1080);

}  // namespace par2d::bench
