// Writes one level of the wall-level benchmark grid (bench/grid_levels.hpp) as scene JSON to stdout.
//
// Usage: par2d_make_grid walls --tile 32 --style tilemap --torch-radius 5 --overlap 1 > lit.json
//        par2d_make_grid walls --tile 32 --style tilemap --torch-radius 5 --overlap -2 > off.json
//        par2d_make_grid field --lights 256 --occluders 4096 --occluder-size 1.5 4 --light-size 3 5 --width 320 --height 180 > rubble.json
// tools/grid_bench.sh runs the whole grid under callgrind.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "grid_levels.hpp"
#include "par2d/scene_write.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Writes a level of the wall-level benchmark grid as scene JSON to stdout."};
  app.require_subcommand(1);
  int width = 640, height = 360;
  std::uint32_t seed = 0;
  bool seed_given = false;

  CLI::App* walls = app.add_subcommand("walls", "Rooms of wall cells with torches on the wall faces");
  par2d::bench::WallLevel level;
  std::string style = "tilemap";
  double range = 0.0;
  walls->add_option("--tile", level.tile, "Wall cell side in px. Default: 32")->check(CLI::Range(4.0, 1024.0));
  walls->add_option("--style", style, "tilemap (a box per cell), merged (row runs as one box), free (rotated runs, round pillars). Default: tilemap")
      ->check(CLI::IsMember({"tilemap", "merged", "free"}));
  walls->add_option("--density", level.density, "Fraction of open room cells made pillars. Default: 0.04")->check(CLI::Range(0.0, 1.0));
  walls->add_option("--torches", level.torches, "Torches. Default: 6")->check(CLI::Range(0, 4096));
  walls->add_option("--torch-radius", level.torch_radius, "Torch radius in px. Default: 5")->check(CLI::Range(0.1, 1000.0));
  walls->add_option("--overlap", level.overlap,
                    "Depth of each torch into its wall in px; negative: that far off the wall. Default: 1");
  walls->add_option("--range", range, "Torch range in px; 0: none. Default: 0")->check(CLI::Range(0.0, 1e6));

  CLI::App* field = app.add_subcommand("field", "A centered crop of a 1920x1080 scattered field of lights and occluders");
  int lights = 16, occluders = 256;
  std::vector<double> occluder_size{4.0, 12.0}, light_size{6.0, 12.0};
  field->add_option("--lights", lights, "Lights in the full frame. Default: 16")->check(CLI::Range(0, 1 << 20));
  field->add_option("--occluders", occluders, "Occluders in the full frame. Default: 256")->check(CLI::Range(0, 1 << 22));
  field->add_option("--occluder-size", occluder_size, "MIN MAX px across. Default: 4 12")->expected(2)->check(CLI::Range(1e-3, 1e4));
  field->add_option("--light-size", light_size, "MIN MAX px across. Default: 6 12")->expected(2)->check(CLI::Range(1e-3, 1e4));

  for (CLI::App* sub : {walls, field}) {
    sub->add_option("--width", width, "Image width in px. Default: 640")->check(CLI::Range(1, par2d::kMaxImageSide));
    sub->add_option("--height", height, "Image height in px. Default: 360")->check(CLI::Range(1, par2d::kMaxImageSide));
    sub->add_option_function<std::uint32_t>("--seed", [&](const std::uint32_t& s) { seed = s; seed_given = true; },
                                            "Random seed. Default: 39 (walls), 20240611 (field)");
  }
  CLI11_PARSE(app, argc, argv);

  par2d::Scene scene;
  if (walls->parsed()) {
    const std::map<std::string, par2d::bench::WallStyle> styles{{"tilemap", par2d::bench::WallStyle::tilemap},
                                                                {"merged", par2d::bench::WallStyle::tilemap_merged},
                                                                {"free", par2d::bench::WallStyle::free_form}};
    level.style = styles.at(style);
    level.width = width;
    level.height = height;
    if (range > 0.0) level.range = range;
    if (seed_given) level.seed = seed;
    scene = par2d::bench::wall_level(level);
  } else {
    if (occluder_size[0] > occluder_size[1] || light_size[0] > light_size[1]) {
      std::cerr << "par2d_make_grid: a size range's MIN is above its MAX\n";
      return 2;
    }
    const par2d::bench::ScatteredSizes sizes{occluder_size[0], occluder_size[1], light_size[0], light_size[1]};
    scene = seed_given ? par2d::bench::field_crop(lights, occluders, sizes, width, height, seed)
                       : par2d::bench::field_crop(lights, occluders, sizes, width, height);
  }
  const par2d::Status status = par2d::validate_scene(scene, "level");
  if (!status.ok()) {
    std::cerr << "par2d_make_grid: " << status.message() << "\n";
    return 1;
  }
  std::cout << par2d::scene_to_json(scene);
  return std::cout ? 0 : 1;
}
