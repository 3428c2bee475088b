// polygons_from_alpha and `par2d outline`: exact pixel outlines, holes, diagonal touches, noise, a drawn sprite.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <spawn.h>
#include <stb/stb_image_write.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/polygon_partition.hpp"
#include "par2d/alpha_outline.hpp"
#include "par2d/render.hpp"
#include "par2d/scene.hpp"
#include "support/temp_dir.hpp"
#include "support/test_tiers.hpp"

extern char** environ;

using namespace par2d;
using par2d::test::TempDir;

namespace {

struct Mask {
  int width = 0, height = 0;
  std::vector<std::uint8_t> alpha;
  bool solid(int x, int y) const {
    return x >= 0 && y >= 0 && x < width && y < height && alpha[static_cast<std::size_t>(y) * width + x] >= 128;
  }
  AlphaMask view() const { return AlphaMask{alpha.data(), width, height, width, 1}; }
  int count() const {
    int n = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) n += solid(x, y);
    return n;
  }
};

// '#' solid (alpha 255), anything else empty (alpha 0).
Mask drawn(const std::vector<std::string>& rows) {
  Mask m;
  m.height = static_cast<int>(rows.size());
  m.width = static_cast<int>(rows[0].size());
  for (const std::string& row : rows)
    for (char c : row) m.alpha.push_back(c == '#' ? 255 : 0);
  return m;
}

Mask noise(std::mt19937& rng, int width, int height, double density) {
  Mask m{width, height, {}};
  std::bernoulli_distribution solid(density);
  for (int k = 0; k < width * height; ++k) m.alpha.push_back(solid(rng) ? 200 : 30);
  return m;
}

std::vector<Polygon> outline(const Mask& m, double tolerance, std::size_t max_vertices = kMaxOutlineVertices) {
  AlphaOutlineOptions options;
  options.tolerance = tolerance;
  options.max_vertices = max_vertices;
  std::vector<Polygon> out;
  const Status s = polygons_from_alpha(m.view(), options, out);
  REQUIRE_MESSAGE(s.ok(), s.message());
  return out;
}

double ring_area(const std::vector<Vec2>& r) {
  double a = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Vec2 p = r[i], q = r[(i + 1) % r.size()];
    a += p.x * q.y - p.y * q.x;
  }
  return a / 2.0;
}

double polygon_area(const Polygon& p) {
  double a = std::fabs(ring_area(p.vertices));
  for (const auto& hole : p.holes) a -= std::fabs(ring_area(hole));
  return a;
}

std::vector<std::vector<Vec2>> all_rings(const std::vector<Polygon>& polygons) {
  std::vector<std::vector<Vec2>> rings;
  for (const Polygon& p : polygons) {
    rings.push_back(p.vertices);
    for (const auto& hole : p.holes) rings.push_back(hole);
  }
  return rings;
}

bool on_segment(Vec2 a, Vec2 b, Vec2 q) {
  return detail::orientation(a, b, q) == 0 && q.x >= std::min(a.x, b.x) && q.x <= std::max(a.x, b.x) &&
         q.y >= std::min(a.y, b.y) && q.y <= std::max(a.y, b.y);
}

// Whether the closed segments a-b and c-d share a point (exact).
bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = detail::orientation(a, b, c), o2 = detail::orientation(a, b, d);
  const int o3 = detail::orientation(c, d, a), o4 = detail::orientation(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return on_segment(a, b, c) || on_segment(a, b, d) || on_segment(c, d, a) || on_segment(c, d, b);
}

// No two edges of any rings meet, but consecutive edges of one ring at their shared vertex.
void check_apart(const std::vector<Polygon>& polygons) {
  const auto rings = all_rings(polygons);
  struct Edge {
    Vec2 a, b;
    std::size_t ring, index;
  };
  std::vector<Edge> edges;
  for (std::size_t r = 0; r < rings.size(); ++r)
    for (std::size_t i = 0; i < rings[r].size(); ++i)
      edges.push_back({rings[r][i], rings[r][(i + 1) % rings[r].size()], r, i});
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const Edge &e = edges[i], &f = edges[j];
      if (e.ring == f.ring) {
        const std::size_t n = rings[e.ring].size();
        if ((e.index + 1) % n == f.index || (f.index + 1) % n == e.index) continue;
      }
      if (segments_meet(e.a, e.b, f.a, f.b)) {
        FAIL_CHECK("rings " << e.ring << " and " << f.ring << " meet (edges " << e.index << ", " << f.index << ")");
        return;
      }
    }
}

void check_valid(const std::vector<Polygon>& polygons, int width, int height) {
  Scene scene;
  scene.width = width;
  scene.height = height;
  scene.view = {0, 0, static_cast<double>(width), static_cast<double>(height)};
  for (const Polygon& p : polygons) scene.occluders.push_back(Occluder{p});
  const Status s = validate_scene(scene);
  CHECK_MESSAGE(s.ok(), s.message());
  check_apart(polygons);
}

double point_segment_distance(Vec2 q, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((q.x - a.x) * dx + (q.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(q.x - a.x - t * dx, q.y - a.y - t * dy);
}

// The unit edges between solid and empty pixels.
std::vector<std::pair<Vec2, Vec2>> pixel_boundary(const Mask& m) {
  std::vector<std::pair<Vec2, Vec2>> out;
  for (int y = 0; y <= m.height; ++y)
    for (int x = 0; x <= m.width; ++x) {
      if (x < m.width && m.solid(x, y) != m.solid(x, y - 1)) out.push_back({{1.0 * x, 1.0 * y}, {x + 1.0, 1.0 * y}});
      if (y < m.height && m.solid(x, y) != m.solid(x - 1, y)) out.push_back({{1.0 * x, 1.0 * y}, {1.0 * x, y + 1.0}});
    }
  return out;
}

// Sample points along segments: ends and 7 between.
std::vector<Vec2> samples(const std::vector<std::pair<Vec2, Vec2>>& segments) {
  std::vector<Vec2> out;
  for (const auto& [a, b] : segments)
    for (int k = 0; k <= 8; ++k) out.push_back({a.x + (b.x - a.x) * k / 8.0, a.y + (b.y - a.y) * k / 8.0});
  return out;
}

double farthest(const std::vector<Vec2>& points, const std::vector<std::pair<Vec2, Vec2>>& segments) {
  double worst = 0.0;
  for (const Vec2& q : points) {
    double best = INFINITY;
    for (const auto& [a, b] : segments) best = std::min(best, point_segment_distance(q, a, b));
    worst = std::max(worst, best);
  }
  return worst;
}

// Both ways: every outline point near the pixel boundary and every boundary point near an outline.
double hausdorff_to_pixels(const std::vector<Polygon>& polygons, const Mask& m) {
  std::vector<std::pair<Vec2, Vec2>> edges;
  for (const auto& ring : all_rings(polygons))
    for (std::size_t i = 0; i < ring.size(); ++i) edges.push_back({ring[i], ring[(i + 1) % ring.size()]});
  const auto boundary = pixel_boundary(m);
  return std::max(farthest(samples(edges), boundary), farthest(samples(boundary), edges));
}

std::size_t vertices_of(const Polygon& p) {
  std::size_t n = p.vertices.size();
  for (const auto& hole : p.holes) n += hole.size();
  return n;
}

const double kSaddleReach = kSaddleShift * std::sqrt(2.0);

}  // namespace

TEST_CASE("alpha outline: a filled 3x3 square is one polygon with its 4 corners, clockwise on screen") {
  const Mask m = drawn({".....", ".###.", ".###.", ".###.", "....."});
  for (double tolerance : {0.0, 0.5, 2.0}) {
    const auto polygons = outline(m, tolerance);
    REQUIRE(polygons.size() == 1);
    CHECK(polygons[0].holes.empty());
    REQUIRE(polygons[0].vertices.size() == 4);
    CHECK(ring_area(polygons[0].vertices) == 9.0);  // positive with y down: clockwise on screen
    for (const Vec2& v : polygons[0].vertices) {
      CHECK((v.x == 1.0 || v.x == 4.0));
      CHECK((v.y == 1.0 || v.y == 4.0));
    }
  }
}

TEST_CASE("alpha outline: a ring of pixels is one polygon with one hole, area 24, the hole the other way round") {
  const Mask m = drawn({"#####", "#####", "##.##", "#####", "#####"});
  const auto polygons = outline(m, 0.0);
  REQUIRE(polygons.size() == 1);
  REQUIRE(polygons[0].holes.size() == 1);
  CHECK(polygons[0].vertices.size() == 4);
  CHECK(polygons[0].holes[0].size() == 4);
  CHECK(ring_area(polygons[0].vertices) > 0.0);
  CHECK(ring_area(polygons[0].holes[0]) == -1.0);
  CHECK(polygon_area(polygons[0]) == 24.0);
  check_valid(polygons, m.width, m.height);
  // A hole one pixel from the outline survives any tolerance: it cannot touch the outline.
  for (double tolerance : {0.5, 1.0, 3.0}) {
    const auto simplified = outline(m, tolerance);
    REQUIRE(simplified.size() == 1);
    CHECK(simplified[0].holes.size() == 1);
    check_valid(simplified, m.width, m.height);
  }
}

TEST_CASE("alpha outline: squares touching only at a corner are one polygon with a neck, area exact, valid") {
  const Mask m = drawn({"##..", "##..", "..##", "..##"});
  const auto polygons = outline(m, 0.0);
  REQUIRE(polygons.size() == 1);
  CHECK(polygons[0].holes.empty());
  CHECK(polygon_area(polygons[0]) == 8.0);
  check_valid(polygons, m.width, m.height);
  CHECK(hausdorff_to_pixels(polygons, m) <= kSaddleReach + 1e-12);
  // The two passes of the shared corner are kept apart, not merged into one vertex.
  std::size_t near_corner = 0;
  for (const Vec2& v : polygons[0].vertices) near_corner += std::hypot(v.x - 2.0, v.y - 2.0) < 0.1;
  CHECK(near_corner == 2);
  // Diagonal empty pixels do not join holes: two holes, each valid and apart.
  const Mask holes = drawn({"######", "##.###", "###.##", "######"});
  const auto holed = outline(holes, 0.0);
  REQUIRE(holed.size() == 1);
  CHECK(holed[0].holes.size() == 2);
  CHECK(polygon_area(holed[0]) == 22.0);
  check_valid(holed, holes.width, holes.height);
}

TEST_CASE("alpha outline: a one-pixel bridge and a one-pixel gap stay valid at every tolerance") {
  const Mask bridge = drawn({"###...###", "#########", "###...###"});
  const Mask gap = drawn({"###.###", "###.###", "###.###", "#######"});
  const Mask comb = drawn({"#.#.#.#", "#.#.#.#", "#######", "#.#.#.#"});
  for (const Mask* m : {&bridge, &gap, &comb}) {
    for (double tolerance : {0.0, 0.3, 0.5, 0.9, 1.5, 4.0}) {
      CAPTURE(tolerance);
      const auto polygons = outline(*m, tolerance);
      REQUIRE(polygons.size() == 1);
      check_valid(polygons, m->width, m->height);
      CHECK(hausdorff_to_pixels(polygons, *m) <= std::max(tolerance, kSaddleReach) + 1e-9);
      if (tolerance == 0.0) CHECK(polygon_area(polygons[0]) == m->count());
    }
  }
}

TEST_CASE("alpha outline: a 45-degree staircase keeps its steps below a tolerance of 0.73 and is one edge above") {
  Mask m{8, 8, {}};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) m.alpha.push_back(x <= y ? 255 : 0);
  const auto exact = outline(m, 0.0);
  REQUIRE(exact.size() == 1);
  CHECK(exact[0].vertices.size() == 18);             // (k, k) for k = 0 .. 8, (k + 1, k) for k = 0 .. 7, and (0, 8)
  CHECK(outline(m, 0.72)[0].vertices.size() == 18);  // 0.707 + kSaddleShift * sqrt(2) = 0.729 needed
  const auto straight = outline(m, 0.74);
  REQUIRE(straight.size() == 1);
  CHECK(straight[0].vertices.size() == 3);
  check_valid(straight, 8, 8);
  CHECK(hausdorff_to_pixels(straight, m) <= 0.74);
}

TEST_CASE("alpha outline: a checkerboard (every corner a diagonal touch) is one valid polygon of exact area") {
  Mask m{8, 8, {}};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) m.alpha.push_back((x + y) % 2 == 0 ? 255 : 0);
  for (double tolerance : {0.0, 0.5, 1.0}) {
    const auto polygons = outline(m, tolerance);
    REQUIRE(polygons.size() == 1);
    check_valid(polygons, 8, 8);
    if (tolerance == 0.0) CHECK(polygon_area(polygons[0]) == 32.0);
  }
}

TEST_CASE("alpha outline: random noise masks give valid, apart polygons within the tolerance, exact area at 0") {
  std::mt19937 rng(20261207);
  int cases = 0;
  for (int seed = 0; seed < 120; ++seed) {
    std::uniform_int_distribution<int> side(1, 20);
    const int width = side(rng), height = side(rng);
    const double density = std::uniform_real_distribution<double>(0.2, 0.8)(rng);
    const Mask m = noise(rng, width, height, density);
    for (double tolerance : {0.0, 0.4, 1.0, 2.5}) {
      CAPTURE(seed);
      CAPTURE(tolerance);
      const auto polygons = outline(m, tolerance);
      check_valid(polygons, width, height);
      double area = 0.0;
      for (const Polygon& p : polygons) area += polygon_area(p);
      if (tolerance == 0.0) CHECK(area == m.count());
      if (m.count() > 0) CHECK(hausdorff_to_pixels(polygons, m) <= std::max(tolerance, kSaddleReach) + 1e-9);
      ++cases;
    }
  }
  CHECK(cases == 480);
}

TEST_CASE("alpha outline: larger noise masks of every density, more seeds" * par2d::test::long_tier()) {
  std::mt19937 rng(99);
  for (int seed = 0; seed < 400; ++seed) {
    std::uniform_int_distribution<int> side(20, 48);
    const int width = side(rng), height = side(rng);
    const Mask m = noise(rng, width, height, std::uniform_real_distribution<double>(0.05, 0.95)(rng));
    for (double tolerance : {0.0, 0.6, 1.2, 5.0}) {
      CAPTURE(seed);
      CAPTURE(tolerance);
      const auto polygons = outline(m, tolerance);
      check_valid(polygons, width, height);
      if (tolerance == 0.0) {
        double area = 0.0;
        for (const Polygon& p : polygons) area += polygon_area(p);
        CHECK(area == m.count());
      }
    }
  }
}

TEST_CASE("alpha outline: the vertex bound holds or the polygon over it is named") {
  std::mt19937 rng(7);
  const Mask m = noise(rng, 24, 24, 0.7);
  const auto free = outline(m, 0.0);
  std::size_t most = 0;
  for (const Polygon& p : free) most = std::max(most, vertices_of(p));
  REQUIRE(most > 12);
  // A bound the polygons meet is met.
  for (const Polygon& p : outline(m, 0.0, most)) CHECK(vertices_of(p) <= most);
  // One they do not is refused, naming the polygon, and nothing is returned.
  AlphaOutlineOptions options;
  options.tolerance = 0.0;
  options.max_vertices = most - 1;
  std::vector<Polygon> out{Polygon{}};
  const Status s = polygons_from_alpha(m.view(), options, out);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(s.message().find("needs " + std::to_string(most) + " vertices") != std::string::npos);
  CHECK(s.message().find("max_vertices") != std::string::npos);
  CHECK(out.empty());
  // A larger tolerance simplifies further: fewer vertices.
  std::size_t simplified = 0;
  for (const Polygon& p : outline(m, 2.0)) simplified = std::max(simplified, vertices_of(p));
  CHECK(simplified < most);
}

TEST_CASE("alpha outline: placement scales and offsets (a negative scale mirrors) and RGBA reads the alpha byte") {
  const Mask m = drawn({"##.", "###", ".##"});
  AlphaOutlineOptions options;
  options.tolerance = 0.0;
  options.scale = {2.0, -0.5};
  options.offset = {10.0, 20.0};
  std::vector<Polygon> placed;
  REQUIRE(polygons_from_alpha(m.view(), options, placed).ok());
  REQUIRE(placed.size() == 1);
  CHECK(polygon_area(placed[0]) == 7.0);
  for (const Vec2& v : placed[0].vertices) {
    CHECK(v.x >= 10.0);
    CHECK(v.x <= 16.0);
    CHECK(v.y <= 20.0);
    CHECK(v.y >= 18.5);
  }
  // The same mask as RGBA8: the alpha byte of each 4.
  std::vector<std::uint8_t> rgba;
  for (std::uint8_t a : m.alpha) rgba.insert(rgba.end(), {17, 99, 250, a});
  rgba.insert(rgba.end(), 8, 0);  // row padding does not matter: the stride says where rows start
  AlphaMask view{rgba.data() + 3, 3, 3, 12, 4};
  std::vector<Polygon> from_rgba;
  REQUIRE(polygons_from_alpha(view, AlphaOutlineOptions{}, from_rgba).ok());
  const auto from_plane = outline(m, AlphaOutlineOptions{}.tolerance);
  REQUIRE(from_rgba.size() == from_plane.size());
  for (std::size_t k = 0; k < from_rgba.size(); ++k) {
    REQUIRE(from_rgba[k].vertices.size() == from_plane[k].vertices.size());
    for (std::size_t i = 0; i < from_plane[k].vertices.size(); ++i) {
      CHECK(from_rgba[k].vertices[i].x == from_plane[k].vertices[i].x);
      CHECK(from_rgba[k].vertices[i].y == from_plane[k].vertices[i].y);
    }
  }
}

TEST_CASE("alpha outline: the threshold decides solid (alpha >= threshold); an empty mask gives no polygon") {
  Mask m{3, 1, {10, 128, 255}};
  AlphaOutlineOptions options;
  options.tolerance = 0.0;
  std::vector<Polygon> out;
  for (const auto& [threshold, area] :
       {std::pair{0, 3.0}, std::pair{11, 2.0}, std::pair{129, 1.0}, std::pair{255, 1.0}}) {
    options.threshold = threshold;
    REQUIRE(polygons_from_alpha(m.view(), options, out).ok());
    REQUIRE(out.size() == 1);
    CHECK(polygon_area(out[0]) == area);
  }
  const Mask empty{4, 4, std::vector<std::uint8_t>(16, 0)};
  REQUIRE(polygons_from_alpha(empty.view(), AlphaOutlineOptions{}, out).ok());
  CHECK(out.empty());
}

TEST_CASE("alpha outline: bad masks and options are refused naming the field") {
  const Mask m = drawn({"#"});
  std::vector<Polygon> out;
  auto refused = [&](AlphaMask mask, AlphaOutlineOptions options, const char* field) {
    const Status s = polygons_from_alpha(mask, options, out);
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK_MESSAGE(s.message().find(field) != std::string::npos, s.message());
    CHECK(out.empty());
  };
  AlphaMask mask = m.view();
  refused(AlphaMask{nullptr, 1, 1, 1, 1}, {}, "mask.alpha");
  refused(AlphaMask{m.alpha.data(), 0, 1, 1, 1}, {}, "mask size");
  refused(AlphaMask{m.alpha.data(), 1, kMaxImageSide + 1, 1, 1}, {}, "mask size");
  refused(AlphaMask{m.alpha.data(), 1, 1, 1, 0}, {}, "pixel_stride");
  refused(AlphaMask{m.alpha.data(), 2, 1, 1, 1}, {}, "row_stride");
  AlphaOutlineOptions o;
  o.threshold = 256;
  refused(mask, o, "threshold");
  o = {};
  o.tolerance = NAN;
  refused(mask, o, "tolerance");
  o.tolerance = -1;
  refused(mask, o, "tolerance");
  o = {};
  o.max_vertices = 2;
  refused(mask, o, "max_vertices");
  o.max_vertices = kMaxOutlineVertices + 1;
  refused(mask, o, "max_vertices");
  o = {};
  o.scale.y = 0;
  refused(mask, o, "scale.y");
  o = {};
  o.offset.x = INFINITY;
  refused(mask, o, "offset");
  // A placement whose rounding merges vertices (1 px at 1e17, where doubles are 16 apart) is
  // refused naming the polygon rather than returned invalid.
  const Mask ring = drawn({"###", "#.#", "###"});
  o = {};
  o.offset = {1e17, 0.0};
  const Status s = polygons_from_alpha(ring.view(), o, out);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK_MESSAGE(
      s.message().find("polygon 0 (from pixel (0, 0)) is not a valid polygon after placement") != std::string::npos,
      s.message());
  CHECK(out.empty());
}

namespace {

// A 48x48 RGBA sprite: an anti-aliased disc with an off-centre hole, two ears, a loose speck.
std::vector<std::uint8_t> sprite_rgba(int side) {
  std::vector<std::uint8_t> rgba;
  auto coverage = [](double inside) { return std::clamp(inside + 0.5, 0.0, 1.0); };
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double body = coverage(18.0 - std::hypot(px - 24.0, py - 27.0));
      const double hole = coverage(5.0 - std::hypot(px - 28.0, py - 24.0));
      const bool ear =
          py > 4.0 && py < 14.0 && (std::fabs(px - 14.0) < (py - 4.0) * 0.5 || std::fabs(px - 34.0) < (py - 4.0) * 0.5);
      const bool speck = x >= 2 && x < 4 && y >= 42 && y < 45;
      const double a = std::max({body * (1.0 - hole), ear ? 1.0 : 0.0, speck ? 1.0 : 0.0});
      rgba.insert(rgba.end(), {200, 120, 40, static_cast<std::uint8_t>(std::lround(255.0 * a))});
    }
  return rgba;
}

// Runs the CLI, standard error to `err_path` and, when given, standard output to `out_path`.
int run_cli(const std::vector<std::string>& args, const std::string& err_path, const std::string& out_path = "") {
  std::vector<char*> argv{const_cast<char*>(PAR2D_CLI_PATH)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  REQUIRE(posix_spawn_file_actions_init(&actions) == 0);
  REQUIRE(posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600) == 0);
  if (!out_path.empty())
    REQUIRE(posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600) == 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, PAR2D_CLI_PATH, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(spawned == 0);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool one_error_line(const std::string& err) { return err.rfind("par2d: ", 0) == 0 && err.find('\n') == err.size() - 1; }

}  // namespace

TEST_CASE("alpha outline: a drawn sprite PNG loads, outlines validly and renders with a light") {
  TempDir dir("par2d_outline");
  const int side = 48;
  const auto rgba = sprite_rgba(side);
  const std::string png = dir / "sprite.png";
  REQUIRE(stbi_write_png(png.c_str(), side, side, 4, rgba.data(), side * 4) != 0);
  AlphaImage image;
  REQUIRE(load_png_alpha(png, image).ok());
  REQUIRE(image.width == side);
  REQUIRE(image.height == side);
  for (std::size_t k = 0; k < image.alpha.size(); ++k) REQUIRE(image.alpha[k] == rgba[4 * k + 3]);

  Mask m{side, side, image.alpha};
  for (double tolerance : {0.0, 0.5, 1.5}) {
    CAPTURE(tolerance);
    const auto polygons = outline(m, tolerance);
    REQUIRE(polygons.size() == 2);  // the body with its ears, and the speck
    CHECK(polygons[0].holes.size() == 1);
    check_valid(polygons, side, side);
    CHECK(hausdorff_to_pixels(polygons, m) <= std::max(tolerance, kSaddleReach) + 1e-9);
    if (tolerance == 0.0) CHECK(polygon_area(polygons[0]) + polygon_area(polygons[1]) == m.count());

    Scene scene;
    scene.width = scene.height = side;
    scene.view = {0, 0, 1.0 * side, 1.0 * side};
    scene.lights.push_back(Light{Circle{{44.0, 4.0}, 1.5}});
    for (const Polygon& p : polygons) scene.occluders.push_back(Occluder{p});
    std::vector<float> pixels(3 * side * side, -1.0f);
    RenderOptions options;
    options.backend = Backend::scalar;
    const Status s = render(scene, options, ImageView{pixels.data(), side, side, 3 * side});
    REQUIRE_MESSAGE(s.ok(), s.message());
    CHECK(std::all_of(pixels.begin(), pixels.end(), [](float v) { return std::isfinite(v) && v >= 0.0f; }));
    // Lit beside the light, dark in the body's shadow (a pixel outside the body behind it).
    CHECK(pixels[3 * (4 * side + 40)] > 0.0f);
    CHECK(pixels[3 * (44 * side + 10)] == 0.0f);
  }
}

TEST_CASE("par2d outline: writes a scene of the sprite's occluders that loads and renders; errors leave no file") {
  TempDir dir("par2d_outline_cli");
  const int side = 48;
  const auto rgba = sprite_rgba(side);
  const std::string png = dir / "sprite.png", json = dir / "occluders.json", err = dir / "err.txt";
  REQUIRE(stbi_write_png(png.c_str(), side, side, 4, rgba.data(), side * 4) != 0);
  const int status = run_cli({"outline", png, "--threshold", "100", "--tolerance", "0.75", "-o", json}, err);
  INFO(read_text(err));
  REQUIRE(status == 0);
  CHECK(read_text(err).empty());
  Scene scene;
  const Status loaded = load_scene_file(json, scene);
  REQUIRE_MESSAGE(loaded.ok(), loaded.message());
  CHECK(scene.width == side);
  CHECK(scene.lights.empty());
  // The file holds exactly what the library gives.
  AlphaImage image;
  REQUIRE(load_png_alpha(png, image).ok());
  AlphaOutlineOptions options;
  options.threshold = 100;
  options.tolerance = 0.75;
  std::vector<Polygon> expected;
  REQUIRE(polygons_from_alpha(image.mask(), options, expected).ok());
  REQUIRE(scene.occluders.size() == expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const auto& got = std::get<Polygon>(scene.occluders[k].shape);
    REQUIRE(got.vertices.size() == expected[k].vertices.size());
    CHECK(got.holes.size() == expected[k].holes.size());
    for (std::size_t i = 0; i < got.vertices.size(); ++i) {
      CHECK(got.vertices[i].x == expected[k].vertices[i].x);
      CHECK(got.vertices[i].y == expected[k].vertices[i].y);
    }
  }
  // "-" writes the same scene to standard output.
  REQUIRE(run_cli({"outline", png, "--threshold", "100", "--tolerance", "0.75", "-o", "-"}, err, dir / "stdout.json") ==
          0);
  CHECK(read_text(dir / "stdout.json") == read_text(json));
  // With a light added, the CLI renders it.
  std::string text = read_text(json);
  const std::string no_lights = R"("lights": [])";
  REQUIRE(text.find(no_lights) != std::string::npos);
  text.replace(text.find(no_lights), no_lights.size(), R"("lights": [{"circle": {"center": [44, 4], "radius": 1.5}}])");
  std::ofstream(dir / "lit.json") << text;
  REQUIRE(run_cli({"render", dir / "lit.json", "--backend", "scalar", "-o", dir / "lit.png"}, err) == 0);
  CHECK(read_text(dir / "lit.png").size() > 8);

  // Failures: one line naming the file and what is wrong, non-zero exit, the output untouched.
  std::ofstream(dir / "keep.json") << "old";
  const std::vector<unsigned char> rgb(3 * 4 * 4, 128);
  REQUIRE(stbi_write_png((dir / "rgb.png").c_str(), 4, 4, 3, rgb.data(), 12) != 0);
  std::ofstream(dir / "text.png") << "not a png";
  const struct {
    std::vector<std::string> args;
    std::string says;
  } failures[] = {
      {{"outline", dir / "missing.png", "-o", dir / "keep.json"}, "missing.png"},
      {{"outline", dir / "rgb.png", "-o", dir / "keep.json"}, "rgb.png: has no alpha channel"},
      {{"outline", dir / "text.png", "-o", dir / "keep.json"}, "text.png: not a PNG file"},
      {{"outline", png, "--max-vertices", "3", "-o", dir / "keep.json"}, "sprite.png: polygons_from_alpha: polygon 0"},
      {{"outline", png, "--tolerance", "-1", "-o", dir / "keep.json"}, "--tolerance"},
      {{"outline", png, "-o", dir / "no_such_dir/x.json"}, "no_such_dir"},
  };
  for (const auto& failure : failures) {
    CAPTURE(failure.says);
    CHECK(run_cli(failure.args, err) != 0);
    const std::string message = read_text(err);
    CHECK_MESSAGE(one_error_line(message), message);
    CHECK_MESSAGE(message.find(failure.says) != std::string::npos, message);
    CHECK(read_text(dir / "keep.json") == "old");
  }
  CHECK(!std::filesystem::exists(dir / "no_such_dir"));
}
