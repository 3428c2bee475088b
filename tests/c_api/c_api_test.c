/* The C API from a C program: world building, updates, every pixel format, regions, errors,
 * file policies (normal-map sizes, scene paths), the version at run time, and everything the C++
 * Renderer reaches (handles of a loaded scene, options, getters, snapshot, stats), long frames
 * (work estimate and limit, progress, cancellation), against closed forms. Exits non-zero on the first failure. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, mkdir */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "par2d/par2d.h"

#include "c_checks.h"

enum { W = 64, H = 48 };

/* ---- Files for the file-policy checks: tiny PNGs and scenes in a temporary folder. ---- */

static unsigned long crc32_of(const unsigned char* bytes, size_t n, unsigned long crc) {
  crc ^= 0xFFFFFFFFul;
  for (size_t i = 0; i < n; ++i) {
    crc ^= bytes[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320ul & (0ul - (crc & 1ul)));
  }
  return crc ^ 0xFFFFFFFFul;
}

static void put_be32(unsigned char* at, unsigned long v) {
  at[0] = (unsigned char)(v >> 24);
  at[1] = (unsigned char)(v >> 16);
  at[2] = (unsigned char)(v >> 8);
  at[3] = (unsigned char)v;
}

/* One PNG chunk: length, type, data, CRC over type and data. */
static void write_chunk(FILE* f, const char type[4], const unsigned char* data, size_t n) {
  unsigned char head[8];
  unsigned char tail[4];
  put_be32(head, (unsigned long)n);
  memcpy(head + 4, type, 4);
  unsigned long crc = crc32_of(head + 4, 4, 0);
  if (n > 0) crc = crc32_of(data, n, crc);
  put_be32(tail, crc);
  fwrite(head, 1, 8, f);
  if (n > 0) fwrite(data, 1, n, f);
  fwrite(tail, 1, 4, f);
}

/* An 8-bit RGB PNG declaring width x height. With `rgb` (width * height * 3 bytes) its pixels
 * are stored uncompressed (one stored deflate block, filter 0); without, it has no pixel data
 * at all: 45 bytes that claim any size, a loader that decodes before checking falls for. */
static int write_png_file(const char* path, unsigned long width, unsigned long height, const unsigned char* rgb) {
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  FILE* f = fopen(path, "wb");
  if (f == NULL) return 0;
  fwrite(signature, 1, 8, f);
  unsigned char ihdr[13] = {0};
  put_be32(ihdr, width);
  put_be32(ihdr + 4, height);
  ihdr[8] = 8; /* bit depth */
  ihdr[9] = 2; /* RGB */
  write_chunk(f, "IHDR", ihdr, sizeof ihdr);
  if (rgb != NULL) {
    const size_t row = 1 + 3 * (size_t)width, raw_size = row * (size_t)height; /* < 65536 here */
    unsigned char* idat = malloc(2 + 5 + raw_size + 4);
    unsigned char* raw = idat + 7;
    for (size_t j = 0; j < height; ++j) {
      raw[j * row] = 0;
      memcpy(raw + j * row + 1, rgb + j * 3 * width, 3 * width);
    }
    unsigned long a = 1, b = 0; /* Adler-32 of the raw rows */
    for (size_t i = 0; i < raw_size; ++i) {
      a = (a + raw[i]) % 65521ul;
      b = (b + a) % 65521ul;
    }
    idat[0] = 0x78; /* zlib header: deflate, 32K window, no dictionary */
    idat[1] = 0x01;
    idat[2] = 1; /* final stored block */
    idat[3] = (unsigned char)(raw_size & 0xFF);
    idat[4] = (unsigned char)(raw_size >> 8);
    idat[5] = (unsigned char)(~raw_size & 0xFF);
    idat[6] = (unsigned char)((~raw_size >> 8) & 0xFF);
    put_be32(raw + raw_size, (b << 16) | a);
    write_chunk(f, "IDAT", idat, 2 + 5 + raw_size + 4);
    free(idat);
  }
  write_chunk(f, "IEND", NULL, 0);
  return fclose(f) == 0;
}

static int write_text_file(const char* path, const char* text) {
  FILE* f = fopen(path, "wb");
  if (f == NULL) return 0;
  fputs(text, f);
  return fclose(f) == 0;
}

/* par2d_load_normal_map checks a PNG's declared size against the renderer's frame before
 * decoding a pixel: a 45-byte file declaring 16000x16000 is refused by name, sizes included.
 * Before any frame is set, the size is capped from the header only. */
static void check_normal_map_size_is_checked_first(par2d_renderer* r, const char* dir) {
  char huge[512], small[512];
  snprintf(huge, sizeof huge, "%s/huge.png", dir);
  snprintf(small, sizeof small, "%s/small.png", dir);
  CHECK(write_png_file(huge, 16000, 16000, NULL));
  unsigned char rgb[W * H * 3];
  memset(rgb, 128, sizeof rgb);
  for (int k = 2; k < W * H * 3; k += 3) rgb[k] = 255; /* (0, 0, 1): facing the viewer */
  CHECK(write_png_file(small, W, H, rgb));

  char expected[1024];
  snprintf(expected, sizeof expected,
           "par2d_load_normal_map: %s: is 16000x16000 but the image is %dx%d (it must be exactly the image's size)",
           huge, W, H);
  CHECK_ERROR(par2d_load_normal_map(r, huge), PAR2D_INVALID_SCENE, expected);
  CHECK(par2d_load_normal_map(r, small) == PAR2D_OK);
  CHECK(par2d_clear_normal_source(r) == PAR2D_OK);

  /* A renderer without a frame: no size to match, so only the header's cap applies. */
  par2d_renderer* bare = NULL;
  CHECK(par2d_renderer_create(NULL, &bare) == PAR2D_OK);
  char beyond[512];
  snprintf(beyond, sizeof beyond, "%s/beyond.png", dir);
  CHECK(write_png_file(beyond, 20000, 16, NULL));
  snprintf(expected, sizeof expected, "par2d_load_normal_map: %s: is 20000x16, larger than any image", beyond);
  CHECK_ERROR(par2d_load_normal_map(bare, beyond), PAR2D_INVALID_SCENE, expected);
  CHECK(par2d_load_normal_map(bare, small) == PAR2D_OK);
  par2d_renderer_destroy(bare);
  remove(huge);
  remove(small);
  remove(beyond);
}

/* A scene's normal_map must stay in the scene's folder unless the caller opts in with
 * PAR2D_LOAD_ALLOW_ANY_PATH; par2d_load_scene keeps the default. */
static void check_scene_path_policy(par2d_renderer* r, const char* dir) {
  char inner[512], map[512], scene_up[512], scene_abs[512], scene_in[512], text[2048], expected[1024];
  snprintf(inner, sizeof inner, "%s/inner", dir);
  CHECK(mkdir(inner, 0700) == 0);
  snprintf(map, sizeof map, "%s/map.png", dir);
  unsigned char rgb[4 * 2 * 3];
  memset(rgb, 128, sizeof rgb);
  for (int k = 2; k < 4 * 2 * 3; k += 3) rgb[k] = 255;
  CHECK(write_png_file(map, 4, 2, rgb));

  /* inner/up.json names ../map.png; inner/abs.json names map.png by its absolute path;
   * inner/in.json a missing map inside its folder (the policy passes, the file does not). */
  snprintf(scene_up, sizeof scene_up, "%s/up.json", inner);
  CHECK(write_text_file(scene_up, "{\"width\": 4, \"height\": 2, \"normal_map\": \"../map.png\"}"));
  snprintf(scene_abs, sizeof scene_abs, "%s/abs.json", inner);
  snprintf(text, sizeof text, "{\"width\": 4, \"height\": 2, \"normal_map\": \"%s\"}", map);
  CHECK(write_text_file(scene_abs, text));
  snprintf(scene_in, sizeof scene_in, "%s/in.json", inner);
  CHECK(write_text_file(scene_in, "{\"width\": 4, \"height\": 2, \"normal_map\": \"missing.png\"}"));

  snprintf(expected, sizeof expected, "par2d_load_scene: %s: normal_map: path leaves the scene's folder", scene_up);
  CHECK_ERROR(par2d_load_scene(r, scene_up), PAR2D_INVALID_SCENE, expected);
  snprintf(expected, sizeof expected, "par2d_load_scene_ex: %s: normal_map: path leaves the scene's folder", scene_up);
  CHECK_ERROR(par2d_load_scene_ex(r, scene_up, 0), PAR2D_INVALID_SCENE, expected);
  snprintf(expected, sizeof expected,
           "par2d_load_scene_ex: %s: normal_map: path is absolute; it must be relative to the scene's folder", scene_abs);
  CHECK_ERROR(par2d_load_scene_ex(r, scene_abs, 0), PAR2D_INVALID_SCENE, expected);
  CHECK_ERROR_PREFIX(par2d_load_scene_ex(r, scene_in, 0), PAR2D_IO_ERROR, "par2d_load_scene_ex: ");

  /* Refused scenes left the world as it was: still the W x H frame. */
  float pixel[3];
  const int corner[4] = {W - 1, H - 1, W, H};
  CHECK(par2d_render(r, pixel, PAR2D_RGB_F32, sizeof pixel, 1.0, corner) == PAR2D_OK);

  CHECK(par2d_load_scene_ex(r, scene_up, PAR2D_LOAD_ALLOW_ANY_PATH) == PAR2D_OK);
  CHECK(par2d_load_scene_ex(r, scene_abs, PAR2D_LOAD_ALLOW_ANY_PATH) == PAR2D_OK);
  CHECK(par2d_render(r, pixel, PAR2D_RGB_F32, sizeof pixel, 1.0, corner) == PAR2D_INVALID_ARGUMENT); /* now 4x2 */
  CHECK_ERROR(par2d_load_scene_ex(r, scene_up, 2u), PAR2D_INVALID_ARGUMENT,
              "par2d_load_scene_ex: flags 0x2 has bits other than PAR2D_LOAD_ALLOW_ANY_PATH");
  CHECK_ERROR(par2d_load_scene_ex(r, NULL, 0), PAR2D_INVALID_ARGUMENT, "par2d_load_scene_ex: path is null");
  CHECK_ERROR(par2d_load_scene_ex(NULL, scene_up, 0), PAR2D_INVALID_ARGUMENT, "par2d_load_scene_ex: renderer is null");

  remove(scene_up);
  remove(scene_abs);
  remove(scene_in);
  rmdir(inner);
  remove(map);
}

/* Every error message names the C function that failed, and absurd counts are refused by
 * name before anything is allocated or read (not a C++ library's length_error or bad_alloc). */
/* ---- Long frames: the work estimate and limit, progress and cancellation. ---- */

struct progress_log {
  int calls, rising, same_thread;
  uint64_t last_done, last_total, cancel_at;
  pthread_t caller;
  par2d_renderer* cancel_from_thread; /* non-NULL: the first call has another thread cancel it */
};

static void* cancel_renderer(void* renderer) {
  par2d_cancel((par2d_renderer*)renderer);
  return NULL;
}

static int on_progress(void* user, uint64_t done, uint64_t total) {
  struct progress_log* log = (struct progress_log*)user;
  if (log->calls > 0 && done <= log->last_done) log->rising = 0;
  if (!pthread_equal(pthread_self(), log->caller)) log->same_thread = 0;
  if (log->calls++ == 0 && log->cancel_from_thread != NULL) {
    pthread_t other;
    CHECK(pthread_create(&other, NULL, cancel_renderer, log->cancel_from_thread) == 0);
    CHECK(pthread_join(other, NULL) == 0);
  }
  log->last_done = done;
  log->last_total = total;
  return log->cancel_at == 0 || done < log->cancel_at;
}

static void reset_log(struct progress_log* log, uint64_t cancel_at, par2d_renderer* cancel_from_thread) {
  memset(log, 0, sizeof *log);
  log->rising = log->same_thread = 1;
  log->cancel_at = cancel_at;
  log->caller = pthread_self();
  log->cancel_from_thread = cancel_from_thread;
}

static int all_sentinel(const float* pixels, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (pixels[i] != -7.25f) return 0;
  return 1;
}

static void fill_sentinel(float* pixels, size_t n) {
  for (size_t i = 0; i < n; ++i) pixels[i] = -7.25f;
}

/* A renderer on two threads with a frame of width x height (no frame when width is 0), or NULL
 * (the failure already counted). */
static par2d_renderer* two_thread_renderer(int width, int height) {
  par2d_options options;
  par2d_options_default(&options);
  options.threads = 2;
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(&options, &r) == PAR2D_OK);
  if (r != NULL && width > 0) CHECK(par2d_set_frame(r, width, height, NULL) == PAR2D_OK);
  return r;
}

static void check_long_frames(void) {
  par2d_options o;
  par2d_options_default(&o);
  o.backend = PAR2D_BACKEND_SCALAR; /* the reference: estimated work, so frames stop midway */
  o.threads = 1;                    /* the first report comes before the frame's last tile */
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(&o, &r) == PAR2D_OK);
  CHECK(par2d_set_frame(r, W, H, NULL) == PAR2D_OK);
  par2d_shape disc;
  memset(&disc, 0, sizeof disc);
  disc.kind = PAR2D_SHAPE_CIRCLE;
  disc.circle[0] = 10.0;
  disc.circle[1] = 10.0;
  disc.circle[2] = 3.0;
  const double white[3] = {1.0, 1.0, 1.0};
  par2d_light light = 0;
  par2d_occluder occluder = 0;
  CHECK(par2d_add_light(r, &disc, white, 1.0, &light) == PAR2D_OK);
  disc.circle[0] = 30.0;
  disc.circle[1] = 25.0;
  CHECK(par2d_add_occluder(r, &disc, &occluder) == PAR2D_OK);

  /* The estimate by counts: the scalar reference looks at every light and occluder per sample. */
  par2d_work_estimate e;
  CHECK(par2d_estimate_work(r, NULL, &e) == PAR2D_OK);
  CHECK(e.samples == W * H && e.scalar == W * H * 1.0 * (1.0 + 1.0) && e.bounce == 0.0 && e.total == e.scalar);
  const int corner[4] = {0, 0, 16, 16};
  CHECK(par2d_estimate_work(r, corner, &e) == PAR2D_OK && e.samples == 256.0);
  CHECK_ERROR(par2d_estimate_work(r, NULL, NULL), PAR2D_INVALID_ARGUMENT, "par2d_estimate_work: out is null");

  /* The limit: refused before any pixel is written; 0 is no limit; kept by par2d_set_options. */
  const size_t n = (size_t)W * H * 3;
  float* pixels = (float*)malloc(n * sizeof(float));
  CHECK(pixels != NULL);
  const ptrdiff_t stride = (ptrdiff_t)(sizeof(float) * W * 3);
  double limit = 0.0;
  CHECK(par2d_get_work_limit(r, &limit) == PAR2D_OK && limit == PAR2D_DEFAULT_WORK_LIMIT);
  CHECK(par2d_set_work_limit(r, W * H * 2.0 - 1.0) == PAR2D_OK);
  CHECK(par2d_set_options(r, &o) == PAR2D_OK);
  CHECK(par2d_get_work_limit(r, &limit) == PAR2D_OK && limit == W * H * 2.0 - 1.0);
  fill_sentinel(pixels, n);
  CHECK_ERROR_PREFIX(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL), PAR2D_WORK_LIMIT,
                     "par2d_render: estimated work 6.14e+03 is past the work limit 6.14e+03");
  CHECK(all_sentinel(pixels, n));
  CHECK(par2d_set_work_limit(r, -1.0) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_set_work_limit(r, 0.0) == PAR2D_OK);
  CHECK(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL) == PAR2D_OK);
  CHECK(!all_sentinel(pixels, n));

  /* Progress: from this thread, rising, ending at the frame's 4 x 3 tiles. */
  struct progress_log log;
  reset_log(&log, 0, NULL);
  CHECK(par2d_set_progress(r, on_progress, &log) == PAR2D_OK);
  CHECK(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL) == PAR2D_OK);
  CHECK(log.calls > 0 && log.rising && log.same_thread && log.last_done == 12 && log.last_total == 12);

  /* Cancelled by the progress function after 2 tiles: the pixels untouched. */
  reset_log(&log, 2, NULL);
  fill_sentinel(pixels, n);
  CHECK_ERROR(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL), PAR2D_CANCELLED, "par2d_render: cancelled");
  CHECK(all_sentinel(pixels, n) && log.last_done == 2 && log.rising && log.same_thread);

  /* Cancelled by another thread while the frame runs. */
  reset_log(&log, 0, r);
  CHECK(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL) == PAR2D_CANCELLED);
  CHECK(all_sentinel(pixels, n) && log.calls >= 1 && log.last_done < 12);

  /* Cancelled before the frame, without a progress function; the request is then used up. */
  CHECK(par2d_set_progress(r, NULL, NULL) == PAR2D_OK);
  par2d_cancel(r);
  CHECK(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL) == PAR2D_CANCELLED);
  CHECK(all_sentinel(pixels, n));
  CHECK(par2d_render(r, pixels, PAR2D_RGB_F32, stride, 1.0, NULL) == PAR2D_OK);
  CHECK(!all_sentinel(pixels, n));
  par2d_cancel(NULL);
  CHECK_ERROR(par2d_set_progress(NULL, on_progress, &log), PAR2D_INVALID_ARGUMENT, "par2d_set_progress: renderer is null");
  free(pixels);
  par2d_renderer_destroy(r);
}

static void check_errors_name_the_call(par2d_renderer* r) {
  const double white[3] = {1.0, 1.0, 1.0};
  par2d_shape circle;
  memset(&circle, 0, sizeof circle);
  circle.kind = PAR2D_SHAPE_CIRCLE;
  circle.circle[0] = circle.circle[1] = 5.0;
  circle.circle[2] = 1.0;
  par2d_light light = 0;
  par2d_occluder occluder = 0;
  CHECK(par2d_add_light(r, &circle, white, 1.0, &light) == PAR2D_OK);
  CHECK(par2d_add_occluder(r, &circle, &occluder) == PAR2D_OK);

  /* Null shape and colour pointers. */
  CHECK_ERROR(par2d_add_light(r, NULL, white, 1.0, &light), PAR2D_INVALID_ARGUMENT, "par2d_add_light: shape is null");
  CHECK_ERROR(par2d_add_light(r, &circle, NULL, 1.0, &light), PAR2D_INVALID_ARGUMENT, "par2d_add_light: color is null");
  CHECK_ERROR(par2d_update_light(r, light, NULL, white, 1.0), PAR2D_INVALID_ARGUMENT,
              "par2d_update_light: shape is null");
  CHECK_ERROR(par2d_update_light(r, light, &circle, NULL, 1.0), PAR2D_INVALID_ARGUMENT,
              "par2d_update_light: color is null");
  CHECK_ERROR(par2d_add_occluder(r, NULL, &occluder), PAR2D_INVALID_ARGUMENT, "par2d_add_occluder: shape is null");
  CHECK_ERROR(par2d_update_occluder(r, occluder, NULL), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape is null");

  /* A kind that is none of the enum's. */
  par2d_shape odd = circle;
  odd.kind = (par2d_shape_kind)7;
  CHECK_ERROR(par2d_add_light(r, &odd, white, 1.0, &light), PAR2D_INVALID_ARGUMENT,
              "par2d_add_light: shape kind 7 is not PAR2D_SHAPE_POLYGON, _CIRCLE or _SEGMENT");
  CHECK_ERROR(par2d_update_occluder(r, occluder, &odd), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape kind 7 is not PAR2D_SHAPE_POLYGON, _CIRCLE or _SEGMENT");
  float pixel[4 * W];
  const int row[4] = {0, 0, W, 1};
  CHECK_ERROR(par2d_render(r, pixel, (par2d_pixel_format)9, sizeof pixel, 1.0, row), PAR2D_INVALID_ARGUMENT,
              "par2d_render: pixel format 9 is not a par2d_pixel_format (0 .. 6)");
  par2d_options bad_options;
  par2d_options_default(&bad_options);
  bad_options.backend = (par2d_backend)5;
  par2d_renderer* none = NULL;
  CHECK_ERROR(par2d_renderer_create(&bad_options, &none), PAR2D_INVALID_ARGUMENT,
              "par2d_renderer_create: backend 5 is not PAR2D_BACKEND_AUTO, _SIMD or _SCALAR");
  CHECK(none == NULL);

  /* Polygons: null vertices, absurd counts (nothing read or allocated), the limit itself. */
  const double tri[6] = {1, 1, 9, 1, 5, 8};
  par2d_shape poly;
  memset(&poly, 0, sizeof poly);
  poly.kind = PAR2D_SHAPE_POLYGON;
  poly.vertices = NULL;
  poly.vertex_count = 3;
  CHECK_ERROR(par2d_add_occluder(r, &poly, &occluder), PAR2D_INVALID_ARGUMENT,
              "par2d_add_occluder: shape vertices are null");
  poly.vertices = tri;
  poly.vertex_count = (size_t)-1;
  CHECK_ERROR(par2d_add_occluder(r, &poly, &occluder), PAR2D_INVALID_ARGUMENT,
              "par2d_add_occluder: shape vertex_count 18446744073709551615 is more than 1048576");
  poly.vertex_count = (size_t)1 << 40; /* 16 TiB of doubles: not an out-of-memory, a refused count */
  CHECK_ERROR(par2d_update_light(r, light, &poly, white, 1.0), PAR2D_INVALID_ARGUMENT,
              "par2d_update_light: shape vertex_count 1099511627776 is more than 1048576");
  poly.vertex_count = (size_t)-1 / 2 + 1;
  CHECK_ERROR(par2d_update_occluder(r, occluder, &poly), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape vertex_count 9223372036854775808 is more than 1048576");
  poly.vertex_count = 3;
  CHECK(par2d_update_occluder(r, occluder, &poly) == PAR2D_OK); /* the buffers still work */
  {
    /* Just over the limit, with that many real (coincident) vertices behind the pointer: the
     * count is refused, not the zero area; at the limit the shape itself is judged. */
    const size_t limit = 1048576;
    double* many = calloc(2 * (limit + 1), sizeof(double));
    CHECK(many != NULL);
    if (many != NULL) {
      poly.vertices = many;
      poly.vertex_count = limit + 1;
      CHECK_ERROR(par2d_add_occluder(r, &poly, &occluder), PAR2D_INVALID_ARGUMENT,
                  "par2d_add_occluder: shape vertex_count 1048577 is more than 1048576");
      poly.vertex_count = limit;
      CHECK_ERROR_PREFIX(par2d_add_occluder(r, &poly, &occluder), PAR2D_INVALID_SCENE, "par2d_add_occluder: ");
      CHECK(strstr(par2d_last_error(), "vertex_count") == NULL);
      free(many);
    }
  }

  /* Other pointers and counts. */
  CHECK_ERROR(par2d_set_light_emission(r, light, NULL, 1.0), PAR2D_INVALID_ARGUMENT,
              "par2d_set_light_emission: color is null");
  par2d_directional_light sun;
  par2d_directional_light_default(&sun);
  sun.angles[0] = 10.0;
  sun.angles[1] = 20.0;
  CHECK_ERROR(par2d_set_directional_lights(r, &sun, (size_t)-1), PAR2D_INVALID_ARGUMENT,
              "par2d_set_directional_lights: count 18446744073709551615 is more than 65536");
  CHECK_ERROR(par2d_set_directional_lights(r, &sun, (size_t)1 << 40), PAR2D_INVALID_ARGUMENT,
              "par2d_set_directional_lights: count 1099511627776 is more than 65536");
  CHECK_ERROR(par2d_set_directional_lights(r, NULL, 1), PAR2D_INVALID_ARGUMENT,
              "par2d_set_directional_lights: lights is null");
  CHECK(par2d_set_directional_lights(r, &sun, 1) == PAR2D_OK);
  CHECK(par2d_set_directional_lights(r, NULL, 0) == PAR2D_OK);

  /* The library's own refusals are named by the call too. */
  CHECK_ERROR_PREFIX(par2d_remove_light(r, light + 777), PAR2D_INVALID_ARGUMENT, "par2d_remove_light: ");
  CHECK_ERROR_PREFIX(par2d_remove_occluder(r, occluder + 777), PAR2D_INVALID_ARGUMENT, "par2d_remove_occluder: ");
  CHECK_ERROR_PREFIX(par2d_set_light_emission(r, light, white, -1.0), PAR2D_INVALID_SCENE, "par2d_set_light_emission: ");
  CHECK_ERROR_PREFIX(par2d_render(r, pixel, PAR2D_RGB_F32, 4, 1.0, row), PAR2D_INVALID_ARGUMENT, "par2d_render: ");
  const int outside[4] = {0, 0, W + 1, 1};
  CHECK_ERROR_PREFIX(par2d_render(r, pixel, PAR2D_RGB_F32, sizeof pixel, 1.0, outside), PAR2D_INVALID_ARGUMENT,
                     "par2d_render: ");
  CHECK_ERROR_PREFIX(par2d_set_frame(r, 0, 10, NULL), PAR2D_INVALID_SCENE, "par2d_set_frame: ");
  CHECK_ERROR_PREFIX(par2d_load_scene(r, "/nonexistent/par2d/scene.json"), PAR2D_IO_ERROR,
                     "par2d_load_scene: /nonexistent/par2d/scene.json");
  par2d_light_terms terms;
  par2d_light_terms_default(&terms);
  CHECK(terms.falloff == 2.0);
  terms.falloff = 17.0;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &terms), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK(strstr(par2d_last_error(), "falloff") != NULL);
  terms.falloff = 3.5;
  terms.range = 40.0;
  CHECK(par2d_set_light_terms(r, light, &terms) == PAR2D_OK);
  par2d_light_terms back;
  CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.falloff == 3.5 && back.range == 40.0);
  CHECK(back.normalize == 0.0);
  terms.normalize = -1.0;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &terms), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK(strstr(par2d_last_error(), "normalize") != NULL);
  terms.normalize = 25.0;
  CHECK(par2d_set_light_terms(r, light, &terms) == PAR2D_OK);
  CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.normalize == 25.0);
  terms.normalize = 0.0;
  /* Shadow strength and colour: defaults, a round trip, refusals naming the field. */
  CHECK(back.shadow_strength == 1.0 && back.shadow_color[0] == 0.0 && back.shadow_color[2] == 0.0);
  terms.shadow_strength = 0.4;
  terms.shadow_color[1] = 0.75;
  CHECK(par2d_set_light_terms(r, light, &terms) == PAR2D_OK);
  CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.shadow_strength == 0.4 &&
        back.shadow_color[0] == 0.0 && back.shadow_color[1] == 0.75);
  terms.shadow_strength = 1.5;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &terms), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK(strstr(par2d_last_error(), "shadow.strength: must be between 0 and 1, got 1.5") != NULL);
  terms.shadow_strength = 1.0;
  terms.shadow_color[2] = -0.5;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &terms), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK(strstr(par2d_last_error(), "shadow.color[2]") != NULL);
  CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.shadow_strength == 0.4);
  terms.shadow_color[1] = terms.shadow_color[2] = 0.0;
  terms.falloff = 2.0;
  terms.elevation = 95.0;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &terms), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK_ERROR_PREFIX(par2d_get_light_terms(r, light + 777, &terms), PAR2D_INVALID_ARGUMENT, "par2d_get_light_terms: ");

  par2d_occluder_terms occluder_terms;
  CHECK_ERROR_PREFIX(par2d_get_occluder_terms(r, occluder + 777, &occluder_terms), PAR2D_INVALID_ARGUMENT,
                     "par2d_get_occluder_terms: ");
  const double zero[3] = {0.0, 0.0, 0.0};
  CHECK_ERROR_PREFIX(par2d_set_normal(r, zero), PAR2D_INVALID_SCENE, "par2d_set_normal: ");
  float flat[3] = {0.0f, 0.0f, 1.0f};
  CHECK_ERROR_PREFIX(par2d_set_normal_map(r, flat, 1, 1), PAR2D_INVALID_SCENE, "par2d_set_normal_map: ");
  CHECK_ERROR_PREFIX(par2d_load_normal_map(r, "/nonexistent/par2d/normals.png"), PAR2D_IO_ERROR,
                     "par2d_load_normal_map: ");
  par2d_options slow;
  par2d_options_default(&slow);
  slow.spp = 0;
  CHECK_ERROR_PREFIX(par2d_renderer_create(&slow, &none), PAR2D_INVALID_ARGUMENT, "par2d_renderer_create: ");
  CHECK(none == NULL);

  CHECK(par2d_remove_light(r, light) == PAR2D_OK);
  CHECK(par2d_remove_occluder(r, occluder) == PAR2D_OK);
}

/* Everything the C++ Renderer reaches, reached from C: handles of a loaded scene and the
 * objects they name, the frame, options (ISA cap and caller-arena mode included), the
 * scene-wide terms, snapshot, stats and frame stats, pixel sizes. */
static void check_parity_with_the_cpp_renderer(const char* dir) {
  char path[512], saved[512];
  snprintf(path, sizeof path, "%s/level.json", dir);
  CHECK(write_text_file(path,
                        "{\"width\": 40, \"height\": 30, \"view\": [0, 0, 80, 60],"
                        " \"lights\": [{\"circle\": {\"center\": [10, 12], \"radius\": 3}, \"intensity\": 2},"
                        "              {\"segment\": [[60, 5], [70, 5]], \"color\": [1, 0.5, 0.25]}],"
                        " \"occluders\": [{\"polygon\": [[30, 20], [40, 20], [40, 30], [30, 30]]},"
                        "                 {\"circle\": {\"center\": [50, 40], \"radius\": 4}}]}"));
  par2d_renderer* r = two_thread_renderer(0, 0);
  if (r == NULL) return;
  CHECK(par2d_load_scene(r, path) == PAR2D_OK);

  /* The frame and view as loaded. */
  int w = 0, h = 0;
  double view[4] = {0, 0, 0, 0};
  CHECK(par2d_get_frame(r, &w, &h, view) == PAR2D_OK);
  CHECK(w == 40 && h == 30 && view[0] == 0 && view[1] == 0 && view[2] == 80 && view[3] == 60);
  CHECK(par2d_get_frame(r, NULL, NULL, NULL) == PAR2D_OK);
  CHECK_ERROR(par2d_get_frame(NULL, &w, &h, view), PAR2D_INVALID_ARGUMENT, "par2d_get_frame: renderer is null");

  /* Handles of the loaded scene, in the file's order: a size query, then the list. */
  size_t count = 99;
  par2d_light lights[4] = {0, 0, 0, 0};
  par2d_occluder occluders[4] = {0, 0, 0, 0};
  CHECK(par2d_get_light_handles(r, NULL, 0, &count) == PAR2D_OK && count == 2);
  CHECK(par2d_light_count(r) == 2 && par2d_occluder_count(r) == 2);
  CHECK(par2d_get_light_handles(r, lights, 1, &count) == PAR2D_OK && count == 2 && lights[0] != 0 && lights[1] == 0);
  CHECK(par2d_get_light_handles(r, lights, 4, &count) == PAR2D_OK && count == 2 && lights[1] != 0);
  CHECK(par2d_get_occluder_handles(r, occluders, 4, &count) == PAR2D_OK && count == 2);
  CHECK_ERROR(par2d_get_light_handles(r, lights, 4, NULL), PAR2D_INVALID_ARGUMENT, "par2d_get_light_handles: count is null");
  CHECK_ERROR(par2d_get_occluder_handles(r, NULL, 3, &count), PAR2D_INVALID_ARGUMENT,
              "par2d_get_occluder_handles: out is null but capacity is 3");

  /* What the handles name, as the file gave it. */
  par2d_shape shape;
  double color[3] = {0, 0, 0}, intensity = 0;
  CHECK(par2d_get_light(r, lights[0], &shape, color, &intensity) == PAR2D_OK);
  CHECK(shape.kind == PAR2D_SHAPE_CIRCLE && shape.circle[0] == 10 && shape.circle[1] == 12 && shape.circle[2] == 3);
  CHECK(intensity == 2 && color[0] == 1 && color[1] == 1 && color[2] == 1);
  CHECK(par2d_get_light(r, lights[1], &shape, color, NULL) == PAR2D_OK);
  CHECK(shape.kind == PAR2D_SHAPE_SEGMENT && shape.segment[0] == 60 && shape.segment[3] == 5 && color[1] == 0.5);
  CHECK(par2d_get_occluder(r, occluders[0], &shape) == PAR2D_OK);
  CHECK(shape.kind == PAR2D_SHAPE_POLYGON && shape.vertex_count == 4 && shape.vertices != NULL &&
        shape.vertices[0] == 30 && shape.vertices[1] == 20 && shape.vertices[7] == 30);
  CHECK(par2d_get_occluder(r, occluders[1], &shape) == PAR2D_OK && shape.kind == PAR2D_SHAPE_CIRCLE &&
        shape.circle[2] == 4);
  CHECK_ERROR_PREFIX(par2d_get_light(r, lights[0] + 7777, &shape, color, &intensity), PAR2D_INVALID_ARGUMENT,
                     "par2d_get_light: ");
  CHECK(shape.kind == PAR2D_SHAPE_CIRCLE && shape.circle[2] == 4); /* left as it was */

  /* The loaded scene's handles work like added ones; removals and additions show in the list. */
  const double red[3] = {1, 0, 0};
  CHECK(par2d_set_light_emission(r, lights[0], red, 5.0) == PAR2D_OK);
  CHECK(par2d_get_light(r, lights[0], NULL, color, &intensity) == PAR2D_OK && intensity == 5 && color[1] == 0);
  CHECK(par2d_remove_occluder(r, occluders[0]) == PAR2D_OK);
  par2d_occluder added = 0;
  CHECK(par2d_add_occluder(r, &shape, &added) == PAR2D_OK);
  par2d_occluder after[4] = {0, 0, 0, 0};
  CHECK(par2d_get_occluder_handles(r, after, 4, &count) == PAR2D_OK && count == 2 && after[0] == occluders[1] &&
        after[1] == added);

  /* Options: read back, replaced, a refused value keeps them. */
  par2d_options got;
  CHECK(par2d_get_options(r, &got) == PAR2D_OK && got.threads == 2 && got.spp == 1 && got.culling == 1 &&
        got.backend == PAR2D_BACKEND_AUTO);
  got.spp = 4;
  got.backend = PAR2D_BACKEND_SCALAR;
  CHECK(par2d_set_options(r, &got) == PAR2D_OK);
  CHECK(par2d_renderer_isa(r) == PAR2D_ISA_SCALAR); /* the scalar backend */
  got.spp = 0;
  CHECK_ERROR_PREFIX(par2d_set_options(r, &got), PAR2D_INVALID_ARGUMENT, "par2d_set_options: ");
  CHECK(par2d_get_options(r, &got) == PAR2D_OK && got.spp == 4 && got.backend == PAR2D_BACKEND_SCALAR);
  got.backend = (par2d_backend)7;
  CHECK_ERROR(par2d_set_options(r, &got), PAR2D_INVALID_ARGUMENT,
              "par2d_set_options: backend 7 is not PAR2D_BACKEND_AUTO, _SIMD or _SCALAR");
  par2d_options_default(&got);
  got.threads = 2;
  CHECK(par2d_set_options(r, &got) == PAR2D_OK);

  /* The ISA cap, caller-arena threading and shading. */
  par2d_advanced_options advanced;
  par2d_advanced_options_default(&advanced);
  CHECK(advanced.isa == PAR2D_ISA_DEFAULT && advanced.threading == PAR2D_THREADING_OWN_POOL && advanced.shaded == 1);
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.threading == PAR2D_THREADING_OWN_POOL);
  const size_t n = (size_t)40 * 30 * 3;
  float* pool = malloc(sizeof(float) * n);
  float* other = malloc(sizeof(float) * n);
  CHECK(par2d_render(r, pool, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  advanced.isa = PAR2D_ISA_SCALAR;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_renderer_isa(r) == PAR2D_ISA_SCALAR);
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.isa == PAR2D_ISA_SCALAR);
  advanced.isa = PAR2D_ISA_DEFAULT;
  advanced.threading = PAR2D_THREADING_CALLER_ARENA;
#if PAR2D_HAVE_TBB
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.threading == PAR2D_THREADING_CALLER_ARENA);
  /* From a plain thread the caller's arena is TBB's implicit one: the same bytes. */
  CHECK(par2d_render(r, other, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(pool, other, sizeof(float) * n) == 0);
#else
  /* A build without TBB has no caller's arena: the mode is refused and the options kept
   * (the scalar ISA set above among them). */
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_INVALID_ARGUMENT);
  CHECK(strstr(par2d_last_error(), "threading caller_arena needs par2d built with TBB") != NULL);
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.threading == PAR2D_THREADING_OWN_POOL &&
        advanced.isa == PAR2D_ISA_SCALAR);
  advanced.isa = PAR2D_ISA_DEFAULT;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_render(r, other, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(pool, other, sizeof(float) * n) == 0);
#endif
  advanced.isa = (par2d_isa)9;
  CHECK_ERROR(par2d_set_advanced_options(r, &advanced), PAR2D_INVALID_ARGUMENT,
              "par2d_set_advanced_options: isa 9 is not PAR2D_ISA_DEFAULT or a PAR2D_ISA_* level");
  advanced.isa = PAR2D_ISA_DEFAULT;
  advanced.threading = (par2d_threading)5;
  CHECK_ERROR(par2d_set_advanced_options(r, &advanced), PAR2D_INVALID_ARGUMENT,
              "par2d_set_advanced_options: threading 5 is not PAR2D_THREADING_OWN_POOL or PAR2D_THREADING_CALLER_ARENA");
#if PAR2D_HAVE_TBB
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.threading == PAR2D_THREADING_CALLER_ARENA);
#else
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.threading == PAR2D_THREADING_OWN_POOL);
#endif
  par2d_advanced_options_default(&advanced);
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(strcmp(par2d_isa_name(PAR2D_ISA_AVX2), "avx2") == 0 && strcmp(par2d_isa_name(PAR2D_ISA_DEFAULT), "") == 0);
  CHECK(par2d_isa_name(par2d_detect_isa())[0] != '\0');
  CHECK(par2d_bytes_per_pixel(PAR2D_RGB_F32) == 12 && par2d_bytes_per_pixel(PAR2D_RGBA_F32) == 16 &&
        par2d_bytes_per_pixel(PAR2D_RGBA8_SRGB) == 4 && par2d_bytes_per_pixel((par2d_pixel_format)7) == 0);

  /* Stats and the last frame's work. */
  par2d_stats stats;
  par2d_frame_stats frame;
  CHECK(par2d_get_stats(r, &stats) == PAR2D_OK && stats.frames == 2 && stats.index_builds >= 1);
  CHECK(par2d_render(r, pool, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_get_stats(r, &stats) == PAR2D_OK && stats.frames == 3);
  CHECK(par2d_get_frame_stats(r, &frame) == PAR2D_OK && frame.pixels == 40 * 30 && frame.tiles == 3 * 2);
  /* The algorithm's counts apart: the SIMD path's one 64x64 block and the kernel's samples (at
   * least the pixels), or the scalar reference's tiles. */
  par2d_frame_diagnostics diagnostics;
  memset(&diagnostics, 0xff, sizeof diagnostics);
  CHECK(par2d_get_frame_diagnostics(r, &diagnostics) == PAR2D_OK);
  if (par2d_renderer_isa(r) == PAR2D_ISA_SCALAR)
    CHECK(diagnostics.scalar_tiles == frame.tiles && diagnostics.blocks == 0 && diagnostics.samples == 0);
  else
    CHECK(diagnostics.blocks == 1 && diagnostics.block_lights == par2d_light_count(r) &&
          diagnostics.samples >= frame.pixels && diagnostics.scalar_tiles == 0);
  const int region[4] = {8, 4, 24, 20};
  CHECK(par2d_render(r, other, PAR2D_RGB_F32, 16 * 12, 1.0, region) == PAR2D_OK);
  CHECK(par2d_get_frame_stats(r, &frame) == PAR2D_OK && frame.pixels == 16 * 16);
  CHECK(par2d_get_frame_diagnostics(r, &diagnostics) == PAR2D_OK && diagnostics.sampled_pixels == 0); /* off by default */
  /* What pixels need, on request: one sampled pixel per 16x16 tile (none from the scalar path). */
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.sample_needs == 0);
  advanced.sample_needs = 1;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_render(r, pool, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_get_frame_stats(r, &frame) == PAR2D_OK && par2d_get_frame_diagnostics(r, &diagnostics) == PAR2D_OK);
  CHECK((diagnostics.sampled_pixels == frame.tiles) == (par2d_renderer_isa(r) != PAR2D_ISA_SCALAR));
  CHECK_ERROR(par2d_get_frame_diagnostics(r, NULL), PAR2D_INVALID_ARGUMENT, "par2d_get_frame_diagnostics: out is null");
  CHECK_ERROR(par2d_get_frame_diagnostics(NULL, &diagnostics), PAR2D_INVALID_ARGUMENT,
              "par2d_get_frame_diagnostics: renderer is null");
  advanced.sample_needs = 0;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK_ERROR(par2d_get_stats(r, NULL), PAR2D_INVALID_ARGUMENT, "par2d_get_stats: out is null");

  /* Scene-wide terms read back. */
  const double ambient[3] = {0.125, 0.25, 0.5};
  double back[3] = {0, 0, 0};
  CHECK(par2d_set_ambient(r, ambient) == PAR2D_OK);
  CHECK(par2d_get_ambient(r, back) == PAR2D_OK && back[0] == 0.125 && back[1] == 0.25 && back[2] == 0.5);
  par2d_directional_light suns[2], sun_back;
  par2d_directional_light_default(&suns[0]);
  par2d_directional_light_default(&suns[1]);
  suns[0].angles[0] = 10;
  suns[0].angles[1] = 20;
  suns[1].angles[0] = 100;
  suns[1].angles[1] = 110;
  suns[1].intensity = 0.5;
  CHECK(par2d_set_directional_lights(r, suns, 2) == PAR2D_OK);
  CHECK(par2d_get_directional_lights(r, &sun_back, 1, &count) == PAR2D_OK && count == 2 && sun_back.angles[1] == 20);
  CHECK(par2d_get_directional_lights(r, suns, 2, &count) == PAR2D_OK && suns[1].intensity == 0.5);
  par2d_normal_source kind = PAR2D_NORMAL_MAP;
  CHECK(par2d_get_normal_source(r, &kind, NULL) == PAR2D_OK && kind == PAR2D_NORMAL_NONE);
  const double tilted[3] = {0, 1, 1};
  double normal[3] = {0, 0, 0};
  CHECK(par2d_set_normal(r, tilted) == PAR2D_OK);
  CHECK(par2d_get_normal_source(r, &kind, normal) == PAR2D_OK && kind == PAR2D_NORMAL_CONSTANT && normal[2] > 0);
  CHECK(par2d_clear_normal_source(r) == PAR2D_OK);

  /* The snapshot: JSON text, and a file that a fresh renderer renders to the same bytes. */
  size_t length = 0;
  CHECK(par2d_snapshot_json(r, NULL, 0, &length) == PAR2D_OK && length > 0);
  char* text = malloc(length + 1);
  CHECK_ERROR_PREFIX(par2d_snapshot_json(r, text, length, &length), PAR2D_INVALID_ARGUMENT,
                     "par2d_snapshot_json: capacity ");
  CHECK(par2d_snapshot_json(r, text, length + 1, &length) == PAR2D_OK && strlen(text) == length);
  CHECK(strstr(text, "\"ambient\"") != NULL && strstr(text, "\"directional_lights\"") != NULL);
  free(text);
  snprintf(saved, sizeof saved, "%s/snapshot.json", dir);
  CHECK(par2d_save_scene(r, saved) == PAR2D_OK);
  par2d_renderer* copy = two_thread_renderer(0, 0);
  CHECK(copy != NULL && par2d_load_scene(copy, saved) == PAR2D_OK);
  CHECK(par2d_render(r, pool, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(copy, other, PAR2D_RGB_F32, 40 * 12, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(pool, other, sizeof(float) * n) == 0);
  CHECK(par2d_light_count(copy) == 2 && par2d_occluder_count(copy) == 2);
  CHECK_ERROR(par2d_save_scene(r, NULL), PAR2D_INVALID_ARGUMENT, "par2d_save_scene: path is null");

  free(pool);
  free(other);
  par2d_renderer_destroy(copy);
  par2d_renderer_destroy(r);
  remove(saved);
  remove(path);
}

/* Incremental frames: the first frame is whole, a frame with no change writes nothing (the
 * canaries stay), a ranged torch flickering rewrites only the blocks it reaches and says which,
 * and the result equals a full frame of a second renderer byte for byte. */
static void check_incremental_frames(void) {
  enum { IW = 256, IH = 192 };
  par2d_renderer *r = two_thread_renderer(0, 0), *full = two_thread_renderer(0, 0);
  if (r == NULL || full == NULL) return;
  par2d_renderer* both[2] = {r, full};
  const double white[3] = {1.0, 0.9, 0.8};
  par2d_shape torch;
  memset(&torch, 0, sizeof torch);
  torch.kind = PAR2D_SHAPE_CIRCLE;
  torch.circle[0] = 30.0;
  torch.circle[1] = 30.0;
  torch.circle[2] = 2.0;
  par2d_light_terms terms;
  par2d_light_terms_default(&terms);
  terms.range = 20.0;
  par2d_light lights[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    CHECK(par2d_set_frame(both[i], IW, IH, NULL) == PAR2D_OK);
    CHECK(par2d_add_light(both[i], &torch, white, 2.0, &lights[i]) == PAR2D_OK);
    CHECK(par2d_set_light_terms(both[i], lights[i], &terms) == PAR2D_OK);
  }
  CHECK(par2d_set_incremental(r, 1) == PAR2D_OK);
  CHECK(par2d_set_incremental(NULL, 1) == PAR2D_INVALID_ARGUMENT);
  unsigned char* a = malloc((size_t)IW * IH * 4);
  unsigned char* b = malloc((size_t)IW * IH * 4);
  if (a == NULL || b == NULL) return;
  par2d_rect rects[8];
  size_t count = 99;
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_dirty_rects(r, rects, 8, &count) == PAR2D_OK);
  CHECK(count == 1 && rects[0].x0 == 0 && rects[0].y0 == 0 && rects[0].x1 == IW && rects[0].y1 == IH);
  CHECK(par2d_dirty_rects(r, NULL, 0, &count) == PAR2D_OK && count == 1);
  CHECK(par2d_dirty_rects(r, NULL, 1, &count) == PAR2D_INVALID_ARGUMENT);

  /* Nothing changed: no pixel written, no rectangle. */
  unsigned char* saved = malloc((size_t)IW * IH * 4);
  if (saved == NULL) return;
  memcpy(saved, a, (size_t)IW * IH * 4);
  memset(a, 0xA5, (size_t)IW * IH * 4);
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_dirty_rects(r, rects, 8, &count) == PAR2D_OK && count == 0);
  int untouched = 1;
  for (size_t i = 0; i < (size_t)IW * IH * 4; ++i) untouched = untouched && a[i] == 0xA5;
  CHECK(untouched);
  memcpy(a, saved, (size_t)IW * IH * 4);

  /* The torch flickers: only the top-left block it reaches (range 20 around (30, 30)). */
  for (int i = 0; i < 2; ++i) CHECK(par2d_set_light_emission(both[i], lights[i], white, 1.5) == PAR2D_OK);
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(full, b, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(a, b, (size_t)IW * IH * 4) == 0);
  CHECK(par2d_dirty_rects(r, rects, 8, &count) == PAR2D_OK);
  CHECK(count == 1 && rects[0].x0 == 0 && rects[0].y0 == 0 && rects[0].x1 == 64 && rects[0].y1 == 64);
  par2d_frame_stats stats;
  CHECK(par2d_get_frame_stats(r, &stats) == PAR2D_OK && stats.pixels == 64 * 64);

  /* Forced: the whole frame again. */
  CHECK(par2d_force_full_frame(r) == PAR2D_OK);
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_dirty_rects(r, rects, 8, &count) == PAR2D_OK && count == 1 && rects[0].x1 == IW && rects[0].y1 == IH);
  CHECK(memcmp(a, b, (size_t)IW * IH * 4) == 0);

  /* The light-layer cache: a flicker's block comes from the stored layers (nothing handed to
   * the kernel), within one 8-bit level of the full render. The scalar path keeps no layers. */
  const int simd = par2d_renderer_isa(r) != PAR2D_ISA_SCALAR;
  CHECK(par2d_set_light_layer_budget(NULL, 1) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_set_light_layer_budget(r, (size_t)8 << 20) == PAR2D_OK);
  CHECK(par2d_light_layer_budget(r) == (size_t)8 << 20 && par2d_light_layer_budget(NULL) == 0);
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_get_frame_stats(r, &stats) == PAR2D_OK && (stats.layer_tiles_filled > 0) == simd &&
        stats.layer_tiles_reused == 0);
  CHECK((par2d_light_layer_bytes(r) > 0) == simd && par2d_light_layer_bytes(r) <= (size_t)8 << 20);
  for (int i = 0; i < 2; ++i) CHECK(par2d_set_light_emission(both[i], lights[i], white, 0.75) == PAR2D_OK);
  CHECK(par2d_render(r, a, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(full, b, PAR2D_RGBA8_SRGB, IW * 4, 1.0, NULL) == PAR2D_OK);
  par2d_frame_diagnostics diagnostics;
  CHECK(par2d_get_frame_stats(r, &stats) == PAR2D_OK && (stats.layer_tiles_reused > 0) == simd &&
        stats.layer_tiles_filled == 0 && stats.pixels == 64 * 64);
  CHECK(par2d_get_frame_diagnostics(r, &diagnostics) == PAR2D_OK && (diagnostics.tile_lights == 0) == simd);
  int close = 1;
  for (size_t i = 0; i < (size_t)IW * IH * 4; ++i) close = close && abs((int)a[i] - (int)b[i]) <= 1;
  CHECK(close);
  CHECK(par2d_set_light_layer_budget(r, 0) == PAR2D_OK && par2d_light_layer_bytes(r) == 0);
  free(saved);
  free(a);
  free(b);
  par2d_renderer_destroy(r);
  par2d_renderer_destroy(full);
}

/* A circle shape for the calls that take one. */
static par2d_shape circle_shape(double x, double y, double radius) {
  par2d_shape shape;
  memset(&shape, 0, sizeof shape);
  shape.kind = PAR2D_SHAPE_CIRCLE;
  shape.circle[0] = x;
  shape.circle[1] = y;
  shape.circle[2] = radius;
  return shape;
}

/* A polygon shape over `count` (x, y) pairs at `xy`. */
static par2d_shape polygon_shape(const double* xy, size_t count) {
  par2d_shape shape;
  memset(&shape, 0, sizeof shape);
  shape.kind = PAR2D_SHAPE_POLYGON;
  shape.vertices = xy;
  shape.vertex_count = count;
  return shape;
}

/* Scrolling: a camera panning by whole pixels. Each incremental frame (dithered BGRA8, whose
 * pattern follows the grid too) shifts the kept pixels, reports the shift, and equals byte for
 * byte a second renderer's full frame at the same offset; a refused offset keeps the old one. */
static void check_scrolling(void) {
  enum { SW = 200, SH = 120 };
  par2d_renderer *r = two_thread_renderer(0, 0), *full = two_thread_renderer(0, 0);
  if (r == NULL || full == NULL) return;
  par2d_renderer* both[2] = {r, full};
  const double warm[3] = {1.0, 0.8, 0.6};
  const double wall_xy[8] = {60.0, 20.0, 70.0, 20.0, 70.0, 90.0, 60.0, 90.0};
  const double view[4] = {0.0, 0.0, 100.0, 60.0}; /* half a world unit per pixel */
  for (int i = 0; i < 2; ++i) {
    par2d_light light;
    par2d_occluder wall;
    par2d_shape torch = circle_shape(40.0, 40.0, 2.0), box = polygon_shape(wall_xy, 4);
    CHECK(par2d_set_frame(both[i], SW, SH, view) == PAR2D_OK);
    CHECK(par2d_add_light(both[i], &torch, warm, 3.0, &light) == PAR2D_OK);
    CHECK(par2d_add_occluder(both[i], &box, &wall) == PAR2D_OK);
  }
  CHECK(par2d_set_incremental(r, 1) == PAR2D_OK);
  const size_t bytes = (size_t)SW * SH * 4;
  unsigned char* a = malloc(bytes);
  unsigned char* b = malloc(bytes);
  if (a == NULL || b == NULL) return;
  CHECK(par2d_render(r, a, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, NULL) == PAR2D_OK);
  const int64_t path[][2] = {{4, 0}, {8, 3}, {5, 9}, {-30, 9}, {-30, -70}, {500, -70}, {503, -66}};
  for (size_t f = 0; f < sizeof path / sizeof path[0]; ++f) {
    int64_t x = 0, y = 0;
    CHECK(par2d_get_view_offset(r, &x, &y) == PAR2D_OK);
    CHECK(par2d_set_view_offset(r, path[f][0], path[f][1]) == PAR2D_OK);
    CHECK(par2d_set_view_offset(full, path[f][0], path[f][1]) == PAR2D_OK);
    CHECK(par2d_render(r, a, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, NULL) == PAR2D_OK);
    CHECK(par2d_render(full, b, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, NULL) == PAR2D_OK);
    CHECK(memcmp(a, b, bytes) == 0);
    int dx = 99, dy = 99;
    CHECK(par2d_frame_shift(r, &dx, &dy) == PAR2D_OK);
    const int64_t mx = path[f][0] - x, my = path[f][1] - y;
    const int kept = mx > -SW && mx < SW && my > -SH && my < SH;
    CHECK(kept ? (dx == mx && dy == my) : (dx == 0 && dy == 0));
    /* A kept frame computes the uncovered bands, widened to whole 16-pixel tiles (and, in the
     * 64-pixel block where a column band meets a row band, the box of both), no more. */
    par2d_frame_stats stats;
    CHECK(par2d_get_frame_stats(r, &stats) == PAR2D_OK);
    if (kept) CHECK(stats.pixels <= (uint64_t)(abs(dx) + 15) * SH + (uint64_t)(abs(dy) + 15) * SW + 64 * 64);
  }
  /* A view offset past 2^40 pixels is refused, naming the call; the offset stays. */
  CHECK(par2d_set_view_offset(r, (int64_t)1 << 41, 0) == PAR2D_INVALID_ARGUMENT);
  CHECK(strstr(par2d_last_error(), "par2d_set_view_offset") != NULL);
  int64_t x = 0, y = 0;
  CHECK(par2d_get_view_offset(r, &x, &y) == PAR2D_OK && x == 503 && y == -66);
  CHECK(par2d_set_view_offset(NULL, 0, 0) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_frame_shift(NULL, NULL, NULL) == PAR2D_INVALID_ARGUMENT);
  /* The ring layout: frame pixel (i, j) at ((x + i) mod w, (y + j) mod h); a pan moves no byte,
   * reports no shift, and the ring read at the offset is the full renderer's frame. */
  CHECK(par2d_set_buffer_layout(r, PAR2D_LAYOUT_RING) == PAR2D_OK);
  CHECK(par2d_set_buffer_layout(r, (par2d_buffer_layout)7) == PAR2D_INVALID_ARGUMENT);
  const int64_t ring_path[][2] = {{510, -60}, {515, -52}, {400, -52}};
  for (size_t f = 0; f < sizeof ring_path / sizeof ring_path[0]; ++f) {
    CHECK(par2d_set_view_offset(r, ring_path[f][0], ring_path[f][1]) == PAR2D_OK);
    CHECK(par2d_set_view_offset(full, ring_path[f][0], ring_path[f][1]) == PAR2D_OK);
    CHECK(par2d_render(r, a, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, NULL) == PAR2D_OK);
    CHECK(par2d_render(full, b, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, NULL) == PAR2D_OK);
    int dx = 99, dy = 99, same = 1;
    CHECK(par2d_frame_shift(r, &dx, &dy) == PAR2D_OK && dx == 0 && dy == 0);
    const int rx = (int)(((ring_path[f][0] % SW) + SW) % SW), ry = (int)(((ring_path[f][1] % SH) + SH) % SH);
    for (int y = 0; y < SH; ++y)
      for (int x = 0; x < SW; ++x)
        same = same && memcmp(&a[(((size_t)(ry + y) % SH) * SW + (size_t)(rx + x) % SW) * 4], &b[((size_t)y * SW + x) * 4], 4) == 0;
    CHECK(same);
  }
  const int region[4] = {0, 0, 10, 10};
  CHECK(par2d_render(r, a, PAR2D_BGRA8_SRGB_DITHERED, SW * 4, 1.0, region) == PAR2D_INVALID_ARGUMENT);
  CHECK(strstr(par2d_last_error(), "BufferLayout::image") != NULL);
  CHECK(par2d_set_buffer_layout(r, PAR2D_LAYOUT_IMAGE) == PAR2D_OK);

  /* par2d_set_frame starts again at offset 0. */
  CHECK(par2d_set_frame(r, SW, SH, view) == PAR2D_OK);
  CHECK(par2d_get_view_offset(r, &x, &y) == PAR2D_OK && x == 0 && y == 0);
  free(a);
  free(b);
  par2d_renderer_destroy(r);
  par2d_renderer_destroy(full);
}


/* Every count and pointer of a par2d_shape is checked before the arrays it sizes are read: a
 * hole_count past PAR2D_MAX_POLYGON_HOLES (as in a struct that was never zeroed), hole counts
 * that overflow the total, null vertices behind holes. Each is refused, nothing crashes. */
/* An IEEE half's value (sign, 5 exponent bits, 10 mantissa bits; no infinities or NaNs here). */
static double half_value(uint16_t h) {
  const int exponent = (h >> 10) & 0x1F;
  const double mantissa = (double)(h & 0x3FF);
  const double magnitude = exponent == 0 ? ldexp(mantissa, -24) : ldexp(1024.0 + mantissa, exponent - 25);
  return (h & 0x8000) ? -magnitude : magnitude;
}

/* Whether half h is the nearest half to f (ties to the even one), or 65504 for f past it. */
static int is_nearest_half(uint16_t h, float f) {
  if (f >= 65520.0f) return h == 0x7BFF;
  if (f < 0.0f || (h & 0x8000) || ((h >> 10) & 0x1F) == 0x1F) return 0;
  const double d = fabs(half_value(h) - f);
  if (h > 0 && fabs(half_value((uint16_t)(h - 1)) - f) < d) return 0;
  if (h < 0x7BFF && fabs(half_value((uint16_t)(h + 1)) - f) < d) return 0;
  if (h > 0 && fabs(half_value((uint16_t)(h - 1)) - f) == d && (h & 1)) return 0;
  if (h < 0x7BFF && fabs(half_value((uint16_t)(h + 1)) - f) == d && (h & 1)) return 0;
  return 1;
}

/* Whether `bgra` holds `rgba`'s count pixels with R and B swapped. */
static int is_swapped(const unsigned char* bgra, const unsigned char* rgba, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    const unsigned char* p = bgra + 4 * i;
    const unsigned char* q = rgba + 4 * i;
    if (p[0] != q[2] || p[1] != q[1] || p[2] != q[0] || p[3] != q[3]) return 0;
  }
  return 1;
}

/* The GPU-ready formats through par2d_render: their sizes; BGRA = RGBA with R and B swapped,
 * plain and dithered; the dither within one code of the rounding; halves nearest to the float
 * frame (ties to even) and saturating at 65504; a region's pixels equal the whole frame's in
 * every format; values that are no format refused without a byte written. */
static void check_gpu_formats(void) {
  enum { FW = 80, FH = 60, N = FW * FH };
  CHECK(par2d_bytes_per_pixel(PAR2D_BGRA8_SRGB) == 4 && par2d_bytes_per_pixel(PAR2D_RGBA16F) == 8 &&
        par2d_bytes_per_pixel(PAR2D_RGBA8_SRGB_DITHERED) == 4 && par2d_bytes_per_pixel(PAR2D_BGRA8_SRGB_DITHERED) == 4);
  CHECK(par2d_bytes_per_pixel((par2d_pixel_format)-1) == 0);
  par2d_renderer* r = two_thread_renderer(FW, FH);
  if (r == NULL) return;
  /* A light bright enough that its disc passes the largest half, dimmer ones around it. */
  const double white[3] = {1.0, 0.8, 0.5};
  const par2d_shape sun = circle_shape(20.0, 20.0, 4.0);
  const par2d_shape lamp = circle_shape(65.0, 45.0, 2.0);
  par2d_light light = 0;
  CHECK(par2d_add_light(r, &sun, white, 2e5, &light) == PAR2D_OK);
  CHECK(par2d_add_light(r, &lamp, white, 0.3, &light) == PAR2D_OK);
  const double box[8] = {40, 10, 46, 10, 46, 50, 40, 50};
  par2d_occluder occluder = 0;
  const par2d_shape wall = polygon_shape(box, 4);
  CHECK(par2d_add_occluder(r, &wall, &occluder) == PAR2D_OK);

  float* rgba = malloc(sizeof(float) * 4 * N);
  uint16_t* half = malloc(sizeof(uint16_t) * 4 * N);
  unsigned char* bytes[4] = {malloc(4 * N), malloc(4 * N), malloc(4 * N), malloc(4 * N)};
  if (rgba == NULL || half == NULL || !bytes[0] || !bytes[1] || !bytes[2] || !bytes[3]) return;
  const par2d_pixel_format eight[4] = {PAR2D_RGBA8_SRGB, PAR2D_BGRA8_SRGB, PAR2D_RGBA8_SRGB_DITHERED,
                                       PAR2D_BGRA8_SRGB_DITHERED};
  CHECK(par2d_render(r, rgba, PAR2D_RGBA_F32, FW * 16, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(r, half, PAR2D_RGBA16F, FW * 8, 1.0, NULL) == PAR2D_OK);
  /* An exposure that puts the sun's surroundings between the codes' ends (E 1e4 .. 1e5). */
  const double exposure = 1e-5;
  for (int k = 0; k < 4; ++k) CHECK(par2d_render(r, bytes[k], eight[k], FW * 4, exposure, NULL) == PAR2D_OK);
  CHECK(is_swapped(bytes[1], bytes[0], N));
  CHECK(is_swapped(bytes[3], bytes[2], N));
  int within_one = 1, differs = 0, between = 0;
  for (size_t i = 0; i < 4 * (size_t)N; ++i) {
    within_one = within_one && abs((int)bytes[2][i] - (int)bytes[0][i]) <= 1;
    differs += bytes[2][i] != bytes[0][i];
    between += bytes[0][i] > 0 && bytes[0][i] < 255;
  }
  CHECK(within_one && differs > N / 8 && between > N);
  int nearest = 1, saturated = 0, lit = 0;
  for (size_t i = 0; i < (size_t)N; ++i) {
    for (int c = 0; c < 3; ++c) {
      nearest = nearest && is_nearest_half(half[4 * i + c], rgba[4 * i + c]);
      saturated += rgba[4 * i + c] > 65504.0f;
      lit += rgba[4 * i + c] > 0.0f && rgba[4 * i + c] < 1000.0f;
    }
    nearest = nearest && half[4 * i + 3] == 0x3C00; /* alpha 1 */
  }
  CHECK(nearest && saturated > 0 && lit > 0);

  /* A region at odd offsets in each format: the whole frame's pixels, dither phase included. */
  const int region[4] = {5, 3, 37, 29};
  const int rw = region[2] - region[0], rh = region[3] - region[1];
  unsigned char* part = malloc((size_t)rw * rh * 8);
  if (part == NULL) return;
  for (int k = 0; k < 5; ++k) {
    const par2d_pixel_format format = k < 4 ? eight[k] : PAR2D_RGBA16F;
    const int bpp = par2d_bytes_per_pixel(format);
    const unsigned char* whole = k < 4 ? bytes[k] : (const unsigned char*)half;
    CHECK(par2d_render(r, part, format, rw * bpp, k < 4 ? exposure : 1.0, region) == PAR2D_OK);
    int same = 1;
    for (int j = 0; j < rh; ++j)
      same = same && memcmp(part + (size_t)j * rw * bpp, whole + ((size_t)(j + region[1]) * FW + region[0]) * bpp,
                            (size_t)rw * bpp) == 0;
    CHECK(same);
  }

  /* Values that are no format: refused, nothing written. */
  const int unknown[2] = {7, -1};
  for (int k = 0; k < 2; ++k) {
    memset(bytes[0], 0xA5, 4 * N);
    CHECK_ERROR_PREFIX(par2d_render(r, bytes[0], (par2d_pixel_format)unknown[k], FW * 16, 1.0, NULL),
                       PAR2D_INVALID_ARGUMENT, "par2d_render: ");
    int untouched = 1;
    for (size_t i = 0; i < 4 * (size_t)N; ++i) untouched = untouched && bytes[0][i] == 0xA5;
    CHECK(untouched);
  }
  free(part);
  for (int k = 0; k < 4; ++k) free(bytes[k]);
  free(half);
  free(rgba);
  par2d_renderer_destroy(r);
}

/* An engine re-sending every entity every frame: each update with the values the item holds
 * (shapes, transforms, emission, terms, ambient) marks nothing, so the next incremental frame
 * writes no byte and reports no rectangle; one real change after them is computed. */
static void check_resync_every_frame(void) {
  enum { RW = 192, RH = 128, N = RW * RH };
  par2d_renderer* r = two_thread_renderer(RW, RH);
  if (r == NULL) return;
  const double warm[3] = {1.0, 0.7, 0.4}, cold[3] = {0.4, 0.6, 1.0}, ambient[3] = {0.01, 0.01, 0.02};
  const par2d_shape torch = circle_shape(30.0, 30.0, 2.0);
  const par2d_shape lamp = circle_shape(150.0, 90.0, 3.0);
  par2d_light lights[2] = {0, 0};
  CHECK(par2d_add_light(r, &torch, warm, 2.0, &lights[0]) == PAR2D_OK);
  CHECK(par2d_add_light(r, &lamp, cold, 1.5, &lights[1]) == PAR2D_OK);
  par2d_light_terms terms;
  par2d_light_terms_default(&terms);
  terms.range = 40.0;
  CHECK(par2d_set_light_terms(r, lights[0], &terms) == PAR2D_OK);
  const double box[8] = {80, 20, 90, 20, 90, 100, 80, 100};
  const double local[8] = {-4, -2, 4, -2, 4, 2, -4, 2};
  const par2d_shape wall = polygon_shape(box, 4), crate = polygon_shape(local, 4);
  par2d_transform crate_at;
  par2d_transform_identity(&crate_at);
  crate_at.position[0] = 120.0;
  crate_at.position[1] = 40.0;
  crate_at.rotation = 30.0;
  par2d_occluder occluders[2] = {0, 0};
  CHECK(par2d_add_occluder(r, &wall, &occluders[0]) == PAR2D_OK);
  CHECK(par2d_add_occluder_transformed(r, &crate, &crate_at, &occluders[1]) == PAR2D_OK);
  par2d_occluder_terms wall_terms;
  par2d_occluder_terms_default(&wall_terms);
  wall_terms.transmittance[1] = 0.5;
  CHECK(par2d_set_occluder_terms(r, occluders[0], &wall_terms) == PAR2D_OK);
  CHECK(par2d_set_ambient(r, ambient) == PAR2D_OK);
  CHECK(par2d_set_incremental(r, 1) == PAR2D_OK);

  unsigned char* frame = malloc(4 * N);
  if (frame == NULL) return;
  par2d_rect rects[4];
  size_t count = 99;
  CHECK(par2d_render(r, frame, PAR2D_BGRA8_SRGB_DITHERED, RW * 4, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_dirty_rects(r, rects, 4, &count) == PAR2D_OK && count == 1);
  for (int frame_number = 0; frame_number < 3; ++frame_number) {
    CHECK(par2d_update_light(r, lights[0], &torch, warm, 2.0) == PAR2D_OK);
    CHECK(par2d_update_light(r, lights[1], &lamp, cold, 1.5) == PAR2D_OK);
    CHECK(par2d_set_light_emission(r, lights[1], cold, 1.5) == PAR2D_OK);
    CHECK(par2d_set_light_terms(r, lights[0], &terms) == PAR2D_OK);
    CHECK(par2d_update_occluder(r, occluders[0], &wall) == PAR2D_OK);
    CHECK(par2d_update_occluder_transformed(r, occluders[1], &crate, &crate_at) == PAR2D_OK);
    CHECK(par2d_set_occluder_terms(r, occluders[0], &wall_terms) == PAR2D_OK);
    CHECK(par2d_set_ambient(r, ambient) == PAR2D_OK);
    memset(frame, 0xA5, 4 * N);
    count = 99;
    CHECK(par2d_render(r, frame, PAR2D_BGRA8_SRGB_DITHERED, RW * 4, 1.0, NULL) == PAR2D_OK);
    CHECK(par2d_dirty_rects(r, rects, 4, &count) == PAR2D_OK && count == 0);
    int untouched = 1;
    for (size_t i = 0; i < 4 * (size_t)N; ++i) untouched = untouched && frame[i] == 0xA5;
    CHECK(untouched);
  }
  /* A real change among the re-sent ones: the torch's emission. Its blocks only (every block
   * without culling, on the scalar path). */
  CHECK(par2d_update_light(r, lights[0], &torch, warm, 2.5) == PAR2D_OK);
  CHECK(par2d_update_light(r, lights[1], &lamp, cold, 1.5) == PAR2D_OK);
  CHECK(par2d_render(r, frame, PAR2D_BGRA8_SRGB_DITHERED, RW * 4, 1.0, NULL) == PAR2D_OK);
  par2d_frame_stats stats;
  CHECK(par2d_dirty_rects(r, rects, 4, &count) == PAR2D_OK && count >= 1);
  const int culled = par2d_renderer_isa(r) != PAR2D_ISA_SCALAR;
  CHECK(par2d_get_frame_stats(r, &stats) == PAR2D_OK && stats.pixels > 0 && (stats.pixels < (uint64_t)N) == culled);
  free(frame);
  par2d_renderer_destroy(r);
}

static void check_shape_counts(void) {
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(NULL, &r) == PAR2D_OK);
  if (r == NULL) return;
  CHECK(par2d_set_frame(r, 16, 16, NULL) == PAR2D_OK);
  const double white[3] = {1.0, 1.0, 1.0};
  const double square[8] = {2, 2, 14, 2, 14, 14, 2, 14};
  const size_t zeros[4] = {0, 0, 0, 0};
  par2d_shape shape = polygon_shape(square, 4);
  par2d_occluder occluder = 0;
  par2d_light light = 0;
  CHECK(par2d_add_occluder(r, &shape, &occluder) == PAR2D_OK);
  par2d_shape dot = circle_shape(8, 8, 1);
  CHECK(par2d_add_light(r, &dot, white, 1.0, &light) == PAR2D_OK);
  par2d_transform identity;
  par2d_transform_identity(&identity);

  shape.hole_vertex_counts = zeros;
  shape.hole_count = (size_t)1 << 40;
  CHECK_ERROR(par2d_add_occluder(r, &shape, &occluder), PAR2D_INVALID_ARGUMENT,
              "par2d_add_occluder: shape hole_count 1099511627776 is more than 349525");
  CHECK_ERROR(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape hole_count 1099511627776 is more than 349525");
  CHECK_ERROR(par2d_update_light(r, light, &shape, white, 1.0), PAR2D_INVALID_ARGUMENT,
              "par2d_update_light: shape hole_count 1099511627776 is more than 349525");
  CHECK_ERROR(par2d_add_occluder_transformed(r, &shape, &identity, &occluder), PAR2D_INVALID_ARGUMENT,
              "par2d_add_occluder_transformed: shape hole_count 1099511627776 is more than 349525");
  shape.hole_count = (size_t)-1;
  CHECK_ERROR(par2d_add_light(r, &shape, white, 1.0, &light), PAR2D_INVALID_ARGUMENT,
              "par2d_add_light: shape hole_count 18446744073709551615 is more than 349525");
  /* Four real zero counts: the shape itself is judged (a hole needs 3 vertices). */
  shape.hole_count = 4;
  CHECK(par2d_update_occluder(r, occluder, &shape) == PAR2D_INVALID_SCENE);
  CHECK(strstr(par2d_last_error(), "holes[0]: needs at least 3 vertices, got 0") != NULL);
  {
    /* The limit itself, with that many counts behind the pointer, goes on to the shape's rules;
     * one more is refused as a count. */
    size_t* many = calloc(PAR2D_MAX_POLYGON_HOLES + 1, sizeof(size_t));
    CHECK(many != NULL);
    if (many != NULL) {
      shape.hole_vertex_counts = many;
      shape.hole_count = PAR2D_MAX_POLYGON_HOLES;
      CHECK(par2d_update_occluder(r, occluder, &shape) == PAR2D_INVALID_SCENE);
      shape.hole_count = PAR2D_MAX_POLYGON_HOLES + 1;
      CHECK_ERROR(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
                  "par2d_update_occluder: shape hole_count 349526 is more than 349525");
      free(many);
    }
  }
  /* Counts that wrap around size_t, or add up past the vertex limit. */
  const size_t wrapping[2] = {(size_t)-1, 5};
  shape.hole_vertex_counts = wrapping;
  shape.hole_count = 2;
  CHECK_ERROR(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape vertex_count and hole_vertex_counts add up to more than 1048576");
  const size_t past[2] = {PAR2D_MAX_POLYGON_VERTICES - 8, 5};
  shape.hole_vertex_counts = past;
  CHECK_ERROR(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape vertex_count and hole_vertex_counts add up to more than 1048576");
  /* Null vertices with an empty outline but holes to read. */
  const size_t three[1] = {3};
  shape.vertices = NULL;
  shape.vertex_count = 0;
  shape.hole_vertex_counts = three;
  shape.hole_count = 1;
  CHECK_ERROR(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
              "par2d_update_occluder: shape vertices are null");
  /* A struct that was never zeroed (every byte 0xA5) with only the outline's fields set: the
   * garbage hole_count is refused; a circle reads only its own fields. */
  memset(&shape, 0xA5, sizeof shape);
  shape.kind = PAR2D_SHAPE_POLYGON;
  shape.vertices = square;
  shape.vertex_count = 4;
  CHECK_ERROR_PREFIX(par2d_update_occluder(r, occluder, &shape), PAR2D_INVALID_ARGUMENT,
                     "par2d_update_occluder: shape hole_count ");
  shape.kind = PAR2D_SHAPE_CIRCLE;
  shape.circle[0] = shape.circle[1] = 8.0;
  shape.circle[2] = 2.0;
  CHECK(par2d_update_light(r, light, &shape, white, 1.0) == PAR2D_OK);
  /* Nothing refused changed the world: the occluder is still the square. */
  par2d_shape got;
  memset(&got, 0, sizeof got);
  CHECK(par2d_get_occluder(r, occluder, &got) == PAR2D_OK);
  CHECK(got.kind == PAR2D_SHAPE_POLYGON && got.vertex_count == 4 && got.hole_count == 0 &&
        memcmp(got.vertices, square, sizeof square) == 0);
  par2d_renderer_destroy(r);
}

/* Holes through the C API with rings of 3 and 5 vertices (so that no ring's count can stand in
 * for another's): what the library holds (the snapshot) is what was given, what is read back
 * is what was given, and the read-back shapes given back to par2d_update_* render the same
 * frame byte for byte. */
static void check_hole_rings(void) {
  par2d_renderer* r = two_thread_renderer(W, H);
  if (r == NULL) return;
  /* An occluder: a pentagon outline, a triangular hole, a pentagonal hole with the light in it. */
  const double wall[26] = {8, 8, 40, 8, 48, 24, 40, 40, 8, 40,              /* outline: 5 */
                           12, 12, 20, 12, 12, 20,                          /* hole 0: 3 */
                           24, 16, 34, 16, 38, 26, 34, 34, 24, 34};         /* hole 1: 5 */
  const size_t wall_holes[2] = {3, 5};
  /* A light: a triangle outline with a pentagonal hole, out in the open. */
  const double lamp[16] = {50, 2, 62, 2, 56, 14,                            /* outline: 3 */
                           54, 4, 57, 4, 58, 5, 56, 8, 55, 7};              /* hole 0: 5 */
  const size_t lamp_holes[1] = {5};
  const double warm[3] = {1.0, 0.8, 0.6};
  par2d_shape shape = polygon_shape(wall, 5);
  shape.hole_vertex_counts = wall_holes;
  shape.hole_count = 2;
  par2d_occluder occluder = 0;
  CHECK(par2d_add_occluder(r, &shape, &occluder) == PAR2D_OK);
  par2d_shape lamp_shape = polygon_shape(lamp, 3);
  lamp_shape.hole_vertex_counts = lamp_holes;
  lamp_shape.hole_count = 1;
  par2d_light lamp_light = 0, inner = 0;
  CHECK(par2d_add_light(r, &lamp_shape, warm, 2.0, &lamp_light) == PAR2D_OK);
  par2d_shape dot = circle_shape(30, 25, 1.5);
  CHECK(par2d_add_light(r, &dot, warm, 2.0, &inner) == PAR2D_OK);

  /* C to C++: the world holds these rings (the snapshot writes them). */
  size_t length = 0;
  CHECK(par2d_snapshot_json(r, NULL, 0, &length) == PAR2D_OK);
  char* json = malloc(length + 1);
  CHECK(json != NULL && par2d_snapshot_json(r, json, length + 1, &length) == PAR2D_OK);
  if (json != NULL) {
    CHECK(strstr(json, "\"polygon\": [[8, 8], [40, 8], [48, 24], [40, 40], [8, 40]], \"holes\": "
                       "[[[12, 12], [20, 12], [12, 20]], [[24, 16], [34, 16], [38, 26], [34, 34], [24, 34]]]") != NULL);
    CHECK(strstr(json, "\"polygon\": [[50, 2], [62, 2], [56, 14]], \"holes\": "
                       "[[[54, 4], [57, 4], [58, 5], [56, 8], [55, 7]]]") != NULL);
    free(json);
  }

  /* C++ to C: the read-back shapes are the given ones, count for count, vertex for vertex. */
  float* before = malloc(sizeof(float) * W * H * 3);
  float* after = malloc(sizeof(float) * W * H * 3);
  CHECK(par2d_render(r, before, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
  CHECK(before[(25 * W + 26) * 3] > 0.0f);  /* in the pentagonal hole, by the light */
  CHECK(before[(14 * W + 14) * 3] == 0.0f); /* in the triangular hole: walled off */
  par2d_shape got;
  memset(&got, 0, sizeof got);
  CHECK(par2d_get_occluder(r, occluder, &got) == PAR2D_OK);
  CHECK(got.kind == PAR2D_SHAPE_POLYGON && got.vertex_count == 5 && got.hole_count == 2);
  if (got.hole_count == 2 && got.vertex_count == 5) {
    CHECK(got.hole_vertex_counts[0] == 3 && got.hole_vertex_counts[1] == 5);
    CHECK(memcmp(got.vertices, wall, sizeof wall) == 0);
  }
  CHECK(par2d_update_occluder(r, occluder, &got) == PAR2D_OK);
  double color[3] = {0, 0, 0}, intensity = 0.0;
  memset(&got, 0, sizeof got);
  CHECK(par2d_get_light(r, lamp_light, &got, color, &intensity) == PAR2D_OK);
  CHECK(got.kind == PAR2D_SHAPE_POLYGON && got.vertex_count == 3 && got.hole_count == 1);
  if (got.hole_count == 1 && got.vertex_count == 3) {
    CHECK(got.hole_vertex_counts[0] == 5);
    CHECK(memcmp(got.vertices, lamp, sizeof lamp) == 0);
  }
  CHECK(par2d_update_light(r, lamp_light, &got, color, intensity) == PAR2D_OK);
  CHECK(par2d_render(r, after, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(before, after, sizeof(float) * W * H * 3) == 0);
  free(before);
  free(after);
  par2d_renderer_destroy(r);
}

/* Cookies: refusals name the call and the place; a constant cookie of weight 1/4 gives a
 * quarter of the light; reading one back; a cone as well is refused; count 0 removes it. */
static void check_cookies(void) {
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(NULL, &r) == PAR2D_OK);
  if (r == NULL) return;
  CHECK(par2d_set_frame(r, W, H, NULL) == PAR2D_OK);
  const double white[3] = {1.0, 1.0, 1.0};
  const par2d_shape circle = circle_shape(20.0, 8.0, 2.0);
  par2d_light light = 0;
  CHECK(par2d_add_light(r, &circle, white, 2.0, &light) == PAR2D_OK);
  const int row[4] = {0, 0, W, 1};
  const double directions[3] = {0.0, 90.0, 200.0}, weights[3] = {1.0, 0.5, 0.0};
  const double bad_order[3] = {0.0, 90.0, 90.0}, bad_weight[3] = {1.0, 1.5, 0.0};
  CHECK_ERROR(par2d_set_light_cookie(r, light, 0.0, NULL, weights, 3), PAR2D_INVALID_ARGUMENT,
              "par2d_set_light_cookie: directions is null with count 3");
  CHECK_ERROR(par2d_set_light_cookie(r, light, 0.0, directions, weights, 33), PAR2D_INVALID_ARGUMENT,
              "par2d_set_light_cookie: count must be at most 32, got 33");
  CHECK_ERROR_PREFIX(par2d_set_light_cookie(r, light, 0.0, bad_order, weights, 3), PAR2D_INVALID_SCENE,
                     "par2d_set_light_cookie: ");
  CHECK(strstr(par2d_last_error(), "cookie.knots[2][0]: directions must increase") != NULL);
  CHECK_ERROR_PREFIX(par2d_set_light_cookie(r, light, 0.0, directions, bad_weight, 3), PAR2D_INVALID_SCENE,
                     "par2d_set_light_cookie: ");
  CHECK(strstr(par2d_last_error(), "cookie.knots[1][1]") != NULL);
  CHECK_ERROR_PREFIX(par2d_set_light_cookie(r, light + 777, 0.0, directions, weights, 3), PAR2D_INVALID_ARGUMENT,
                     "par2d_set_light_cookie: ");
  par2d_light_terms plain_terms;
  par2d_light_terms_default(&plain_terms);
  CHECK(par2d_set_light_terms(r, light, &plain_terms) == PAR2D_OK);
  float full[3 * W], quarter[3 * W];
  CHECK(par2d_render(r, full, PAR2D_RGB_F32, 3 * W * sizeof(float), 1.0, row) == PAR2D_OK);
  const double constant = 0.25, at = 45.0;
  CHECK(par2d_set_light_cookie(r, light, 10.0, &at, &constant, 1) == PAR2D_OK);
  CHECK(par2d_render(r, quarter, PAR2D_RGB_F32, 3 * W * sizeof(float), 1.0, row) == PAR2D_OK);
  int same = 1;
  for (int i = 0; i < 3 * W; ++i) same = same && fabsf(quarter[i] - 0.25f * full[i]) <= 1e-5f * (fabsf(full[i]) + 1e-3f);
  CHECK(same);
  CHECK(par2d_set_light_cookie(r, light, -15.0, directions, weights, 3) == PAR2D_OK);
  double rotation = 0.0, got_directions[2] = {0, 0}, got_weights[2] = {0, 0};
  size_t knots = 0;
  CHECK(par2d_get_light_cookie(r, light, &rotation, got_directions, got_weights, 2, &knots) == PAR2D_OK);
  CHECK(knots == 3 && rotation == -15.0 && got_directions[1] == 90.0 && got_weights[1] == 0.5);
  /* A cone as well is refused while the cookie stays. */
  par2d_light_terms coned = plain_terms;
  coned.has_cone = 1;
  coned.cone_half_angle = 30.0;
  CHECK_ERROR_PREFIX(par2d_set_light_terms(r, light, &coned), PAR2D_INVALID_SCENE, "par2d_set_light_terms: ");
  CHECK(strstr(par2d_last_error(), "a cone or a cookie, not both") != NULL);
  CHECK(par2d_set_light_cookie(r, light, 0.0, NULL, NULL, 0) == PAR2D_OK);
  CHECK(par2d_get_light_cookie(r, light, NULL, NULL, NULL, 0, &knots) == PAR2D_OK && knots == 0);
  CHECK_ERROR(par2d_get_light_cookie(r, light, NULL, NULL, NULL, 0, NULL), PAR2D_INVALID_ARGUMENT,
              "par2d_get_light_cookie: count is null");
  par2d_renderer_destroy(r);
}

/* Sprite transforms: a crate added and moved by its transform renders exactly what the same
 * crate placed by hand renders; the world holds the placed shape; refusals name the field. */
static void check_transforms(void) {
  par2d_renderer* a = NULL;
  par2d_renderer* b = NULL;
  CHECK(par2d_renderer_create(NULL, &a) == PAR2D_OK && par2d_renderer_create(NULL, &b) == PAR2D_OK);
  if (a == NULL || b == NULL) return;
  CHECK(par2d_set_frame(a, W, H, NULL) == PAR2D_OK && par2d_set_frame(b, W, H, NULL) == PAR2D_OK);
  const double white[3] = {1.0, 0.9, 0.8};
  par2d_shape lamp = circle_shape(0.0, 0.0, 1.5);
  par2d_transform at;
  par2d_transform_identity(&at);
  CHECK(at.scale[0] == 1.0 && at.scale[1] == 1.0 && at.rotation == 0.0 && at.position[0] == 0.0);
  at.position[0] = 12.0;
  at.position[1] = 10.0;
  par2d_light la = 0, lb = 0;
  CHECK(par2d_add_light_transformed(a, &lamp, &at, white, 2.0, &la) == PAR2D_OK);
  lamp.circle[0] = 12.0;
  lamp.circle[1] = 10.0;
  CHECK(par2d_add_light(b, &lamp, white, 2.0, &lb) == PAR2D_OK);
  /* A 8 x 4 crate centred on its origin, turned a quarter (exact) and moved to (30, 24). */
  const double local[8] = {-4, -2, 4, -2, 4, 2, -4, 2};
  const double placed[8] = {32, 20, 32, 28, 28, 28, 28, 20};
  const par2d_shape crate = polygon_shape(local, 4);
  par2d_transform crate_at;
  par2d_transform_identity(&crate_at);
  crate_at.position[0] = 30.0;
  crate_at.position[1] = 24.0;
  crate_at.rotation = 90.0;
  par2d_occluder oa = 0, ob = 0;
  CHECK(par2d_add_occluder_transformed(a, &crate, &crate_at, &oa) == PAR2D_OK);
  par2d_shape crate_placed = crate;
  crate_placed.vertices = placed;
  CHECK(par2d_add_occluder(b, &crate_placed, &ob) == PAR2D_OK);
  float* fa = malloc(sizeof(float) * 3 * W * H);
  float* fb = malloc(sizeof(float) * 3 * W * H);
  CHECK(par2d_render(a, fa, PAR2D_RGB_F32, (ptrdiff_t)sizeof(float) * 3 * W, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(b, fb, PAR2D_RGB_F32, (ptrdiff_t)sizeof(float) * 3 * W, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(fa, fb, sizeof(float) * 3 * W * H) == 0);
  /* Moved by a new transform: a half-size mirrored crate at (20, 30). */
  crate_at.position[0] = 20.0;
  crate_at.position[1] = 30.0;
  crate_at.rotation = 0.0;
  crate_at.scale[0] = -0.5;
  crate_at.scale[1] = 0.5;
  CHECK(par2d_update_occluder_transformed(a, oa, &crate, &crate_at) == PAR2D_OK);
  const double moved[8] = {22, 29, 18, 29, 18, 31, 22, 31};
  crate_placed.vertices = moved;
  CHECK(par2d_update_occluder(b, ob, &crate_placed) == PAR2D_OK);
  at.position[0] = 40.0;
  lamp.circle[0] = lamp.circle[1] = 0.0;
  CHECK(par2d_update_light_transformed(a, la, &lamp, &at, white, 2.0) == PAR2D_OK);
  lamp.circle[0] = 40.0;
  lamp.circle[1] = 10.0;
  CHECK(par2d_update_light(b, lb, &lamp, white, 2.0) == PAR2D_OK);
  CHECK(par2d_render(a, fa, PAR2D_RGB_F32, (ptrdiff_t)sizeof(float) * 3 * W, 1.0, NULL) == PAR2D_OK);
  CHECK(par2d_render(b, fb, PAR2D_RGB_F32, (ptrdiff_t)sizeof(float) * 3 * W, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(fa, fb, sizeof(float) * 3 * W * H) == 0);
  /* Refusals. */
  crate_at.scale[1] = 0.0;
  CHECK_ERROR_PREFIX(par2d_update_occluder_transformed(a, oa, &crate, &crate_at), PAR2D_INVALID_SCENE,
                     "par2d_update_occluder_transformed: occluder ");
  CHECK(strstr(par2d_last_error(), "transform.scale[1]: must be non-zero, got 0") != NULL);
  at.scale[1] = 2.0;
  CHECK_ERROR_PREFIX(par2d_update_light_transformed(a, la, &lamp, &at, white, 2.0), PAR2D_INVALID_SCENE,
                     "par2d_update_light_transformed: light ");
  CHECK(strstr(par2d_last_error(), "a circle takes the same scale on both axes, got [1, 2]") != NULL);
  CHECK_ERROR(par2d_add_occluder_transformed(a, &crate, NULL, &oa), PAR2D_INVALID_ARGUMENT,
              "par2d_add_occluder_transformed: transform is null");
  CHECK_ERROR(par2d_add_light_transformed(NULL, &lamp, NULL, white, 1.0, &la), PAR2D_INVALID_ARGUMENT,
              "par2d_add_light_transformed: renderer is null");
  /* Nothing changed. */
  CHECK(par2d_render(a, fa, PAR2D_RGB_F32, (ptrdiff_t)sizeof(float) * 3 * W, 1.0, NULL) == PAR2D_OK);
  CHECK(memcmp(fa, fb, sizeof(float) * 3 * W * H) == 0);
  free(fa);
  free(fb);
  par2d_renderer_destroy(a);
  par2d_renderer_destroy(b);
}

/* One bounce from C: an occluder's albedo through its terms, the piece length, refusals. */
static void check_bounce(void) {
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(NULL, &r) == PAR2D_OK);
  if (r == NULL) return;
  CHECK(par2d_set_frame(r, 24, 16, NULL) == PAR2D_OK);
  const double white[3] = {1.0, 1.0, 1.0};
  const par2d_shape lamp = circle_shape(4.0, 4.0, 1.5);
  par2d_light light = 0;
  CHECK(par2d_add_light(r, &lamp, white, 3.0, &light) == PAR2D_OK);
  const double box[8] = {10, 2, 12, 2, 12, 12, 10, 12};
  const par2d_shape wall = polygon_shape(box, 4);
  par2d_occluder occluder = 0;
  CHECK(par2d_add_occluder(r, &wall, &occluder) == PAR2D_OK);
  par2d_occluder_terms terms;
  par2d_occluder_terms_default(&terms);
  CHECK(terms.albedo[0] == 0.0 && terms.albedo[2] == 0.0);
  float dark[24 * 3], lit[24 * 3];
  const int row[4] = {0, 10, 24, 11};
  CHECK(par2d_render(r, dark, PAR2D_RGB_F32, sizeof dark, 1.0, row) == PAR2D_OK);
  terms.albedo[0] = 0.8;
  terms.albedo[1] = 0.4;
  terms.albedo[2] = 0.2;
  CHECK(par2d_set_occluder_terms(r, occluder, &terms) == PAR2D_OK);
  par2d_occluder_terms back;
  CHECK(par2d_get_occluder_terms(r, occluder, &back) == PAR2D_OK && back.albedo[1] == 0.4);
  CHECK(par2d_render(r, lit, PAR2D_RGB_F32, sizeof lit, 1.0, row) == PAR2D_OK);
  /* Left of the wall, the lit face reflects onto the floor: more red than before. */
  CHECK(lit[8 * 3] > dark[8 * 3]);
  /* The terms apart: the direct light alone is the frame without albedo, the bounce alone is
   * what albedo adds (within float rounding of the sum), and the frame's stats count pieces. */
  par2d_frame_stats frame;
  par2d_frame_diagnostics diagnostics;
  CHECK(par2d_get_frame_stats(r, &frame) == PAR2D_OK && frame.bounce_pieces == 8 && frame.bounce_lit_sources == 1);
  CHECK(par2d_get_frame_diagnostics(r, &diagnostics) == PAR2D_OK && diagnostics.bounce_source_walks > 0 &&
        diagnostics.bounce_tile_sources >= diagnostics.bounce_tile_sources_hidden);
  float direct[24 * 3], bounce[24 * 3];
  par2d_advanced_options advanced;
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.bounce == PAR2D_BOUNCE_INCLUDED);
  advanced.bounce = PAR2D_BOUNCE_EXCLUDED;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_render(r, direct, PAR2D_RGB_F32, sizeof direct, 1.0, row) == PAR2D_OK);
  CHECK(memcmp(direct, dark, sizeof dark) == 0);
  advanced.bounce = PAR2D_BOUNCE_ONLY;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  CHECK(par2d_get_advanced_options(r, &advanced) == PAR2D_OK && advanced.bounce == PAR2D_BOUNCE_ONLY);
  CHECK(par2d_render(r, bounce, PAR2D_RGB_F32, sizeof bounce, 1.0, row) == PAR2D_OK);
  for (int i = 0; i < 24 * 3; ++i) CHECK(fabs((double)direct[i] + bounce[i] - lit[i]) <= 1e-6 * 3.0);
  CHECK(bounce[8 * 3] > 0.0f);
  advanced.bounce = (par2d_bounce_term)3;
  CHECK_ERROR(par2d_set_advanced_options(r, &advanced), PAR2D_INVALID_ARGUMENT,
              "par2d_set_advanced_options: bounce 3 is not PAR2D_BOUNCE_INCLUDED, PAR2D_BOUNCE_EXCLUDED or "
              "PAR2D_BOUNCE_ONLY");
  advanced.bounce = PAR2D_BOUNCE_INCLUDED;
  CHECK(par2d_set_advanced_options(r, &advanced) == PAR2D_OK);
  double piece = 0.0;
  CHECK(par2d_get_bounce(r, &piece) == PAR2D_OK && piece == 4.0);
  CHECK(par2d_set_bounce(r, 0.5) == PAR2D_OK);
  CHECK(par2d_get_bounce(r, &piece) == PAR2D_OK && piece == 0.5);
  CHECK_ERROR(par2d_set_bounce(r, -1.0), PAR2D_INVALID_SCENE, "par2d_set_bounce: bounce.piece: must be > 0, got -1");
  CHECK_ERROR_PREFIX(par2d_set_bounce(r, 1e-9), PAR2D_INVALID_SCENE,
                     "par2d_set_bounce: bounce.piece: cuts the reflecting occluders");
  CHECK(par2d_get_bounce(r, &piece) == PAR2D_OK && piece == 0.5);
  terms.albedo[0] = 1.5;
  CHECK_ERROR_PREFIX(par2d_set_occluder_terms(r, occluder, &terms), PAR2D_INVALID_SCENE, "par2d_set_occluder_terms: ");
  CHECK(strstr(par2d_last_error(), "albedo[0]: must be between 0 and 1, got 1.5") != NULL);
  CHECK_ERROR(par2d_get_bounce(r, NULL), PAR2D_INVALID_ARGUMENT, "par2d_get_bounce: piece is null");
  par2d_renderer_destroy(r);
}

int main(void) {
  int major = -1, minor = -1, patch = -1;
  char expected[32];
  par2d_version_numbers(&major, &minor, &patch);
  snprintf(expected, sizeof expected, "%d.%d.%d", major, minor, patch);
  CHECK(strcmp(par2d_version(), expected) == 0);
  /* The library loaded has the ABI this program was compiled against (its SONAME's). */
  CHECK(major == PAR2D_ABI_MAJOR && minor == PAR2D_ABI_MINOR);

  par2d_options options;
  par2d_options_default(&options);
  options.threads = 2;
  par2d_renderer* r = NULL;
  CHECK(par2d_renderer_create(&options, &r) == PAR2D_OK);
  if (r == NULL) return 1;
  CHECK(par2d_renderer_threads(r) >= 1 && par2d_renderer_threads(r) <= 2);
  CHECK(par2d_set_frame(r, W, H, NULL) == PAR2D_OK);
  check_incremental_frames();
  check_scrolling();
  check_gpu_formats();
  check_resync_every_frame();
  check_cookies();
  check_transforms();
  check_bounce();
  check_shape_counts();
  check_hole_rings();

  /* A circle light of radius 2 at (10, 10) with emission 3 (white), and a box occluder. */
  par2d_shape light_shape;
  memset(&light_shape, 0, sizeof light_shape);
  light_shape.kind = PAR2D_SHAPE_CIRCLE;
  light_shape.circle[0] = 10.0;
  light_shape.circle[1] = 10.0;
  light_shape.circle[2] = 2.0;
  const double white[3] = {1.0, 1.0, 1.0};
  par2d_light light = 0;
  CHECK(par2d_add_light(r, &light_shape, white, 3.0, &light) == PAR2D_OK);
  CHECK(light != 0);

  const double box[8] = {40, 30, 56, 30, 56, 44, 40, 44};
  par2d_shape occluder_shape;
  memset(&occluder_shape, 0, sizeof occluder_shape);
  occluder_shape.kind = PAR2D_SHAPE_POLYGON;
  occluder_shape.vertices = box;
  occluder_shape.vertex_count = 4;
  par2d_occluder occluder = 0;
  CHECK(par2d_add_occluder(r, &occluder_shape, &occluder) == PAR2D_OK);

  float* rgb = malloc(sizeof(float) * W * H * 3);
  CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
  /* Pixel (30, 10) has its center at (30.5, 10.5), unshadowed: E = e * 2 asin(r/d) / 2pi. */
  {
    const double d = hypot(30.5 - 10.0, 10.5 - 10.0);
    const double e = 3.0 * 2.0 * asin(2.0 / d) / (2.0 * 3.14159265358979323846);
    const float got = rgb[(10 * W + 30) * 3];
    CHECK(fabs(got - e) <= 1e-4 * 3.0);
  }
  CHECK(rgb[(37 * W + 48) * 3 + 1] == 0.0f); /* inside the occluder */

  /* Move the light behind the box: the far side of the box goes dark. */
  light_shape.circle[0] = 60.0;
  light_shape.circle[1] = 37.0;
  light_shape.circle[2] = 1.0;
  CHECK(par2d_update_light(r, light, &light_shape, white, 3.0) == PAR2D_OK);
  CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
  CHECK(rgb[(37 * W + 20) * 3] == 0.0f);
  CHECK(rgb[(10 * W + 60) * 3] > 0.0f); /* straight above the light, past the box */

  /* A region in 8-bit sRGB equals the encoding of the same pixels of the full float frame. */
  {
    const int region[4] = {5, 3, 37, 29};
    const int rw = region[2] - region[0], rh = region[3] - region[1];
    unsigned char* rgba8 = malloc((size_t)rw * 4 * rh);
    float* rgba = malloc(sizeof(float) * (size_t)rw * 4 * rh);
    CHECK(par2d_render(r, rgba8, PAR2D_RGBA8_SRGB, rw * 4, 2.0, region) == PAR2D_OK);
    CHECK(par2d_render(r, rgba, PAR2D_RGBA_F32, (ptrdiff_t)sizeof(float) * rw * 4, 1.0, region) == PAR2D_OK);
    for (int j = 0; j < rh; ++j) {
      for (int i = 0; i < rw; ++i) {
        const float* full = &rgb[((j + region[1]) * W + i + region[0]) * 3];
        const float* part = &rgba[(j * rw + i) * 4];
        CHECK(memcmp(full, part, 3 * sizeof(float)) == 0 && part[3] == 1.0f);
        double v = 2.0 * full[0];
        v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
        const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
        CHECK(abs((int)rgba8[(j * rw + i) * 4] - (int)lround(255.0 * s)) <= 1);
        CHECK(rgba8[(j * rw + i) * 4 + 3] == 255);
      }
    }
    free(rgba8);
    free(rgba);
  }

  /* Errors: a concave light and a self-crossing occluder are refused with a message (an
     occluder may be concave, a light not); the world stays as it was. */
  {
    const double bent[10] = {10, 10, 30, 10, 20, 10, 30, 30, 10, 30}; /* folds back at vertex 1 */
    const double crossing[8] = {10, 10, 30, 30, 30, 10, 10, 30};
    const double grey[3] = {0.5, 0.5, 0.5};
    par2d_shape bad = occluder_shape;
    bad.vertices = bent;
    bad.vertex_count = 5;
    CHECK(par2d_update_light(r, light, &bad, grey, 1.0) == PAR2D_INVALID_SCENE);
    CHECK(strstr(par2d_last_error(), "polygon: the edges at vertex 1 fold back onto each other") != NULL);
    bad.vertices = crossing;
    bad.vertex_count = 4;
    CHECK(par2d_update_occluder(r, occluder, &bad) == PAR2D_INVALID_SCENE);
    CHECK(strstr(par2d_last_error(), "polygon: edges 0 and 2 cross") != NULL);
    /* A concave occluder is accepted under one handle, read back as given, and removed whole. */
    const double ell[12] = {40, 40, 60, 40, 60, 60, 56, 60, 56, 44, 40, 44};
    par2d_shape concave = occluder_shape;
    concave.vertices = ell;
    concave.vertex_count = 6;
    const size_t before = par2d_occluder_count(r);
    par2d_occluder corner = 0;
    CHECK(par2d_add_occluder(r, &concave, &corner) == PAR2D_OK);
    CHECK(par2d_occluder_count(r) == before + 1);
    par2d_shape got;
    memset(&got, 0, sizeof got);
    CHECK(par2d_get_occluder(r, corner, &got) == PAR2D_OK);
    CHECK(got.kind == PAR2D_SHAPE_POLYGON && got.vertex_count == 6 && got.vertices[6] == 56.0);
    CHECK(got.hole_count == 0 && got.hole_vertex_counts == NULL);
    CHECK(par2d_remove_occluder(r, corner) == PAR2D_OK);
    CHECK(par2d_occluder_count(r) == before);
    /* A square with two holes (their vertices after the outline's), and one light with a hole. */
    const double framed[20] = {40, 40, 60, 40, 60, 60, 40, 60, 42, 42, 48, 42, 48, 48, 42, 48, 52, 52, 56, 52};
    const double framed_tail[4] = {56, 56, 52, 56};
    double all[24];
    memcpy(all, framed, sizeof framed);
    memcpy(all + 20, framed_tail, sizeof framed_tail);
    const size_t holes[2] = {4, 4};
    par2d_shape holed = occluder_shape;
    holed.vertices = all;
    holed.vertex_count = 4;
    holed.hole_vertex_counts = holes;
    holed.hole_count = 2;
    par2d_occluder courtyard = 0;
    CHECK(par2d_add_occluder(r, &holed, &courtyard) == PAR2D_OK);
    memset(&got, 0, sizeof got);
    CHECK(par2d_get_occluder(r, courtyard, &got) == PAR2D_OK);
    CHECK(got.vertex_count == 4 && got.hole_count == 2 && got.hole_vertex_counts[1] == 4 && got.vertices[2 * 9] == 56.0);
    holed.hole_vertex_counts = NULL;
    CHECK_ERROR(par2d_update_occluder(r, courtyard, &holed), PAR2D_INVALID_ARGUMENT,
                "par2d_update_occluder: shape hole_vertex_counts are null");
    const size_t outside[1] = {3};
    const double poking[14] = {40, 40, 60, 40, 60, 60, 40, 60, 58, 58, 70, 58, 70, 70};
    holed.vertices = poking;
    holed.hole_vertex_counts = outside;
    holed.hole_count = 1;
    CHECK(par2d_update_occluder(r, courtyard, &holed) == PAR2D_INVALID_SCENE);
    CHECK(strstr(par2d_last_error(), "holes[0]: ") != NULL);
    CHECK(par2d_remove_occluder(r, courtyard) == PAR2D_OK);
    CHECK(par2d_remove_light(r, light + 12345) == PAR2D_INVALID_ARGUMENT);
    CHECK(par2d_render(r, NULL, PAR2D_RGB_F32, W * 12, 1.0, NULL) == PAR2D_INVALID_ARGUMENT);
    CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, 4, 1.0, NULL) == PAR2D_INVALID_ARGUMENT);
    CHECK(strstr(par2d_last_error(), "row_stride") != NULL);
    float* again = malloc(sizeof(float) * W * H * 3);
    CHECK(par2d_render(r, again, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
    CHECK(memcmp(again, rgb, sizeof(float) * W * H * 3) == 0);
    free(again);
  }

  CHECK(par2d_remove_occluder(r, occluder) == PAR2D_OK);
  CHECK(par2d_remove_occluder(r, occluder) == PAR2D_INVALID_ARGUMENT);
  CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
  CHECK(rgb[(37 * W + 20) * 3] > 0.0f); /* no longer shadowed */

  /* The lighting model's terms in the game loop: a torch with a range whose mask shares no bit
   * with a wall's, so the wall does not shadow it; nothing is lit beyond its range. */
  {
    CHECK(par2d_remove_light(r, light) == PAR2D_OK);
    par2d_shape torch = light_shape;
    torch.circle[0] = 20.0;
    torch.circle[1] = 20.0;
    CHECK(par2d_add_light(r, &torch, white, 3.0, &light) == PAR2D_OK);
    par2d_light_terms terms;
    par2d_light_terms_default(&terms);
    CHECK(terms.range == 0.0 && terms.has_cone == 0 && terms.mask == 0xFFFFFFFFu && terms.elevation == 0.0);
    terms.range = 20.0;
    terms.mask = 1u;
    CHECK(par2d_set_light_terms(r, light, &terms) == PAR2D_OK);
    par2d_light_terms back;
    CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK);
    CHECK(back.range == 20.0 && back.mask == 1u && back.has_cone == 0);
    /* Moving the torch every frame keeps its terms. */
    for (int frame = 0; frame < 3; ++frame) {
      torch.circle[1] = 20.0 + 0.5 * frame;
      CHECK(par2d_update_light(r, light, &torch, white, 3.0) == PAR2D_OK);
    }
    torch.circle[1] = 20.0;
    CHECK(par2d_update_light(r, light, &torch, white, 3.0) == PAR2D_OK);
    CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.range == 20.0 && back.mask == 1u);
    terms.range = -1.0;
    CHECK(par2d_set_light_terms(r, light, &terms) == PAR2D_INVALID_SCENE);
    CHECK(strstr(par2d_last_error(), "range: must be > 0, got -1") != NULL);
    CHECK(par2d_get_light_terms(r, light, &back) == PAR2D_OK && back.range == 20.0);

    par2d_shape wall_shape;
    memset(&wall_shape, 0, sizeof wall_shape);
    wall_shape.kind = PAR2D_SHAPE_SEGMENT;
    wall_shape.segment[0] = 30.0;
    wall_shape.segment[1] = 10.0;
    wall_shape.segment[2] = 30.0;
    wall_shape.segment[3] = 30.0;
    par2d_occluder wall = 0;
    CHECK(par2d_add_occluder(r, &wall_shape, &wall) == PAR2D_OK);
    par2d_occluder_terms wall_terms;
    par2d_occluder_terms_default(&wall_terms);
    CHECK(wall_terms.mask == 0xFFFFFFFFu && wall_terms.interior == PAR2D_INTERIOR_DARK);
    /* Default masks: the wall shadows the pixel behind it. */
    CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
    CHECK(rgb[(20 * W + 35) * 3] == 0.0f);
    wall_terms.mask = 2u;
    CHECK(par2d_set_occluder_terms(r, wall, &wall_terms) == PAR2D_OK);
    wall_terms.transmittance[0] = 1.5;
    CHECK(par2d_set_occluder_terms(r, wall, &wall_terms) == PAR2D_INVALID_SCENE);
    CHECK(strstr(par2d_last_error(), "transmittance[0]: must be between 0 and 1") != NULL);
    CHECK(par2d_get_occluder_terms(r, wall, &wall_terms) == PAR2D_OK);
    CHECK(wall_terms.mask == 2u && wall_terms.transmittance[0] == 0.0);
    CHECK(par2d_render(r, rgb, PAR2D_RGB_F32, (ptrdiff_t)(sizeof(float) * W * 3), 1.0, NULL) == PAR2D_OK);
    CHECK(rgb[(20 * W + 35) * 3] > 0.0f);        /* masks share no bit: not shadowed */
    CHECK(rgb[((H - 1) * W + 0) * 3] == 0.0f);   /* beyond the range (31.7 from the torch): exactly 0 */
    CHECK(rgb[(35 * W + 20) * 3] > 0.0f);       /* within it (13.5), in the open */

    /* Scene-wide terms are validated too. */
    const double bad_ambient[3] = {0.0, -1.0, 0.0};
    CHECK_ERROR(par2d_set_ambient(r, bad_ambient), PAR2D_INVALID_SCENE, "par2d_set_ambient: ambient[1]: must be >= 0, got -1");
    par2d_directional_light sun;
    par2d_directional_light_default(&sun);
    sun.angles[0] = 10.0;
    sun.angles[1] = 5.0;
    CHECK(par2d_set_directional_lights(r, &sun, 1) == PAR2D_INVALID_SCENE);
    CHECK(par2d_set_directional_lights(r, NULL, 0) == PAR2D_OK);
    const double up[3] = {0.0, 0.0, 1.0};
    CHECK(par2d_set_normal(r, up) == PAR2D_OK);
    float flat[3 * 2 * 2] = {0};
    CHECK(par2d_set_normal_map(r, flat, 2, 2) == PAR2D_INVALID_SCENE); /* not the frame's size */
    CHECK(par2d_clear_normal_source(r) == PAR2D_OK);
    CHECK(par2d_remove_occluder(r, wall) == PAR2D_OK);
  }

  check_errors_name_the_call(r);
  check_long_frames();

  {
    char dir[] = "/tmp/par2d_c_api_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    check_normal_map_size_is_checked_first(r, dir);
    check_scene_path_policy(r, dir);
    check_parity_with_the_cpp_renderer(dir);
    CHECK(rmdir(dir) == 0);
  }

  free(rgb);
  par2d_renderer_destroy(r);
  if (failures == 0) printf("C API: all checks passed (par2d %s)\n", par2d_version());
  return failures == 0 ? 0 : 1;
}
