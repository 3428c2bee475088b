/* Game-loop example in C: a persistent par2d world, a torch moving every frame, rendered
 * into an RGBA8 texture buffer. Build: cc game_loop.c $(pkg-config --cflags --libs par2d) -lm
 * `game_loop IMAGE.pfm` also writes the torch's last position at full intensity as a linear
 * float image (the Windows gate compares it with a native build's, docs/platforms.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <par2d/par2d.h>

/* The torch at intensity 4 as linear RGB floats, written as a PFM (rows bottom first). */
static int write_pfm(par2d_renderer* r, par2d_light torch, const par2d_shape* shape, const double color[3],
                     const char* path) {
  float* image = malloc(sizeof(float) * 320 * 180 * 3);
  FILE* f = fopen(path, "wb");
  int ok = image != NULL && f != NULL && par2d_update_light(r, torch, shape, color, 4.0) == PAR2D_OK &&
           par2d_render(r, image, PAR2D_RGB_F32, 320 * 3 * sizeof(float), 1.0, NULL) == PAR2D_OK;
  if (ok) ok = fprintf(f, "PF\n320 180\n-1.0\n") > 0;
  for (int y = 179; ok && y >= 0; --y) ok = fwrite(image + (size_t)y * 320 * 3, sizeof(float), 320 * 3, f) == 320 * 3;
  if (f != NULL && fclose(f) != 0) ok = 0;
  if (!ok) fprintf(stderr, "game_loop: cannot write %s (%s)\n", path, par2d_last_error());
  free(image);
  return ok;
}

int main(int argc, char** argv) {
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
  printf("par2d %s (%s), %d threads, texel (100, 90): %d %d %d %d\n", par2d_version(),
         par2d_isa_name(par2d_renderer_isa(r)), par2d_renderer_threads(r),
         texture[(90 * 320 + 100) * 4], texture[(90 * 320 + 100) * 4 + 1], texture[(90 * 320 + 100) * 4 + 2],
         texture[(90 * 320 + 100) * 4 + 3]);
  const int ok = texture[(90 * 320 + 100) * 4] > 0 && (argc < 2 || write_pfm(r, torch, &torch_shape, warm, argv[1]));
  free(texture);
  par2d_renderer_destroy(r);
  return ok ? 0 : 1;
}
