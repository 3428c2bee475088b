// Greedy vertex removal within a tolerance over many rings at once, each removal checked against a grid of vertices.
#include "geometry/ring_simplify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <tuple>
#include <vector>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {
namespace {

constexpr int kMaxPasses = 16;

// Every vertex of every ring in one array; links make each ring a circular list of the kept ones.
struct RingVertices {
  std::vector<Vec2> pos;
  std::vector<std::uint32_t> ring;   // which ring
  std::vector<std::uint32_t> index;  // position in its ring's input
  std::vector<std::uint32_t> prev, next;
  std::vector<std::uint32_t> first;  // per ring: where its vertices start in `pos`
  std::vector<std::uint32_t> size;   // per ring: its input vertex count
  std::vector<std::uint32_t> kept;   // per ring: vertices still in it
  std::vector<std::uint8_t> alive;
};

// The vertices by cell of a uniform grid over their bounding box (they never move; removed
// ones are skipped where they are found).
class VertexGrid {
 public:
  explicit VertexGrid(const std::vector<Vec2>& pos) {
    lo_ = hi_ = pos.empty() ? Vec2{} : pos[0];
    for (const Vec2& p : pos) {
      lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y)};
      hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y)};
    }
    const double w = std::max(hi_.x - lo_.x, 1e-300), h = std::max(hi_.y - lo_.y, 1e-300);
    // About two vertices a cell where they spread evenly.
    const double cells = std::max(1.0, static_cast<double>(pos.size()) / 2.0);
    cell_ = std::sqrt(w * h / cells);
    if (!(cell_ > 0.0) || !std::isfinite(cell_)) cell_ = std::max(w, h);
    nx_ = static_cast<int>(std::min(4096.0, std::floor(w / cell_) + 1.0));
    ny_ = static_cast<int>(std::min(4096.0, std::floor(h / cell_) + 1.0));
    cell_x_ = w / nx_;
    cell_y_ = h / ny_;
    start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
    for (const Vec2& p : pos) ++start_[cell_of(p) + 1];
    for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
    items_.resize(pos.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::uint32_t v = 0; v < pos.size(); ++v) items_[fill[cell_of(pos[v])]++] = v;
  }

  // Calls f(v) for every vertex in the cells the box [a, b] overlaps; stops when f returns true.
  template <class F>
  bool any_in_box(Vec2 a, Vec2 b, F&& f) const {
    const int x0 = column(a.x), x1 = column(b.x), y0 = row(a.y), y1 = row(b.y);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t c = static_cast<std::size_t>(y) * nx_ + x;
        for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k)
          if (f(items_[k])) return true;
      }
    return false;
  }

 private:
  int column(double x) const { return std::clamp(static_cast<int>(std::floor((x - lo_.x) / cell_x_)), 0, nx_ - 1); }
  int row(double y) const { return std::clamp(static_cast<int>(std::floor((y - lo_.y) / cell_y_)), 0, ny_ - 1); }
  std::size_t cell_of(Vec2 p) const { return static_cast<std::size_t>(row(p.y)) * nx_ + column(p.x); }

  Vec2 lo_, hi_;
  double cell_ = 1.0, cell_x_ = 1.0, cell_y_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_, items_;
};

// Distance from q to the segment a-b; exactly 0 where q lies on it (exact orientation).
double segment_distance(Vec2 a, Vec2 b, Vec2 q) {
  const bool in_box =
      q.x >= std::min(a.x, b.x) && q.x <= std::max(a.x, b.x) && q.y >= std::min(a.y, b.y) && q.y <= std::max(a.y, b.y);
  if (in_box && orientation(a, b, q) == 0) return 0.0;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((q.x - a.x) * dx + (q.y - a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(q.x - (a.x + t * dx), q.y - (a.y + t * dy));
}

class Simplifier {
 public:
  Simplifier(RingVertices& r, double tolerance) : r_(r), tolerance_(tolerance), grid_(r.pos) {}

  // The largest distance from the segment prev(v)-next(v) of the input vertices it would
  // replace; infinity past the tolerance.
  double error(std::uint32_t v) const {
    const std::uint32_t p = r_.prev[v], n = r_.next[v], ring = r_.ring[v];
    const std::uint32_t size = r_.size[ring], base = r_.first[ring];
    const std::uint32_t count = (r_.index[n] + size - r_.index[p]) % size;
    double worst = 0.0;
    for (std::uint32_t k = 1; k < count; ++k) {
      const std::uint32_t q = base + (r_.index[p] + k) % size;
      worst = std::max(worst, segment_distance(r_.pos[p], r_.pos[n], r_.pos[q]));
      if (worst > tolerance_) return std::numeric_limits<double>::infinity();
    }
    return worst;
  }

  // Whether another kept vertex lies in the closed triangle prev(v), v, next(v).
  bool blocked(std::uint32_t v) const {
    const std::uint32_t p = r_.prev[v], n = r_.next[v];
    const Vec2 a = r_.pos[p], b = r_.pos[v], c = r_.pos[n];
    const int turn = orientation(a, b, c);
    const Vec2 lo{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y})};
    const Vec2 hi{std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y})};
    return grid_.any_in_box(lo, hi, [&](std::uint32_t q) {
      if (!r_.alive[q] || q == p || q == v || q == n) return false;
      const Vec2 x = r_.pos[q];
      if (x.x < lo.x || x.x > hi.x || x.y < lo.y || x.y > hi.y) return false;
      if (turn == 0) return orientation(a, c, x) == 0;  // v on the segment a-c: x on it too
      return orientation(a, b, x) * turn >= 0 && orientation(b, c, x) * turn >= 0 && orientation(c, a, x) * turn >= 0;
    });
  }

  // One pass: removes what it can, smallest error first. Whether it removed anything.
  bool pass() {
    using Entry = std::tuple<double, std::uint32_t, std::uint32_t>;  // error, vertex, stamp
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    stamp_.resize(r_.pos.size(), 0);
    auto offer = [&](std::uint32_t v) {
      if (r_.kept[r_.ring[v]] <= 3) return;
      const double e = error(v);
      if (e <= tolerance_) heap.emplace(e, v, stamp_[v]);
    };
    for (std::uint32_t v = 0; v < r_.pos.size(); ++v)
      if (r_.alive[v]) offer(v);
    bool removed = false;
    while (!heap.empty()) {
      const auto [e, v, stamp] = heap.top();
      heap.pop();
      if (!r_.alive[v] || stamp != stamp_[v] || r_.kept[r_.ring[v]] <= 3 || blocked(v)) continue;
      const std::uint32_t p = r_.prev[v], n = r_.next[v];
      r_.next[p] = n;
      r_.prev[n] = p;
      r_.alive[v] = 0;
      --r_.kept[r_.ring[v]];
      ++stamp_[p];
      ++stamp_[n];
      offer(p);
      offer(n);
      removed = true;
    }
    return removed;
  }

 private:
  RingVertices& r_;
  double tolerance_;
  VertexGrid grid_;
  std::vector<std::uint32_t> stamp_;
};

}  // namespace

void simplify_rings(std::vector<std::vector<Vec2>>& rings, double tolerance) {
  RingVertices r;
  std::size_t total = 0;
  for (const auto& ring : rings) total += ring.size();
  r.pos.reserve(total);
  for (std::uint32_t k = 0; k < rings.size(); ++k) {
    const auto base = static_cast<std::uint32_t>(r.pos.size());
    const auto n = static_cast<std::uint32_t>(rings[k].size());
    r.first.push_back(base);
    r.size.push_back(n);
    r.kept.push_back(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      r.pos.push_back(rings[k][i]);
      r.ring.push_back(k);
      r.index.push_back(i);
      r.prev.push_back(base + (i + n - 1) % n);
      r.next.push_back(base + (i + 1) % n);
    }
  }
  r.alive.assign(r.pos.size(), 1);
  Simplifier simplifier(r, tolerance);
  for (int pass = 0; pass < kMaxPasses && simplifier.pass(); ++pass) {
  }
  for (std::uint32_t k = 0; k < rings.size(); ++k) {
    std::vector<Vec2> kept;
    kept.reserve(r.kept[k]);
    for (std::uint32_t i = 0; i < r.size[k]; ++i)
      if (r.alive[r.first[k] + i]) kept.push_back(r.pos[r.first[k] + i]);
    rings[k] = std::move(kept);
  }
}

}  // namespace par2d::detail
