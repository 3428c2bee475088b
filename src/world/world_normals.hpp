// A normal map converted for rendering: unit normals in world axes, one plane per component.
#pragma once

#include <cstddef>
#include <memory>

#include "par2d/scene.hpp"

namespace par2d::detail {

// width * height unit normals in world axes, row-major from image row 0, stored as three
// planes (x, y, z) so that a tile row of each component is one contiguous run to copy.
class WorldNormals {
 public:
  WorldNormals(int width, int height);

  int width() const noexcept { return width_; }
  int height() const noexcept { return height_; }
  // Component c (0 x, 1 y, 2 z) of image row j.
  const float* row(int c, int j) const noexcept { return plane(c) + static_cast<std::size_t>(j) * static_cast<std::size_t>(width_); }
  const float* plane(int c) const noexcept { return values_.get() + static_cast<std::size_t>(c) * pixels(); }
  float* plane(int c) noexcept { return values_.get() + static_cast<std::size_t>(c) * pixels(); }
  std::size_t pixels() const noexcept { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }

 private:
  int width_ = 0;
  int height_ = 0;
  std::unique_ptr<float[]> values_;  // 3 planes, left uninitialized until converted
};

// A normal map's normals in world axes for a view (a mirrored view flips components), each
// scaled to unit length. Null when some normal is not finite or is zero: the one pass that
// converts also checks (check_normal_map words the problem). The map's buffer must hold
// 3 * width * height floats.
std::shared_ptr<const WorldNormals> world_normals(const NormalMap& map, const View& view);

}  // namespace par2d::detail
