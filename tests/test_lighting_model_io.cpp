// The game lighting model's terms as users state them: JSON keys, validation, scene_write, PNG normal maps, Renderer setters.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <stb/stb_image_write.h>

#include "support/temp_dir.hpp"
#include "par2d/image_io.hpp"
#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "support/test_tiers.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using par2d::Scene;
using par2d::Status;
using par2d::StatusCode;

using par2d::test::TempDir;

Status parse(const std::string& json, Scene& scene) { return par2d::parse_scene(json, "s.json", scene); }

// The whole message, exactly: file name, place and problem on one line.
void check_message(const std::string& json, const std::string& message) {
  Scene scene;
  const Status status = parse(json, scene);
  CAPTURE(json);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == message);
}

std::string scene_with(const std::string& members) { return R"({"width": 4, "height": 3, )" + members + "}"; }
std::string light_with(const std::string& terms) {
  return scene_with(R"("lights": [{"circle": {"center": [1, 1], "radius": 1}, )" + terms + "}]");
}
std::string occluder_with(const std::string& terms) {
  return scene_with(R"("occluders": [{"segment": [[0, 0], [1, 1]], )" + terms + "}]");
}
std::string directional_with(const std::string& terms) {
  return scene_with(R"("directional_lights": [{)" + terms + "}]");
}

// Writes a width x height PNG with `channels` channels whose every pixel is `value`.
void write_png(const std::string& path, int width, int height, int channels, std::vector<unsigned char> value) {
  std::vector<unsigned char> pixels;
  for (int k = 0; k < width * height; ++k) pixels.insert(pixels.end(), value.begin(), value.end());
  REQUIRE(value.size() == static_cast<std::size_t>(channels));
  REQUIRE(stbi_write_png(path.c_str(), width, height, channels, pixels.data(), width * channels) != 0);
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Runs the CLI with `args`; returns the exit status (or 128 + signal).
int run_cli(const std::vector<std::string>& args) {
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, PAR2D_CLI_PATH, nullptr, nullptr, argv.data(), environ) == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs the CLI with `args`; its exit status, and what it wrote to file descriptor `fd` (1:
// standard output, 2: standard error) in `text`.
int run_cli_capture(const std::vector<std::string>& args, int fd, std::string& text) {
  TempDir capture("par2d_cli_capture");
  const std::string text_path = capture / "captured.txt";
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  REQUIRE(posix_spawn_file_actions_init(&actions) == 0);
  REQUIRE(posix_spawn_file_actions_addopen(&actions, fd, text_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600) == 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, PAR2D_CLI_PATH, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(spawned == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  std::ifstream in(text_path, std::ios::binary);
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Its exit status, and its standard error in `err`.
int run_cli_err(const std::vector<std::string>& args, std::string& err) { return run_cli_capture(args, 2, err); }

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A PNG of a few dozen bytes that declares `width` x `height` 8-bit RGB pixels and holds a
// cut-off zlib stream: its header is all it has, so decoding it can only fail, after
// allocating for the declared size. A refusal that names the declared size came from the header.
std::string header_only_png(std::uint32_t width, std::uint32_t height) {
  auto crc32 = [](const std::string& bytes) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
  };
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32(type + data));
  };
  const std::string ihdr = be32(width) + be32(height) + std::string{8, 2, 0, 0, 0};  // 8-bit RGB
  const std::string idat("\x78\x9C\x62\x60", 4);                                 // zlib header, then nothing
  return std::string("\x89PNG\r\n\x1A\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", idat) + chunk("IEND", "");
}

std::vector<float> read_pfm_file(const std::string& path) {
  int width = 0, height = 0;
  std::vector<float> pixels;
  REQUIRE(par2d::read_pfm(path, width, height, pixels).ok());
  return pixels;
}

// What the library renders for `scene`, shaded or plain, as the CLI's PFM holds it.
std::vector<float> render_direct(const Scene& scene, bool shaded,
                                 par2d::BounceTerm bounce = par2d::BounceTerm::included) {
  std::vector<float> pixels(3 * static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height));
  par2d::RenderOptions options;
  options.shaded = shaded;
  options.bounce = bounce;
  par2d::ImageView view{pixels.data(), scene.width, scene.height, 3 * static_cast<std::ptrdiff_t>(scene.width)};
  REQUIRE(par2d::render(scene, options, view).ok());
  return pixels;
}

}  // namespace

TEST_CASE("every lighting-model key of a scene file is read into the scene") {
  const std::string json = R"({"width": 4, "height": 3,
    "ambient": [0.1, 0.2, 0.3],
    "directional_lights": [{"angles": [-30, 45.5], "color": [1, 0.5, 0.25], "intensity": 2, "mask": 6, "elevation": 30},
                           {"angles": [10, 20]}],
    "normal": [0, -1, 2],
    "lights": [{"circle": {"center": [1, 1], "radius": 1}, "range": 50, "falloff": 0.5, "cone": {"direction": 90,
                "half_angle": 40, "fade": 10}, "mask": 5.0, "elevation": 15, "shadow": {"strength": 0.25,
                "color": [1, 0, 0.5]}},
               {"segment": [[0, 0], [1, 0]], "cone": {"direction": -45, "half_angle": 180}},
               {"circle": {"center": [2, 1], "radius": 0.5}, "shadow": {"color": [0, 0.75, 0]}, "cookie": {"rotation": -30, "knots": [[-10, 1],
                [45.5, 0.25], [200, 0]]}},
               {"circle": {"center": [3, 1], "radius": 0.5}, "cookie": {"knots": [[7, 0.5]]}}],
    "occluders": [{"circle": {"center": [2, 2], "radius": 1}},
                  {"polygon": [[0, 0], [1, 0], [0, 1]], "transmittance": [0.5, 0.25, 1], "mask": 4294967295,
                   "interior": "lit"},
                  {"segment": [[0, 0], [1, 1]], "mask": 0, "interior": "dark"},
                  {"circle": {"center": [3, 2], "radius": 0.5}, "transmittance": [0, 0, 0.125]}]})";
  Scene scene;
  const Status status = parse(json, scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  CHECK(scene.ambient == par2d::Rgb{0.1, 0.2, 0.3});
  REQUIRE(scene.directional_lights.size() == 2);
  const par2d::DirectionalLight& sun = scene.directional_lights[0];
  CHECK(sun.angle0 == -30.0);
  CHECK(sun.angle1 == 45.5);
  CHECK(sun.color == par2d::Rgb{1, 0.5, 0.25});
  CHECK(sun.intensity == 2.0);
  CHECK(sun.mask == 6u);
  CHECK(sun.elevation == 30.0);
  // Defaults where a directional light leaves them out.
  const par2d::DirectionalLight& sky = scene.directional_lights[1];
  CHECK(sky.color == par2d::Rgb{1, 1, 1});
  CHECK(sky.intensity == 1.0);
  CHECK(sky.mask == par2d::kAllMaskBits);
  CHECK(sky.elevation == 0.0);
  REQUIRE(scene.normal.has_value());
  CHECK(scene.normal->x == 0.0);
  CHECK(scene.normal->y == -1.0);
  CHECK(scene.normal->z == 2.0);  // as written; renderers normalize
  CHECK_FALSE(scene.normal_map.has_value());

  REQUIRE(scene.lights.size() == 4);
  const par2d::Light& spot = scene.lights[0];
  REQUIRE(spot.range.has_value());
  CHECK(*spot.range == 50.0);
  CHECK(spot.falloff == 0.5);
  REQUIRE(spot.cone.has_value());
  CHECK(spot.cone->direction == 90.0);
  CHECK(spot.cone->half_angle == 40.0);
  CHECK(spot.cone->fade == 10.0);
  CHECK(spot.mask == 5u);
  CHECK(spot.elevation == 15.0);
  CHECK(spot.shadow.strength == 0.25);
  CHECK(spot.shadow.color == par2d::Rgb{1, 0, 0.5});
  const par2d::Light& wide = scene.lights[1];
  CHECK_FALSE(wide.range.has_value());
  REQUIRE(wide.cone.has_value());
  CHECK(wide.cone->fade == 0.0);  // fade defaults to 0
  CHECK(wide.mask == par2d::kAllMaskBits);
  CHECK(wide.falloff == 2.0);  // the default
  CHECK(wide.shadow.strength == 1.0);  // full shadows by default
  CHECK(wide.shadow.color == par2d::Rgb{0, 0, 0});
  CHECK_FALSE(wide.cookie.has_value());
  const par2d::Light& patterned = scene.lights[2];
  CHECK(patterned.shadow.strength == 1.0);  // strength defaults to 1 when only a colour is given
  CHECK(patterned.shadow.color == par2d::Rgb{0, 0.75, 0});
  REQUIRE(patterned.cookie.has_value());
  CHECK(patterned.cookie->rotation == -30.0);
  REQUIRE(patterned.cookie->knots.size() == 3);
  CHECK(patterned.cookie->knots[1].direction == 45.5);
  CHECK(patterned.cookie->knots[1].weight == 0.25);
  CHECK(patterned.cookie->knots[2].weight == 0.0);
  const par2d::Light& dimmed = scene.lights[3];
  REQUIRE(dimmed.cookie.has_value());
  CHECK(dimmed.cookie->rotation == 0.0);  // the default
  REQUIRE(dimmed.cookie->knots.size() == 1);
  CHECK(dimmed.cookie->knots[0].direction == 7.0);
  CHECK(dimmed.cookie->knots[0].weight == 0.5);

  // The compact store hands each occluder its own terms, in file order.
  REQUIRE(scene.occluders.size() == 4);
  CHECK(scene.occluders[0].transmittance == par2d::Rgb{0, 0, 0});
  CHECK(scene.occluders[0].mask == par2d::kAllMaskBits);
  CHECK(scene.occluders[0].interior == par2d::Interior::dark);
  CHECK(std::holds_alternative<par2d::Circle>(scene.occluders[0].shape));
  CHECK(scene.occluders[1].transmittance == par2d::Rgb{0.5, 0.25, 1});
  CHECK(scene.occluders[1].interior == par2d::Interior::lit);
  CHECK(std::holds_alternative<par2d::Polygon>(scene.occluders[1].shape));
  CHECK(scene.occluders[2].mask == 0u);
  CHECK(scene.occluders[2].interior == par2d::Interior::dark);
  CHECK(std::holds_alternative<par2d::Segment>(scene.occluders[2].shape));
  CHECK(scene.occluders[3].transmittance == par2d::Rgb{0, 0, 0.125});
  CHECK(scene.occluders[3].mask == par2d::kAllMaskBits);
  CHECK(std::get<par2d::Circle>(scene.occluders[3].shape).radius == 0.5);
  CHECK(par2d::validate_scene(scene).ok());
}

TEST_CASE("masks are integers from 0 to 2^32 - 1; anything else is refused with its value") {
  Scene scene;
  REQUIRE(parse(light_with(R"("mask": 4294967295.0)"), scene).ok());
  CHECK(scene.lights[0].mask == 0xFFFFFFFFu);
  REQUIRE(parse(occluder_with(R"("mask": 0)"), scene).ok());
  CHECK(scene.occluders[0].mask == 0u);
  const std::string range = "must be an integer from 0 to 4294967295, got ";
  check_message(light_with(R"("mask": 1.5)"), "s.json: lights[0].mask: " + range + "1.5");
  check_message(light_with(R"("mask": -1)"), "s.json: lights[0].mask: " + range + "-1");
  check_message(occluder_with(R"("mask": 4294967296)"), "s.json: occluders[0].mask: " + range + "4294967296");
  check_message(directional_with(R"("angles": [0, 1], "mask": 1e300)"),
                "s.json: directional_lights[0].mask: " + range + "1e+300");
  check_message(light_with(R"("mask": "7")"), "s.json: lights[0].mask: expected an integer");
  check_message(light_with(R"("mask": [7])"), "s.json: lights[0].mask: expected an integer");
}

TEST_CASE("every bad lighting-model value is refused with a one-line message naming its place") {
  // Lights.
  check_message(light_with(R"("range": 0)"), "s.json: lights[0].range: must be > 0, got 0");
  check_message(light_with(R"("range": -2)"), "s.json: lights[0].range: must be > 0, got -2");
  check_message(light_with(R"("range": "far")"), "s.json: lights[0].range: expected a number");
  check_message(light_with(R"("falloff": 16.5)"), "s.json: lights[0].falloff: must be between 0 and 16, got 16.5");
  check_message(light_with(R"("falloff": -0.5)"), "s.json: lights[0].falloff: must be between 0 and 16, got -0.5");
  check_message(light_with(R"("falloff": "fast")"), "s.json: lights[0].falloff: expected a number");
  check_message(light_with(R"("elevation": 90.5)"), "s.json: lights[0].elevation: must be between 0 and 90, got 90.5");
  check_message(light_with(R"("elevation": -1)"), "s.json: lights[0].elevation: must be between 0 and 90, got -1");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 0})"),
                "s.json: lights[0].cone.half_angle: must be > 0 and <= 180, got 0");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 181})"),
                "s.json: lights[0].cone.half_angle: must be > 0 and <= 180, got 181");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 30, "fade": 31})"),
                "s.json: lights[0].cone.fade: must be between 0 and half_angle, got 31");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 30, "fade": -1})"),
                "s.json: lights[0].cone.fade: must be between 0 and half_angle, got -1");
  check_message(light_with(R"("cone": {"half_angle": 30})"), "s.json: lights[0].cone.direction: missing (required)");
  check_message(light_with(R"("cone": {"direction": 30})"), "s.json: lights[0].cone.half_angle: missing (required)");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 30, "width": 1})"),
                "s.json: lights[0].cone.width: unknown key (expected direction, half_angle, fade)");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 30, "fade": [1]})"),
                "s.json: lights[0].cone.fade: expected a number");
  check_message(light_with(R"("cone": 30)"),
                R"(s.json: lights[0].cone: expected {"direction": d, "half_angle": h, "fade": f})");
  // Shadows.
  check_message(light_with(R"("shadow": 0.5)"), R"(s.json: lights[0].shadow: expected {"strength": s, "color": [r, g, b]})");
  check_message(light_with(R"("shadow": [0.5])"), R"(s.json: lights[0].shadow: expected {"strength": s, "color": [r, g, b]})");
  check_message(light_with(R"("shadow": {"strength": 1.5})"), "s.json: lights[0].shadow.strength: must be between 0 and 1, got 1.5");
  check_message(light_with(R"("shadow": {"strength": -0.25})"), "s.json: lights[0].shadow.strength: must be between 0 and 1, got -0.25");
  check_message(light_with(R"("shadow": {"strength": "half"})"), "s.json: lights[0].shadow.strength: expected a number");
  check_message(light_with(R"("shadow": {"color": [0, 2, 0]})"), "s.json: lights[0].shadow.color[1]: must be between 0 and 1, got 2");
  check_message(light_with(R"("shadow": {"color": [0, 0]})"), "s.json: lights[0].shadow.color: expected [r, g, b]");
  check_message(light_with(R"("shadow": {"color": 0.5})"), "s.json: lights[0].shadow.color: expected [r, g, b]");
  check_message(light_with(R"("shadow": {"softness": 1})"), "s.json: lights[0].shadow.softness: unknown key (expected strength, color)");
  check_message(occluder_with(R"("shadow": {"strength": 0.5})"),
                "s.json: occluders[0].shadow: unknown key (expected polygon, circle, segment, transmittance, mask, interior, albedo)");
  // Cookies.
  check_message(light_with(R"("cookie": 30)"),
                R"(s.json: lights[0].cookie: expected {"rotation": r, "knots": [[direction, weight], ...]})");
  check_message(light_with(R"("cookie": {"rotation": 10})"), "s.json: lights[0].cookie.knots: missing (required)");
  check_message(light_with(R"("cookie": {"knots": []})"), "s.json: lights[0].cookie.knots: must hold 1 to 32 knots, got 0");
  check_message(light_with(R"("cookie": {"knots": [[0, 1]], "scale": 2})"),
                "s.json: lights[0].cookie.scale: unknown key (expected rotation, knots)");
  check_message(light_with(R"("cookie": {"knots": 3})"),
                "s.json: lights[0].cookie.knots: expected an array of [direction, weight] knots");
  check_message(light_with(R"("cookie": {"knots": [[0, 1], [10]]})"),
                "s.json: lights[0].cookie.knots[1]: expected [direction, weight]");
  check_message(light_with(R"("cookie": {"knots": [[0, 1], {"d": 1}]})"),
                "s.json: lights[0].cookie.knots[1]: expected [direction, weight]");
  check_message(light_with(R"("cookie": {"knots": [[0, 1], [10, 1.5]]})"),
                "s.json: lights[0].cookie.knots[1][1]: weight must be between 0 and 1, got 1.5");
  check_message(light_with(R"("cookie": {"knots": [[0, 1], [10, -0.5]]})"),
                "s.json: lights[0].cookie.knots[1][1]: weight must be between 0 and 1, got -0.5");
  check_message(light_with(R"("cookie": {"knots": [[0, 1], [10, 1], [10, 0]]})"),
                "s.json: lights[0].cookie.knots[2][0]: directions must increase, got 10 after 10");
  check_message(light_with(R"("cookie": {"knots": [[-90, 1], [270, 0]]})"),
                "s.json: lights[0].cookie.knots[1][0]: must be less than 360 degrees past the first knot's "
                "direction, got 270");
  check_message(light_with(R"("cookie": {"rotation": "up", "knots": [[0, 1]]})"),
                "s.json: lights[0].cookie.rotation: expected a number");
  check_message(light_with(R"("cone": {"direction": 0, "half_angle": 30}, "cookie": {"knots": [[0, 1]]})"),
                "s.json: lights[0].cookie: a light takes a cone or a cookie, not both");
  {
    std::string knots;
    for (int k = 0; k < 33; ++k) knots += (k ? ", [" : "[") + std::to_string(k) + ", 1]";
    check_message(light_with(R"("cookie": {"knots": [)" + knots + "]}"),
                  "s.json: lights[0].cookie.knots: must hold 1 to 32 knots, got 33");
  }
  check_message(light_with(R"("transmittance": [1, 1, 1])"),
                "s.json: lights[0].transmittance: unknown key (expected polygon, circle, segment, color, intensity, "
                "range, falloff, normalize, cone, cookie, mask, elevation, shadow)");
  // Occluders.
  check_message(occluder_with(R"("transmittance": [0.5, 1.5, 0])"),
                "s.json: occluders[0].transmittance[1]: must be between 0 and 1, got 1.5");
  check_message(occluder_with(R"("transmittance": [0.5, -0.5, 0])"),
                "s.json: occluders[0].transmittance[1]: must be between 0 and 1, got -0.5");
  check_message(occluder_with(R"("transmittance": [0.5, 0.5])"), "s.json: occluders[0].transmittance: expected [r, g, b]");
  check_message(occluder_with(R"("transmittance": 0.5)"), "s.json: occluders[0].transmittance: expected [r, g, b]");
  check_message(occluder_with(R"("interior": "glass")"),
                R"(s.json: occluders[0].interior: must be "dark" or "lit", got "glass")");
  check_message(occluder_with(R"("interior": true)"), R"(s.json: occluders[0].interior: expected "dark" or "lit")");
  check_message(occluder_with(R"("range": 3)"),
                "s.json: occluders[0].range: unknown key (expected polygon, circle, segment, transmittance, mask, "
                "interior, albedo)");
  check_message(occluder_with(R"("mask": 1, "mask": 2)"), "s.json: occluders[0].mask: duplicate key");
  // Directional lights.
  check_message(directional_with(R"("angles": [10, 10])"),
                "s.json: directional_lights[0].angles: must satisfy a0 < a1 < a0 + 360, got [10, 10]");
  check_message(directional_with(R"("angles": [0, 360])"),
                "s.json: directional_lights[0].angles: must satisfy a0 < a1 < a0 + 360, got [0, 360]");
  check_message(directional_with(R"("angles": [0, 1, 2])"), "s.json: directional_lights[0].angles: expected [a0, a1]");
  check_message(directional_with(R"("color": [1, 1, 1])"), "s.json: directional_lights[0].angles: missing (required)");
  check_message(directional_with(R"("angles": [0, 1], "intensity": -1)"),
                "s.json: directional_lights[0].intensity: must be >= 0, got -1");
  check_message(directional_with(R"("angles": [0, 1], "elevation": 91)"),
                "s.json: directional_lights[0].elevation: must be between 0 and 90, got 91");
  check_message(directional_with(R"("angles": [0, 1], "polygon": [])"),
                "s.json: directional_lights[0].polygon: unknown key (expected angles, color, intensity, mask, "
                "elevation)");
  check_message(scene_with(R"("directional_lights": {})"), "s.json: directional_lights: expected an array");
  // Scene-wide terms.
  check_message(scene_with(R"("ambient": [0, -1, 0])"), "s.json: ambient[1]: must be >= 0, got -1");
  check_message(scene_with(R"("ambient": 1)"), "s.json: ambient: expected [r, g, b]");
  check_message(scene_with(R"("normal": [0, 0, 0])"), "s.json: normal: must have a non-zero length");
  check_message(scene_with(R"("normal": [0, 1])"), "s.json: normal: expected [nx, ny, nz]");
  check_message(scene_with(R"("normal_map": 3)"), "s.json: normal_map: expected a PNG file path");
  check_message(scene_with(R"("normal_map": "")"), "s.json: normal_map: expected a PNG file path");
  check_message(scene_with(R"("normal": [0, 0, 1], "normal_map": "n.png")"),
                "s.json: normal_map: the scene has both normal and normal_map (at most one normal source)");
  check_message(scene_with(R"("ambient": [1e38, 0, 0], "directional_lights": [{"angles": [0, 1], "intensity": 1e38}])"),
                "s.json: ambient: emission too large: the total intensity * color of lights, directional lights and "
                "ambient reaches 2e+38 (at most 1e38, so that float32 output stays finite)");
  check_message(scene_with(R"("sun": [])"),
                "s.json: sun: unknown key (expected width, height, view, lights, occluders, ambient, "
                "directional_lights, normal, normal_map, bounce)");
}

TEST_CASE("scenes built in code are checked for the same terms by validate_scene") {
  Scene scene;
  scene.width = 3;
  scene.height = 2;
  scene.view = {0, 0, 3, 2};
  REQUIRE(par2d::validate_scene(scene).ok());
  auto refused = [&](const std::string& message) {
    const Status status = par2d::validate_scene(scene, "code");
    CHECK(status.code() == StatusCode::invalid_scene);
    CHECK(status.message() == message);
  };
  par2d::Light light;
  light.shape = par2d::Circle{{1, 1}, 1};
  light.range = std::nan("");
  scene.lights = {light};
  refused("code: lights[0].range: not a finite number (nan)");
  scene.lights[0].range.reset();
  scene.lights[0].cone = par2d::Cone{0, 10, 11};
  refused("code: lights[0].cone.fade: must be between 0 and half_angle, got 11");
  scene.lights[0].cone.reset();
  scene.lights[0].cookie = par2d::Cookie{0, {{0, 1}, {std::nan(""), 0}}};
  refused("code: lights[0].cookie.knots[1][0]: not a finite number (nan)");
  scene.lights[0].cookie = par2d::Cookie{std::numeric_limits<double>::infinity(), {{0, 1}}};
  refused("code: lights[0].cookie.rotation: not a finite number (inf)");
  scene.lights[0].cookie.reset();
  par2d::Occluder occluder;
  occluder.shape = par2d::Segment{{0, 0}, {1, 0}};
  occluder.transmittance = {0, 0, 2};
  scene.occluders = {occluder};
  refused("code: occluders[0].transmittance[2]: must be between 0 and 1, got 2");
  scene.occluders[0].transmittance = {0, 0, 0};
  scene.occluders[0].interior = static_cast<par2d::Interior>(7);
  refused("code: occluders[0].interior: must be dark or lit");
  scene.occluders[0].interior = par2d::Interior::lit;
  scene.directional_lights = {par2d::DirectionalLight{50, -50}};
  refused("code: directional_lights[0].angles: must satisfy a0 < a1 < a0 + 360, got [50, -50]");
  scene.directional_lights = {par2d::DirectionalLight{-50, 50}};
  REQUIRE(par2d::validate_scene(scene).ok());

  par2d::NormalMap map;
  map.width = 3;
  map.height = 2;
  map.normals.assign(3 * 3 * 2, 0.5f);
  scene.normal_map = map;
  REQUIRE(par2d::validate_scene(scene).ok());
  scene.normal = par2d::Vec3{0, 0, 1};
  refused("code: normal_map: the scene has both normal and normal_map (at most one normal source)");
  scene.normal.reset();
  scene.normal_map->height = 3;
  refused("code: normal_map: is 3x3 but the image is 3x2 (it must be exactly the image's size)");
  scene.normal_map->height = 2;
  scene.normal_map->normals.pop_back();
  refused("code: normal_map.normals: expected 3 * width * height = 18 floats, got 17");
  scene.normal_map->normals.push_back(std::nanf(""));
  refused("code: normal_map: pixel (2, 1): not a finite normal (0.5, 0.5, nan)");
  scene.normal_map->normals[17] = 0.5f;
  for (int c = 0; c < 3; ++c) scene.normal_map->normals[static_cast<std::size_t>(3 + c)] = 0.0f;
  refused("code: normal_map: pixel (1, 0): has a zero normal");
  scene.normal_map.reset();
  scene.normal = par2d::Vec3{0, 0, -0.0};
  refused("code: normal: must have a non-zero length");
  scene.normal = par2d::Vec3{1e-300, 0, 0};  // tiny but not zero: a direction
  CHECK(par2d::validate_scene(scene).ok());
}

TEST_CASE("scene_to_json writes every lighting-model term so that the scene loads back bit for bit") {
  TempDir dir("par2d_model_io");
  write_png(dir / "bumps.png", 4, 3, 3, {128, 200, 255});
  Scene scene;
  scene.width = 4;
  scene.height = 3;
  scene.view = {0, 0, 4, 3};
  scene.ambient = {0.1, 0, 1.0 / 3.0};
  scene.directional_lights = {par2d::DirectionalLight{-10.25, 80, {0.3, 0.2, 0.1}, 3, 0x00FF00FFu, 42.5},
                              par2d::DirectionalLight{100, 120}};
  par2d::Light light;
  light.shape = par2d::Circle{{1, 1}, 0.7};
  light.range = 0.1 + 0.2;
  light.falloff = 1.0 / 3.0;
  light.cone = par2d::Cone{-170.5, 12.5, 2.5};
  light.mask = 0x80000000u;
  light.elevation = 89.99;
  light.shadow = par2d::Shadow{1.0 / 3.0, {0.0, 1.0 / 7.0, 1.0}};
  par2d::Light plain;
  plain.shape = par2d::Segment{{0, 0}, {2, 0}};
  plain.cookie = par2d::Cookie{1.0 / 3.0, {{-0.1, 0.7}, {1e-9, 1.0 / 7.0}, {359.8, 0}}};
  scene.lights = {light, plain};
  par2d::Occluder glass;
  glass.shape = par2d::Polygon{{{0, 0}, {1, 0}, {1, 1}}};
  glass.transmittance = {0.9, 0.5, 1.0 / 7.0};
  glass.mask = 3;
  glass.interior = par2d::Interior::lit;
  par2d::Occluder wall;
  wall.shape = par2d::Circle{{3, 2}, 0.5};
  scene.occluders = {wall, glass, wall};
  par2d::NormalMap map;
  map.path = "bumps.png";
  map.width = 4;
  map.height = 3;
  map.normals.assign(36, 0.5f);
  scene.normal_map = map;
  REQUIRE(par2d::validate_scene(scene).ok());

  REQUIRE(par2d::save_scene_file(dir / "level.json", scene).ok());
  Scene back;
  const Status status = par2d::load_scene_file(dir / "level.json", back);
  REQUIRE_MESSAGE(status.ok(), status.message());
  for (std::size_t c = 0; c < 3; ++c) CHECK(same(back.ambient[c], scene.ambient[c]));
  REQUIRE(back.directional_lights.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& a = scene.directional_lights[i];
    const auto& b = back.directional_lights[i];
    CHECK(same(a.angle0, b.angle0));
    CHECK(same(a.angle1, b.angle1));
    for (std::size_t c = 0; c < 3; ++c) CHECK(same(a.color[c], b.color[c]));
    CHECK(same(a.intensity, b.intensity));
    CHECK(a.mask == b.mask);
    CHECK(same(a.elevation, b.elevation));
  }
  REQUIRE(back.lights.size() == 2);
  REQUIRE(back.lights[0].range.has_value());
  CHECK(same(*back.lights[0].range, 0.1 + 0.2));
  CHECK(same(back.lights[0].falloff, 1.0 / 3.0));
  CHECK(back.lights[1].falloff == 2.0);
  REQUIRE(back.lights[0].cone.has_value());
  CHECK(same(back.lights[0].cone->direction, -170.5));
  CHECK(same(back.lights[0].cone->half_angle, 12.5));
  CHECK(same(back.lights[0].cone->fade, 2.5));
  CHECK(back.lights[0].mask == 0x80000000u);
  CHECK(same(back.lights[0].elevation, 89.99));
  CHECK(same(back.lights[0].shadow.strength, 1.0 / 3.0));
  for (std::size_t c = 0; c < 3; ++c) CHECK(same(back.lights[0].shadow.color[c], light.shadow.color[c]));
  CHECK(back.lights[1].shadow.strength == 1.0);  // the default, not written
  CHECK(back.lights[1].shadow.color == par2d::Rgb{0.0, 0.0, 0.0});
  CHECK_FALSE(back.lights[1].range.has_value());
  CHECK_FALSE(back.lights[1].cone.has_value());
  CHECK_FALSE(back.lights[0].cookie.has_value());
  REQUIRE(back.lights[1].cookie.has_value());
  CHECK(same(back.lights[1].cookie->rotation, 1.0 / 3.0));
  REQUIRE(back.lights[1].cookie->knots.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(same(back.lights[1].cookie->knots[k].direction, plain.cookie->knots[k].direction));
    CHECK(same(back.lights[1].cookie->knots[k].weight, plain.cookie->knots[k].weight));
  }
  CHECK(back.lights[1].mask == par2d::kAllMaskBits);
  REQUIRE(back.occluders.size() == 3);
  for (std::size_t c = 0; c < 3; ++c) CHECK(same(back.occluders[1].transmittance[c], glass.transmittance[c]));
  CHECK(back.occluders[1].mask == 3u);
  CHECK(back.occluders[1].interior == par2d::Interior::lit);
  CHECK(back.occluders[2].transmittance == par2d::Rgb{0, 0, 0});
  CHECK(back.occluders[2].interior == par2d::Interior::dark);
  // The map is named, not embedded: it is read again from the PNG next to the scene.
  REQUIRE(back.normal_map.has_value());
  CHECK(back.normal_map->path == "bumps.png");
  CHECK(back.normal_map->normals.size() == 36u);
  CHECK(back.normal_map->normals[1] == doctest::Approx(2.0 * 200 / 255 - 1).epsilon(1e-7));

  // A plain scene's text has none of the new keys.
  Scene bare = scene;
  bare.ambient = {0, 0, 0};
  bare.directional_lights.clear();
  bare.normal_map.reset();
  bare.lights = {plain};
  bare.occluders = {wall};
  const std::string text = par2d::scene_to_json(bare);
  for (const char* key : {"ambient", "directional", "normal", "range", "cone", "mask", "elevation", "transmittance",
                          "interior"}) {
    CHECK(text.find(key) == std::string::npos);
  }
  // A constant normal is written too; a map without a path cannot be named in a file.
  bare.normal = par2d::Vec3{0.25, -0.5, 1};
  REQUIRE(parse(par2d::scene_to_json(bare), back).ok());
  REQUIRE(back.normal.has_value());
  CHECK(back.normal->y == -0.5);
  bare.normal.reset();
  bare.normal_map = map;
  bare.normal_map->path.clear();
  const Status unnamed = par2d::save_scene_file(dir / "unnamed.json", bare);
  CHECK(unnamed.code() == StatusCode::invalid_argument);
  CHECK(unnamed.message() == (dir / "unnamed.json") +
                                 ": normal_map: has no path (a scene file names its normal map's PNG; set "
                                 "NormalMap::path)");
  CHECK_FALSE(fs::exists(dir / "unnamed.json"));
}

TEST_CASE("a PNG normal map is read relative to the scene file, decoded as 2 rgb / 255 - 1, and refused unless it fits") {
  TempDir dir("par2d_model_io");
  fs::create_directory(dir / "maps");
  write_png(dir / "maps/rgb.png", 4, 3, 3, {255, 0, 128});
  write_png(dir / "maps/rgba.png", 4, 3, 4, {0, 255, 191, 7});
  write_png(dir / "maps/small.png", 3, 3, 3, {128, 128, 255});
  write_png(dir / "maps/gray.png", 4, 3, 1, {128});
  { std::ofstream(dir / "maps/text.png") << "not an image at all"; }
  auto scene_file = [&](const std::string& name, const std::string& map) {
    std::ofstream(dir / name) << scene_with(R"("normal_map": ")" + map + R"(")");
    return dir / name;
  };
  Scene scene;
  Status status = par2d::load_scene_file(scene_file("a.json", "maps/rgb.png"), scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  REQUIRE(scene.normal_map.has_value());
  CHECK(scene.normal_map->path == "maps/rgb.png");
  CHECK(scene.normal_map->width == 4);
  CHECK(scene.normal_map->height == 3);
  REQUIRE(scene.normal_map->normals.size() == 36u);
  CHECK(scene.normal_map->normals[33] == 1.0f);
  CHECK(scene.normal_map->normals[34] == -1.0f);
  CHECK(scene.normal_map->normals[35] == doctest::Approx(2.0 * 128 / 255 - 1).epsilon(1e-7));
  CHECK(par2d::validate_scene(scene).ok());

  // RGBA: alpha is ignored.
  status = par2d::load_scene_file(scene_file("b.json", "maps/rgba.png"), scene);
  REQUIRE_MESSAGE(status.ok(), status.message());
  CHECK(scene.normal_map->normals[0] == -1.0f);
  CHECK(scene.normal_map->normals[1] == 1.0f);
  CHECK(scene.normal_map->normals[2] == doctest::Approx(2.0 * 191 / 255 - 1).epsilon(1e-7));

  // parse_scene resolves against the directory of the name it is given.
  std::ifstream in(dir / "a.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(par2d::parse_scene(text, dir / "a.json", scene).ok());
  CHECK(scene.normal_map->width == 4);

  const std::string a = dir / "c.json";
  status = par2d::load_scene_file(scene_file("c.json", "maps/small.png"), scene);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == a + ": normal_map: " + (dir / "maps/small.png") +
                                ": is 3x3 but the image is 4x3 (it must be exactly the image's size)");
  status = par2d::load_scene_file(scene_file("c.json", "maps/gray.png"), scene);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == a + ": normal_map: " + (dir / "maps/gray.png") +
                                ": has 1 channel; normal maps must be 8-bit RGB");
  status = par2d::load_scene_file(scene_file("c.json", "maps/text.png"), scene);
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == a + ": normal_map: " + (dir / "maps/text.png") + ": not a PNG file");
  status = par2d::load_scene_file(scene_file("c.json", "maps/none.png"), scene);
  CHECK(status.code() == StatusCode::io_error);
  CHECK(status.message() == a + ": normal_map: " + (dir / "maps/none.png") + ": cannot open: No such file or directory");
  REQUIRE(::mkfifo((dir / "maps/fifo.png").c_str(), 0600) == 0);
  status = par2d::load_scene_file(scene_file("c.json", "maps/fifo.png"), scene);
  CHECK(status.code() == StatusCode::io_error);
  CHECK(status.message() == a + ": normal_map: " + (dir / "maps/fifo.png") + ": cannot read: not a regular file");
  // A refused scene leaves the output scene as it was.
  CHECK(scene.normal_map->width == 4);

  // The public loader, for maps given through the API.
  par2d::NormalMap map;
  REQUIRE(par2d::load_normal_map_png(dir / "maps/small.png", map).ok());
  CHECK(map.width == 3);
  CHECK(map.path == dir / "maps/small.png");
  CHECK(map.normals[2] == 1.0f);
}

TEST_CASE("Renderer setters for the scene-wide terms refuse bad values and keep the previous ones") {
  par2d::Renderer renderer;
  REQUIRE(renderer.set_frame(4, 3).ok());
  REQUIRE(renderer.set_ambient({0.25, 0.5, 0}).ok());
  Status status = renderer.set_ambient({0.1, -1, 0});
  CHECK(status.code() == StatusCode::invalid_scene);
  CHECK(status.message() == "set_ambient: ambient[1]: must be >= 0, got -1");
  CHECK(renderer.model_terms().ambient == par2d::Rgb{0.25, 0.5, 0});
  CHECK(renderer.snapshot().ambient == par2d::Rgb{0.25, 0.5, 0});

  REQUIRE(renderer.set_directional_lights({par2d::DirectionalLight{0, 90}}).ok());
  status = renderer.set_directional_lights({par2d::DirectionalLight{0, 10}, par2d::DirectionalLight{0, 10, {1, 1, 1}, 1,
                                                                                                     1, 95}});
  CHECK(status.message() == "set_directional_lights: directional_lights[1].elevation: must be between 0 and 90, got 95");
  REQUIRE(renderer.model_terms().directional_lights.size() == 1);
  CHECK(renderer.model_terms().directional_lights[0].angle1 == 90.0);

  REQUIRE(renderer.set_normal({0, 0, 1}).ok());
  status = renderer.set_normal({0, std::nan(""), 1});
  CHECK(status.message() == "set_normal: normal[1]: not a finite number (nan)");
  REQUIRE(renderer.model_terms().normal.has_value());

  par2d::NormalMap map;
  map.width = 4;
  map.height = 2;
  map.normals.assign(24, 1.0f);
  status = renderer.set_normal_map(map);
  CHECK(status.message() == "set_normal_map: normal_map: is 4x2 but the image is 4x3 (it must be exactly the image's size)");
  CHECK(renderer.model_terms().normal.has_value());  // the constant normal stays
  CHECK_FALSE(renderer.model_terms().normal_map.has_value());
  map.height = 3;
  map.normals.assign(36, 1.0f);
  REQUIRE(renderer.set_normal_map(map).ok());
  CHECK_FALSE(renderer.model_terms().normal.has_value());  // one source replaces the other
  REQUIRE(renderer.model_terms().normal_map.has_value());
  // The frame cannot change size under a map.
  status = renderer.set_frame(5, 3);
  CHECK_FALSE(status.ok());
  CHECK(renderer.width() == 4);
  REQUIRE(renderer.clear_normal_source().ok());
  CHECK_FALSE(renderer.model_terms().normal_map.has_value());
  CHECK(renderer.set_frame(5, 3).ok());

  // Emission totals count ambient and directional lights with the lights.
  par2d::Light light;
  light.shape = par2d::Circle{{1, 1}, 1};
  light.intensity = 1e38;
  par2d::LightHandle handle;
  REQUIRE(renderer.add_light(light, &handle).ok());
  status = renderer.set_ambient({1e38, 0, 0});
  CHECK(status.message() == "set_ambient: ambient: emission too large: the total intensity * color of lights, "
                            "directional lights and ambient reaches 2e+38 (at most 1e38, so that float32 output "
                            "stays finite)");
  CHECK(renderer.model_terms().ambient == par2d::Rgb{0.25, 0.5, 0});

  // Lights and occluders carry their own terms through add/update, validated the same way.
  light.intensity = 1;
  light.cone = par2d::Cone{0, 200, 0};
  status = renderer.update_light(handle, light);
  CHECK_FALSE(status.ok());
  CHECK(status.message().find("cone.half_angle: must be > 0 and <= 180, got 200") != std::string::npos);
  par2d::Occluder occluder;
  occluder.shape = par2d::Segment{{0, 0}, {1, 1}};
  occluder.transmittance = {0.5, 0.5, -0.5};
  par2d::OccluderHandle oh;
  status = renderer.add_occluder(occluder, &oh);
  CHECK(status.message() == "add_occluder: transmittance[2]: must be between 0 and 1, got -0.5");
  CHECK(renderer.occluder_count() == 0u);
}

TEST_CASE("the CLI writes the plain irradiance next to the shaded one, all files or none" * par2d::test::per_isa()) {
  TempDir dir("par2d_model_io");
  write_png(dir / "n.png", 12, 8, 3, {200, 90, 230});
  {
    std::ofstream(dir / "scene.json")
        << R"({"width": 12, "height": 8, "normal_map": "n.png", "lights": [{"circle": {"center": [3, 4], "radius": 1},)"
           R"( "intensity": 2, "elevation": 30}], "occluders": [{"segment": [[6, 1], [6, 7]], "transmittance": [0.5, 0.5, 0.5]}]})";
  }
  Scene scene;
  REQUIRE(par2d::load_scene_file(dir / "scene.json", scene).ok());
  REQUIRE(run_cli({"render", dir / "scene.json", "--pfm", dir / "shaded.pfm", "--plain-pfm", dir / "plain.pfm",
                   "--plain-png", dir / "plain.png"}) == 0);
  CHECK(read_pfm_file(dir / "shaded.pfm") == render_direct(scene, true));
  CHECK(read_pfm_file(dir / "plain.pfm") == render_direct(scene, false));
  CHECK(fs::file_size(dir / "plain.png") > 0u);

  // Without a normal source the plain output is allowed and is the main image.
  {
    std::ofstream(dir / "flat.json") << R"({"width": 12, "height": 8, "lights": [{"circle": {"center": [3, 4], "radius": 1}}]})";
  }
  REQUIRE(run_cli({"render", dir / "flat.json", "--pfm", dir / "flat.pfm", "--plain-pfm", dir / "flat_plain.pfm"}) == 0);
  CHECK(read_pfm_file(dir / "flat.pfm") == read_pfm_file(dir / "flat_plain.pfm"));

  // One output that cannot be written: none is.
  CHECK(run_cli({"render", dir / "scene.json", "--pfm", dir / "again.pfm", "--plain-pfm", dir / "missing/plain.pfm"}) ==
        1);
  CHECK_FALSE(fs::exists(dir / "again.pfm"));
  // Two options naming one file are refused before anything is rendered.
  CHECK(run_cli({"render", dir / "scene.json", "-o", dir / "x.png", "--plain-png", dir / "x.png"}) == 2);
  CHECK_FALSE(fs::exists(dir / "x.png"));
}

TEST_CASE("the CLI's --bounce renders the direct and bounce terms apart; an unknown term is refused" *
          par2d::test::per_isa()) {
  TempDir dir("par2d_bounce_cli");
  {
    std::ofstream(dir / "scene.json")
        << R"({"width": 24, "height": 16, "lights": [{"circle": {"center": [4, 4], "radius": 1.5}, "intensity": 3}],)"
           R"( "occluders": [{"polygon": [[10, 2], [12, 2], [12, 12], [10, 12]], "albedo": [0.8, 0.4, 0.2]}]})";
  }
  Scene scene;
  REQUIRE(par2d::load_scene_file(dir / "scene.json", scene).ok());
  for (const par2d::BounceTerm term :
       {par2d::BounceTerm::included, par2d::BounceTerm::excluded, par2d::BounceTerm::only}) {
    const std::string name = par2d::bounce_term_name(term);
    CAPTURE(name);
    REQUIRE(run_cli({"render", dir / "scene.json", "--bounce", name, "--pfm", dir / (name + ".pfm")}) == 0);
    CHECK(read_pfm_file(dir / (name + ".pfm")) == render_direct(scene, true, term));
  }
  CHECK(read_pfm_file(dir / "only.pfm") != read_pfm_file(dir / "included.pfm"));
  std::string err;
  CHECK(run_cli_err({"render", dir / "scene.json", "--bounce", "indirect", "--pfm", dir / "x.pfm"}, err) == 2);
  CHECK(err.find("unknown bounce term 'indirect' (expected included, excluded or only)") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.pfm"));
}

TEST_CASE("a large normal map is checked in blocks: the first bad pixel of a late block is named, tiny normals pass") {
  Scene scene;
  scene.width = 1500;
  scene.height = 7;  // 10500 pixels: ten blocks of 1024 and a partial one
  scene.view = {0, 0, 1500, 7};
  par2d::NormalMap map;
  map.width = scene.width;
  map.height = scene.height;
  map.normals.assign(3 * static_cast<std::size_t>(map.width) * map.height, 0.0f);
  for (std::size_t p = 2; p < map.normals.size(); p += 3) map.normals[p] = 1.0f;
  map.normals[3 * 9000 + 2] = 1e-45f;  // subnormal but not zero: a direction
  scene.normal_map = map;
  REQUIRE(par2d::validate_scene(scene).ok());
  auto message = [&] { return par2d::validate_scene(scene, "code").message(); };
  auto at = [&](int i, int j, int c) -> float& {
    return scene.normal_map->normals[3 * (static_cast<std::size_t>(j) * 1500 + static_cast<std::size_t>(i)) +
                                     static_cast<std::size_t>(c)];
  };
  at(1499, 6, 0) = std::numeric_limits<float>::infinity();  // the last pixel, in the partial block
  CHECK(message() == "code: normal_map: pixel (1499, 6): not a finite normal (inf, 0, 1)");
  at(3, 5, 2) = -0.0f;  // a negative zero is zero too; this pixel comes first
  CHECK(message() == "code: normal_map: pixel (3, 5): has a zero normal");
  at(1023, 0, 1) = -std::numeric_limits<float>::infinity();  // the last pixel of the first block
  CHECK(message() == "code: normal_map: pixel (1023, 0): not a finite normal (0, -inf, 1)");
}

TEST_CASE("a normal map's declared size is checked from its PNG header, before any pixel is decoded") {
  // The issue: a tiny PNG declaring a huge size was decoded whole (gigabytes, half a minute)
  // before its size was compared with the scene's. These files hold no pixel data, so a
  // message naming their declared size can only have come from the header.
  TempDir dir("par2d_model_io");
  { std::ofstream(dir / "huge.png", std::ios::binary) << header_only_png(16000, 16000); }
  { std::ofstream(dir / "huger.png", std::ios::binary) << header_only_png(60000, 60000); }
  { std::ofstream(dir / "wide.png", std::ios::binary) << header_only_png(4, 60000); }
  REQUIRE(fs::file_size(dir / "huge.png") < 100u);
  for (const char* name : {"huge.png", "huger.png", "wide.png"}) {
    std::ofstream(dir / "s.json") << scene_with(std::string(R"("normal_map": ")") + name + R"(")");
    Scene scene;
    const Status status = par2d::load_scene_file(dir / "s.json", scene);
    CAPTURE(status.message());
    CHECK(status.code() == StatusCode::invalid_scene);
    const std::string declared = name == std::string("huge.png") ? "16000x16000" : name == std::string("huger.png") ? "60000x60000" : "4x60000";
    CHECK(status.message() == (dir / "s.json") + ": normal_map: " + (dir / name) + ": is " + declared +
                                  " but the image is 4x3 (it must be exactly the image's size)");
    CHECK_FALSE(scene.normal_map.has_value());
  }
  // The loaders for maps given through the API (C and Python use them) read the header first too.
  par2d::NormalMap map;
  Status status = par2d::load_normal_map_png(dir / "huge.png", map, 4, 3);
  CHECK(status.message() == (dir / "huge.png") + ": is 16000x16000 but the image is 4x3 (it must be exactly the image's size)");
  status = par2d::load_normal_map_png(dir / "huger.png", map);
  CHECK(status.message() == (dir / "huger.png") + ": is 60000x60000, larger than any image");
  CHECK(par2d::load_normal_map_png(dir / "huge.png", map, 0, 3).code() == StatusCode::invalid_argument);
  // A real map of the right size still loads through the sized form.
  write_png(dir / "ok.png", 4, 3, 3, {128, 128, 255});
  REQUIRE(par2d::load_normal_map_png(dir / "ok.png", map, 4, 3).ok());
  CHECK(map.width == 4);
}

TEST_CASE("normal_map paths stay inside the scene's folder unless any path is allowed") {
  TempDir dir("par2d_model_io");
  fs::create_directories(dir / "scenes/maps");
  write_png(dir / "scenes/maps/n.png", 4, 3, 3, {128, 128, 255});
  write_png(dir / "outside.png", 4, 3, 3, {128, 128, 255});
  fs::create_symlink("../../outside.png", dir / "scenes/maps/escape.png");  // leaves the folder
  fs::create_symlink("n.png", dir / "scenes/maps/inside.png");              // stays inside
  const std::string scene_path = dir / "scenes/s.json";
  auto load = [&](const std::string& map, bool allow_any_path) {
    std::ofstream(scene_path) << scene_with(std::string(R"("normal_map": ")") + map + "\"");
    Scene scene;
    par2d::LoadOptions options;
    options.allow_any_path = allow_any_path;
    return par2d::load_scene_file(scene_path, scene, options);
  };
  const std::string leaves = scene_path + ": normal_map: path leaves the scene's folder";
  const std::string absolute = scene_path + ": normal_map: path is absolute; it must be relative to the scene's folder";
  // Refused by default, before the file is opened (a missing file gets the same answer).
  CHECK(load(dir / "outside.png", false).message() == absolute);
  CHECK(load(dir / "scenes/maps/n.png", false).message() == absolute);  // even when it points inside
  CHECK(load("../outside.png", false).message() == leaves);
  CHECK(load("maps/../../outside.png", false).message() == leaves);
  CHECK(load("../missing.png", false).message() == leaves);
  CHECK(load("maps/escape.png", false).message() == leaves);
  CHECK(load("maps/escape.png", false).code() == StatusCode::invalid_scene);
  // Inside the folder, by any route.
  CHECK(load("maps/n.png", false).ok());
  CHECK(load("maps/../maps/./n.png", false).ok());
  CHECK(load("maps/inside.png", false).ok());
  // The opt-in takes any path.
  CHECK(load(dir / "outside.png", true).ok());
  CHECK(load("../outside.png", true).ok());
  CHECK(load("maps/escape.png", true).ok());
  // Scene text without a file: its folder is that of the name, the current directory for a
  // bare name; the same rule applies.
  Scene scene;
  CHECK(par2d::parse_scene(scene_with(R"("normal_map": "../x.png")"), "s.json", scene).message() ==
        "s.json: normal_map: path leaves the scene's folder");
  CHECK(par2d::parse_scene(scene_with(R"("normal_map": "/x.png")"), "s.json", scene).message() ==
        "s.json: normal_map: path is absolute; it must be relative to the scene's folder");
  par2d::LoadOptions any;
  any.allow_any_path = true;
  CHECK(par2d::parse_scene(scene_with(R"("normal_map": ")" + (dir / "outside.png") + R"(")"), "s.json", scene, any).ok());

  // The CLI: refused by default (one line, nothing written), accepted with --allow-any-path.
  std::ofstream(scene_path) << scene_with(R"("normal_map": "../outside.png")");
  std::string err;
  CHECK(run_cli_err({"render", scene_path, "--backend", "scalar", "-o", dir / "out.png"}, err) == 1);
  CHECK(err == "par2d: " + leaves + "\n");
  CHECK_FALSE(fs::exists(dir / "out.png"));
  CHECK(run_cli_err({"bench", scene_path, "--backend", "scalar", "--frames", "1"}, err) == 1);
  CHECK(err == "par2d: " + leaves + "\n");
  CHECK(run_cli_err({"render", scene_path, "--backend", "scalar", "--allow-any-path", "-o", dir / "out.png"}, err) == 0);
  CHECK(err.empty());
  CHECK(fs::exists(dir / "out.png"));
}

TEST_CASE("an output that is the scene's normal map, by any name, is refused before anything is written") {
  TempDir dir("par2d_model_io");
  fs::create_directory(dir / "maps");
  write_png(dir / "maps/n.png", 4, 3, 3, {128, 128, 255});
  const std::string original = file_bytes(dir / "maps/n.png");
  fs::create_symlink("maps/n.png", dir / "link.pfm");
  fs::create_hard_link(dir / "maps/n.png", dir / "hard.png");
  std::ofstream(dir / "s.json") << scene_with(R"("normal_map": "maps/n.png")");
  for (const char* option : {"-o", "--pfm", "--plain-png", "--plain-pfm"}) {
    for (const std::string& name : {dir / "maps/n.png", dir / "link.pfm", dir / "hard.png"}) {
      std::string err;
      CAPTURE(option);
      CAPTURE(name);
      CHECK(run_cli_err({"render", dir / "s.json", "--backend", "scalar", option, name}, err) == 2);
      CAPTURE(err);
      CHECK(err == "par2d: render: " + std::string(option) + " '" + name + "' is the scene's normal map '" +
                       (dir / "maps/n.png") + "': an output may not replace an input\n");
      CHECK(file_bytes(dir / "maps/n.png") == original);
    }
  }
  // Through a link the scene file names, and with any path allowed: the same.
  fs::create_symlink("n.png", dir / "maps/alias.png");
  std::ofstream(dir / "s.json") << scene_with(R"("normal_map": "maps/alias.png")");
  std::string err;
  CHECK(run_cli_err({"render", dir / "s.json", "--allow-any-path", "--pfm", dir / "hard.png"}, err) == 2);
  CHECK(file_bytes(dir / "maps/n.png") == original);
}

TEST_CASE("bench --width/--height on a normal-mapped scene is refused naming the scene file") {
  TempDir dir("par2d_model_io");
  write_png(dir / "n.png", 4, 3, 3, {128, 128, 255});
  std::ofstream(dir / "s.json") << scene_with(R"("normal_map": "n.png")");
  for (const std::vector<std::string>& size : {std::vector<std::string>{"--width", "8"}, std::vector<std::string>{"--height", "5"}}) {
    std::vector<std::string> args{"bench", dir / "s.json", "--backend", "scalar", "--frames", "1"};
    args.insert(args.end(), size.begin(), size.end());
    std::string err;
    CHECK(run_cli_err(args, err) == 2);
    CAPTURE(err);
    CHECK(err.rfind("par2d: " + (dir / "s.json") + ": normal_map: n.png is 4x3 but --width/--height make the image ", 0) == 0);
    CHECK(err.find('\n') == err.size() - 1);
  }
  // Its own size is fine.
  std::string err;
  CHECK(run_cli_err({"bench", dir / "s.json", "--backend", "scalar", "--frames", "1", "--width", "4"}, err) == 0);
}

// `bench --stats` puts the kernel's pairs per sample against the pairs each pixel needs
// (a measure of wasted kernel work): the ratio of the two numbers it prints.
TEST_CASE("bench --stats puts the pairs per sample against the exact pairs per pixel") {
  TempDir dir("par2d_model_io");
  std::ofstream(dir / "s.json") << R"({"width": 96, "height": 64, "lights": [{"circle": {"center": [20, 30], "radius": 4}}],
    "occluders": [{"circle": {"center": [40, 30], "radius": 5}}, {"polygon": [[60, 10], [70, 10], [70, 50], [60, 50]]},
                  {"circle": {"center": [30, 50], "radius": 3}}]})";
  std::string out;
  REQUIRE(run_cli_capture({"bench", dir / "s.json", "--frames", "1", "--threads", "1", "--stats"}, 1, out) == 0);
  CAPTURE(out);
  double arcs = 0, kernel = 0, visible = 0, exact = 0, ratio = 0;
  const std::size_t at_kernel = out.find("per sample (kernel):"), at_exact = out.find("sampled pixels):");
  REQUIRE(at_kernel != std::string::npos);
  REQUIRE(at_exact != std::string::npos);
  REQUIRE(std::sscanf(out.c_str() + at_kernel, "per sample (kernel): %lf light arcs, %lf pairs", &arcs, &kernel) == 2);
  REQUIRE(std::sscanf(out.c_str() + at_exact,
                      "sampled pixels): %lf lights visible, %lf occluders cutting into their arcs; the kernel takes %lfx",
                      &visible, &exact, &ratio) == 3);
  REQUIRE(exact > 0.0);
  CHECK(std::abs(ratio - kernel / exact) <= 0.05 * ratio + 0.01);  // the printed numbers are rounded
}
