/* Game-loop example in C: a persistent par2d world, a torch moving every frame, rendered
 * into an RGBA8 texture buffer. Build: cc game_loop.c $(pkg-config --cflags --libs par2d) -lm */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <par2d/par2d.h>

int main(void) {
  par2d_renderer* r = NULL;
  if (par2d_renderer_create(NULL, &r) != PAR2D_OK) {  /* defaults: auto backend, all threads */
    fprintf(stderr, "%s\n", par2d_last_error());
    return 1;
  }
  /* 320 x 180 texels showing the world rectangle [0, 0, 640, 360]. */
  const double view[4] = {0, 0, 640, 360};
  par2d_set_frame(r, 320, 180, view);

  const double wall[8] = {300, 0, 320, 0, 320, 150, 300, 150};
  par2d_shape shape = {PAR2D_SHAPE_POLYGON, wall, 4, {0, 0, 0}, {0, 0, 0, 0}};
  par2d_occluder occluder;
  par2d_add_occluder(r, &shape, &occluder);

  par2d_shape torch_shape = {PAR2D_SHAPE_CIRCLE, NULL, 0, {150, 180, 6}, {0, 0, 0, 0}};
  const double warm[3] = {1.0, 0.7, 0.4};
  par2d_light torch;
  if (par2d_add_light(r, &torch_shape, warm, 4.0, &torch) != PAR2D_OK) {
    fprintf(stderr, "%s\n", par2d_last_error());
    return 1;
  }

  unsigned char* texture = malloc(320 * 180 * 4);
  for (int frame = 0; frame < 60; ++frame) {
    const double t = frame / 60.0;
    torch_shape.circle[0] = 150 + 40 * cos(6.28 * t);
    torch_shape.circle[1] = 180 + 40 * sin(6.28 * t);
    if (par2d_update_light(r, torch, &torch_shape, warm, 4.0 * (0.9 + 0.1 * sin(40 * t))) != PAR2D_OK ||
        par2d_render(r, texture, PAR2D_RGBA8_SRGB, 320 * 4, 1.5, NULL) != PAR2D_OK) {
      fprintf(stderr, "%s\n", par2d_last_error());
      return 1;
    }
    /* ... upload `texture` to the GPU. */
  }
  printf("par2d %s, %d threads, texel (100, 90): %d %d %d %d\n", par2d_version(), par2d_renderer_threads(r),
         texture[(90 * 320 + 100) * 4], texture[(90 * 320 + 100) * 4 + 1], texture[(90 * 320 + 100) * 4 + 2],
         texture[(90 * 320 + 100) * 4 + 3]);
  const int ok = texture[(90 * 320 + 100) * 4] > 0;
  free(texture);
  par2d_renderer_destroy(r);
  return ok ? 0 : 1;
}
