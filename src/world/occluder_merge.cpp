// Tilemap box merging: see occluder_merge.hpp.
//
// The World keeps the groups behind the callers' handles: world/world_merge.cpp.
#include "world/occluder_merge.hpp"

#include <algorithm>
#include <functional>
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

bool mergeable_box(const Occluder& o) {
  Box b;
  return mergeable(o) && as_box(o, b);
}

bool joinable(const Occluder& a, const Occluder& b) {
  Box p, q;
  if (!mergeable(a) || !mergeable(b) || !as_box(a, p) || !as_box(b, q) || properties(a) != properties(b)) return false;
  const bool row = p.y0 == q.y0 && p.y1 == q.y1 && (p.x1 == q.x0 || q.x1 == p.x0);
  const bool column = p.x0 == q.x0 && p.x1 == q.x1 && (p.y1 == q.y0 || q.y1 == p.y0);
  return row || column;
}

std::vector<BoxRun> tilemap_box_runs(std::size_t n, const std::function<const Occluder&(std::size_t)>& occluder) {
  // Each box and its properties read once: the sorts below compare these, not the
  // accessor's results through a tuple of properties per comparison.
  struct Key {
    Box box;
    std::tuple<double, double, double, std::uint32_t, int> properties;
  };
  std::vector<Key> keys(n);
  std::vector<char> is_box(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Occluder& o = occluder(i);
    is_box[i] = mergeable(o) && as_box(o, keys[i].box);
    if (is_box[i]) keys[i].properties = properties(o);
  }
  std::vector<Box> boxes(n);
  for (std::size_t i = 0; i < n; ++i) boxes[i] = keys[i].box;
  std::vector<char> taken(n, 0);
  std::vector<std::size_t> next_box(n);  // a box's successor in its chain
  std::vector<BoxRun> runs;
  std::vector<std::size_t> order;
  order.reserve(n);

  // Rows, then columns of what is left: sort by (line, properties, start) and join ends.
  for (int pass = 0; pass < 2; ++pass) {
    order.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (is_box[i] && !taken[i]) order.push_back(i);
    // (line, properties, start, end): boxes in one line differ in start or end, but for exact
    // duplicates (left out below), so the chains follow from the boxes alone, never from the
    // order they are given in. The World regroups in its snapshot order, which forming a
    // group changes, and a load of the snapshot must find the same runs (world_merge.cpp).
    const auto same = [&](std::size_t a, std::size_t b) {
      const Box &p = keys[a].box, &q = keys[b].box;
      return p.x0 == q.x0 && p.y0 == q.y0 && p.x1 == q.x1 && p.y1 == q.y1 && keys[a].properties == keys[b].properties;
    };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const Box &p = keys[a].box, &q = keys[b].box;
      const double pl0 = pass == 0 ? p.y0 : p.x0, ql0 = pass == 0 ? q.y0 : q.x0;
      if (pl0 != ql0) return pl0 < ql0;
      const double pl1 = pass == 0 ? p.y1 : p.x1, ql1 = pass == 0 ? q.y1 : q.x1;
      if (pl1 != ql1) return pl1 < ql1;
      if (keys[a].properties != keys[b].properties) return keys[a].properties < keys[b].properties;
      const double ps = pass == 0 ? p.x0 : p.y0, qs = pass == 0 ? q.x0 : q.y0;
      if (ps != qs) return ps < qs;
      const double pe = pass == 0 ? p.x1 : p.y1, qe = pass == 0 ? q.x1 : q.y1;
      if (pe != qe) return pe < qe;
      return a < b;
    });
    // Within each line (and properties), boxes join end to end: a box continues the chain
    // ending where it starts (the earliest such chain), else starts one. Boxes that overlap
    // or lie between do not break a chain, so whether two boxes join depends only on the
    // boxes meeting them (World::may_join relies on this).
    // A chain: its boxes linked through next_box, first to last; `open` holds the chains
    // that may still grow, `closed` those of two or more boxes that cannot.
    struct Chain {
      double end;
      std::size_t first, last, size;
    };
    std::vector<Chain> chains;
    std::vector<std::size_t> open, closed;
    auto flush = [&] {
      closed.insert(closed.end(), open.begin(), open.end());
      for (const std::size_t c : closed) {
        if (chains[c].size < 2) continue;
        BoxRun run;
        run.sources.reserve(chains[c].size);
        for (std::size_t k = chains[c].first;; k = next_box[k]) {
          run.sources.push_back(k);
          if (k == chains[c].last) break;
        }
        std::sort(run.sources.begin(), run.sources.end());
        Box u = boxes[run.sources[0]];
        for (const std::size_t k : run.sources) {
          taken[k] = 1;
          u.x0 = std::min(u.x0, boxes[k].x0);
          u.y0 = std::min(u.y0, boxes[k].y0);
          u.x1 = std::max(u.x1, boxes[k].x1);
          u.y1 = std::max(u.y1, boxes[k].y1);
        }
        run.shape = box_polygon(u);
        runs.push_back(std::move(run));
      }
      open.clear();
      closed.clear();
      chains.clear();
    };
    for (std::size_t s = 0; s < order.size(); ++s) {
      const std::size_t i = order[s];
      if (s > 0) {
        const Box &prev = boxes[order[s - 1]], &b = boxes[i];
        const bool same_line = pass == 0 ? (prev.y0 == b.y0 && prev.y1 == b.y1) : (prev.x0 == b.x0 && prev.x1 == b.x1);
        if (!same_line || keys[order[s - 1]].properties != keys[i].properties) flush();
      }
      // A box given twice (and its twins) joins nothing: which twin would join is a matter of
      // order alone.
      if ((s > 0 && same(order[s - 1], i)) || (s + 1 < order.size() && same(i, order[s + 1]))) continue;
      const double start = pass == 0 ? boxes[i].x0 : boxes[i].y0;
      // Chains ending before this start can grow no more (starts only increase): closed.
      std::size_t kept = 0, joined = chains.size();
      for (const std::size_t c : open) {
        if (chains[c].end < start) {
          if (chains[c].size >= 2) closed.push_back(c);
          continue;
        }
        if (chains[c].end == start && joined == chains.size()) joined = c;
        open[kept++] = c;
      }
      open.resize(kept);
      const double end = pass == 0 ? boxes[i].x1 : boxes[i].y1;
      if (joined < chains.size()) {
        Chain& c = chains[joined];
        next_box[c.last] = i;
        c.last = i;
        c.end = end;
        ++c.size;
      } else {
        chains.push_back({end, i, i, 1});
        open.push_back(chains.size() - 1);
      }
    }
    flush();
  }
  std::sort(runs.begin(), runs.end(), [](const BoxRun& a, const BoxRun& b) { return a.sources[0] < b.sources[0]; });
  return runs;
}

std::vector<MergedOccluder> merge_tilemap_boxes(const std::vector<Occluder>& occluders) {
  const std::vector<BoxRun> runs =
      tilemap_box_runs(occluders.size(), [&](std::size_t i) -> const Occluder& { return occluders[i]; });
  std::vector<std::ptrdiff_t> group(occluders.size(), -1);
  for (std::size_t g = 0; g < runs.size(); ++g)
    for (const std::size_t k : runs[g].sources) group[k] = static_cast<std::ptrdiff_t>(g);
  std::vector<MergedOccluder> out;
  for (std::size_t i = 0; i < occluders.size(); ++i) {
    if (group[i] < 0) {
      out.push_back({occluders[i], {i}});
    } else if (runs[static_cast<std::size_t>(group[i])].sources[0] == i) {
      const BoxRun& run = runs[static_cast<std::size_t>(group[i])];
      MergedOccluder m{occluders[i], run.sources};
      m.occluder.shape = run.shape;
      out.push_back(std::move(m));
    }
  }
  return out;
}

}  // namespace par2d::detail
