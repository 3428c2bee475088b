// Pixel loops of the per-pixel backends (scalar reference, ray caster) over a rectangle.
#pragma once

#include "par2d/types.hpp"
#include "raycast/raycast_renderer.hpp"
#include "world/prepared_scene.hpp"
#include "render/tiling.hpp"
#include "scalar/scalar_renderer.hpp"

namespace par2d::detail {

// Mean of the scalar reference over the samples of each pixel of `rect`. `shaded`:
// RenderOptions::shaded (the shaded irradiance where the scene has a normal source).
void render_rect_scalar(const PreparedScene& scene, int spp, const TileRect& rect, ScalarScratch& scratch,
                        const ImageView& image, bool shaded = true);

// The same for pixels `rect` of the tile whose top-left pixel is (tile_x0, tile_y0), into
// the tile's result planes (as the SIMD kernel writes them).
void render_tile_scalar(const PreparedScene& scene, int spp, const TileRect& rect, int tile_x0, int tile_y0,
                        ScalarScratch& scratch, TileResult& out, bool shaded = true);

// Mean of the ray caster over the samples of each pixel of `rect`; each sample's ray
// pattern is offset by a hash of (pixel, sample), the same on every run.
// `scene` is the source scene the caster was built from (the ray caster works in its
// coordinates, independent of the prepared scene).
void render_rect_raycast(const Scene& scene, const RaycastRenderer& caster, int spp, int rays, const TileRect& rect,
                         const ImageView& image, bool shaded = true);

}  // namespace par2d::detail
