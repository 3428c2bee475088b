// The bundled example scenes: each loads, and on the lighting-model examples every SIMD ISA
// matches the scalar reference within docs/contract.md section 5's bound (shaded and plain).
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

std::vector<std::string> example_scenes(const std::string& prefix) {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(PAR2D_SOURCE_DIR "/examples")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".json" && name.rfind(prefix, 0) == 0) paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

}  // namespace

TEST_CASE("every example scene loads") {
  const std::vector<std::string> paths = example_scenes("");
  CHECK(paths.size() >= 10);
  for (const std::string& path : paths) {
    Scene scene;
    const Status status = load_scene_file(path, scene);
    INFO(path, ": ", status.message());
    CHECK(status.ok());
  }
}

namespace {

// The lighting-model examples whose file name is (`in_default_tier`) or is not `lighting_game.json`
// and `lighting_normals.json` (every term together, and the normal-mapped one: shaded and plain
// differ there), each at full size, on every SIMD ISA against the scalar reference.
void check_lighting_examples(bool in_default_tier) {
  const std::vector<std::string> paths = example_scenes("lighting_");
  CHECK(paths.size() == 9);
  int checked_scenes = 0;
  for (const std::string& path : paths) {
    const std::string name = std::filesystem::path(path).filename().string();
    if ((name == "lighting_game.json" || name == "lighting_normals.json") != in_default_tier) continue;
    ++checked_scenes;
    Scene scene;
    REQUIRE(load_scene_file(path, scene).ok());
    const double bound = 1e-4 * emission_max_sum(scene);
    for (bool shaded : {true, false}) {
      if (!shaded && !scene.normal && !scene.normal_map) continue;  // the same image as shaded
      RenderOptions scalar = options_for(Backend::scalar);
      scalar.shaded = shaded;
      const RenderedImage reference = render_or_fail(scene, scalar);
      for (Isa isa : simd_isas_here()) {
        RenderOptions simd = options_for(Backend::simd, isa);
        simd.shaded = shaded;
        const RenderedImage got = render_or_fail(scene, simd);
        const Comparison c = compare_renders(scene, reference, got, bound, 0.05 * pixel_width(scene));
        INFO(path, " shaded=", shaded, " isa=", std::string(isa_name(isa)), " checked=", c.checked,
             " max_error=", c.max_error, " bound=", bound);
        CHECK(c.checked > scene.width * scene.height / 2);
        CHECK_MESSAGE(c.over == 0, c.first_failure);
      }
    }
  }
  CHECK(checked_scenes == (in_default_tier ? 2 : 7));
}

}  // namespace

TEST_CASE("the lighting-model examples: every SIMD ISA matches the scalar reference, shaded and plain") {
  check_lighting_examples(true);
}

TEST_CASE("the other lighting-model examples: every SIMD ISA matches the scalar reference" * par2d::test::long_tier()) {
  check_lighting_examples(false);
}

TEST_CASE("the concave-shapes example (concave lights, holes, a concave occluder): every SIMD ISA matches scalar") {
  Scene scene;
  REQUIRE(load_scene_file(PAR2D_SOURCE_DIR "/examples/concave_shapes.json", scene).ok());
  scene.width = 320;  // half size, the same view: the default tier's time
  scene.height = 200;
  const RenderedImage reference = render_or_fail(scene, options_for(Backend::scalar));
  const double bound = 1e-4 * emission_max_sum(scene);
  for (Isa isa : simd_isas_here()) {
    const RenderedImage got = render_or_fail(scene, options_for(Backend::simd, isa));
    const Comparison c = compare_renders(scene, reference, got, bound, 0.05 * pixel_width(scene));
    INFO("isa=", std::string(isa_name(isa)), " checked=", c.checked, " max_error=", c.max_error);
    CHECK(c.checked > scene.width * scene.height / 2);
    CHECK_MESSAGE(c.over == 0, c.first_failure);
  }
}
