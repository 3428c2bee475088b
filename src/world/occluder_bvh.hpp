// Bounding volume hierarchy over occluder boxes: finds the occluders a tile-to-light hull can touch.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/aabb.hpp"
#include "geometry/convex_shape.hpp"
#include "par2d/scene.hpp"

namespace par2d::detail {

// Convex hull by Andrew's monotone chain. Counter-clockwise in the math sense: the cross
// product of consecutive edges is positive (with the contract's y-down axes that looks clockwise on
// screen). Starts at the lowest (x, then y) point. Duplicate and collinear points are dropped,
// so the result has 0 points (empty input), 1 (all points equal), 2 (all collinear: the two
// extremes) or >= 3 strictly convex vertices. Exact for coordinates whose pairwise products
// do not overflow (|coordinate| < ~1e150).
std::vector<Vec2> convex_hull(std::vector<Vec2> points);

// The same without allocating: sorts `points` in place and writes the hull to `out`, which
// must hold 2 * count + 1 points (the chains grow before they are trimmed). Returns the
// number of hull points.
int convex_hull(Vec2* points, int count, Vec2* out) noexcept;

// The convex hull of `extra[0..extra_count)` and a shape (circles by their bounding box): a
// polygon every segment from those points to the shape stays inside, for query_convex.
// `points` is scratch; the hull is written to `hull`. Allocates only while they grow.
void hull_with_shape(const Vec2* extra, int extra_count, const ConvexShape& shape, std::vector<Vec2>& points,
                     std::vector<Vec2>& hull);

// A convex polygon (e.g. from convex_hull) prepared for repeated box tests: its
// separating axes are computed once. Keeps a pointer to `hull`, which must outlive it.
class ConvexQuery {
 public:
  static constexpr int kMaxCachedAxes = 32;
  // One separating-axis candidate: a unit normal and the hull's extent along it.
  struct Axis {
    double nx, ny, lo, hi;
  };
  // One side of an axis test in a branch-free form: the box lies beyond the hull where
  // nx * corner_x + ny * corner_y < bound, for the box corner (x_index, y_index into
  // {min_x, min_y, max_x, max_y}) that maximises that sum. The side `lo > hi_of_hull` is
  // stored negated ((-n).p < -hi, the same comparison: negation rounds symmetrically).
  struct HalfTest {
    double nx, ny, bound;
    int x_index, y_index;
  };

  ConvexQuery(const Vec2* hull, int count) noexcept;
  const Aabb& bounds() const noexcept { return bounds_; }
  // May report a box the hull misses (hulls of more than kMaxCachedAxes edges), never the reverse.
  bool may_touch(const Aabb& b) const noexcept;
  // Exact: no separating axis among the box axes and the hull's edge normals (touching counts).
  bool touches(const Aabb& b) const noexcept;

 private:
  void add_half_test(const HalfTest& t) noexcept;

  const Vec2* hull_;
  int count_;
  int edges_ = 0;
  int orientation_ = 0;  // +1 counterclockwise, -1 clockwise, 0 unknown (see edge_axis)
  int half_test_count_ = 0;
  Aabb bounds_;
  // Two per axis at most; one where the hull's orientation is known (the other side is
  // unbounded, so it never separates).
  HalfTest half_tests_[2 * kMaxCachedAxes];
};

// The convex hull of two axis-aligned boxes (a tile and a light's box: every ray from the
// tile to the light stays inside), for exact box tests without building a general hull:
// it is the boxes' union bounding box with up to four corners cut off, each by the edge
// joining the two boxes' corners on that side (a corner is cut when neither box reaches
// both of its extremes).
class BoxPairHull {
 public:
  BoxPairHull() noexcept = default;  // holds nothing until assigned a pair's hull
  BoxPairHull(const Aabb& a, const Aabb& b) noexcept { assign(a, b); }
  // Made the hull of a and b in place. The tile setup reuses one object per tile and light
  // rather than copying a fresh hull into it: the copy reads the 8-byte fields just stored
  // back as 16-byte loads, which stores cannot forward.
  void assign(const Aabb& a, const Aabb& b) noexcept;
  // Exact separating-axis test (the union box's axes and the cut edges' normals);
  // touching counts as intersecting.
  bool touches(const Aabb& box) const noexcept;

 private:
  struct Cut {
    double nx, ny, offset;  // outside the hull where nx*x + ny*y > offset
  };
  Aabb bounds_;
  Cut cuts_[4];
  int cut_count_ = 0;
};

// Inline: built per tile and light and tested per occluder in the tile setup's inner loop.
inline void BoxPairHull::assign(const Aabb& a, const Aabb& b) noexcept {
  cut_count_ = 0;
  bounds_ = box_union(a, b);
  for (int sx = -1; sx <= 1; sx += 2) {
    for (int sy = -1; sy <= 1; sy += 2) {
      // Does box x reach the union's extreme in x (resp. y) on this side?
      auto reaches_x = [&](const Aabb& x) { return sx < 0 ? x.min_x <= bounds_.min_x : x.max_x >= bounds_.max_x; };
      auto reaches_y = [&](const Aabb& x) { return sy < 0 ? x.min_y <= bounds_.min_y : x.max_y >= bounds_.max_y; };
      if ((reaches_x(a) && reaches_y(a)) || (reaches_x(b) && reaches_y(b))) continue;
      const Vec2 pa{sx < 0 ? a.min_x : a.max_x, sy < 0 ? a.min_y : a.max_y};
      const Vec2 pb{sx < 0 ? b.min_x : b.max_x, sy < 0 ? b.min_y : b.max_y};
      const Vec2 corner{sx < 0 ? bounds_.min_x : bounds_.max_x, sy < 0 ? bounds_.min_y : bounds_.max_y};
      const Vec2 edge = pb - pa;
      if ((edge.x == 0.0 && edge.y == 0.0) || !std::isfinite(edge.x) || !std::isfinite(edge.y)) continue;
      // The edge's normal unnormalized: the test compares two products with the same normal,
      // so its length does not matter, and no square root or division rounds it (they would
      // be a third of the hull's cost, built per tile and light).
      Vec2 n{-edge.y, edge.x};
      if (dot(n, corner - pa) < 0.0) n = Vec2{-n.x, -n.y};  // outward: toward the cut corner
      cuts_[cut_count_++] = {n.x, n.y, std::max(dot(n, pa), dot(n, pb))};
    }
  }
}

inline bool BoxPairHull::touches(const Aabb& box) const noexcept {
  if (!boxes_meet(box, bounds_)) return false;
  for (int i = 0; i < cut_count_; ++i) {
    const Cut& c = cuts_[i];
    const double nearest = c.nx * (c.nx >= 0.0 ? box.min_x : box.max_x) + c.ny * (c.ny >= 0.0 ? box.min_y : box.max_y);
    if (nearest > c.offset) return false;
  }
  return true;
}

// A binned-SAH BVH over boxes (build is linear per level, O(n log n) total, and reuses its
// buffers across builds), updated in place when occluders move, appear or disappear (a
// persistent Renderer): a moved box is refitted along its leaf's path to the root, a removed
// one leaves its leaf, an added one waits in a short unindexed list that every query also
// scans. needs_rebuild() says when the refitted tree has degraded enough that a fresh build
// pays off. Queries give the same answer either way: they are exact box tests.
//
// Layout: nodes are flattened depth-first; an interior node's left child is the next node, its
// right child index is stored. Leaves hold at most kLeafSize items, whose boxes are copied in
// leaf order so a leaf test reads contiguous memory. The depth is bounded (see kMaxDepth), so
// traversal uses a fixed stack and never allocates.
//
// Queries are exact in this sense: a box is reported iff the separating axis test (box axes and
// the hull's edge normals, touching = intersecting) finds no separating axis, computed in double
// with the same arithmetic for inner nodes and items; the inner-node test is monotone under
// rounding, so no box that passes is ever pruned by an ancestor.
class OccluderBvh {
 public:
  static constexpr uint32_t kLeafSize = 4;
  static constexpr int kBins = 16;
  // SAH splits are used down to this depth; below it splits are at the centroid median, so the
  // depth is at most kSahDepth + log2(2^32 / kLeafSize) < kMaxDepth for any input.
  static constexpr int kSahDepth = 32;
  static constexpr int kMaxDepth = 64;

  // Builds over the boxes (index i = occluder i). Throws std::bad_alloc, or std::length_error
  // with more than 2^32 - 1 boxes.
  void build(const std::vector<Aabb>& boxes);

  // Appends to `out`, in increasing index order, every box that intersects the convex polygon
  // `hull` (either winding; 1 point = a point, 2 = a segment; hull_count <= 0 finds nothing).
  // The points must be in convex position in order (e.g. from convex_hull). noexcept: `out` is
  // meant to be per-thread scratch whose capacity has grown, so a failed growth terminates.
  void query_convex(const Vec2* hull, int hull_count, std::vector<uint32_t>& out) const noexcept;

  // Appends to `out`, in increasing index order, every box that intersects `query` (touching counts).
  void query_box(const Aabb& query, std::vector<uint32_t>& out) const noexcept;

  size_t node_count() const noexcept { return nodes_.size(); }
  // Boxes indexed: those in the tree plus the unindexed ones.
  size_t size() const noexcept { return position_.size(); }

  // Incremental updates. Indices stay dense: insert appends index size(); remove(i) drops
  // box i and gives the last box index i (the caller's arrays do the same swap).
  // None allocates once the buffers have grown, except insert past earlier capacity.
  void update(uint32_t index, const Aabb& box) noexcept;
  void insert(const Aabb& box);
  void remove(uint32_t index) noexcept;
  // Whether a fresh build would pay off: many unindexed boxes, or refits have grown the
  // nodes' summed half-perimeters (the SAH cost) to twice what the last build gave.
  bool needs_rebuild() const noexcept;

 private:
  static constexpr uint32_t kInterior = 0xffffffffu;  // Node::count of interior nodes
  static constexpr uint32_t kUnindexed = 0x80000000u;  // position_ flag: in unindexed_
  struct Node {
    Aabb box;
    uint32_t offset;  // leaf: first item in items_; interior: index of the right child
    uint32_t count;   // leaf: number of items (0 once all were removed); interior: kInterior
  };
  struct BuildTask {
    uint32_t begin, end;
    uint32_t parent;  // node whose right-child index this task fills, or kNoParent
    int depth;
  };

  // A box with its occluder index; the build partitions these in place so every pass reads
  // memory sequentially (indirect access through an index array is several times slower).
  struct BuildRef {
    Aabb box;
    uint32_t index;
  };

  uint32_t split(uint32_t begin, uint32_t end, const Aabb& centroid_bounds, int depth);
  template <class NodeTest, class ItemTest>
  void collect(NodeTest&& node_test, ItemTest&& item_test, std::vector<uint32_t>& out) const noexcept;

  void refit_from(uint32_t node) noexcept;
  void set_position(uint32_t index, uint32_t position) noexcept;

  std::vector<Node> nodes_;
  std::vector<uint32_t> items_;  // occluder indices in leaf order
  std::vector<Aabb> item_boxes_;  // boxes in leaf order
  // Incremental state: parent of each node, leaf of each item slot, and where each index
  // lives (an item slot, or kUnindexed | position in unindexed_).
  std::vector<uint32_t> parent_;
  std::vector<uint32_t> item_leaf_;
  std::vector<uint32_t> position_;
  std::vector<BuildRef> unindexed_;
  double built_cost_ = 0.0;  // summed half-perimeters right after build
  double cost_ = 0.0;        // the same now
  // Build scratch, kept so a per-frame rebuild does not reallocate.
  std::vector<BuildRef> refs_;
  std::vector<BuildTask> tasks_;
};

}  // namespace par2d::detail
