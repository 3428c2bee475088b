// Level generators for the wall-level grid: wall levels as 2D games build them (tilemaps of wall
// boxes or free-form walls, torches on wall faces at a chosen overlap) and crops of the
// many-light rubble fields. Deterministic per seed; used by par2d_make_grid and the grid script.
#pragma once

#include <cstdint>
#include <optional>

#include "par2d/scene.hpp"
#include "scattered_scene.hpp"

namespace par2d::bench {

enum class WallStyle : std::uint8_t {
  tilemap,         // one box per wall cell (as a tilemap editor exports them)
  tilemap_merged,  // the same cells, each row's runs of adjacent boxes as one box, then columns'
  free_form,       // the same walls as one slightly rotated quad per run, pillars as circles
};

struct WallLevel {
  int width = 640, height = 360;  // image = view, pixels = world units
  double tile = 32.0;             // wall cell side, px (16-64 in the grid)
  WallStyle style = WallStyle::tilemap;
  // Fraction of the rooms' open cells that become pillars (one cell each).
  double density = 0.04;
  int torches = 6;
  double torch_radius = 5.0;
  // How deep each torch reaches into its wall face (px, > 0); a negative value keeps the torch
  // that far off the face (-2: the "2 px off").
  double overlap = 1.0;
  std::optional<double> range;  // torch range (px); empty: none
  std::uint32_t seed = 39;
};

// Rooms of about 6 x 4 cells of `tile` px, walls with doorways, border walls, pillars; torches
// on wall faces that look into open cells, each at the middle of its cell's face. The torch
// positions do not depend on `style`, and differ between two `overlap` values only by the
// shift along the face normal.
Scene wall_level(const WallLevel& level);

// The many-light field of scattered_scene made for a full `full_width` x `full_height` frame
// (the 1920 x 1080, with 16 x 256 or 256 x 4096 at that size), rendered through a
// `width` x `height` window at its center at one world unit per pixel: every pixel sees what
// it would see in the full frame, at a fraction of the cost.
Scene field_crop(int lights, int occluders, const ScatteredSizes& sizes, int width, int height,
                 std::uint32_t seed = 20240611, int full_width = 1920, int full_height = 1080);

}  // namespace par2d::bench
