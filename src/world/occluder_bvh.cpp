// Binned-SAH BVH build and separating-axis queries for occluder gathering, plus the convex hull helper.
#include "world/occluder_bvh.hpp"

#include "geometry/convex_shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace par2d::detail {

void hull_with_shape(const Vec2* extra, int extra_count, const ConvexShape& shape, std::vector<Vec2>& points,
                     std::vector<Vec2>& hull) {
  points.assign(extra, extra + extra_count);
  if (shape.kind == ShapeKind::circle) {
    const Vec2 lo = shape.bounds_min, hi = shape.bounds_max;
    points.insert(points.end(), {lo, Vec2{hi.x, lo.y}, hi, Vec2{lo.x, hi.y}});
  } else {
    points.insert(points.end(), shape.vertices.begin(), shape.vertices.end());
  }
  hull.resize(2 * points.size() + 1);
  hull.resize(static_cast<std::size_t>(convex_hull(points.data(), static_cast<int>(points.size()), hull.data())));
}


namespace {

constexpr uint32_t kNoParent = std::numeric_limits<uint32_t>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Half the perimeter, the 2D SAH measure: a random line hits a convex set with probability
// proportional to its perimeter. Halves are taken first so that boxes spanning +-1e308 stay finite.
inline double half_perimeter(const Aabb& b) noexcept {
  return (0.5 * b.max_x - 0.5 * b.min_x) + (0.5 * b.max_y - 0.5 * b.min_y);
}

inline double axis_of(Vec2 c, int axis) noexcept { return axis == 0 ? c.x : c.y; }

// 0.5*a + 0.5*b rather than (a+b)/2: stays finite for boxes near +-DBL_MAX.
inline Vec2 centroid(const Aabb& b) noexcept {
  return {0.5 * b.min_x + 0.5 * b.max_x, 0.5 * b.min_y + 0.5 * b.max_y};
}

// Axis of hull edge i -> i+1 (unit length, so projections keep the coordinates' magnitude and
// neither overflow for huge nor underflow for tiny scenes). Returns false for a zero-length edge,
// which separates nothing. `orientation`: +1 for a counterclockwise hull, -1 clockwise, 0 when
// unknown (a segment, or no area). With a known orientation only the edge's outer side is
// kept (the hull lies behind its edge's line, and two disjoint convex polygons always have an
// edge of one with the other wholly on its outer side), in O(1): the hull's full extent along
// each of n edges would cost n^2 per box, billions of operations for one light of
// thousands of vertices.
inline bool edge_axis(const Vec2* hull, int count, int i, int orientation, ConvexQuery::Axis& axis) noexcept {
  const Vec2 a = hull[i];
  const Vec2 b = hull[(i + 1) % count];
  const double len = length(b - a);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  axis.nx = (a.y - b.y) / len;
  axis.ny = (b.x - a.x) / len;
  if (orientation != 0) {
    // (nx, ny) is the edge's left-hand normal: it points into a counterclockwise hull, which
    // then lies at projections >= the edge's. The edge's projection is widened by far more
    // than its rounding (nearly straight neighbours may project an ulp beyond it): touching
    // boxes still count.
    const double pa = axis.nx * a.x + axis.ny * a.y, pb = axis.nx * b.x + axis.ny * b.y;
    const double margin = 0x1p-40 * std::max({std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y)});
    if (orientation > 0) {
      axis.lo = std::min(pa, pb) - margin;
      axis.hi = kInf;
    } else {
      axis.lo = -kInf;
      axis.hi = std::max(pa, pb) + margin;
    }
    return true;
  }
  axis.lo = kInf;
  axis.hi = -kInf;
  for (int k = 0; k < count; ++k) {
    const double p = axis.nx * hull[k].x + axis.ny * hull[k].y;
    axis.lo = std::min(axis.lo, p);
    axis.hi = std::max(axis.hi, p);
  }
  return true;
}

// +1 for a counterclockwise hull of at least 3 points, -1 clockwise, 0 otherwise (twice the
// signed area, summed relative to the first point; a sliver whose sign rounding could flip
// is treated as unknown).
inline int hull_orientation(const Vec2* hull, int count) noexcept {
  if (count < 3) return 0;
  double area = 0.0, magnitude = 0.0;
  for (int k = 1; k + 1 < count; ++k) {
    const Vec2 u = hull[k] - hull[0], v = hull[k + 1] - hull[0];
    area += u.x * v.y - u.y * v.x;
    magnitude += std::abs(u.x * v.y) + std::abs(u.y * v.x);
  }
  if (!std::isfinite(area) || !(std::abs(area) > 0x1p-30 * magnitude)) return 0;
  return area > 0.0 ? 1 : -1;
}

// Picks the box corner that minimises / maximises the projection. Each term is monotone in the
// box's extent even after rounding, so a parent box never projects inside its child's interval:
// that is what makes pruning exact with respect to the per-item test.
inline bool axis_separates(const ConvexQuery::Axis& a, const Aabb& b) noexcept {
  const double lo = a.nx * (a.nx >= 0.0 ? b.min_x : b.max_x) + a.ny * (a.ny >= 0.0 ? b.min_y : b.max_y);
  const double hi = a.nx * (a.nx >= 0.0 ? b.max_x : b.min_x) + a.ny * (a.ny >= 0.0 ? b.max_y : b.min_y);
  return hi < a.lo || lo > a.hi;
}

}  // namespace

ConvexQuery::ConvexQuery(const Vec2* hull, int count) noexcept : hull_(hull), count_(count) {
  bounds_ = kEmptyBox;
  for (int i = 0; i < count; ++i) grow(bounds_, hull[i]);
  edges_ = count < 2 ? 0 : (count == 2 ? 1 : count);
  orientation_ = hull_orientation(hull, count);
  const int cached = std::min(edges_, kMaxCachedAxes);
  for (int i = 0; i < cached; ++i) {
    Axis axis;
    if (!edge_axis(hull, count, i, orientation_, axis)) continue;
    // axis_separates' two sides, each with the corner it picks made an index: the same sums
    // and comparisons without a branch per coordinate (may_touch runs for every node and item).
    // hi < lo_of_hull, hi from the box's maximising corner:
    if (axis.lo != -kInf)
      add_half_test({axis.nx, axis.ny, axis.lo, axis.nx >= 0.0 ? 2 : 0, axis.ny >= 0.0 ? 3 : 1});
    // lo > hi_of_hull, lo from the minimising corner, negated:
    if (axis.hi != kInf)
      add_half_test({-axis.nx, -axis.ny, -axis.hi, axis.nx >= 0.0 ? 0 : 2, axis.ny >= 0.0 ? 1 : 3});
  }
}

void ConvexQuery::add_half_test(const HalfTest& t) noexcept {
  // An axis-aligned test (an edge along the hull's bounding box, as most edges of a block's
  // hull with a box are) reduces exactly to a comparison with one box coordinate (0 * x is
  // 0, +-1 * y is +-y); where its bound does not pass the hull's bounds, any box it
  // separates already fails the bounds test in may_touch: not kept.
  if (t.nx == 0.0 && t.ny == 1.0 && t.bound <= bounds_.min_y) return;    // max_y < bound
  if (t.nx == 0.0 && t.ny == -1.0 && t.bound <= -bounds_.max_y) return;  // -min_y < bound
  if (t.ny == 0.0 && t.nx == 1.0 && t.bound <= bounds_.min_x) return;    // max_x < bound
  if (t.ny == 0.0 && t.nx == -1.0 && t.bound <= -bounds_.max_x) return;  // -min_x < bound
  half_tests_[half_test_count_++] = t;
}

bool ConvexQuery::may_touch(const Aabb& b) const noexcept {
  if (!boxes_meet(b, bounds_)) return false;
  const double corner[4] = {b.min_x, b.min_y, b.max_x, b.max_y};
  for (int i = 0; i < half_test_count_; ++i) {
    const HalfTest& t = half_tests_[i];
    if (t.nx * corner[t.x_index] + t.ny * corner[t.y_index] < t.bound) return false;
  }
  return true;
}

bool ConvexQuery::touches(const Aabb& b) const noexcept {
  if (!may_touch(b)) return false;
  for (int i = kMaxCachedAxes; i < edges_; ++i) {
    Axis axis;
    if (edge_axis(hull_, count_, i, orientation_, axis) && axis_separates(axis, b)) return false;
  }
  return true;
}

int convex_hull(Vec2* points, int count, Vec2* out) noexcept {
  auto less = [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); };
  std::sort(points, points + count, less);
  const int n = static_cast<int>(std::unique(points, points + count,
                                             [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }) -
                                 points);
  if (n <= 2) {
    std::copy(points, points + n, out);
    return n;
  }
  int k = 0;
  // Lower chain then upper chain; popping on cross <= 0 drops collinear points.
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && cross(out[k - 1] - out[k - 2], points[i] - out[k - 2]) <= 0.0) --k;
    out[k++] = points[i];
  }
  for (int i = n - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(out[k - 1] - out[k - 2], points[i] - out[k - 2]) <= 0.0) --k;
    out[k++] = points[i];
  }
  return k - 1;  // the last point repeats the first
}

std::vector<Vec2> convex_hull(std::vector<Vec2> points) {
  std::vector<Vec2> hull(2 * points.size() + 1);
  hull.resize(static_cast<std::size_t>(convex_hull(points.data(), static_cast<int>(points.size()), hull.data())));
  return hull;
}

void OccluderBvh::build(const std::vector<Aabb>& boxes) {
  nodes_.clear();
  items_.clear();
  item_boxes_.clear();
  tasks_.clear();
  refs_.clear();
  parent_.clear();
  item_leaf_.clear();
  unindexed_.clear();
  position_.clear();
  built_cost_ = cost_ = 0.0;
  const size_t n = boxes.size();
  if (n == 0) return;
  if (n >= kNoParent) throw std::length_error("OccluderBvh: too many boxes");

  refs_.resize(n);
  for (size_t i = 0; i < n; ++i) refs_[i] = {boxes[i], static_cast<uint32_t>(i)};
  nodes_.reserve(2 * n - 1);  // a binary tree with n or fewer leaves

  // Explicit pre-order: the left task is pushed last so it is built right after its parent, and
  // the right task patches its index into the parent when it starts.
  tasks_.push_back({0, static_cast<uint32_t>(n), kNoParent, 0});
  while (!tasks_.empty()) {
    const BuildTask task = tasks_.back();
    tasks_.pop_back();
    const auto index = static_cast<uint32_t>(nodes_.size());
    if (task.parent != kNoParent) nodes_[task.parent].offset = index;
    // The left child directly follows its parent, which is then the node before it.
    parent_.push_back(task.parent != kNoParent ? task.parent : (index == 0 ? kNoParent : index - 1));

    Aabb bounds = kEmptyBox;
    Aabb centroid_bounds = kEmptyBox;
    for (uint32_t i = task.begin; i < task.end; ++i) {
      grow(bounds, refs_[i].box);
      grow(centroid_bounds, centroid(refs_[i].box));
    }
    const uint32_t count = task.end - task.begin;
    if (count <= kLeafSize) {
      nodes_.push_back({bounds, task.begin, count});
      continue;
    }
    nodes_.push_back({bounds, 0, kInterior});
    const uint32_t mid = split(task.begin, task.end, centroid_bounds, task.depth);
    tasks_.push_back({mid, task.end, index, task.depth + 1});
    tasks_.push_back({task.begin, mid, kNoParent, task.depth + 1});
  }

  items_.resize(n);
  item_boxes_.resize(n);
  position_.resize(n);
  item_leaf_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    items_[i] = refs_[i].index;
    item_boxes_[i] = refs_[i].box;
    position_[refs_[i].index] = static_cast<uint32_t>(i);
  }
  for (uint32_t node = 0; node < nodes_.size(); ++node) {
    const Node& nd = nodes_[node];
    if (nd.count != kInterior) std::fill_n(item_leaf_.begin() + nd.offset, nd.count, node);
    built_cost_ += half_perimeter(nd.box);
  }
  cost_ = built_cost_;
}

void OccluderBvh::refit_from(uint32_t node) noexcept {
  while (node != kNoParent) {
    Node& nd = nodes_[node];
    Aabb box = kEmptyBox;
    if (nd.count == kInterior) {
      grow(box, nodes_[node + 1].box);
      grow(box, nodes_[nd.offset].box);
    } else {
      for (uint32_t i = nd.offset; i < nd.offset + nd.count; ++i) grow(box, item_boxes_[i]);
    }
    if (box.min_x == nd.box.min_x && box.min_y == nd.box.min_y && box.max_x == nd.box.max_x &&
        box.max_y == nd.box.max_y)
      return;  // nothing above changes either
    // An empty leaf's box is the empty box, whose half-perimeter is -inf: count it as 0.
    const auto cost = [](const Aabb& b) { return b.min_x <= b.max_x ? half_perimeter(b) : 0.0; };
    cost_ += cost(box) - cost(nd.box);
    nd.box = box;
    node = parent_[node];
  }
}

void OccluderBvh::set_position(uint32_t index, uint32_t position) noexcept {
  position_[index] = position;
  if (position & kUnindexed) {
    unindexed_[position & ~kUnindexed].index = index;
  } else {
    items_[position] = index;
  }
}

void OccluderBvh::update(uint32_t index, const Aabb& box) noexcept {
  const uint32_t position = position_[index];
  if (position & kUnindexed) {
    unindexed_[position & ~kUnindexed].box = box;
    return;
  }
  item_boxes_[position] = box;
  refit_from(item_leaf_[position]);
}

void OccluderBvh::insert(const Aabb& box) {
  if (position_.size() + 1 >= kUnindexed) throw std::length_error("OccluderBvh: too many boxes");
  const auto index = static_cast<uint32_t>(position_.size());
  position_.push_back(kUnindexed | static_cast<uint32_t>(unindexed_.size()));
  unindexed_.push_back({box, index});
}

void OccluderBvh::remove(uint32_t index) noexcept {
  const uint32_t position = position_[index];
  if (position & kUnindexed) {
    // Swap with the last unindexed box.
    const uint32_t slot = position & ~kUnindexed;
    unindexed_[slot] = unindexed_.back();
    unindexed_.pop_back();
    if (slot < unindexed_.size()) position_[unindexed_[slot].index] = kUnindexed | slot;
  } else {
    // Swap with the last item of the same leaf, which shrinks by one.
    const uint32_t leaf = item_leaf_[position];
    Node& nd = nodes_[leaf];
    const uint32_t last = nd.offset + nd.count - 1;
    if (position != last) {
      items_[position] = items_[last];
      item_boxes_[position] = item_boxes_[last];
      position_[items_[position]] = position;
    }
    --nd.count;
    refit_from(leaf);
  }
  // The last index takes the removed one's place.
  const auto last_index = static_cast<uint32_t>(position_.size() - 1);
  if (index != last_index) set_position(index, position_[last_index]);
  position_.pop_back();
}

bool OccluderBvh::needs_rebuild() const noexcept {
  const size_t limit = std::max<size_t>(8, position_.size() / 8);
  return unindexed_.size() > limit || cost_ > 2.0 * built_cost_ + 1e-300;
}

// Returns the split point of items_[begin, end), reordered; both sides are non-empty.
uint32_t OccluderBvh::split(uint32_t begin, uint32_t end, const Aabb& cb, int depth) {
  const uint32_t count = end - begin;
  // Halved extents stay finite whatever the (finite) coordinates.
  const double ext_x = 0.5 * cb.max_x - 0.5 * cb.min_x;
  const double ext_y = 0.5 * cb.max_y - 0.5 * cb.min_y;
  const int axis = ext_y > ext_x ? 1 : 0;
  const double extent = axis == 0 ? ext_x : ext_y;
  const double low = 0.5 * (axis == 0 ? cb.min_x : cb.min_y);
  BuildRef* first = refs_.data() + begin;
  BuildRef* last = refs_.data() + end;
  const uint32_t half = begin + count / 2;

  // All centroids equal (e.g. identical boxes): any split is as good; halving bounds the depth.
  if (!(extent > 0.0)) return half;

  auto median_split = [&]() {
    std::nth_element(first, refs_.data() + half, last, [&](const BuildRef& a, const BuildRef& b) {
      return axis_of(centroid(a.box), axis) < axis_of(centroid(b.box), axis);
    });
    return half;
  };
  const double scale = kBins / extent;
  // Below kSahDepth, or when binning cannot resolve the extent (denormal), median splits keep the
  // tree within kMaxDepth.
  if (depth >= kSahDepth || !std::isfinite(scale)) return median_split();

  auto bin_of = [&](const BuildRef& ref) {
    const double t = (0.5 * axis_of(centroid(ref.box), axis) - low) * scale;
    // t >= 0 up to rounding; the clamp also maps the maximum (t == kBins) into the last bin.
    return std::clamp(static_cast<int>(t), 0, kBins - 1);
  };

  uint32_t bin_count[kBins] = {};
  Aabb bin_box[kBins];
  std::fill(bin_box, bin_box + kBins, kEmptyBox);
  for (const BuildRef* it = first; it != last; ++it) {
    const int b = bin_of(*it);
    ++bin_count[b];
    grow(bin_box[b], it->box);
  }

  // Sweep from the right to get the cost of every right side, then from the left to pick the
  // plane (after bin `best`) with the least count * half-perimeter sum; ties go to the lowest plane.
  double right_cost[kBins];
  Aabb acc = kEmptyBox;
  uint32_t acc_count = 0;
  for (int b = kBins - 1; b > 0; --b) {
    grow(acc, bin_box[b]);
    acc_count += bin_count[b];
    right_cost[b] = acc_count == 0 ? kInf : static_cast<double>(acc_count) * half_perimeter(acc);
  }
  acc = kEmptyBox;
  acc_count = 0;
  int best = -1;
  double best_cost = kInf;
  for (int b = 0; b < kBins - 1; ++b) {
    grow(acc, bin_box[b]);
    acc_count += bin_count[b];
    if (acc_count == 0 || acc_count == count) continue;
    const double cost = static_cast<double>(acc_count) * half_perimeter(acc) + right_cost[b + 1];
    if (cost < best_cost) {
      best_cost = cost;
      best = b;
    }
  }
  if (best < 0) return median_split();  // e.g. costs overflowed
  const BuildRef* mid = std::partition(first, last, [&](const BuildRef& ref) { return bin_of(ref) <= best; });
  return begin + static_cast<uint32_t>(mid - first);
}

// Depth-first traversal with a fixed stack: `node_test` prunes subtrees, `item_test`
// decides each item of a reached leaf. Appends the hits in increasing index order.
template <class NodeTest, class ItemTest>
void OccluderBvh::collect(NodeTest&& node_test, ItemTest&& item_test, std::vector<uint32_t>& out) const noexcept {
  const size_t first_out = out.size();
  for (const BuildRef& ref : unindexed_) {
    if (item_test(ref.box)) out.push_back(ref.index);
  }
  if (nodes_.empty()) {
    std::sort(out.begin() + static_cast<std::ptrdiff_t>(first_out), out.end());
    return;
  }
  uint32_t stack[kMaxDepth];
  int top = 0;
  uint32_t node = 0;
  for (;;) {
    const Node& nd = nodes_[node];
    if (node_test(nd.box)) {
      if (nd.count == kInterior) {
        stack[top++] = nd.offset;
        node += 1;
        continue;
      }
      for (uint32_t i = nd.offset; i < nd.offset + nd.count; ++i) {
        if (item_test(item_boxes_[i])) out.push_back(items_[i]);
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first_out), out.end());
}

void OccluderBvh::query_convex(const Vec2* hull, int hull_count, std::vector<uint32_t>& out) const noexcept {
  if (hull == nullptr || hull_count <= 0) return;
  const ConvexQuery query(hull, hull_count);
  collect([&](const Aabb& b) { return query.may_touch(b); }, [&](const Aabb& b) { return query.touches(b); }, out);
}

void OccluderBvh::query_box(const Aabb& query, std::vector<uint32_t>& out) const noexcept {
  auto overlaps = [&](const Aabb& b) { return boxes_meet(b, query); };
  collect(overlaps, overlaps, out);
}

}  // namespace par2d::detail
