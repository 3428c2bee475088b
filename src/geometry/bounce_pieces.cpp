// The boundary pieces of docs/contract.md section 7: equal cuts of each polygon edge, each
// segment face, each circle.
#include "geometry/bounce_pieces.hpp"

#include <cmath>

#include "geometry/vec2.hpp"

namespace par2d::detail {
namespace {

constexpr double kTwoPiValue = 6.283185307179586476925286766559;

// ceil(length / h) for one straight run, 0 for a zero-length one.
double straight_count(Vec2 a, Vec2 b, double h) noexcept {
  const double l = length(b - a);
  return l > 0.0 ? std::ceil(l / h) : 0.0;
}

// Twice the signed area of a polygon (relative to its first vertex, so far-off polygons
// keep their precision): > 0 when counter-clockwise in a y-up frame.
double signed_area2(const std::vector<Vec2>& v) noexcept {
  double sum = 0.0;
  for (std::size_t i = 1; i + 1 < v.size(); ++i) sum += cross(v[i] - v[0], v[i + 1] - v[0]);
  return sum;
}

Vec2 scaled(Vec2 p, double f) noexcept { return {f * p.x, f * p.y}; }

// The n pieces of the straight run a -> b with outward normal `normal`.
void straight_pieces(Vec2 a, Vec2 b, Vec2 normal, std::size_t n, double factor, std::vector<BouncePiece>& out) {
  const Vec2 e = b - a;
  for (std::size_t i = 0; i < n; ++i) {
    const double u0 = static_cast<double>(i) / static_cast<double>(n);
    const double u1 = static_cast<double>(i + 1) / static_cast<double>(n);
    const double um = (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    BouncePiece p;
    p.a = scaled(i == 0 ? a : a + u0 * e, factor);
    p.b = scaled(i + 1 == n ? b : a + u1 * e, factor);
    p.mid = scaled(a + um * e, factor);
    p.normal = normal;
    out.push_back(p);
  }
}

}  // namespace

double bounce_piece_count(const Shape& shape, double h, double stop_after) noexcept {
  if (const auto* circle = std::get_if<Circle>(&shape)) return std::ceil(kTwoPiValue * circle->radius / h);
  if (const auto* segment = std::get_if<Segment>(&shape)) return 2.0 * straight_count(segment->a, segment->b, h);
  const auto& v = std::get<Polygon>(shape).vertices;
  double count = 0.0;
  for (std::size_t i = 0; i < v.size() && count <= stop_after; ++i)
    count += straight_count(v[i], v[i + 1 == v.size() ? 0 : i + 1], h);
  return count;
}

void bounce_pieces(const Shape& shape, double h, std::vector<BouncePiece>& out) { bounce_pieces(shape, h, 1.0, out); }

void bounce_pieces(const Shape& shape, double h, double factor, std::vector<BouncePiece>& out) {
  if (const auto* circle = std::get_if<Circle>(&shape)) {
    const auto n = static_cast<std::size_t>(std::ceil(kTwoPiValue * circle->radius / h));
    const Vec2 c = scaled(circle->center, factor);
    const double r = factor * circle->radius;
    for (std::size_t k = 0; k < n; ++k) {
      BouncePiece p;
      p.arc = true;
      p.center = c;
      p.radius = r;
      p.angle0 = kTwoPiValue * static_cast<double>(k) / static_cast<double>(n);
      p.angle1 = k + 1 == n ? kTwoPiValue : kTwoPiValue * static_cast<double>(k + 1) / static_cast<double>(n);
      const double middle = kTwoPiValue * (static_cast<double>(k) + 0.5) / static_cast<double>(n);
      p.normal = {std::cos(middle), std::sin(middle)};
      p.mid = c + r * p.normal;
      p.a = c + r * Vec2{std::cos(p.angle0), std::sin(p.angle0)};
      p.b = c + r * Vec2{std::cos(p.angle1), std::sin(p.angle1)};
      out.push_back(p);
    }
    return;
  }
  if (const auto* segment = std::get_if<Segment>(&shape)) {
    const Vec2 e = segment->b - segment->a;
    const double l = length(e);
    if (!(l > 0.0)) return;
    const auto n = static_cast<std::size_t>(std::ceil(l / h));
    const Vec2 perp{e.y / l, -e.x / l};
    straight_pieces(segment->a, segment->b, perp, n, factor, out);
    straight_pieces(segment->a, segment->b, Vec2{-perp.x, -perp.y}, n, factor, out);
    return;
  }
  const auto& v = std::get<Polygon>(shape).vertices;
  // Counter-clockwise (y-up sense): the inside is left of each edge, the outside right.
  const double orientation = signed_area2(v) > 0.0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[i + 1 == v.size() ? 0 : i + 1];
    const Vec2 e = b - a;
    const double l = length(e);
    if (!(l > 0.0)) continue;
    const Vec2 normal{orientation * e.y / l, -orientation * e.x / l};
    straight_pieces(a, b, normal, static_cast<std::size_t>(std::ceil(l / h)), factor, out);
  }
}

}  // namespace par2d::detail
