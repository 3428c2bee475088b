// Google Benchmark: what each game lighting model term (docs/contract.md section 6) costs
// against the plain renderer, on 1920x1080 scattered levels at the default SIMD ISA.
//
// Names: lighting_model/<case>/threads:<n>. Compare within one run:
//   plain vs model_noop   the model path on an identical image (every mask 1) vs the plain path
//   torches256/no_range vs torches256/range200   range culling (issue 11 target: >= 5x)
//   plain vs normal_map   per-pixel shading (target: <= 1.5x), one-shot render() and
//                         persistent/<case>: a Renderer that keeps the scene across frames
//   plain vs cone, cookie, translucent, directional   one feature each; normal_map vs
//                         cookie_normal_map: a cookie under per-pixel shading
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "par2d/par2d.hpp"

namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;
constexpr std::uint32_t kSeed = 20261201;

// The features' base level: 16 lights and 256 occluders, as in the scaling benchmark.
par2d::Scene base_level() { return par2d::bench::scattered_scene(16, 256, kSeed, kWidth, kHeight); }

// A bumpy normal map over the whole frame (a grid of domes, like a brick floor).
par2d::NormalMap bumpy_normals(int width, int height) {
  par2d::NormalMap map;
  map.width = width;
  map.height = height;
  map.normals.resize(static_cast<std::size_t>(width) * height * 3);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const double u = std::sin(i * 0.19), v = std::sin(j * 0.23);
      const double nx = 0.45 * u, ny = 0.45 * v, nz = 1.0;
      const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
      float* n = map.normals.data() + 3 * (static_cast<std::size_t>(j) * width + i);
      n[0] = static_cast<float>(nx / len);
      n[1] = static_cast<float>(ny / len);
      n[2] = static_cast<float>(nz / len);
    }
  }
  return map;
}

par2d::Scene feature_level(const std::string& feature) {
  par2d::Scene s = base_level();
  if (feature == "model_noop") {
    for (par2d::Light& l : s.lights) l.mask = 1;
    for (par2d::Occluder& o : s.occluders) o.mask = 1;
  } else if (feature == "normal_map") {
    s.normal_map = bumpy_normals(s.width, s.height);
    for (par2d::Light& l : s.lights) l.elevation = 25.0;
  } else if (feature == "cone") {
    int k = 0;
    for (par2d::Light& l : s.lights) l.cone = par2d::Cone{45.0 * k++, 35.0, 10.0};
  } else if (feature == "cookie" || feature == "cookie_normal_map") {
    // Three soft beams of different strengths (12 knots), turned per light.
    par2d::Cookie beams;
    for (const double centre : {0.0, 120.0, 240.0}) {
      const double peak = 1.0 - centre / 400.0;
      for (const auto& [offset, weight] : {std::pair{-20.0, 0.0}, {-8.0, peak}, {8.0, peak}, {20.0, 0.0}})
        beams.knots.push_back({centre + offset, weight});
    }
    int k = 0;
    for (par2d::Light& l : s.lights) {
      l.cookie = beams;
      l.cookie->rotation = 45.0 * k++;
    }
    if (feature == "cookie_normal_map") {
      s.normal_map = bumpy_normals(s.width, s.height);
      for (par2d::Light& l : s.lights) l.elevation = 25.0;
    }
  } else if (feature == "translucent") {
    int k = 0;
    for (par2d::Occluder& o : s.occluders)
      if (k++ % 2 == 0) o.transmittance = {0.6, 0.4, 0.2};
  } else if (feature == "directional") {
    par2d::DirectionalLight sun;
    sun.angle0 = 230.0;
    sun.angle1 = 250.0;
    sun.intensity = 0.5;
    s.directional_lights.push_back(sun);
  }
  return s;
}

// 256 torches over a level of 256 occluders, with or without a 200 px range.
par2d::Scene torches(bool ranged) {
  par2d::Scene s = par2d::bench::scattered_scene(256, 256, kSeed + 1, kWidth, kHeight);
  if (ranged)
    for (par2d::Light& l : s.lights) l.range = 200.0;
  return s;
}

void register_case(const std::string& name, par2d::Scene scene, int threads) {
  par2d::RenderOptions options;
  options.backend = par2d::Backend::simd;
  options.threads = threads;
  auto* b = benchmark::RegisterBenchmark(
      ("lighting_model/" + name + "/threads:" + std::to_string(threads)).c_str(),
      [scene = std::move(scene), options](benchmark::State& state) { par2d::bench::run_render(state, scene, options); });
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

// The same frame from a persistent Renderer (what a game keeps across frames): the scene,
// its normal map in world axes and its validation are set once, outside the timed loop.
void register_persistent_case(const std::string& name, par2d::Scene scene, int threads) {
  par2d::RenderOptions options;
  options.backend = par2d::Backend::simd;
  options.threads = threads;
  auto* b = benchmark::RegisterBenchmark(
      ("lighting_model/persistent/" + name + "/threads:" + std::to_string(threads)).c_str(),
      [scene = std::move(scene), options](benchmark::State& state) {
        par2d::Renderer renderer;
        if (!renderer.set_options(options).ok() || !renderer.set_scene(scene).ok())
          return state.SkipWithError("set_options or set_scene failed");
        std::vector<float> pixels(static_cast<std::size_t>(scene.width) * scene.height * 3);
        const par2d::ImageView image{pixels.data(), scene.width, scene.height, std::ptrdiff_t{3} * scene.width};
        if (!renderer.render(image).ok()) return state.SkipWithError("render failed");  // sizes the buffers
        for (auto _ : state) {
          if (!renderer.render(image).ok()) return state.SkipWithError("render failed");
          benchmark::DoNotOptimize(pixels.data());
          benchmark::ClobberMemory();
        }
      });
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

const bool kRegistered = [] {
  for (const int threads : {1, 2}) {
    for (const char* feature : {"plain", "normal_map"})
      register_persistent_case(feature, feature_level(feature), threads);
    for (const char* feature :
         {"plain", "model_noop", "normal_map", "cone", "cookie", "cookie_normal_map", "translucent", "directional"})
      register_case(feature, feature_level(feature), threads);
    register_case("torches256/no_range", torches(false), threads);
    register_case("torches256/range200", torches(true), threads);
  }
  return true;
}();

}  // namespace
