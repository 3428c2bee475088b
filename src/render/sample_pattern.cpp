// The sample pattern inside a pixel (sample_offset), the same for every backend.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "par2d/types.hpp"

namespace par2d {

void sample_offset(int k, int spp, double& dx, double& dy) noexcept {
  if (spp <= 1) {
    dx = dy = 0.5;
    return;
  }
  // Rank-1 lattice: one sample per column and per row of an spp x spp grid, rows visited
  // with a golden-ratio stride so the samples also spread in 2D.
  int stride = std::max(1, static_cast<int>(std::lround(spp * 0.6180339887498949)));
  while (std::gcd(stride, spp) != 1) ++stride;
  dx = (k + 0.5) / spp;
  dy = (static_cast<double>((static_cast<long long>(k) * stride) % spp) + 0.5) / spp;
}

}  // namespace par2d
