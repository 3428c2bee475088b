// Triangulation of a polygon with holes by monotone decomposition (de Berg et al.,
// Computational Geometry, ch. 3; monotone_triangulation.hpp): a sweep from top to bottom adds
// the diagonals that cut the polygon, holes included, into pieces monotone along the sweep, and
// each piece is triangulated in one pass down its two chains. "Above" is the sweep order: larger
// y, or equal y and smaller x (a symbolic rotation, so that no two vertices tie and a
// horizontal edge is treated as descending to the right). Every decision is that order or an
// exact orientation sign.
#include "geometry/monotone_triangulation.hpp"

#include <algorithm>
#include <set>
#include <utility>

#include "geometry/polygon_partition.hpp"

namespace par2d::detail {

bool same_direction(Vec2 apex, Vec2 p, Vec2 q) noexcept {
  if (p.x != apex.x) return (p.x > apex.x) == (q.x > apex.x);
  return (p.y > apex.y) == (q.y > apex.y);  // a vertical line
}

namespace {

// Whether the direction d - apex lies in the closed wedge swept counter-clockwise from s - apex
// to e - apex (a straight angle: the closed left half-plane; s and e the same way: the full
// turn).
bool in_wedge(Vec2 apex, Vec2 s, Vec2 e, Vec2 d) noexcept {
  const int se = orientation(apex, s, e);
  if (se > 0) return orientation(apex, s, d) >= 0 && orientation(apex, d, e) >= 0;
  if (se < 0) return !(orientation(apex, e, d) > 0 && orientation(apex, d, s) > 0);
  if (same_direction(apex, s, e)) return true;
  return orientation(apex, s, d) >= 0;
}

bool above(Vec2 p, Vec2 q) noexcept { return p.y > q.y || (p.y == q.y && p.x < q.x); }

// The rings and the diagonals added to them: nodes in doubly linked rings, each naming a vertex
// id. A vertex where diagonals end has one node ("copy") per piece around it, each with its
// own wedge of the polygon.
struct Mesh {
  std::vector<Vec2> points;             // by vertex id
  std::vector<int> vertex, prev, next;  // by node
  std::vector<int> next_copy;           // by node: the vertex's next node, or -1
  std::vector<int> first_copy;          // by vertex id

  Vec2 at(int node) const noexcept { return points[static_cast<std::size_t>(vertex[node])]; }
  int add_node(int vertex_id) {
    vertex.push_back(vertex_id);
    prev.push_back(-1);
    next.push_back(-1);
    next_copy.push_back(first_copy[static_cast<std::size_t>(vertex_id)]);
    const int node = static_cast<int>(vertex.size()) - 1;
    first_copy[static_cast<std::size_t>(vertex_id)] = node;
    return node;
  }
  // Whether the direction from node x toward d lies in the polygon's (closed) wedge at x: from
  // the outgoing edge counter-clockwise to the incoming one (the interior lies left of edges).
  bool wedge_holds(int x, Vec2 d) const noexcept { return in_wedge(at(x), at(next[x]), at(prev[x]), d); }
  // The copy of vertex v whose wedge holds the direction toward d, or -1.
  int copy_toward(int v, Vec2 d) const noexcept {
    for (int x = first_copy[static_cast<std::size_t>(v)]; x >= 0; x = next_copy[static_cast<std::size_t>(x)])
      if (wedge_holds(x, d)) return x;
    return -1;
  }
  // Cuts the piece holding the diagonal between vertices a and b (distinct, the diagonal inside
  // the polygon) into two along it. False if no wedge at a or b holds it (a bug).
  bool split(int a, int b) {
    const int na = copy_toward(a, points[static_cast<std::size_t>(b)]);
    const int nb = copy_toward(b, points[static_cast<std::size_t>(a)]);
    if (na < 0 || nb < 0) return false;
    const int a_next = next[na], b_next = next[nb];
    const int a2 = add_node(a), b2 = add_node(b);
    // na -> b2 -> (old next of nb) ... na, and nb -> a2 -> (old next of na) ... nb.
    next[na] = b2;
    prev[b2] = na;
    next[b2] = b_next;
    prev[b_next] = b2;
    next[nb] = a2;
    prev[a2] = nb;
    next[a2] = a_next;
    prev[a_next] = a2;
    return true;
  }
};

// The edges the sweep line crosses with the polygon's interior on their right, left to right.
// An edge is named by the node it starts at; it runs downward (its start is above its end).
// Two such edges never cross, so the one that entered later has its start between the other's
// ends, strictly left or right of it: that orders them.
class SweepStatus {
 public:
  SweepStatus(const Mesh& mesh, std::size_t node_count, std::size_t& tests)
      : edges_(Order{&mesh, &tests}), where_(node_count), inside_(node_count, 0) {}

  void insert(int edge) {
    where_[static_cast<std::size_t>(edge)] = edges_.insert(edge).first;
    inside_[static_cast<std::size_t>(edge)] = 1;
  }
  void erase(int edge) {
    if (!inside_[static_cast<std::size_t>(edge)]) return;
    edges_.erase(where_[static_cast<std::size_t>(edge)]);
    inside_[static_cast<std::size_t>(edge)] = 0;
  }
  // The edge directly left of p (the nearest whose crossing with p's sweep line is left of p),
  // or -1.
  int left_of(Vec2 p) const {
    auto it = edges_.lower_bound(p);  // the first edge not left of p
    if (it == edges_.begin()) return -1;
    return *--it;
  }

 private:
  struct Order {
    using is_transparent = void;
    const Mesh* mesh;
    std::size_t* tests;
    // Whether edge e passes left of p, p strictly between its ends in the sweep order.
    bool edge_left(int e, Vec2 p) const noexcept {
      ++*tests;
      return orientation(mesh->at(e), mesh->at(mesh->next[e]), p) > 0;
    }
    bool operator()(int a, int b) const noexcept {
      if (a == b) return false;
      const Vec2 pa = mesh->at(a), pb = mesh->at(b);
      if (above(pb, pa)) return !edge_left(b, pa);  // a entered later: a is left of b unless b passes left of a's start
      return edge_left(a, pb);
    }
    bool operator()(int e, Vec2 p) const noexcept { return edge_left(e, p); }
    bool operator()(Vec2 p, int e) const noexcept { return !edge_left(e, p); }
  };
  std::set<int, Order> edges_;
  std::vector<std::set<int, Order>::iterator> where_;  // by edge, while inside_
  std::vector<char> inside_;
};

// Adds the diagonals that cut the mesh's rings (outer counter-clockwise, holes clockwise) into
// pieces monotone in the sweep order: each split vertex (a reflex vertex whose neighbours are
// both below) gets a diagonal up, each merge vertex (reflex, both neighbours above) one down, to
// the "helper" of the edge left of it (the lowest vertex above the sweep line that sees that
// edge horizontally). False on a bug (no edge where one must be).
bool monotone_diagonals(const Mesh& mesh, int node_count, std::vector<std::pair<int, int>>& diagonals,
                        std::size_t& tests) {
  std::vector<int> order(static_cast<std::size_t>(node_count));
  for (int n = 0; n < node_count; ++n) order[static_cast<std::size_t>(n)] = n;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return above(mesh.at(a), mesh.at(b)); });
  std::vector<int> helper(static_cast<std::size_t>(node_count), -1);
  std::vector<char> merge(static_cast<std::size_t>(node_count), 0);
  SweepStatus status(mesh, static_cast<std::size_t>(node_count), tests);
  const auto connect_if_merge = [&](int v, int edge) {
    const int h = helper[static_cast<std::size_t>(edge)];
    if (h >= 0 && merge[static_cast<std::size_t>(h)]) diagonals.emplace_back(v, h);
  };
  for (const int v : order) {
    const int u = mesh.prev[v], w = mesh.next[v];
    const Vec2 pu = mesh.at(u), pv = mesh.at(v), pw = mesh.at(w);
    const bool reflex = orientation(pu, pv, pw) < 0;  // no straight vertex is left
    const bool u_below = above(pv, pu), w_below = above(pv, pw);
    if (u_below && w_below) {
      if (reflex) {  // split
        const int e = status.left_of(pv);
        if (e < 0) return false;
        diagonals.emplace_back(v, helper[static_cast<std::size_t>(e)]);
        helper[static_cast<std::size_t>(e)] = v;
      }
      status.insert(v);  // start or split: the edge v -> w enters
      helper[static_cast<std::size_t>(v)] = v;
    } else if (!u_below && !w_below) {
      connect_if_merge(v, u);  // end or merge: the edge u -> v leaves
      status.erase(u);
      if (reflex) {
        merge[static_cast<std::size_t>(v)] = 1;
        const int e = status.left_of(pv);
        if (e < 0) return false;
        connect_if_merge(v, e);
        helper[static_cast<std::size_t>(e)] = v;
      }
    } else if (w_below) {  // going down: the interior is right of v
      connect_if_merge(v, u);
      status.erase(u);
      status.insert(v);
      helper[static_cast<std::size_t>(v)] = v;
    } else {  // going up: the interior is left of v
      const int e = status.left_of(pv);
      if (e < 0) return false;
      connect_if_merge(v, e);
      helper[static_cast<std::size_t>(e)] = v;
    }
  }
  return true;
}

// Triangulates one monotone piece (the ring through `start`) in one pass down its two chains,
// appending counter-clockwise triangles of vertex ids. Triangles a run of collinear vertices
// would make flat are left out (they hold no area).
void triangulate_monotone(const Mesh& mesh, int start, std::vector<std::array<int, 3>>& triangles,
                          std::vector<std::pair<int, bool>>& sorted, std::vector<std::pair<int, bool>>& stack,
                          std::size_t& tests) {
  int top = start, bottom = start;
  for (int x = mesh.next[start]; x != start; x = mesh.next[x]) {
    if (above(mesh.at(x), mesh.at(top))) top = x;
    if (above(mesh.at(bottom), mesh.at(x))) bottom = x;
  }
  // Down the left chain (following next from the top) and the right one (prev from the top),
  // merged; `true` marks the left chain.
  sorted.clear();
  sorted.emplace_back(top, true);
  int l = mesh.next[top], r = mesh.prev[top];
  while (l != bottom || r != bottom) {
    if (r == bottom || (l != bottom && above(mesh.at(l), mesh.at(r)))) {
      sorted.emplace_back(l, true);
      l = mesh.next[l];
    } else {
      sorted.emplace_back(r, false);
      r = mesh.prev[r];
    }
  }
  sorted.emplace_back(bottom, true);
  const auto emit = [&](int a, int b, int c) {
    ++tests;
    const int o = orientation(mesh.at(a), mesh.at(b), mesh.at(c));
    if (o > 0) triangles.push_back({mesh.vertex[a], mesh.vertex[b], mesh.vertex[c]});
    if (o < 0) triangles.push_back({mesh.vertex[a], mesh.vertex[c], mesh.vertex[b]});
  };
  const std::size_t n = sorted.size();
  if (n < 3) return;
  stack.assign(sorted.begin(), sorted.begin() + 2);
  for (std::size_t j = 2; j + 1 < n; ++j) {
    const auto [v, left] = sorted[j];
    if (left != stack.back().second) {
      // v sees the whole reflex chain on the other side: a fan.
      for (std::size_t k = 0; k + 1 < stack.size(); ++k) emit(v, stack[k].first, stack[k + 1].first);
      const auto last = stack.back();
      stack.clear();
      stack.push_back(last);
      stack.emplace_back(v, left);
    } else {
      // Same chain: clip while the triangle with the next vertex up turns the way the chain's
      // interior lies (strictly: a collinear run stays on the stack).
      auto x = stack.back();
      stack.pop_back();
      while (!stack.empty()) {
        const int t = stack.back().first;
        ++tests;
        const int o = left ? orientation(mesh.at(t), mesh.at(x.first), mesh.at(v))
                           : orientation(mesh.at(v), mesh.at(x.first), mesh.at(t));
        if (o <= 0) break;
        if (left)
          triangles.push_back({mesh.vertex[t], mesh.vertex[x.first], mesh.vertex[v]});
        else
          triangles.push_back({mesh.vertex[v], mesh.vertex[x.first], mesh.vertex[t]});
        x = stack.back();
        stack.pop_back();
      }
      stack.push_back(x);
      stack.emplace_back(v, left);
    }
  }
  const int b = sorted[n - 1].first;
  for (std::size_t k = 0; k + 1 < stack.size(); ++k) emit(b, stack[k].first, stack[k + 1].first);
}

}  // namespace

bool triangulate_polygon(const std::vector<Vec2>& points, const std::vector<int>& ring_sizes,
                         std::vector<std::array<int, 3>>& triangles, std::size_t& tests) {
  Mesh mesh;
  mesh.points = points;
  mesh.first_copy.assign(points.size(), -1);
  int first = 0;
  for (const int n : ring_sizes) {
    for (int k = 0; k < n; ++k) {
      const int node = mesh.add_node(first + k);
      mesh.prev[node] = first + (k + n - 1) % n;
      mesh.next[node] = first + (k + 1) % n;
    }
    first += n;
  }
  const int ring_nodes = static_cast<int>(mesh.vertex.size());
  std::vector<std::pair<int, int>> diagonals;
  if (!monotone_diagonals(mesh, ring_nodes, diagonals, tests)) return false;
  for (const auto& [a, b] : diagonals)
    if (!mesh.split(mesh.vertex[a], mesh.vertex[b])) return false;
  std::vector<char> seen(mesh.vertex.size(), 0);
  std::vector<std::pair<int, bool>> sorted, stack;
  for (int n = 0; n < static_cast<int>(mesh.vertex.size()); ++n) {
    if (seen[static_cast<std::size_t>(n)]) continue;
    int x = n;
    do {
      seen[static_cast<std::size_t>(x)] = 1;
      x = mesh.next[x];
    } while (x != n);
    triangulate_monotone(mesh, n, triangles, sorted, stack, tests);
  }
  return true;
}


}  // namespace par2d::detail
