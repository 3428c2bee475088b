// Tilemap box merging: see occluder_merge.hpp.
//
// Wiring (not done here; the World's incremental frames are being reworked): the World would
// keep, per handle, the group it belongs to, prepare only the groups' occluders, and on
// update_occluder / remove_occluder of a member split its group back into its members and
// merge that row again (only boxes of the same row or column can join it), reporting the
// group's old and new boxes as changed regions. Handles stay the caller's boxes.
#include "world/occluder_merge.hpp"

#include <algorithm>
#include <map>
#include <tuple>

namespace par2d::detail {
namespace {

struct Box {
  double x0, y0, x1, y1;
};

// The rectangle a polygon occluder is, if it is one: 4 vertices on two x and two y values.
bool as_box(const Occluder& o, Box& out) {
  const auto* p = std::get_if<Polygon>(&o.shape);
  if (!p || p->vertices.size() != 4 || !p->holes.empty()) return false;
  double xs[2] = {p->vertices[0].x, p->vertices[0].x}, ys[2] = {p->vertices[0].y, p->vertices[0].y};
  int nx = 1, ny = 1;
  for (const Vec2 v : p->vertices) {
    if (v.x != xs[0] && (nx == 1 || v.x != xs[1])) {
      if (nx == 2) return false;
      xs[nx++] = v.x;
    }
    if (v.y != ys[0] && (ny == 1 || v.y != ys[1])) {
      if (ny == 2) return false;
      ys[ny++] = v.y;
    }
  }
  if (nx != 2 || ny != 2) return false;
  // Each corner once: an axis-aligned rectangle, not a degenerate 4-gon.
  int corners = 0;
  for (const Vec2 v : p->vertices) corners |= 1 << ((v.x == xs[1]) * 2 + (v.y == ys[1]));
  if (corners != 0xF) return false;
  out = {std::min(xs[0], xs[1]), std::min(ys[0], ys[1]), std::max(xs[0], xs[1]), std::max(ys[0], ys[1])};
  return true;
}

// Only where the union's visibility is each box's: a ray along a row crosses every box of it,
// and a point on a shared edge lies in two, so with transmittances multiplying per occluder
// crossed (docs/contract.md section 6) a translucent row would let t^2 through where the
// merged box lets t. A channel of 0 or 1 is the same however often it is crossed. A lit
// interior ignores only the box the point is in, so the next box of the row still shadows
// it: such boxes stay apart too. Reflecting walls' bounce pieces follow their given edges.
bool mergeable(const Occluder& o) {
  for (int c = 0; c < 3; ++c) {
    if (o.albedo[c] != 0.0) return false;
    if (o.transmittance[c] != 0.0 && o.transmittance[c] != 1.0) return false;
  }
  return o.interior == Interior::dark;
}

// Properties as a sortable key.
auto properties(const Occluder& o) {
  return std::make_tuple(o.transmittance[0], o.transmittance[1], o.transmittance[2], o.mask,
                         static_cast<int>(o.interior));
}

Polygon box_polygon(const Box& b) { return Polygon{{{b.x0, b.y0}, {b.x1, b.y0}, {b.x1, b.y1}, {b.x0, b.y1}}}; }

}  // namespace

std::vector<MergedOccluder> merge_tilemap_boxes(const std::vector<Occluder>& occluders) {
  const std::size_t n = occluders.size();
  std::vector<Box> boxes(n);
  std::vector<char> is_box(n, 0);
  for (std::size_t i = 0; i < n; ++i) is_box[i] = mergeable(occluders[i]) && as_box(occluders[i], boxes[i]);
  std::vector<std::ptrdiff_t> group(n, -1);  // index into `runs`
  std::vector<std::vector<std::size_t>> runs;

  // Rows, then columns of what is left: sort by (line, properties, start) and join ends.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < n; ++i)
      if (is_box[i] && group[i] < 0) order.push_back(i);
    auto key = [&](std::size_t i) {
      const Box& b = boxes[i];
      return pass == 0 ? std::make_tuple(b.y0, b.y1, b.x0) : std::make_tuple(b.x0, b.x1, b.y0);
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const auto ka = key(a), kb = key(b);
      if (std::get<0>(ka) != std::get<0>(kb)) return std::get<0>(ka) < std::get<0>(kb);
      if (std::get<1>(ka) != std::get<1>(kb)) return std::get<1>(ka) < std::get<1>(kb);
      if (properties(occluders[a]) != properties(occluders[b])) return properties(occluders[a]) < properties(occluders[b]);
      return std::get<2>(ka) < std::get<2>(kb);
    });
    for (std::size_t s = 0; s < order.size();) {
      std::size_t e = s + 1;
      while (e < order.size()) {
        const Box &prev = boxes[order[e - 1]], &next = boxes[order[e]];
        const bool same_line = pass == 0 ? (prev.y0 == next.y0 && prev.y1 == next.y1) : (prev.x0 == next.x0 && prev.x1 == next.x1);
        const bool joined = pass == 0 ? prev.x1 == next.x0 : prev.y1 == next.y0;
        if (!same_line || !joined || properties(occluders[order[e - 1]]) != properties(occluders[order[e]])) break;
        ++e;
      }
      if (e - s >= 2) {
        for (std::size_t k = s; k < e; ++k) group[order[k]] = static_cast<std::ptrdiff_t>(runs.size());
        runs.emplace_back(order.begin() + static_cast<std::ptrdiff_t>(s), order.begin() + static_cast<std::ptrdiff_t>(e));
      }
      s = e;
    }
  }

  std::vector<MergedOccluder> out;
  std::vector<char> emitted(runs.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (group[i] < 0) {
      out.push_back({occluders[i], {i}});
      continue;
    }
    const auto g = static_cast<std::size_t>(group[i]);
    if (emitted[g]) continue;
    emitted[g] = 1;
    MergedOccluder m;
    m.sources = runs[g];
    std::sort(m.sources.begin(), m.sources.end());
    Box u = boxes[m.sources[0]];
    for (const std::size_t k : m.sources) {
      u.x0 = std::min(u.x0, boxes[k].x0);
      u.y0 = std::min(u.y0, boxes[k].y0);
      u.x1 = std::max(u.x1, boxes[k].x1);
      u.y1 = std::max(u.y1, boxes[k].y1);
    }
    m.occluder = occluders[m.sources[0]];
    m.occluder.shape = box_polygon(u);
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace par2d::detail
