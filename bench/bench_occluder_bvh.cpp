// Benchmarks the occluder BVH: per-frame build cost and tile-to-light hull queries against a linear scan.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "world/occluder_bvh.hpp"

namespace {

using par2d::Vec2;
using par2d::detail::Aabb;
using par2d::detail::convex_hull;
using par2d::detail::OccluderBvh;

constexpr double kWorld = 4096.0;

// Small occluders scattered over a 4096 x 4096 world, like debris or foliage in a large scene.
std::vector<Aabb> scattered_boxes(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, kWorld);
  std::uniform_real_distribution<double> size(2.0, 16.0);
  std::vector<Aabb> boxes(n);
  for (Aabb& b : boxes) {
    const double x = pos(rng), y = pos(rng);
    b = {x, y, x + size(rng), y + size(rng)};
  }
  return boxes;
}

// Hulls of a 32 x 32 tile and a small light 200-1500 units away: the long thin triangles the
// renderer gathers occluders with. Several, so the benchmark does not replay one cached path.
std::vector<std::vector<Vec2>> tile_light_hulls(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, kWorld - 32.0);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> dist(200.0, 1500.0);
  std::vector<std::vector<Vec2>> hulls;
  for (int i = 0; i < 64; ++i) {
    const double x = pos(rng), y = pos(rng), a = angle(rng), d = dist(rng);
    const Vec2 light{x + 16.0 + d * std::cos(a), y + 16.0 + d * std::sin(a)};
    hulls.push_back(convex_hull({{x, y},
                                 {x + 32, y},
                                 {x + 32, y + 32},
                                 {x, y + 32},
                                 {light.x - 4, light.y - 4},
                                 {light.x + 4, light.y + 4},
                                 {light.x - 4, light.y + 4},
                                 {light.x + 4, light.y - 4}}));
  }
  return hulls;
}

// The linear scan the BVH replaces, with the same separating-axis test and axes computed once per
// query, so the comparison measures only the pruning.
void brute_force_query(const std::vector<Aabb>& boxes, const std::vector<Vec2>& hull, std::vector<uint32_t>& out) {
  struct Axis {
    double nx, ny, lo, hi;
  };
  Axis axes[16];
  int axis_count = 0;
  Aabb bounds{INFINITY, INFINITY, -INFINITY, -INFINITY};
  const size_t n = hull.size();
  for (size_t i = 0; i < n; ++i) {
    bounds = {std::min(bounds.min_x, hull[i].x), std::min(bounds.min_y, hull[i].y),
              std::max(bounds.max_x, hull[i].x), std::max(bounds.max_y, hull[i].y)};
    const Vec2 a = hull[i], b = hull[(i + 1) % n];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    Axis& ax = axes[axis_count++];
    ax = {(a.y - b.y) / len, (b.x - a.x) / len, INFINITY, -INFINITY};
    for (const Vec2& p : hull) {
      ax.lo = std::min(ax.lo, ax.nx * p.x + ax.ny * p.y);
      ax.hi = std::max(ax.hi, ax.nx * p.x + ax.ny * p.y);
    }
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Aabb& b = boxes[i];
    if (b.max_x < bounds.min_x || b.min_x > bounds.max_x || b.max_y < bounds.min_y || b.min_y > bounds.max_y) {
      continue;
    }
    bool hit = true;
    for (int k = 0; k < axis_count && hit; ++k) {
      const Axis& a = axes[k];
      const double lo = a.nx * (a.nx >= 0.0 ? b.min_x : b.max_x) + a.ny * (a.ny >= 0.0 ? b.min_y : b.max_y);
      const double hi = a.nx * (a.nx >= 0.0 ? b.max_x : b.min_x) + a.ny * (a.ny >= 0.0 ? b.max_y : b.min_y);
      hit = !(hi < a.lo || lo > a.hi);
    }
    if (hit) out.push_back(static_cast<uint32_t>(i));
  }
}

void BM_BvhBuild(benchmark::State& state) {
  const auto boxes = scattered_boxes(static_cast<size_t>(state.range(0)), 1);
  OccluderBvh bvh;  // reused, as in a per-frame rebuild
  for (auto _ : state) {
    bvh.build(boxes);
    benchmark::DoNotOptimize(bvh.node_count());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["nodes"] = static_cast<double>(bvh.node_count());
}
BENCHMARK(BM_BvhBuild)->Arg(256)->Arg(1024)->Arg(4096)->Arg(16384)->Unit(benchmark::kMicrosecond);

void BM_BvhQueryTileLight(benchmark::State& state) {
  const auto boxes = scattered_boxes(static_cast<size_t>(state.range(0)), 1);
  const auto hulls = tile_light_hulls(2);
  OccluderBvh bvh;
  bvh.build(boxes);
  std::vector<uint32_t> out;
  size_t found = 0, i = 0;
  for (auto _ : state) {
    out.clear();
    const auto& hull = hulls[i++ % hulls.size()];
    bvh.query_convex(hull.data(), static_cast<int>(hull.size()), out);
    found += out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_BvhQueryTileLight)->Arg(4096)->Arg(16384);

void BM_BruteForceQueryTileLight(benchmark::State& state) {
  const auto boxes = scattered_boxes(static_cast<size_t>(state.range(0)), 1);
  const auto hulls = tile_light_hulls(2);
  std::vector<uint32_t> out;
  size_t found = 0, i = 0;
  for (auto _ : state) {
    out.clear();
    brute_force_query(boxes, hulls[i++ % hulls.size()], out);
    found += out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_BruteForceQueryTileLight)->Arg(4096)->Arg(16384);

}  // namespace
