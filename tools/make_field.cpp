// Writes a synthetic level of small scattered occluders and lights (the scaling benchmark's scenes) as scene JSON.
//
// Usage: par2d_make_field --lights 256 --occluders 4096 > field.json
//        par2d_make_field --lights 256 --occluders 4096 --occluder-size 1.5 4 --light-size 3 5 > small.json
//        par2d bench field.json --threads 2
// The scene is the one bench/par2d_bench's scaling/ benchmarks render for the same counts,
// seed and size, so `par2d bench` reproduces their numbers from the command line.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <iostream>
#include <string>
#include <utility>
#include <vector>
#include <type_traits>
#include <variant>

#include "par2d/scene.hpp"
#include "scattered_scene.hpp"

namespace {

using Json = nlohmann::ordered_json;

Json point(par2d::Vec2 p) { return Json::array({p.x, p.y}); }

// docs/contract.md section 3's shape members.
void put_shape(Json& out, const par2d::Shape& shape) {
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, par2d::Polygon>) {
          Json vertices = Json::array();
          for (const par2d::Vec2& v : s.vertices) vertices.push_back(point(v));
          out["polygon"] = vertices;
        } else if constexpr (std::is_same_v<T, par2d::Circle>) {
          out["circle"] = Json{{"center", point(s.center)}, {"radius", s.radius}};
        } else {
          out["segment"] = Json::array({point(s.a), point(s.b)});
        }
      },
      shape);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Writes a level of small scattered occluders and lights (the scaling benchmark's) as scene JSON to stdout."};
  int lights = 16, occluders = 256, width = 1920, height = 1080;
  std::uint32_t seed = 20240611;  // the seed bench/bench_scaling.cpp uses
  app.add_option("--lights", lights, "Number of lights. Default: 16")->check(CLI::Range(0, 1 << 20));
  app.add_option("--occluders", occluders, "Number of occluders. Default: 256")->check(CLI::Range(0, 1 << 22));
  app.add_option("--width", width, "Image width in pixels (the view is [0, 0, width, height]). Default: 1920")
      ->check(CLI::Range(1, par2d::kMaxImageSide));
  app.add_option("--height", height, "Image height in pixels. Default: 1080")->check(CLI::Range(1, par2d::kMaxImageSide));
  app.add_option("--seed", seed, "Random seed. Default: 20240611 (the benchmark's)");
  par2d::bench::ScatteredSizes sizes;
  std::vector<double> occluder_size{sizes.occluder_min, sizes.occluder_max};
  std::vector<double> light_size{sizes.light_min, sizes.light_max};
  app.add_option("--occluder-size", occluder_size,
                 "Occluder size range MIN MAX in pixels across, drawn uniformly. Default: 4 12")
      ->expected(2)
      ->check(CLI::Range(1e-3, 1e4));
  app.add_option("--light-size", light_size, "Light size range MIN MAX in pixels across (diameter). Default: 6 12")
      ->expected(2)
      ->check(CLI::Range(1e-3, 1e4));
  CLI11_PARSE(app, argc, argv);
  for (const auto& [name, range] : {std::pair{"--occluder-size", &occluder_size}, std::pair{"--light-size", &light_size}}) {
    if ((*range)[0] > (*range)[1]) {
      std::cerr << "par2d_make_field: " << name << " " << (*range)[0] << " " << (*range)[1] << ": MIN is above MAX\n";
      return 2;
    }
  }
  sizes = {occluder_size[0], occluder_size[1], light_size[0], light_size[1]};

  const par2d::Scene scene = par2d::bench::scattered_scene(lights, occluders, seed, width, height, sizes);
  Json out;
  out["width"] = scene.width;
  out["height"] = scene.height;
  out["view"] = Json::array({scene.view.x0, scene.view.y0, scene.view.x1, scene.view.y1});
  out["lights"] = Json::array();
  for (const par2d::Light& l : scene.lights) {
    Json j;
    put_shape(j, l.shape);
    j["color"] = Json::array({l.color[0], l.color[1], l.color[2]});
    j["intensity"] = l.intensity;
    out["lights"].push_back(j);
  }
  out["occluders"] = Json::array();
  for (const par2d::Occluder& o : scene.occluders) {
    Json j;
    put_shape(j, o.shape);
    out["occluders"].push_back(j);
  }
  std::cout << out.dump() << "\n";
  return std::cout ? 0 : 1;
}
