// Builds the prepared scene: canonical shapes and the overlap relation between lights and occluders.
#include "render/prepared_scene.hpp"

#include <algorithm>

namespace par2d::detail {
namespace {

bool boxes_touch(const ConvexShape& a, const ConvexShape& b) noexcept {
  return a.bounds_min.x <= b.bounds_max.x && b.bounds_min.x <= a.bounds_max.x &&
         a.bounds_min.y <= b.bounds_max.y && b.bounds_min.y <= a.bounds_max.y;
}

}  // namespace

void PairSeparators::reset(std::size_t lights, std::size_t occluders) {
  occluders_ = occluders;
  state_ = std::make_unique<std::atomic<std::uint8_t>[]>(lights * occluders);
  lines_ = std::make_unique<Line[]>(lights * occluders);
}

std::optional<Line> PairSeparators::get(std::size_t light, std::size_t occluder, const ConvexShape& light_shape,
                                        const ConvexShape& occluder_shape) const noexcept {
  const std::size_t index = light * occluders_ + occluder;
  std::atomic<std::uint8_t>& state = state_[index];
  const std::uint8_t seen = state.load(std::memory_order_acquire);
  if (seen == kSeparated) return lines_[index];
  if (seen == kTouching) return std::nullopt;
  const std::optional<Line> line = separating_line(occluder_shape, light_shape);
  // Only the thread that claims the slot writes it; a thread that loses the race just
  // uses its own (identical) result.
  std::uint8_t expected = kUnknown;
  if (state.compare_exchange_strong(expected, kComputing, std::memory_order_acq_rel)) {
    if (line) lines_[index] = *line;
    state.store(line ? kSeparated : kTouching, std::memory_order_release);
  }
  return line;
}

PreparedScene prepare_scene(const Scene& scene) {
  PreparedScene out;
  out.width = scene.width;
  out.height = scene.height;
  out.view = scene.view;
  out.occluders.reserve(scene.occluders.size());
  for (const Occluder& o : scene.occluders) out.occluders.push_back(make_convex_shape(o.shape));
  for (const Light& l : scene.lights) {
    PreparedLight light;
    for (int c = 0; c < 3; ++c) light.emission[c] = l.intensity * l.color[c];
    const double e = std::max({light.emission[0], light.emission[1], light.emission[2]});
    if (!(e > 0.0)) continue;  // contributes nothing anywhere
    out.e_max += e;
    light.shape = make_convex_shape(l.shape);
    for (std::uint32_t k = 0; k < out.occluders.size(); ++k) {
      const ConvexShape& occ = out.occluders[k];
      if (boxes_touch(light.shape, occ) && shape_distance(light.shape, occ) <= 0.0)
{
        light.overlapping_occluders.push_back(k);
        light.overlap_points.emplace_back();
        boundary_intersections(light.shape, occ, light.overlap_points.back());
      }
    }
    out.lights.push_back(std::move(light));
  }
  std::vector<Aabb> boxes;
  boxes.reserve(out.occluders.size());
  for (const ConvexShape& o : out.occluders)
    boxes.push_back({o.bounds_min.x, o.bounds_min.y, o.bounds_max.x, o.bounds_max.y});
  out.occluder_bvh.build(boxes);
  out.separators.reset(out.lights.size(), out.occluders.size());
  return out;
}

}  // namespace par2d::detail
