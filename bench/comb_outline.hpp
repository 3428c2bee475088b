// A comb outline, the concave shape a ray can enter most often for its vertex count: the
// polygon-preparation benchmarks and the partition and concave-light tests build it.
#pragma once

#include <utility>
#include <vector>

#include "par2d/scene.hpp"

namespace par2d::bench {

// `teeth` teeth 1 wide and 10 tall, 1 apart, on a base 1 high (4 teeth + 2 vertices,
// clockwise): a ray along the base, between heights 1 and 10, enters every tooth. The teeth
// stand side by side along x, or along y when `sideways`.
inline std::vector<Vec2> comb_outline(int teeth, bool sideways) {
  std::vector<Vec2> v{{0.0, 0.0}};
  for (int k = 0; k < teeth; ++k) {
    const double x = 2.0 * k;
    v.insert(v.end(), {{x, 10.0}, {x + 1.0, 10.0}, {x + 1.0, 1.0}, {x + 2.0, 1.0}});
  }
  v.push_back({2.0 * teeth, 0.0});
  if (sideways)
    for (Vec2& p : v) std::swap(p.x, p.y);
  return v;
}

}  // namespace par2d::bench
