// polygons_from_alpha: the solid pixels' boundary traced on the pixel-corner grid, simplified, placed and validated.
#include "par2d/alpha_outline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "geometry/ring_simplify.hpp"
#include "scene/scene_validate.hpp"

namespace par2d {
namespace {

Status bad_argument(const std::string& what) {
  return Status(StatusCode::invalid_argument, "polygons_from_alpha: " + what);
}

struct Point {
  int x = 0;
  int y = 0;
  bool operator==(const Point& o) const { return x == o.x && y == o.y; }
  bool operator!=(const Point& o) const { return !(*this == o); }
};

// The solid pixels, one bit each and row by row as runs, the runs joined into 8-connected
// groups (union-find).
class SolidRuns {
 public:
  SolidRuns(const AlphaMask& mask, int threshold)
      : width_(mask.width),
        height_(mask.height),
        bits_(static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height)) {
    row_first_.reserve(static_cast<std::size_t>(height_) + 1);
    for (int y = 0; y < height_; ++y) {
      row_first_.push_back(static_cast<std::uint32_t>(runs_.size()));
      const std::uint8_t* row = mask.alpha + static_cast<std::ptrdiff_t>(y) * mask.row_stride;
      for (int x = 0; x < width_;) {
        if (row[static_cast<std::ptrdiff_t>(x) * mask.pixel_stride] < threshold) {
          ++x;
          continue;
        }
        const int begin = x;
        while (x < width_ && row[static_cast<std::ptrdiff_t>(x) * mask.pixel_stride] >= threshold) ++x;
        runs_.push_back({begin, x});
        for (int k = begin; k < x; ++k) bits_[index(k, y)] = true;
      }
    }
    row_first_.push_back(static_cast<std::uint32_t>(runs_.size()));
    parent_.resize(runs_.size());
    for (std::uint32_t k = 0; k < parent_.size(); ++k) parent_[k] = k;
    // Runs of adjacent rows join where they share an edge or a corner: [a, b) and [c, d)
    // overlap once widened by one pixel.
    for (int y = 1; y < height_; ++y) {
      std::uint32_t up = row_first_[y - 1];
      for (std::uint32_t k = row_first_[y]; k < row_first_[y + 1]; ++k) {
        while (up < row_first_[y] && runs_[up].end < runs_[k].begin) ++up;
        for (std::uint32_t u = up; u < row_first_[y] && runs_[u].begin <= runs_[k].end; ++u) join(u, k);
      }
    }
  }

  bool solid(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    return bits_[index(x, y)];
  }
  // The group of solid pixel (x, y): its first run's index.
  std::uint32_t group(int x, int y) { return find(run_at(x, y)); }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  struct Run {
    int begin, end;
  };
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }
  std::uint32_t run_at(int x, int y) const {
    const auto first = runs_.begin() + row_first_[y], last = runs_.begin() + row_first_[y + 1];
    const auto it = std::upper_bound(first, last, x, [](int v, const Run& r) { return v < r.begin; });
    if (it == first || (it - 1)->end <= x) return kNone;
    return static_cast<std::uint32_t>(it - 1 - runs_.begin());
  }
  std::uint32_t find(std::uint32_t k) {
    while (parent_[k] != k) k = parent_[k] = parent_[parent_[k]];
    return k;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

  int width_, height_;
  std::vector<Run> runs_;
  std::vector<std::uint32_t> row_first_;
  std::vector<std::uint32_t> parent_;
  std::vector<bool> bits_;  // solid or not, row by row: the tracer's many lookups
};

// -1 for a step of -1 and 0 for +1: the pixel offset of the side a unit step points to.
int low(int k) { return k > 0 ? 0 : -1; }

// One traced ring: its vertices (pixel units) and the group of the solid pixels it bounds.
struct TracedRing {
  std::vector<Vec2> vertices;
  std::uint32_t group = 0;
  Point pixel;         // the solid pixel left of its first edge
  double area2 = 0.0;  // twice the signed area: > 0 for an outline, < 0 for a hole
};

// Follows the boundary edges between solid and empty pixels, each directed so that the solid
// pixel is on the side n = (-d.y, d.x) of its direction d (rows down: an outline runs
// clockwise on screen). Where two solid pixels touch only at a corner (a saddle) the boundary
// turns away from the solid side, around the empty pixel, so the two solid pixels stay in one
// ring (8-connected solid); that pass is then moved kSaddleShift along both axes toward the
// next pixel clockwise, along the line through the midpoints of its two edges (the area stays
// exact), which keeps the two passes of the corner 2 * kSaddleShift apart.
class Tracer {
 public:
  explicit Tracer(SolidRuns& runs, int width, int height)
      : runs_(runs),
        width_(width),
        height_(height),
        horizontal_(static_cast<std::size_t>(width) * (static_cast<std::size_t>(height) + 1)),
        vertical_((static_cast<std::size_t>(width) + 1) * static_cast<std::size_t>(height)) {}

  std::vector<TracedRing> trace() {
    std::vector<TracedRing> rings;
    for (int y = 0; y <= height_; ++y)
      for (int x = 0; x < width_; ++x) {
        const bool below = runs_.solid(x, y), above = runs_.solid(x, y - 1);
        if (below == above || horizontal_[static_cast<std::size_t>(y) * width_ + x]) continue;
        rings.push_back(below ? follow({x, y}, {1, 0}) : follow({x + 1, y}, {-1, 0}));
      }
    return rings;
  }

 private:
  bool outgoing(Point p, Point o) const {
    const Point n{-o.y, o.x};
    return runs_.solid(p.x + low(o.x + n.x), p.y + low(o.y + n.y)) &&
           !runs_.solid(p.x + low(o.x - n.x), p.y + low(o.y - n.y));
  }
  void mark(Point p, Point d) {
    if (d.y == 0)
      horizontal_[static_cast<std::size_t>(p.y) * width_ + std::min(p.x, p.x + d.x)] = true;
    else
      vertical_[static_cast<std::size_t>(std::min(p.y, p.y + d.y)) * (width_ + 1) + p.x] = true;
  }
  static void emit(std::vector<Vec2>& out, Vec2 v) {
    if (out.empty() || out.back().x != v.x || out.back().y != v.y) out.push_back(v);
  }

  TracedRing follow(Point start, Point start_dir) {
    TracedRing ring;
    const Point n0{-start_dir.y, start_dir.x};
    ring.pixel = {start.x + low(start_dir.x + n0.x), start.y + low(start_dir.y + n0.y)};
    ring.group = runs_.group(ring.pixel.x, ring.pixel.y);
    Point p = start, d = start_dir;
    do {
      mark(p, d);
      const Point q{p.x + d.x, p.y + d.y};
      const Point n{-d.y, d.x};
      Point o{-n.x, -n.y};
      if (!outgoing(q, o)) o = outgoing(q, d) ? d : n;
      const bool tl = runs_.solid(q.x - 1, q.y - 1), tr = runs_.solid(q.x, q.y - 1);
      const bool bl = runs_.solid(q.x - 1, q.y), br = runs_.solid(q.x, q.y);
      const bool saddle = tl == br && tr == bl && tl != tr;
      const Vec2 at{static_cast<double>(q.x), static_cast<double>(q.y)};
      if (saddle) {
        // w = o - d points at the empty pixel wrapped; rotated a quarter clockwise on screen.
        const Point w{o.x - d.x, o.y - d.y};
        emit(ring.vertices, {at.x - 0.5 * d.x, at.y - 0.5 * d.y});
        emit(ring.vertices, {at.x - kSaddleShift * w.y, at.y + kSaddleShift * w.x});
        emit(ring.vertices, {at.x + 0.5 * o.x, at.y + 0.5 * o.y});
      } else if (o != d) {
        emit(ring.vertices, at);
      }
      p = q;
      d = o;
    } while (p != start || d != start_dir);
    auto& v = ring.vertices;
    if (v.size() > 1 && v.front().x == v.back().x && v.front().y == v.back().y) v.pop_back();
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Vec2 a = v[i], b = v[(i + 1) % v.size()];
      ring.area2 += a.x * b.y - a.y * b.x;
    }
    return ring;
  }

  SolidRuns& runs_;
  int width_, height_;
  std::vector<bool> horizontal_;  // edge (x, y) -> (x + 1, y) seen
  std::vector<bool> vertical_;    // edge (x, y) -> (x, y + 1) seen
};

Status check_arguments(const AlphaMask& mask, const AlphaOutlineOptions& options) {
  if (mask.alpha == nullptr) return bad_argument("mask.alpha is null");
  if (mask.width < 1 || mask.width > kMaxImageSide || mask.height < 1 || mask.height > kMaxImageSide)
    return bad_argument("mask size " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                        " is not an image size (1 .. " + std::to_string(kMaxImageSide) + " per side)");
  if (mask.pixel_stride < 1)
    return bad_argument("mask.pixel_stride must be >= 1, got " + std::to_string(mask.pixel_stride));
  if (mask.row_stride < static_cast<std::ptrdiff_t>(mask.width) * mask.pixel_stride)
    return bad_argument("mask.row_stride " + std::to_string(mask.row_stride) + " is less than width * pixel_stride (" +
                        std::to_string(static_cast<std::ptrdiff_t>(mask.width) * mask.pixel_stride) + ")");
  if (options.threshold < 0 || options.threshold > 255)
    return bad_argument("threshold must be 0 .. 255, got " + std::to_string(options.threshold));
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance))
    return bad_argument("tolerance must be a finite number >= 0, got " + detail::format_number(options.tolerance));
  if (options.max_vertices < 3 || options.max_vertices > kMaxOutlineVertices)
    return bad_argument("max_vertices must be 3 .. " + std::to_string(kMaxOutlineVertices) + ", got " +
                        std::to_string(options.max_vertices));
  for (const auto& [value, name] : {std::pair{options.scale.x, "scale.x"}, std::pair{options.scale.y, "scale.y"}}) {
    if (!std::isfinite(value) || value == 0.0)
      return bad_argument(std::string(name) + " must be finite and non-zero, got " + detail::format_number(value));
  }
  if (!std::isfinite(options.offset.x) || !std::isfinite(options.offset.y))
    return bad_argument("offset must be finite, got (" + detail::format_number(options.offset.x) + ", " +
                        detail::format_number(options.offset.y) + ")");
  return Status::success();
}

std::size_t vertex_count(const Polygon& polygon) {
  std::size_t count = polygon.vertices.size();
  for (const auto& hole : polygon.holes) count += hole.size();
  return count;
}

}  // namespace

Status polygons_from_alpha(const AlphaMask& mask, const AlphaOutlineOptions& options, std::vector<Polygon>& out) {
  out.clear();
  if (Status s = check_arguments(mask, options); !s) return s;
  try {
    SolidRuns runs(mask, options.threshold);
    std::vector<TracedRing> traced = Tracer(runs, mask.width, mask.height).trace();

    // One polygon per group, in the order of the groups' outlines (found first: a group's top
    // row's leftmost pixel comes before any of its holes in row order).
    std::vector<std::vector<Vec2>> rings;
    std::vector<std::size_t> polygon_of;                               // per ring
    std::vector<Point> first_pixel;                                    // per polygon
    std::vector<std::pair<std::uint32_t, std::size_t>> group_polygon;  // sorted by group
    rings.reserve(traced.size());
    for (TracedRing& ring : traced) {
      if (ring.area2 > 0.0) {
        group_polygon.emplace_back(ring.group, first_pixel.size());
        first_pixel.push_back(ring.pixel);
      }
    }
    std::sort(group_polygon.begin(), group_polygon.end());
    for (TracedRing& ring : traced) {
      const auto it = std::lower_bound(group_polygon.begin(), group_polygon.end(),
                                       std::pair<std::uint32_t, std::size_t>{ring.group, 0});
      polygon_of.push_back(it->second);
      rings.push_back(std::move(ring.vertices));
    }
    traced.clear();
    std::size_t total = 0;
    for (const auto& ring : rings) total += ring.size();
    // The simplification numbers vertices with 32 bits.
    if (total >= std::numeric_limits<std::uint32_t>::max())
      return Status(StatusCode::out_of_memory, "polygons_from_alpha: " + std::to_string(total) + " vertices, too many");

    // The saddle shift already moves the outline up to kSaddleShift * sqrt(2) off the pixel
    // boundary: the simplification gets what remains of the tolerance.
    const double slack = std::max(0.0, options.tolerance - kSaddleShift * std::sqrt(2.0));
    detail::simplify_rings(rings, slack);

    std::vector<Polygon> polygons(first_pixel.size());
    for (std::size_t k = 0; k < rings.size(); ++k) {
      for (Vec2& v : rings[k]) v = {options.offset.x + options.scale.x * v.x, options.offset.y + options.scale.y * v.y};
      Polygon& polygon = polygons[polygon_of[k]];
      if (polygon.vertices.empty())
        polygon.vertices = std::move(rings[k]);
      else
        polygon.holes.push_back(std::move(rings[k]));
    }
    for (std::size_t k = 0; k < polygons.size(); ++k) {
      const std::string name = "polygon " + std::to_string(k) + " (from pixel (" + std::to_string(first_pixel[k].x) +
                               ", " + std::to_string(first_pixel[k].y) + "))";
      if (const std::size_t count = vertex_count(polygons[k]); count > options.max_vertices)
        return bad_argument(name + " needs " + std::to_string(count) + " vertices at tolerance " +
                            detail::format_number(options.tolerance) + ", more than max_vertices (" +
                            std::to_string(options.max_vertices) + "): raise the tolerance");
      // The placement is affine, so it keeps the rings apart; rounding at an extreme scale or
      // offset could still merge vertices: the scene's own check has the last word.
      if (auto problem = detail::check_shape(Shape{polygons[k]}, "polygon", true))
        return bad_argument(name + " is not a valid polygon after placement (" + problem->what +
                            "): use a scale and offset of more moderate ratio");
    }
    out = std::move(polygons);
    return Status::success();
  } catch (const std::bad_alloc&) {
    out.clear();
    return Status(StatusCode::out_of_memory, "polygons_from_alpha: out of memory");
  }
}

}  // namespace par2d
