/* The C API's occluders from an alpha mask: a ring of pixels becomes one polygon with a hole,
 * added to a renderer as an occluder that shadows; RGBA strides; errors. Exits non-zero on the
 * first failure. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "par2d/par2d.h"

#include "c_checks.h"

enum { W = 8, H = 6 };

/* Twice the signed area of n (x, y) pairs. */
static double area2(const double* v, size_t n) {
  double a = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double* p = v + 2 * i;
    const double* q = v + 2 * ((i + 1) % n);
    a += p[0] * q[1] - p[1] * q[0];
  }
  return a;
}

int main(void) {
  /* A 4x4 block of solid pixels at (2, 1) with its middle 2x2 empty: a ring of 12 pixels. */
  uint8_t alpha[H][W];
  memset(alpha, 0, sizeof alpha);
  for (int y = 1; y < 5; ++y)
    for (int x = 2; x < 6; ++x) alpha[y][x] = (y == 2 || y == 3) && (x == 3 || x == 4) ? 0 : 255;

  par2d_outline* outline = NULL;
  CHECK(par2d_outline_alpha(&alpha[0][0], W, H, W, 1, 128, 0.0, 65536, NULL, &outline) == PAR2D_OK);
  CHECK(par2d_outline_polygon_count(outline) == 1);
  par2d_shape shape;
  CHECK(par2d_outline_polygon(outline, 0, &shape) == PAR2D_OK);
  CHECK(shape.kind == PAR2D_SHAPE_POLYGON && shape.vertex_count == 4 && shape.hole_count == 1);
  CHECK(shape.hole_vertex_counts != NULL && shape.hole_vertex_counts[0] == 4);
  CHECK(area2(shape.vertices, 4) == 32.0);                 /* 4x4, clockwise on screen */
  CHECK(area2(shape.vertices + 8, 4) == -8.0);             /* the 2x2 hole, the other way */
  CHECK(par2d_outline_polygon(outline, 1, &shape) == PAR2D_INVALID_ARGUMENT);
  CHECK(strncmp(par2d_last_error(), "par2d_outline_polygon: index 1", 30) == 0);

  /* The same as RGBA with a placement: scaled by 2, moved by (10, 20). */
  uint8_t rgba[H][W][4];
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      rgba[y][x][0] = 9;
      rgba[y][x][1] = 9;
      rgba[y][x][2] = 9;
      rgba[y][x][3] = alpha[y][x];
    }
  const double placement[4] = {2.0, 2.0, 10.0, 20.0};
  par2d_outline* placed = NULL;
  CHECK(par2d_outline_alpha(&rgba[0][0][3], W, H, 4 * W, 4, 128, 0.5, 65536, placement, &placed) == PAR2D_OK);
  CHECK(par2d_outline_polygon_count(placed) == 1);
  par2d_shape big;
  CHECK(par2d_outline_polygon(placed, 0, &big) == PAR2D_OK);
  CHECK(big.vertex_count == 4 && big.hole_count == 1);
  CHECK(area2(big.vertices, 4) == 4.0 * 32.0);
  for (size_t i = 0; i < 4; ++i) CHECK(big.vertices[2 * i] >= 14.0 && big.vertices[2 * i + 1] >= 22.0);

  /* As an occluder: a light in the hole lights the hole and not the far side of the ring. */
  par2d_renderer* r = NULL;
  par2d_options options;
  par2d_options_default(&options);
  options.backend = PAR2D_BACKEND_SCALAR;
  CHECK(par2d_renderer_create(&options, &r) == PAR2D_OK);
  CHECK(par2d_set_frame(r, W, H, NULL) == PAR2D_OK);
  par2d_shape light;
  memset(&light, 0, sizeof light);
  light.kind = PAR2D_SHAPE_CIRCLE;
  light.circle[0] = 4.0;
  light.circle[1] = 3.0;
  light.circle[2] = 0.5;
  const double white[3] = {1.0, 1.0, 1.0};
  par2d_light light_handle;
  par2d_occluder ring_handle;
  CHECK(par2d_add_light(r, &light, white, 1.0, &light_handle) == PAR2D_OK);
  CHECK(par2d_add_occluder(r, &shape, &ring_handle) == PAR2D_OK);
  float pixels[H][W][3];
  CHECK(par2d_render(r, &pixels[0][0][0], PAR2D_RGB_F32, sizeof pixels[0], 1.0, NULL) == PAR2D_OK);
  CHECK(pixels[2][3][0] > 0.0f);   /* inside the hole */
  CHECK(pixels[0][0][0] == 0.0f);  /* outside the ring: every line to the light crosses it */
  par2d_renderer_destroy(r);

  /* Errors: one line naming the call and the field; *out NULL. */
  par2d_outline* none = placed;
  CHECK(par2d_outline_alpha(NULL, W, H, W, 1, 128, 0.5, 65536, NULL, &none) == PAR2D_INVALID_ARGUMENT);
  CHECK(none == NULL);
  CHECK(strstr(par2d_last_error(), "par2d_outline_alpha: ") == par2d_last_error());
  CHECK(strstr(par2d_last_error(), "mask.alpha") != NULL);
  CHECK(par2d_outline_alpha(&alpha[0][0], W, H, W, 1, 128, -1.0, 65536, NULL, &none) == PAR2D_INVALID_ARGUMENT);
  CHECK(strstr(par2d_last_error(), "tolerance") != NULL);
  CHECK(par2d_outline_alpha(&alpha[0][0], W, H, W, 1, 128, 0.0, 7, NULL, &none) == PAR2D_INVALID_ARGUMENT);
  CHECK(strstr(par2d_last_error(), "polygon 0 (from pixel (2, 1)) needs 8 vertices") != NULL);
  CHECK(par2d_outline_alpha(&alpha[0][0], W, H, W, 1, 128, 0.0, 65536, NULL, NULL) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_outline_polygon(NULL, 0, &shape) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_outline_polygon_count(NULL) == 0);

  par2d_outline_destroy(outline);
  par2d_outline_destroy(placed);
  par2d_outline_destroy(NULL);
  if (failures) fprintf(stderr, "%d failure(s)\n", failures);
  return failures ? 1 : 0;
}
