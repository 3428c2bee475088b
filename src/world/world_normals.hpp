// A normal map converted for rendering: unit normals in world axes, one plane per component.
#pragma once

#include <cstddef>
#include <memory>

#include "par2d/scene.hpp"

namespace par2d::detail {

// width * height unit normals in world axes, row-major from image row 0, stored as three
// planes (x, y, z). Each plane is padded to a multiple of kNormalPadding pixels in both
// directions with (0, 0, 1), and planes and rows start on 64-byte boundaries, so the tile
// kernels read a tile's normals in place (a tile of at most kNormalPadding pixels square
// never reads past a plane), with no per-tile copy.
inline constexpr int kNormalPadding = 64;

class WorldNormals {
 public:
  WorldNormals(int width, int height);

  int width() const noexcept { return width_; }
  int height() const noexcept { return height_; }
  // Floats from one row to the next (the padded width).
  std::size_t stride() const noexcept { return stride_; }
  // Component c (0 x, 1 y, 2 z) of image row j (j up to the padded height).
  const float* row(int c, int j) const noexcept { return plane(c) + static_cast<std::size_t>(j) * stride_; }
  float* row(int c, int j) noexcept { return plane(c) + static_cast<std::size_t>(j) * stride_; }
  const float* plane(int c) const noexcept { return values_ + static_cast<std::size_t>(c) * plane_size_; }
  float* plane(int c) noexcept { return values_ + static_cast<std::size_t>(c) * plane_size_; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::size_t stride_ = 0;
  std::size_t plane_size_ = 0;  // stride_ times the padded height
  std::unique_ptr<float[]> storage_;
  float* values_ = nullptr;  // storage_ aligned to 64 bytes: 3 planes, the image part written by the conversion
};

// A normal map's normals in world axes for a view (a mirrored view flips components), each
// scaled to unit length. Null when some normal is not finite or is zero: the one pass that
// converts also checks (check_normal_map words the problem). The map's buffer must hold
// 3 * width * height floats.
std::shared_ptr<const WorldNormals> world_normals(const NormalMap& map, const View& view);

}  // namespace par2d::detail
