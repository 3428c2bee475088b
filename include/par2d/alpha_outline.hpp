// Occluder polygons from an image's alpha (a sprite's shadow caster): trace, simplify within a tolerance, stay valid.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "par2d/scene.hpp"
#include "par2d/status.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// An 8-bit alpha plane the caller owns: the alpha of pixel (i, j) (column i, row j from the top)
// is alpha[j * row_stride + i * pixel_stride]. pixel_stride 1 reads a plain alpha plane; an RGBA8
// image is read with pixel_stride 4 and `alpha` pointing at its first pixel's fourth byte.
struct AlphaMask {
  const std::uint8_t* alpha = nullptr;
  int width = 0;                  // 1 .. kMaxImageSide
  int height = 0;                 // 1 .. kMaxImageSide
  std::ptrdiff_t row_stride = 0;  // bytes from one row to the next, >= width * pixel_stride
  int pixel_stride = 1;           // bytes from one pixel to the next, >= 1
};

// The most vertices (outline and holes together) a polygon may have to be rendered with holes
// or concave (the exact convex partition's bound, docs/contract.md section 3).
inline constexpr std::size_t kMaxOutlineVertices = 65536;

// How polygons_from_alpha reads the mask and places and simplifies what it traces.
struct AlphaOutlineOptions {
  // A pixel is solid where its alpha >= threshold, 0 .. 255 (0: every pixel). Default: 128.
  int threshold = 128;
  // Pixels (before `scale`), >= 0 and finite: every point of an outline lies within
  // max(tolerance, kSaddleShift * sqrt(2)) of the boundary of the solid pixels, and every point
  // of that boundary within as much of an outline. 0 keeps every corner of the pixel
  // boundary (straight runs become one edge). Kept vertices are traced ones (pixel corners), so a 45-degree
  // staircase, whose outer corners lie 0.71 px off the line through its inner ones, becomes
  // one edge only from a tolerance of about 0.73. Default: 1.
  double tolerance = 1.0;
  // The most vertices one polygon (its outline and holes) may keep, 3 .. kMaxOutlineVertices. A
  // polygon that needs more at `tolerance` is an error naming it (raise the tolerance).
  // Default: kMaxOutlineVertices.
  std::size_t max_vertices = kMaxOutlineVertices;
  // Placement: pixel (i, j) covers [i, i + 1] x [j, j + 1] in pixel units, and a pixel-unit
  // point p lands in the world at offset + (scale.x * p.x, scale.y * p.y). Each scale finite
  // and non-zero (negative mirrors); offset finite. Default: world = pixel units.
  Vec2 scale{1.0, 1.0};
  Vec2 offset{0.0, 0.0};
};

// How far (pixels, along each axis) a corner where two solid pixels touch only diagonally is
// moved to keep the outline simple: 1/64 pixel.
inline constexpr double kSaddleShift = 1.0 / 64.0;

// The solid pixels of `mask` as polygons with holes, one per 8-connected group of solid pixels
// (pixels that share an edge or only a corner belong to one polygon; empty pixels that share
// only a corner do not join: such holes stay apart). Rows from the top, so with the default
// placement an outline runs clockwise on screen (positive shoelace area with y down) and its
// holes the other way. Where two solid pixels touch only at a corner, the outline passes that
// corner twice: each pass is moved kSaddleShift along both axes, keeping the area exact, so the
// polygon there has a neck about 2 * kSaddleShift wide instead of touching itself. Simplified
// within `tolerance` by removing vertices, most redundant first, each only where the triangle it
// cuts off (or adds) holds no other vertex: no ring crosses or touches itself, another ring of
// its polygon or any other polygon, and a hole stays strictly inside its outline. Every polygon
// passes validate_scene as an occluder or a light. With tolerance 0 the area of each polygon
// (outline minus holes) is its solid pixel count exactly (times |scale.x * scale.y|, up to the
// placement's rounding).
//
// Polygons come in the order of their first pixel in row order; `out` is cleared first and
// left empty on error. Refused: a null alpha pointer, sizes, strides or options out of range
// (invalid_argument, naming the field), a polygon over max_vertices or one that the
// placement's rounding breaks (an offset far larger than the scale: invalid_argument naming
// the polygon and its first pixel). Memory: about 3 bits per pixel plus the vertices.
Status polygons_from_alpha(const AlphaMask& mask, const AlphaOutlineOptions& options, std::vector<Polygon>& out);

// An image's alpha plane, as load_png_alpha reads it.
struct AlphaImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> alpha;  // width * height, rows from the top

  // A view of it for polygons_from_alpha.
  AlphaMask mask() const noexcept {
    return AlphaMask{alpha.data(), width, height, static_cast<std::ptrdiff_t>(width), 1};
  }
};

// Reads a PNG's alpha (8 or 16 bits, gray or color with alpha; 16-bit values are scaled to 8 bits).
// A PNG without an alpha channel is refused (a sprite's outline needs one). The size is checked
// from the header first: at most kMaxImageSide per side. Messages start with `path`.
Status load_png_alpha(const std::string& path, AlphaImage& out);

}  // namespace par2d
#pragma GCC visibility pop
