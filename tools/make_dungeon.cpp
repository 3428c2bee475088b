// Generates examples/dungeon.json (1920x1080 floor plan, 16 lights, ~200 occluders) deterministically to stdout.
//
// Usage: par2d_make_dungeon > examples/dungeon.json
// The output only depends on kSeed: std::mt19937's sequence is fixed by the standard, and
// we map it to numbers ourselves because the <random> distributions are not portable.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::uint32_t kSeed = 20240611;
constexpr double kWidth = 1920, kHeight = 1080;
constexpr double kWall = 12;          // wall thickness
constexpr double kLightMargin = 8;    // minimum gap between any light and any occluder
constexpr double kClutterMargin = 4;  // gap between clutter items, so shapes stay readable
constexpr double kPi = 3.14159265358979323846;

struct P {
  double x, y;
};

// Rounded to 0.1 so the JSON is short and the checks below see the numbers that get written.
double r1(double v) { return std::round(v * 10.0) / 10.0; }

class Rng {
 public:
  explicit Rng(std::uint32_t seed) : gen_(seed) {}
  double uniform(double a, double b) { return a + (b - a) * (static_cast<double>(gen_()) / 4294967296.0); }
  int integer(int a, int b) { return a + static_cast<int>(gen_() % static_cast<std::uint32_t>(b - a + 1)); }
  bool chance(double p) { return uniform(0, 1) < p; }

 private:
  std::mt19937 gen_;
};

// A conservative stand-in for a shape when checking clearance: every point within
// `radius` of the segment a-b (a disc when a == b). It always contains the real shape.
struct Capsule {
  P a, b;
  double radius;
};

double dot(P u, P v) { return u.x * v.x + u.y * v.y; }
P sub(P u, P v) { return {u.x - v.x, u.y - v.y}; }
double cross(P u, P v) { return u.x * v.y - u.y * v.x; }

double point_segment_distance(P p, P a, P b) {
  P ab = sub(b, a);
  double len2 = dot(ab, ab);
  double t = len2 > 0 ? std::clamp(dot(sub(p, a), ab) / len2, 0.0, 1.0) : 0.0;
  P q{a.x + t * ab.x - p.x, a.y + t * ab.y - p.y};
  return std::sqrt(dot(q, q));
}

bool segments_cross(P a, P b, P c, P d) {
  double d1 = cross(sub(b, a), sub(c, a)), d2 = cross(sub(b, a), sub(d, a));
  double d3 = cross(sub(d, c), sub(a, c)), d4 = cross(sub(d, c), sub(b, c));
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 &&
         d4 != 0;
}

double gap(const Capsule& u, const Capsule& v) {
  double d = 0;
  if (!segments_cross(u.a, u.b, v.a, v.b)) {
    d = std::min({point_segment_distance(u.a, v.a, v.b), point_segment_distance(u.b, v.a, v.b),
                  point_segment_distance(v.a, u.a, u.b), point_segment_distance(v.b, u.a, u.b)});
  }
  return d - u.radius - v.radius;
}

struct Item {
  std::string json;
  std::vector<Capsule> bounds;  // union covers the shape
  bool clean = true;            // no pixel center within kCenterGap of the boundary
};

// Pixel centers sit at k + 0.5. One lying (almost) on a shape boundary is where float and
// double paths may legitimately disagree (docs/contract.md section 5), so the example keeps clear.
constexpr double kCenterGap = 1e-3;

bool edge_clear_of_centers(P a, P b) {
  const int i0 = static_cast<int>(std::floor(std::min(a.x, b.x))) - 1;
  const int i1 = static_cast<int>(std::ceil(std::max(a.x, b.x))) + 1;
  const int j0 = static_cast<int>(std::floor(std::min(a.y, b.y))) - 1;
  const int j1 = static_cast<int>(std::ceil(std::max(a.y, b.y))) + 1;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      if (point_segment_distance({i + 0.5, j + 0.5}, a, b) < kCenterGap) return false;
  return true;
}

bool outline_clear_of_centers(const std::vector<P>& v, bool closed) {
  for (std::size_t k = 0; k + (closed ? 0 : 1) < v.size(); ++k)
    if (!edge_clear_of_centers(v[k], v[(k + 1) % v.size()])) return false;
  return true;
}

bool circle_clear_of_centers(P c, double r) {
  for (int j = static_cast<int>(std::floor(c.y - r)) - 1; j <= static_cast<int>(c.y + r) + 1; ++j)
    for (int i = static_cast<int>(std::floor(c.x - r)) - 1; i <= static_cast<int>(c.x + r) + 1; ++i)
      if (std::fabs(std::hypot(i + 0.5 - c.x, j + 0.5 - c.y) - r) < kCenterGap) return false;
  return true;
}

Capsule disc(P c, double r) { return {c, c, r}; }

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", r1(v));
  std::string s = buf;
  if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
  if (s == "-0") s = "0";
  return s;
}

std::string point(P p) { return "[" + num(p.x) + ", " + num(p.y) + "]"; }

std::string polygon_json(const std::vector<P>& v) {
  std::string s = "\"polygon\": [";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + point(v[i]);
  return s + "]";
}

// Axis-aligned rectangle [x0, x1] x [y0, y1] as a polygon, bounded by its own center line
// capsule (exact for thin walls, conservative at the corners).
// Corners are whole numbers so that no pixel center (at k + 0.5) lies exactly on a wall edge,
// where float and double paths may legitimately disagree about inside/outside.
Item rectangle(double x0, double y0, double x1, double y1) {
  x0 = std::round(x0), y0 = std::round(y0), x1 = std::round(x1), y1 = std::round(y1);
  Item it;
  it.json = "{ " + polygon_json({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) + " }";
  it.clean = outline_clear_of_centers({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, true);
  double hw = (x1 - x0) / 2, hh = (y1 - y0) / 2;
  P c{(x0 + x1) / 2, (y0 + y1) / 2};
  if (hw >= hh)
    it.bounds.push_back({{x0 + hh, c.y}, {x1 - hh, c.y}, hh * std::sqrt(2.0)});
  else
    it.bounds.push_back({{c.x, y0 + hw}, {c.x, y1 - hw}, hw * std::sqrt(2.0)});
  return it;
}

// A regular-ish convex polygon (crate, barrel rack, rubble block) with rounded vertices.
Item convex_blob(P c, double radius, int sides, double rotation, double squash) {
  std::vector<P> v;
  for (int k = 0; k < sides; ++k) {
    double a = rotation + 2 * kPi * k / sides;
    v.push_back({r1(c.x + radius * std::cos(a)), r1(c.y + squash * radius * std::sin(a))});
  }
  Item it;
  it.json = "{ " + polygon_json(v) + " }";
  it.bounds.push_back(disc(c, radius + 0.2));
  it.clean = outline_clear_of_centers(v, true);
  return it;
}

Item circle_item(P c, double r) {
  c = {r1(c.x), r1(c.y)};
  r = r1(r);
  Item it;
  it.json = "{ \"circle\": { \"center\": " + point(c) + ", \"radius\": " + num(r) + " } }";
  it.bounds.push_back(disc(c, r));
  it.clean = circle_clear_of_centers(c, r);
  return it;
}

Item segment_item(P a, P b) {
  a = {r1(a.x), r1(a.y)};
  b = {r1(b.x), r1(b.y)};
  Item it;
  it.json = "{ \"segment\": [" + point(a) + ", " + point(b) + "] }";
  it.bounds.push_back({a, b, 0.0});
  it.clean = outline_clear_of_centers({a, b}, false);
  return it;
}

std::string light_json(const Item& shape, double r, double g, double b, double intensity) {
  // Reuse the occluder JSON of the shape and add emission.
  std::string s = shape.json.substr(0, shape.json.size() - 2);
  char buf[128];
  std::snprintf(buf, sizeof buf, ", \"color\": [%.2f, %.2f, %.2f], \"intensity\": %g }", r, g, b,
                intensity);
  return s + buf;
}

double min_gap(const std::vector<Capsule>& a, const std::vector<Item>& items) {
  double best = 1e300;
  for (const Item& it : items)
    for (const Capsule& u : it.bounds)
      for (const Capsule& v : a) best = std::min(best, gap(u, v));
  return best;
}

struct Room {
  double x0, y0, x1, y1;  // floor inside the walls
};

}  // namespace

int main() {
  Rng rng(kSeed);
  std::vector<Item> walls, clutter, lights;
  std::vector<std::string> light_lines;
  std::vector<Capsule> doors;  // keep-out zones so doorways stay passable

  // Room grid: 4 x 3 rooms with jittered wall lines inside an outer wall.
  const double ox0 = 24, oy0 = 24, ox1 = kWidth - 24, oy1 = kHeight - 24;
  std::vector<double> xs{ox0}, ys{oy0};
  for (int k = 1; k < 4; ++k) xs.push_back(r1(ox0 + (ox1 - ox0) * k / 4 + rng.uniform(-50, 50)));
  xs.push_back(ox1);
  for (int k = 1; k < 3; ++k) ys.push_back(r1(oy0 + (oy1 - oy0) * k / 3 + rng.uniform(-40, 40)));
  ys.push_back(oy1);
  const double h = kWall / 2;

  // Outer wall, with a gap for the entrance at the bottom.
  const double entrance = r1((xs[1] + xs[2]) / 2);
  walls.push_back(rectangle(ox0 - h, oy0 - h, ox1 + h, oy0 + h));
  walls.push_back(rectangle(ox0 - h, oy1 - h, entrance - 40, oy1 + h));
  walls.push_back(rectangle(entrance + 40, oy1 - h, ox1 + h, oy1 + h));
  walls.push_back(rectangle(ox0 - h, oy0 - h, ox0 + h, oy1 + h));
  walls.push_back(rectangle(ox1 - h, oy0 - h, ox1 + h, oy1 + h));
  doors.push_back(disc({entrance, oy1}, 50));

  // Interior walls, each with one door; a couple of walls are ruined (segments with gaps).
  for (int c = 1; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) {
      double a = ys[r], b = ys[r + 1];
      double door = r1(rng.uniform(a + 70, b - 70)), half = r1(rng.uniform(28, 40));
      doors.push_back(disc({xs[c], door}, half + 12));
      if (c == 2 && r == 1) {  // a collapsed wall: broken segments instead of masonry
        // Nudge the broken ends until no pixel center lies on them (see kCenterGap).
        auto broken = [&](P p, P q) {
          Item it = segment_item(p, q);
          for (int k = 1; !it.clean && k < 20; ++k) it = segment_item(p, {q.x + 0.1 * k, q.y});
          return it;
        };
        walls.push_back(broken({xs[c] - 3, a + h}, {xs[c] + 4, door - half - 20}));
        walls.push_back(broken({xs[c] + 2, door + half + 20}, {xs[c] - 5, b - h}));
        continue;
      }
      walls.push_back(rectangle(xs[c] - h, a, xs[c] + h, door - half));
      walls.push_back(rectangle(xs[c] - h, door + half, xs[c] + h, b));
    }
  }
  for (int r = 1; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      double a = xs[c], b = xs[c + 1];
      double door = r1(rng.uniform(a + 80, b - 80)), half = r1(rng.uniform(28, 44));
      doors.push_back(disc({door, ys[r]}, half + 12));
      walls.push_back(rectangle(a, ys[r] - h, door - half, ys[r] + h));
      walls.push_back(rectangle(door + half, ys[r] - h, b, ys[r] + h));
    }
  }

  for (const Item& w : walls)
    if (!w.clean) std::fprintf(stderr, "par2d_make_dungeon: wall passes through a pixel center: %s\n", w.json.c_str());

  std::vector<Room> rooms;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) rooms.push_back({xs[c] + h, ys[r] + h, xs[c + 1] - h, ys[r + 1] - h});

  auto all_occluders = [&]() {
    std::vector<Item> v = walls;
    v.insert(v.end(), clutter.begin(), clutter.end());
    return v;
  };

  // Lights first, away from the walls; clutter is then kept clear of them.
  auto place_light = [&](const Room& room, auto make, double r, double g, double b, double intensity) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      P c{rng.uniform(room.x0 + 40, room.x1 - 40), rng.uniform(room.y0 + 40, room.y1 - 40)};
      Item it = make(c);
      if (!it.clean) continue;
      if (min_gap(it.bounds, all_occluders()) < 3 * kLightMargin) continue;
      if (min_gap(it.bounds, lights) < 120) continue;  // spread the light around
      light_lines.push_back(light_json(it, r, g, b, intensity));
      lights.push_back(it);
      return;
    }
    std::fprintf(stderr, "par2d_make_dungeon: could not place a light\n");
    std::exit(1);
  };
  for (const Room& room : rooms) {
    double radius = r1(rng.uniform(5, 8));
    place_light(room, [&](P c) { return circle_item(c, radius); }, 1.0, 0.62, 0.3,
                r1(rng.uniform(6, 9)));
  }
  // Four special lights: a magic pool, a lava crack, a blue crystal, a green rune stone.
  place_light(rooms[5], [&](P c) { return convex_blob(c, 18, 6, 0.3, 1.0); }, 0.35, 0.55, 1.0, 3);
  place_light(rooms[8], [&](P c) { return segment_item({c.x - 45, c.y + 10}, {c.x + 40, c.y - 12}); },
              1.0, 0.35, 0.1, 2.5);
  place_light(rooms[3], [&](P c) { return circle_item(c, 4); }, 0.4, 0.7, 1.0, 10);
  place_light(rooms[10], [&](P c) { return convex_blob(c, 9, 4, 0.7, 0.6); }, 0.4, 1.0, 0.5, 5);

  // Clutter: accept an item only if it keeps clear of lights, doors, walls and other clutter.
  auto try_place = [&](const Item& it) {
    if (!it.clean) return false;
    if (min_gap(it.bounds, lights) < kLightMargin) return false;
    if (min_gap(it.bounds, all_occluders()) < kClutterMargin) return false;
    for (const Capsule& d : doors)
      for (const Capsule& u : it.bounds)
        if (gap(u, d) < 0) return false;
    clutter.push_back(it);
    return true;
  };

  for (std::size_t k = 0; k < rooms.size(); ++k) {
    const Room& room = rooms[k];
    const double w = room.x1 - room.x0, hgt = room.y1 - room.y0;
    // Halls: a symmetric pillar colonnade.
    if (k % 3 != 1) {
      const int cols = w > 420 ? 3 : 2;
      const double pr = r1(rng.uniform(9, 15));
      for (int i = 0; i < cols; ++i)
        for (int j = 0; j < 2; ++j) {
          P c{room.x0 + w * (i + 1) / (cols + 1), room.y0 + hgt * (j == 0 ? 0.27 : 0.73)};
          try_place(circle_item(c, pr));
        }
    }
    // Storerooms get many crates, other rooms a few, mostly along the walls.
    const int crates = k % 3 == 1 ? 14 : 6;
    int placed = 0;
    for (int attempt = 0; attempt < 400 && placed < crates; ++attempt) {
      double size = rng.uniform(7, 15);
      P c;
      if (rng.chance(0.7)) {  // hug a wall
        switch (rng.integer(0, 3)) {
          case 0: c = {room.x0 + size + 6, rng.uniform(room.y0, room.y1)}; break;
          case 1: c = {room.x1 - size - 6, rng.uniform(room.y0, room.y1)}; break;
          case 2: c = {rng.uniform(room.x0, room.x1), room.y0 + size + 6}; break;
          default: c = {rng.uniform(room.x0, room.x1), room.y1 - size - 6}; break;
        }
      } else {
        c = {rng.uniform(room.x0 + 30, room.x1 - 30), rng.uniform(room.y0 + 30, room.y1 - 30)};
      }
      int sides = rng.chance(0.75) ? 4 : rng.integer(3, 6);
      double squash = sides == 4 ? rng.uniform(0.6, 1.0) : 1.0;
      if (try_place(convex_blob(c, size, sides, rng.uniform(0, kPi), squash))) ++placed;
    }
    // Rubble: short loose segments.
    for (int attempt = 0, n = 0; attempt < 100 && n < 2; ++attempt) {
      P a{rng.uniform(room.x0 + 20, room.x1 - 20), rng.uniform(room.y0 + 20, room.y1 - 20)};
      double ang = rng.uniform(0, kPi), len = rng.uniform(14, 30);
      if (try_place(segment_item(a, {a.x + len * std::cos(ang), a.y + len * std::sin(ang)}))) ++n;
    }
  }

  std::printf("{\n  \"width\": %d, \"height\": %d,\n  \"view\": [0, 0, %d, %d],\n", int(kWidth),
              int(kHeight), int(kWidth), int(kHeight));
  std::printf("  \"lights\": [\n");
  for (std::size_t i = 0; i < light_lines.size(); ++i)
    std::printf("    %s%s\n", light_lines[i].c_str(), i + 1 < light_lines.size() ? "," : "");
  std::printf("  ],\n  \"occluders\": [\n");
  std::vector<Item> occ = all_occluders();
  for (std::size_t i = 0; i < occ.size(); ++i)
    std::printf("    %s%s\n", occ[i].json.c_str(), i + 1 < occ.size() ? "," : "");
  std::printf("  ]\n}\n");
  return 0;
}
