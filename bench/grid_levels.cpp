// Issue 39's grid levels: wall levels (tilemap, merged tilemap, free-form) with torches on wall
// faces, and centered crops of the many-light rubble fields.
#include "grid_levels.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace par2d::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Uniform doubles from std::mt19937's specified output (portable, like scattered_scene's).
class Random {
 public:
  explicit Random(std::uint32_t seed) : engine_(seed) {}
  double unit() {
    const std::uint64_t hi = engine_() >> 5;
    const std::uint64_t lo = engine_() >> 6;
    return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);
  }
  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }
  int below(int n) { return std::min(n - 1, static_cast<int>(unit() * n)); }

 private:
  std::mt19937 engine_;
};

// A wall run: cells [c0, c1] x [r0, r1] (inclusive) of the map, one occluder.
struct Run {
  int c0, r0, c1, r1;
};

class CellMap {
 public:
  CellMap(int columns, int rows) : columns_(columns), rows_(rows), wall_(static_cast<std::size_t>(columns * rows), 0) {}
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  bool inside(int c, int r) const { return c >= 0 && r >= 0 && c < columns_ && r < rows_; }
  bool wall(int c, int r) const { return !inside(c, r) || wall_[index(c, r)] != 0; }
  void set(int c, int r, bool w) {
    if (inside(c, r)) wall_[index(c, r)] = w ? 1 : 0;
  }

 private:
  std::size_t index(int c, int r) const { return static_cast<std::size_t>(r * columns_ + c); }
  int columns_, rows_;
  std::vector<unsigned char> wall_;
};

// Border walls, room walls every `room_w` / `room_h` cells with a doorway in each wall piece,
// pillars in open cells whose 8 neighbours are open.
CellMap make_map(const WallLevel& level, Random& rng) {
  const int columns = std::max(3, static_cast<int>(std::ceil(level.width / level.tile)));
  const int rows = std::max(3, static_cast<int>(std::ceil(level.height / level.tile)));
  CellMap map(columns, rows);
  const int room_w = 7, room_h = 5;  // 6 x 4 open cells between walls
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const bool border = c == 0 || r == 0 || c == columns - 1 || r == rows - 1;
      const bool inner = (c % room_w == 0 && c + 2 < columns) || (r % room_h == 0 && r + 2 < rows);
      map.set(c, r, border || inner);
    }
  }
  // Doorways: every wall piece between two crossings gets an opening of 1-2 cells.
  for (int c = room_w; c + 2 < columns; c += room_w) {
    for (int r0 = 0; r0 + 1 < rows - 1; r0 += room_h) {
      const int r1 = std::min(rows - 1, r0 + room_h);
      if (r1 - r0 < 3) continue;
      const int d = r0 + 1 + rng.below(r1 - r0 - 2);
      map.set(c, d, false);
      if (r1 - r0 > 4 && d + 1 < r1) map.set(c, d + 1, false);
    }
  }
  for (int r = room_h; r + 2 < rows; r += room_h) {
    for (int c0 = 0; c0 + 1 < columns - 1; c0 += room_w) {
      const int c1 = std::min(columns - 1, c0 + room_w);
      if (c1 - c0 < 3) continue;
      const int d = c0 + 1 + rng.below(c1 - c0 - 2);
      map.set(d, r, false);
      if (c1 - c0 > 4 && d + 1 < c1) map.set(d + 1, r, false);
    }
  }
  std::vector<std::pair<int, int>> pillars;
  for (int r = 1; r + 1 < rows; ++r) {
    for (int c = 1; c + 1 < columns; ++c) {
      bool clear = true;
      for (int dr = -1; dr <= 1 && clear; ++dr)
        for (int dc = -1; dc <= 1; ++dc) clear = clear && !map.wall(c + dc, r + dr);
      if (clear && rng.unit() < level.density) pillars.emplace_back(c, r);
    }
  }
  for (const auto& [c, r] : pillars) map.set(c, r, true);
  return map;
}

// Each row's maximal runs of two or more wall cells, then the remaining cells' column runs.
std::vector<Run> merged_runs(const CellMap& map, std::vector<int>& owner) {
  std::vector<Run> runs;
  owner.assign(static_cast<std::size_t>(map.columns() * map.rows()), -1);
  auto own = [&](int c, int r) -> int& { return owner[static_cast<std::size_t>(r * map.columns() + c)]; };
  for (int r = 0; r < map.rows(); ++r) {
    for (int c = 0; c < map.columns();) {
      int e = c;
      while (e < map.columns() && map.wall(e, r)) ++e;
      if (e - c >= 2) {
        for (int k = c; k < e; ++k) own(k, r) = static_cast<int>(runs.size());
        runs.push_back({c, r, e - 1, r});
      }
      c = std::max(e, c + 1);
    }
  }
  for (int c = 0; c < map.columns(); ++c) {
    for (int r = 0; r < map.rows();) {
      int e = r;
      while (e < map.rows() && map.wall(c, e) && own(c, e) < 0) ++e;
      if (e > r) {
        for (int k = r; k < e; ++k) own(c, k) = static_cast<int>(runs.size());
        runs.push_back({c, r, c, e - 1});
      }
      r = std::max(e, r + 1);
    }
  }
  return runs;
}

Polygon box(double x0, double y0, double x1, double y1) { return Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}; }

// A rigid motion of the plane: rotation by `angle` about `center`.
struct Motion {
  Vec2 center{};
  double c = 1.0, s = 0.0;
  Vec2 point(Vec2 p) const {
    const double x = p.x - center.x, y = p.y - center.y;
    return {center.x + c * x - s * y, center.y + s * x + c * y};
  }
  Vec2 direction(Vec2 d) const { return {c * d.x - s * d.y, s * d.x + c * d.y}; }
};

}  // namespace

Scene wall_level(const WallLevel& level) {
  Random rng(level.seed);
  const CellMap map = make_map(level, rng);
  const double t = level.tile;
  Scene scene;
  scene.width = level.width;
  scene.height = level.height;
  scene.view = {0.0, 0.0, static_cast<double>(level.width), static_cast<double>(level.height)};

  std::vector<int> owner;
  const std::vector<Run> runs = merged_runs(map, owner);
  // Occluders, and for each cell the motion its wall went through (free-form) and whether
  // it became a circle.
  Random turns(level.seed ^ 0x9e3779b9u);  // its own stream: torches do not move with the style
  std::vector<Motion> motions(runs.size());
  std::vector<bool> round(runs.size(), false);
  if (level.style == WallStyle::tilemap) {
    for (int r = 0; r < map.rows(); ++r)
      for (int c = 0; c < map.columns(); ++c)
        if (map.wall(c, r)) scene.occluders.push_back(Occluder{box(c * t, r * t, (c + 1) * t, (r + 1) * t)});
  } else {
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const Run& u = runs[k];
      const double x0 = u.c0 * t, y0 = u.r0 * t, x1 = (u.c1 + 1) * t, y1 = (u.r1 + 1) * t;
      if (level.style == WallStyle::tilemap_merged) {
        scene.occluders.push_back(Occluder{box(x0, y0, x1, y1)});
        continue;
      }
      const Vec2 center{0.5 * (x0 + x1), 0.5 * (y0 + y1)};
      if (u.c0 == u.c1 && u.r0 == u.r1) {  // a single cell: a round pillar
        round[k] = true;
        motions[k].center = center;
        scene.occluders.push_back(Occluder{Circle{center, 0.5 * t}});
        continue;
      }
      // Rotated so that its ends move by at most a quarter cell.
      const double half_length = 0.5 * std::max(x1 - x0, y1 - y0);
      const double limit = std::min(4.0 * kPi / 180.0, std::atan(0.25 * t / half_length));
      const double angle = turns.range(-limit, limit);
      motions[k] = Motion{center, std::cos(angle), std::sin(angle)};
      Polygon p = box(x0, y0, x1, y1);
      for (Vec2& v : p.vertices) v = motions[k].point(v);
      scene.occluders.push_back(Occluder{std::move(p)});
    }
  }

  // Torch spots: a wall cell's face toward an open cell, at the face's middle.
  struct Spot {
    int c, r, dc, dr;
  };
  std::vector<Spot> spots;
  for (int r = 0; r < map.rows(); ++r) {
    for (int c = 0; c < map.columns(); ++c) {
      if (!map.wall(c, r)) continue;
      for (const auto& [dc, dr] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        const int oc = c + dc, orow = r + dr;
        if (!map.inside(oc, orow) || map.wall(oc, orow)) continue;
        // The open cell must lie inside the frame, so the torch is seen.
        if ((oc + 1) * t > level.width || (orow + 1) * t > level.height) continue;
        spots.push_back({c, r, dc, dr});
      }
    }
  }
  std::vector<Vec2> taken;
  const double spacing = std::max(3.0 * t, 0.12 * std::min(level.width, level.height));
  for (int tries = 0; static_cast<int>(taken.size()) < level.torches && tries < 20000 && !spots.empty(); ++tries) {
    const Spot& s = spots[static_cast<std::size_t>(rng.below(static_cast<int>(spots.size())))];
    const Vec2 cell_center{(s.c + 0.5) * t, (s.r + 0.5) * t};
    if (std::any_of(taken.begin(), taken.end(), [&](Vec2 p) { return std::hypot(p.x - cell_center.x, p.y - cell_center.y) < spacing; }))
      continue;
    taken.push_back(cell_center);
    Vec2 face{cell_center.x + 0.5 * t * s.dc, cell_center.y + 0.5 * t * s.dr};
    Vec2 normal{static_cast<double>(s.dc), static_cast<double>(s.dr)};
    if (level.style == WallStyle::free_form) {
      const auto k = static_cast<std::size_t>(owner[static_cast<std::size_t>(s.r * map.columns() + s.c)]);
      face = motions[k].point(face);
      normal = motions[k].direction(normal);
    }
    const double r = level.torch_radius;
    const double d = r - level.overlap;  // center to face, along the face's outward normal
    Light light;
    light.shape = Circle{{face.x + d * normal.x, face.y + d * normal.y}, r};
    const double tint = rng.unit();
    light.color = {1.0, 0.6 + 0.2 * tint, 0.35 + 0.2 * tint};
    light.intensity = 3.0;
    light.range = level.range;
    scene.lights.push_back(std::move(light));
  }
  return scene;
}

Scene field_crop(int lights, int occluders, const ScatteredSizes& sizes, int width, int height, std::uint32_t seed,
                 int full_width, int full_height) {
  Scene scene = scattered_scene(lights, occluders, seed, full_width, full_height, sizes);
  const double x0 = std::floor(0.5 * (full_width - width)), y0 = std::floor(0.5 * (full_height - height));
  scene.width = width;
  scene.height = height;
  scene.view = {x0, y0, x0 + width, y0 + height};
  return scene;
}

}  // namespace par2d::bench
