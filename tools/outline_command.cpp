// `par2d outline`: a sprite PNG's alpha traced into occluder polygons (polygons_from_alpha), saved as a scene.
#include "outline_command.hpp"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"

namespace par2d::cli {

CLI::App* add_outline_command(CLI::App& app, OutlineArgs& args) {
  CLI::App* outline = app.add_subcommand(
      "outline", "Trace a PNG's alpha into occluder polygons (with holes) and write them as a scene file");
  outline->add_option("png", args.png_path, "PNG with an alpha channel (gray+alpha or RGBA, 8 or 16 bits)")->required();
  outline
      ->add_option(
          "-o,--output", args.output_path,
          "Scene JSON to write (- for standard output): the image's size and view, no lights, one occluder per "
          "polygon")
      ->required();
  outline->add_option("--threshold", args.options.threshold, "A pixel is solid where alpha >= threshold. Default: 128")
      ->check(CLI::Range(0, 255));
  outline
      ->add_option("--tolerance", args.options.tolerance,
                   "Pixels: how far an outline may stray from the solid pixels' boundary (a 45-degree staircase "
                   "straightens from about 0.73). Default: 1")
      ->check(CLI::NonNegativeNumber);
  outline
      ->add_option("--max-vertices", args.options.max_vertices,
                   "The most vertices one polygon may keep (an error names a polygon that needs more). Default: 65536")
      ->check(CLI::Range(std::size_t{3}, par2d::kMaxOutlineVertices));
  outline->add_option("--scale", args.options.scale.x, "World units per pixel (both axes). Default: 1")
      ->each([&args](const std::string&) { args.options.scale.y = args.options.scale.x; });
  outline->add_option("--offset-x", args.options.offset.x, "World x of the image's left edge. Default: 0");
  outline->add_option("--offset-y", args.options.offset.y, "World y of the image's top edge. Default: 0");
  return outline;
}

par2d::Status run_outline(const OutlineArgs& args, bool stdout_closed) {
  if (args.output_path == "-" && stdout_closed)
    return par2d::Status(par2d::StatusCode::io_error, "outline: '-' (standard output): standard output is closed");
  par2d::AlphaImage image;
  if (par2d::Status s = par2d::load_png_alpha(args.png_path, image); !s) return s;
  std::vector<par2d::Polygon> polygons;
  if (par2d::Status s = par2d::polygons_from_alpha(image.mask(), args.options, polygons); !s)
    return par2d::Status(s.code(), args.png_path + ": " + s.message());
  par2d::Scene scene;
  scene.width = image.width;
  scene.height = image.height;
  const par2d::Vec2 o = args.options.offset, k = args.options.scale;
  scene.view = {o.x, o.y, o.x + k.x * image.width, o.y + k.y * image.height};
  scene.occluders.reserve(polygons.size());
  for (par2d::Polygon& polygon : polygons) {
    par2d::Occluder occluder;
    occluder.shape = std::move(polygon);
    scene.occluders.push_back(std::move(occluder));
  }
  if (args.output_path != "-") return par2d::save_scene_file(args.output_path, scene);
  if (par2d::Status s = par2d::validate_scene(scene, "-"); !s) return s;
  const std::string text = par2d::scene_to_json(scene);
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
    return par2d::Status(par2d::StatusCode::io_error, "outline: '-' (standard output): write failed");
  return par2d::Status::success();
}

}  // namespace par2d::cli
