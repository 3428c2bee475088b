/* par2d C API: a persistent soft-shadow renderer for game loops, through opaque handles.
 *
 * Every function that can fail returns a par2d_status; on failure par2d_last_error()
 * gives a one-line message that starts with the function's name
 * ("par2d_add_light: shape is null"), per thread, until the next failing call on that thread.
 * Nothing here allocates per frame once a renderer has rendered a frame of its size.
 * See docs/api.md for the full reference and docs/contract.md for what is computed. */
#ifndef PAR2D_PAR2D_H
#define PAR2D_PAR2D_H

#include <stddef.h>
#include <stdint.h>

/* What the shared library exports. On Windows: dllexport while par2d itself is built
 * (PAR2D_BUILDING, set by its CMake), dllimport in a program using par2d's DLL, and nothing in
 * one linking the static library (define PAR2D_STATIC; CMake's par2d target sets it). */
#if defined(_WIN32)
#if defined(PAR2D_STATIC)
#define PAR2D_C_API
#elif defined(PAR2D_BUILDING)
#define PAR2D_C_API __declspec(dllexport)
#else
#define PAR2D_C_API __declspec(dllimport)
#endif
#else
#define PAR2D_C_API __attribute__((visibility("default")))
#endif

/* The ABI these declarations describe: the shared library's SONAME is
 * libpar2d.so.PAR2D_ABI_MAJOR.PAR2D_ABI_MINOR, the library version's major.minor
 * (par2d_version_numbers at run time). Within one ABI no struct below changes its size or
 * layout, no function its signature and no constant its value. A release that must change one
 * (a struct that gains a field) moves to a new ABI, so a program built against an older one
 * does not start with it rather than hand it structs of the wrong size. Start each struct you
 * fill from its *_default function where it has one, else zero-initialize it: a field added in
 * a later ABI then holds its default when the program is rebuilt. */
#define PAR2D_ABI_MAJOR 0
#define PAR2D_ABI_MINOR 2

#ifdef __cplusplus
extern "C" {
#endif

typedef enum par2d_status {
  PAR2D_OK = 0,
  PAR2D_INVALID_ARGUMENT = 1, /* API misuse: null pointer, bad size, stride, option, handle */
  PAR2D_INVALID_SCENE = 2,    /* a shape, color or frame breaks the scene rules */
  PAR2D_IO_ERROR = 3,         /* a file could not be read */
  PAR2D_OUT_OF_MEMORY = 4,
  PAR2D_UNSUPPORTED = 5,
  PAR2D_WORK_LIMIT = 6, /* the frame's estimated work is past the work limit (par2d_set_work_limit); nothing written */
  PAR2D_CANCELLED = 7   /* the frame was cancelled (par2d_cancel, or the progress function); nothing written */
} par2d_status;

typedef enum par2d_backend {
  PAR2D_BACKEND_AUTO = 0,   /* fastest path this CPU supports */
  PAR2D_BACKEND_SIMD = 1,
  PAR2D_BACKEND_SCALAR = 2  /* the double-precision reference */
} par2d_backend;

typedef enum par2d_pixel_format {
  PAR2D_RGB_F32 = 0,    /* 3 floats per pixel: linear irradiance */
  PAR2D_RGBA_F32 = 1,   /* 4 floats: irradiance, alpha 1 */
  PAR2D_RGBA8_SRGB = 2, /* 4 bytes: sRGB of clamp(exposure * E, 0, 1), alpha 255 */
  PAR2D_BGRA8_SRGB = 3, /* the same bytes in B, G, R, A order */
  PAR2D_RGBA16F = 4,    /* 4 IEEE halves (8 bytes): E rounded to nearest even, saturating at 65504, alpha 1 */
  PAR2D_RGBA8_SRGB_DITHERED = 5, /* PAR2D_RGBA8_SRGB with an 8x8 ordered dither (docs/api.md, "Pixel formats") */
  PAR2D_BGRA8_SRGB_DITHERED = 6  /* PAR2D_BGRA8_SRGB with the same dither */
} par2d_pixel_format;

typedef enum par2d_shape_kind {
  PAR2D_SHAPE_POLYGON = 0, /* convex, either winding, >= 3 vertices; an occluder's may be concave
                              (a simple outline, opaque and dark inside; docs/contract.md section 3) */
  PAR2D_SHAPE_CIRCLE = 1,  /* a disc */
  PAR2D_SHAPE_SEGMENT = 2  /* a line segment */
} par2d_shape_kind;

/* The largest counts the C API accepts (a polygon's vertices, outline and holes together; its
 * holes, each of which needs 3 vertices; the directional lights of one
 * par2d_set_directional_lights call). Larger ones are refused with PAR2D_INVALID_ARGUMENT
 * before the arrays they size are read or anything is allocated. */
#define PAR2D_MAX_POLYGON_VERTICES 1048576
#define PAR2D_MAX_POLYGON_HOLES (PAR2D_MAX_POLYGON_VERTICES / 3)
#define PAR2D_MAX_DIRECTIONAL_LIGHTS 65536

/* A shape in world coordinates (x right, y down). Only the fields of `kind` are read. A
 * polygon may be concave (a simple outline) and have holes (docs/contract.md section 3). */
typedef struct par2d_shape {
  par2d_shape_kind kind;
  const double* vertices; /* polygon: x0, y0, x1, y1, ... of the outline, then of each hole */
  size_t vertex_count;    /* polygon: (x, y) pairs of the outline, at most PAR2D_MAX_POLYGON_VERTICES */
  double circle[3];       /* circle: center x, center y, radius (> 0) */
  double segment[4];      /* segment: ax, ay, bx, by (distinct points) */
  /* polygon: hole k's (x, y) pairs follow the outline's and the earlier holes' in `vertices`,
   * hole_vertex_counts[k] of them; hole_count (at most PAR2D_MAX_POLYGON_HOLES) 0 for none,
   * as in a zero-initialized struct. */
  const size_t* hole_vertex_counts;
  size_t hole_count;
} par2d_shape;

typedef struct par2d_options {
  par2d_backend backend; /* default PAR2D_BACKEND_AUTO */
  int threads;           /* worker threads, 0 = all hardware threads (default) */
  int spp;               /* samples per pixel, 1..256 (default 1) */
  int culling;           /* nonzero (default): skip lights proven hidden; same image */
} par2d_options;

typedef struct par2d_renderer par2d_renderer; /* opaque */
typedef uint64_t par2d_light;                 /* 0 never names a light */
typedef uint64_t par2d_occluder;              /* 0 never names an occluder */

/* Library version at run time ("0.1.0") and as numbers. */
PAR2D_C_API const char* par2d_version(void);
PAR2D_C_API void par2d_version_numbers(int* major, int* minor, int* patch);

/* The message of the last failed call on this thread ("" when none failed). */
PAR2D_C_API const char* par2d_last_error(void);

/* Fills `options` with the defaults. */
PAR2D_C_API void par2d_options_default(par2d_options* options);

/* A renderer with an empty world and its own thread pool (created here, never per frame).
 * `options` may be NULL for the defaults. */
PAR2D_C_API par2d_status par2d_renderer_create(const par2d_options* options, par2d_renderer** out);
PAR2D_C_API void par2d_renderer_destroy(par2d_renderer* renderer); /* NULL is ignored */
/* Worker threads the renderer uses. */
PAR2D_C_API int par2d_renderer_threads(const par2d_renderer* renderer);

/* The lightmap: width x height pixels showing the world rectangle view = {x0, y0, x1, y1}
 * (NULL: {0, 0, width, height}). Independent of the host's screen size. */
PAR2D_C_API par2d_status par2d_set_frame(par2d_renderer* renderer, int width, int height, const double* view);
/* Scrolling (docs/api.md, "Scrolling"): the frame shows pixels (x + i, y + j) of the pixel
 * grid of par2d_set_frame's view (that image extended past its edges) as pixel (i, j). A
 * camera that moves by whole pixels sets this; an incremental frame then shifts the pixels
 * that stay in view (par2d_frame_shift) and computes only the uncovered bands and what changed,
 * byte for byte a renderer's at that offset. par2d_set_frame starts again at (0, 0).
 * |x|, |y| <= 2^40; a refused offset keeps the old one. */
PAR2D_C_API par2d_status par2d_set_view_offset(par2d_renderer* renderer, int64_t x, int64_t y);
PAR2D_C_API par2d_status par2d_get_view_offset(const par2d_renderer* renderer, int64_t* x, int64_t* y);
/* Where whole frames go in the buffer. PAR2D_LAYOUT_IMAGE (default): pixel (i, j) at (i, j).
 * PAR2D_LAYOUT_RING: at ((x + i) mod width, (y + j) mod height), (x, y) the view offset, so a
 * scroll moves no byte (par2d_frame_shift stays 0, 0; the dirty rectangles are in the buffer's
 * coordinates, split where the ring wraps): a texture sampled with wrapping at the offset
 * shows the frame. Region renders need the image layout. */
typedef enum par2d_buffer_layout { PAR2D_LAYOUT_IMAGE = 0, PAR2D_LAYOUT_RING = 1 } par2d_buffer_layout;
PAR2D_C_API par2d_status par2d_set_buffer_layout(par2d_renderer* renderer, par2d_buffer_layout layout);

/* Replaces the world (frame included) with a scene file (docs/contract.md, section 3). A
 * refused scene leaves the world as it was. The scene's normal_map path must be relative and
 * stay inside the scene file's folder (docs/contract.md section 6): an absolute path or one
 * that leaves it is refused before anything is opened. */
PAR2D_C_API par2d_status par2d_load_scene(par2d_renderer* renderer, const char* path);

/* par2d_load_scene_ex flags; 0 is par2d_load_scene. */
#define PAR2D_LOAD_ALLOW_ANY_PATH 1u /* the scene's normal_map may be any path: trusted scenes only */

/* par2d_load_scene with `flags`, a combination of PAR2D_LOAD_* bits (others are refused with
 * PAR2D_INVALID_ARGUMENT). */
PAR2D_C_API par2d_status par2d_load_scene_ex(par2d_renderer* renderer, const char* path, unsigned flags);

/* Lights: color is linear RGB (each >= 0), emission = intensity * color. */
PAR2D_C_API par2d_status par2d_add_light(par2d_renderer* renderer, const par2d_shape* shape, const double color[3],
                                         double intensity, par2d_light* out);
PAR2D_C_API par2d_status par2d_update_light(par2d_renderer* renderer, par2d_light light, const par2d_shape* shape,
                                            const double color[3], double intensity);
PAR2D_C_API par2d_status par2d_set_light_emission(par2d_renderer* renderer, par2d_light light,
                                                  const double color[3], double intensity);
PAR2D_C_API par2d_status par2d_remove_light(par2d_renderer* renderer, par2d_light light);

PAR2D_C_API par2d_status par2d_add_occluder(par2d_renderer* renderer, const par2d_shape* shape, par2d_occluder* out);
PAR2D_C_API par2d_status par2d_update_occluder(par2d_renderer* renderer, par2d_occluder occluder,
                                               const par2d_shape* shape);
PAR2D_C_API par2d_status par2d_remove_occluder(par2d_renderer* renderer, par2d_occluder occluder);

/* A sprite's transform: a shape given in its own local frame is scaled per axis (non-zero; a
 * circle needs the same absolute scale on both), rotated by `rotation` degrees (from +x toward
 * +y: clockwise on screen; multiples of 90 are exact), then moved to `position`. The
 * *_transformed calls take the shape in that local frame; what the world holds (and
 * par2d_get_* and snapshots return) is the placed shape. A refused transform names the field
 * ("transform.scale[1]: must be non-zero, got 0") and changes nothing. */
typedef struct par2d_transform {
  double position[2];
  double rotation; /* degrees */
  double scale[2];
} par2d_transform;
PAR2D_C_API void par2d_transform_identity(par2d_transform* transform);
PAR2D_C_API par2d_status par2d_add_light_transformed(par2d_renderer* renderer, const par2d_shape* local,
                                                     const par2d_transform* transform, const double color[3],
                                                     double intensity, par2d_light* out);
PAR2D_C_API par2d_status par2d_update_light_transformed(par2d_renderer* renderer, par2d_light light,
                                                        const par2d_shape* local, const par2d_transform* transform,
                                                        const double color[3], double intensity);
PAR2D_C_API par2d_status par2d_add_occluder_transformed(par2d_renderer* renderer, const par2d_shape* local,
                                                        const par2d_transform* transform, par2d_occluder* out);
PAR2D_C_API par2d_status par2d_update_occluder_transformed(par2d_renderer* renderer, par2d_occluder occluder,
                                                           const par2d_shape* local,
                                                           const par2d_transform* transform);

/* The game lighting model (docs/contract.md section 6). Angles are in degrees; masks default
 * to 0xFFFFFFFF (an occluder acts on a light only where their masks share a bit). The light
 * and occluder functions above keep a light's or occluder's terms (par2d_add_* gives the
 * defaults); these set them. Refused values leave everything as it was. */
typedef struct par2d_light_terms {
  double range;           /* > 0; 0 (default): no range window */
  int has_cone;           /* nonzero: emit only within the cone below; 0 (default): everywhere */
  double cone_direction;  /* world direction of the cone's axis (90 points down by default) */
  double cone_half_angle; /* 0 < half_angle <= 180 */
  double cone_fade;       /* 0 <= fade <= half_angle */
  uint32_t mask;
  double elevation;       /* 0..90, default 0; used only with a normal source */
  double falloff;         /* the range window's exponent, 0..16; default 2 (start from
                             par2d_light_terms_default: a zeroed struct means 0, a hard disc) */
  double normalize;       /* > 0: reference distance at which intensity is the irradiance
                             (docs/contract.md section 6); 0 (default): intensity * color as given */
  double shadow_strength; /* 0..1, default 1: the fraction of the light an occluder removes, times
                             1 - shadow_color per channel (0: no shadows; start from
                             par2d_light_terms_default: a zeroed struct casts no shadows) */
  double shadow_color[3]; /* each 0..1, default 0: a shadow's tint (what of each channel it lets through) */
} par2d_light_terms;

typedef enum par2d_interior {
  PAR2D_INTERIOR_DARK = 0, /* default: points inside the occluder are shadowed by it */
  PAR2D_INTERIOR_LIT = 1   /* points inside are lit as if it were absent (sprites) */
} par2d_interior;

typedef struct par2d_occluder_terms {
  double transmittance[3]; /* each in [0, 1]; default 0 (opaque) */
  uint32_t mask;
  par2d_interior interior;
  double albedo[3]; /* one bounce (docs/contract.md section 7): each in [0, 1]; default 0 (reflects nothing) */
} par2d_occluder_terms;

/* A sun or sky: radiance intensity * color along ray directions in [angles[0], angles[1]]
 * (angles[0] < angles[1] < angles[0] + 360), from infinitely far away. */
typedef struct par2d_directional_light {
  double angles[2];
  double color[3];
  double intensity;
  uint32_t mask;
  double elevation; /* 0..90 */
} par2d_directional_light;

/* Fill with the defaults (no range, no cone, all mask bits, elevation 0 / opaque, dark). */
PAR2D_C_API void par2d_light_terms_default(par2d_light_terms* terms);
PAR2D_C_API void par2d_occluder_terms_default(par2d_occluder_terms* terms);
PAR2D_C_API void par2d_directional_light_default(par2d_directional_light* light);

PAR2D_C_API par2d_status par2d_get_light_terms(par2d_renderer* renderer, par2d_light light, par2d_light_terms* out);
PAR2D_C_API par2d_status par2d_set_light_terms(par2d_renderer* renderer, par2d_light light,
                                               const par2d_light_terms* terms);
/* A light's cookie, its angular emission profile (docs/contract.md section 6): light emitted in
 * world direction psi is weighted by the periodic piecewise-linear function through the knots
 * (directions[k] degrees, weights[k] in [0, 1]) at psi - rotation. 1 to 32 knots, directions
 * strictly increasing and spanning less than 360 degrees; count 0 removes the cookie (the
 * arrays may then be null). A light has a cone or a cookie, not both. Refused values leave the
 * light as it was. */
PAR2D_C_API par2d_status par2d_set_light_cookie(par2d_renderer* renderer, par2d_light light, double rotation,
                                                const double* directions, const double* weights, size_t count);
/* The light's cookie: *count knots (0: none), the first `capacity` of them written to
 * directions and weights (null only with capacity 0), and its rotation (may be null). */
PAR2D_C_API par2d_status par2d_get_light_cookie(par2d_renderer* renderer, par2d_light light, double* rotation,
                                                double* directions, double* weights, size_t capacity, size_t* count);
PAR2D_C_API par2d_status par2d_get_occluder_terms(par2d_renderer* renderer, par2d_occluder occluder,
                                                  par2d_occluder_terms* out);
PAR2D_C_API par2d_status par2d_set_occluder_terms(par2d_renderer* renderer, par2d_occluder occluder,
                                                  const par2d_occluder_terms* terms);

/* Scene-wide terms: ambient RGB (each >= 0) added to every pixel; the directional lights
 * (replacing any before; count 0 removes them). */
PAR2D_C_API par2d_status par2d_set_ambient(par2d_renderer* renderer, const double ambient[3]);
/* One bounce's piece length in world units (> 0, default 4; docs/contract.md section 7).
 * Refused where the reflecting occluders would be cut into more than 1048576 pieces, as is an
 * occluder added or changed past that limit. */
PAR2D_C_API par2d_status par2d_set_bounce(par2d_renderer* renderer, double piece);
PAR2D_C_API par2d_status par2d_get_bounce(const par2d_renderer* renderer, double* piece);
/* The coarse bounce's step in pixels (1 .. 64, default 1: every pixel exact; docs/contract.md
 * section 7, "Coarse bounce"): the bounce computed at every step-th pixel of the grid and
 * interpolated between, never across an occluder. The piece length is kept. */
PAR2D_C_API par2d_status par2d_set_bounce_step(par2d_renderer* renderer, int step);
PAR2D_C_API par2d_status par2d_get_bounce_step(const par2d_renderer* renderer, int* step);
PAR2D_C_API par2d_status par2d_set_directional_lights(par2d_renderer* renderer, const par2d_directional_light* lights,
                                                      size_t count);
/* Normal source for 2.5D shading (one at a time; each replaces the other):
 * one normal {nx, ny, nz} in world axes (+z toward the viewer, any non-zero length);
 * a map of width x height normals (exactly the frame's size), 3 floats per pixel, rows from
 * the top, in image axes (x right, y UP, z toward the viewer);
 * or an 8-bit RGB PNG normal map (n = 2 * rgb / 255 - 1, alpha ignored), whose size is checked
 * against the frame's from the PNG header before a pixel is decoded (before the first
 * par2d_set_frame: any size up to 16384 per side). */
PAR2D_C_API par2d_status par2d_set_normal(par2d_renderer* renderer, const double normal[3]);
PAR2D_C_API par2d_status par2d_set_normal_map(par2d_renderer* renderer, const float* normals, int width, int height);
PAR2D_C_API par2d_status par2d_load_normal_map(par2d_renderer* renderer, const char* png_path);
PAR2D_C_API par2d_status par2d_clear_normal_source(par2d_renderer* renderer);

/* ---- Options beyond par2d_options, the frame, the world's contents and what was done ---- */

/* The renderer's options as last set (par2d_renderer_create or par2d_set_options). */
PAR2D_C_API par2d_status par2d_get_options(const par2d_renderer* renderer, par2d_options* out);
/* Replaces backend, threads, spp and culling; the advanced options below stay. A refused value
 * (spp 0, negative threads, an unknown backend) keeps the options as they were. Recreates the
 * thread pool here, never per frame. */
PAR2D_C_API par2d_status par2d_set_options(par2d_renderer* renderer, const par2d_options* options);

/* SIMD instruction-set levels. PAR2D_ISA_DEFAULT: the PAR2D_ISA environment variable if set,
 * else the best the CPU has. A level the CPU lacks falls back to the best it has. */
typedef enum par2d_isa {
  PAR2D_ISA_DEFAULT = -1,
  PAR2D_ISA_SCALAR = 0, /* the double-precision reference */
  PAR2D_ISA_SSE4_2 = 1,
  PAR2D_ISA_AVX2 = 2,
  PAR2D_ISA_AVX512 = 3,
  PAR2D_ISA_NEON64 = 4
} par2d_isa;

/* Where a frame's parallel work runs. */
typedef enum par2d_threading {
  PAR2D_THREADING_OWN_POOL = 0,    /* default: the renderer's pool of par2d_options.threads workers */
  PAR2D_THREADING_CALLER_ARENA = 1 /* the TBB arena par2d_render is called from (a C++ host calling it
                                      inside tbb::task_arena::execute); threads is ignored. A par2d
                                      built without TBB refuses it: PAR2D_INVALID_ARGUMENT */
} par2d_threading;

/* Which terms of a scene with one bounce a frame outputs (docs/contract.md section 7). */
typedef enum par2d_bounce_term {
  PAR2D_BOUNCE_INCLUDED = 0, /* default: direct light plus the bounce */
  PAR2D_BOUNCE_EXCLUDED = 1, /* the direct light alone (the ambient term included) */
  PAR2D_BOUNCE_ONLY = 2      /* the bounce term alone */
} par2d_bounce_term;

/* The options par2d_options lacks (they came later, so they have their own struct). */
typedef struct par2d_advanced_options {
  par2d_isa isa;             /* cap on the SIMD level; default PAR2D_ISA_DEFAULT */
  par2d_threading threading; /* default PAR2D_THREADING_OWN_POOL */
  int shaded;                /* nonzero (default): the normal-shaded value when there is a normal
                                source; 0: the plain irradiance */
  int sample_needs;          /* nonzero: also measure what pixels need (par2d_frame_diagnostics'
                                sampled_* fields; about one scalar pixel per 16x16 tile); default 0 */
  par2d_bounce_term bounce;  /* default PAR2D_BOUNCE_INCLUDED */
} par2d_advanced_options;

PAR2D_C_API void par2d_advanced_options_default(par2d_advanced_options* options);
PAR2D_C_API par2d_status par2d_get_advanced_options(const par2d_renderer* renderer, par2d_advanced_options* out);
/* A refused value keeps every option as it was. */
PAR2D_C_API par2d_status par2d_set_advanced_options(par2d_renderer* renderer, const par2d_advanced_options* options);
/* The level the renderer's SIMD path runs at on this CPU with its options (PAR2D_ISA_SCALAR for
 * the scalar backend or a NULL renderer); the best level this CPU has; "scalar", "sse4",
 * "avx2", "avx512", "neon64" ("" for a value that is no level). */
PAR2D_C_API par2d_isa par2d_renderer_isa(const par2d_renderer* renderer);
PAR2D_C_API par2d_isa par2d_detect_isa(void);
PAR2D_C_API const char* par2d_isa_name(par2d_isa isa);

/* Bytes one pixel of `format` takes (12, 16, 4, 4, 8, 4, 4; 0 for a value that is no format). */
PAR2D_C_API int par2d_bytes_per_pixel(par2d_pixel_format format);

/* The frame as last set: width, height and the view it shows {x0, y0, x1, y1} (par2d_set_frame's
 * moved by the view offset); any pointer may be NULL.
 * 0 x 0 before the first par2d_set_frame or scene. */
PAR2D_C_API par2d_status par2d_get_frame(const par2d_renderer* renderer, int* width, int* height, double view[4]);

/* How many lights and occluders the world holds (0 for a NULL renderer). */
PAR2D_C_API size_t par2d_light_count(const par2d_renderer* renderer);
PAR2D_C_API size_t par2d_occluder_count(const par2d_renderer* renderer);
/* The handles of the world's lights (occluders): a loaded scene's in the scene file's order,
 * then those added since, in the order they were added (removed ones left out). Writes the
 * first min(capacity, count) into `out` (NULL when capacity is 0) and the total into *count,
 * so a call with capacity 0 asks for the size. */
PAR2D_C_API par2d_status par2d_get_light_handles(const par2d_renderer* renderer, par2d_light* out, size_t capacity,
                                                 size_t* count);
PAR2D_C_API par2d_status par2d_get_occluder_handles(const par2d_renderer* renderer, par2d_occluder* out,
                                                    size_t capacity, size_t* count);

/* The light (occluder) a handle names, as last given: its shape, color and intensity (any
 * output may be NULL; the terms come from par2d_get_light_terms). A polygon's
 * shape->vertices point into memory the renderer owns, valid until the next par2d_get_light
 * or par2d_get_occluder on it or its destruction. An unknown handle is refused and the
 * outputs are left as they were. */
PAR2D_C_API par2d_status par2d_get_light(par2d_renderer* renderer, par2d_light light, par2d_shape* shape,
                                         double color[3], double* intensity);
PAR2D_C_API par2d_status par2d_get_occluder(par2d_renderer* renderer, par2d_occluder occluder, par2d_shape* shape);

/* The scene-wide terms as last set: ambient; the directional lights (the first
 * min(capacity, count) into `out`, the total into *count); the normal source. */
PAR2D_C_API par2d_status par2d_get_ambient(const par2d_renderer* renderer, double ambient[3]);
PAR2D_C_API par2d_status par2d_get_directional_lights(const par2d_renderer* renderer, par2d_directional_light* out,
                                                      size_t capacity, size_t* count);
typedef enum par2d_normal_source {
  PAR2D_NORMAL_NONE = 0,     /* plain irradiance */
  PAR2D_NORMAL_CONSTANT = 1, /* one normal for every pixel */
  PAR2D_NORMAL_MAP = 2       /* a normal per pixel */
} par2d_normal_source;
/* Which normal source is set; with PAR2D_NORMAL_CONSTANT, `normal` (may be NULL) receives it. */
PAR2D_C_API par2d_status par2d_get_normal_source(const par2d_renderer* renderer, par2d_normal_source* kind,
                                                 double normal[3]);

/* The world as a scene file (docs/contract.md section 3): lights that emit first, then dark
 * ones, then occluders; rendering it gives the same image. par2d_save_scene writes it to `path`
 * atomically (a normal map is written as the path it was loaded from; one given as floats
 * cannot be saved). par2d_snapshot_json copies the JSON text, NUL-terminated, into `out` when
 * it fits in `capacity` bytes and always sets *length to its length without the NUL (so a
 * call with capacity 0 asks for the size); text that does not fit is refused with
 * PAR2D_INVALID_ARGUMENT and nothing is written. */
PAR2D_C_API par2d_status par2d_save_scene(const par2d_renderer* renderer, const char* path);
PAR2D_C_API par2d_status par2d_snapshot_json(const par2d_renderer* renderer, char* out, size_t capacity,
                                             size_t* length);

/* What the renderer has done so far (docs/api.md, RendererStats). */
typedef struct par2d_stats {
  uint64_t frames;             /* successful par2d_render calls */
  uint64_t index_builds;       /* occluder index built from scratch */
  uint64_t index_updates;      /* occluder index updated in place */
  uint64_t reach_computations; /* per-light reach proofs run */
  uint64_t full_prepares;      /* whole world re-prepared */
} par2d_stats;
PAR2D_C_API par2d_status par2d_get_stats(const par2d_renderer* renderer, par2d_stats* out);

/* What the last successful par2d_render computed (all zero before one; docs/api.md, FrameStats):
 * pixels and 16x16 tiles (an incremental frame: its changed blocks only); the light-layer
 * cache's (tile, light) shares added from stored layers and computed to be stored; one
 * bounce's pieces and reflecting occluders with a lit piece (zero without reflecting occluders
 * or with PAR2D_BOUNCE_EXCLUDED). */
typedef struct par2d_frame_stats {
  uint64_t pixels, tiles;
  uint64_t layer_tiles_reused, layer_tiles_filled;
  uint64_t bounce_pieces, bounce_lit_sources;
} par2d_frame_stats;
PAR2D_C_API par2d_status par2d_get_frame_stats(const par2d_renderer* renderer, par2d_frame_stats* out);
/* What the last successful par2d_render's culling and kernel did (all zero before one): the
 * fields of docs/api.md's FrameDiagnostics table, totals over the frame. They follow the
 * algorithm, so a later ABI may change them. */
typedef struct par2d_frame_diagnostics {
  uint64_t samples;
  uint64_t blocks, block_lights, block_lights_out_of_reach, block_candidates;
  uint64_t block_proofs_tried, block_proofs_succeeded, block_proofs_skipped;
  uint64_t tile_lights, tile_pairs, tile_general_pairs;
  uint64_t tile_proofs_tried, tile_proofs_succeeded, tile_proofs_skipped;
  uint64_t umbra_tests, umbra_hits, tile_pairs_outside_hull;
  uint64_t light_samples, pair_samples, scalar_tiles;
  /* Only with par2d_advanced_options.sample_needs (else 0): at each tile's middle pixel, by
   * exact double geometry, the lights visible there and the occluders cutting into their arcs. */
  uint64_t sampled_pixels, sampled_visible_lights, sampled_blocking_pairs;
  /* One bounce: (tile, lit reflector) pairs and those proofs hid, (sample, reflector) walks
   * and the occluders depth-tested in them. */
  uint64_t bounce_tile_sources, bounce_tile_sources_hidden;
  uint64_t bounce_source_walks, bounce_depth_tests;
} par2d_frame_diagnostics;
PAR2D_C_API par2d_status par2d_get_frame_diagnostics(const par2d_renderer* renderer, par2d_frame_diagnostics* out);

/* Renders region = {x0, y0, x1, y1} (pixels [x0, x1) x [y0, y1); NULL: the whole frame)
 * into `pixels`, whose first byte is the region's top-left pixel, rows `row_stride` bytes
 * apart. `exposure` (finite, >= 0) is used by the 8-bit formats only. A region's pixels are
 * bit-identical to the same pixels of a whole frame. */
PAR2D_C_API par2d_status par2d_render(par2d_renderer* renderer, void* pixels, par2d_pixel_format format,
                                      ptrdiff_t row_stride, double exposure, const int* region);

/* Incremental frames (docs/api.md, "Incremental frames"). Off by default. With `on` non-zero,
 * a whole-frame par2d_render computes only the 64x64 blocks whose inputs changed since the
 * last whole frame and leaves the buffer's other pixels as they are (so the buffer must hold
 * that frame; a new pointer, format, row stride or exposure computes the whole frame); the
 * pixels equal a full render's byte for byte. par2d_force_full_frame makes the next whole
 * frame compute every pixel. */
PAR2D_C_API par2d_status par2d_set_incremental(par2d_renderer* renderer, int on);
PAR2D_C_API par2d_status par2d_force_full_frame(par2d_renderer* renderer);
/* The light-layer cache (docs/api.md, "Light-layer cache"): with a budget above 0 bytes and
 * incremental frames on, each light's share of each 64x64 block is kept before its emission is
 * applied, so a frame where lights only change intensity or colour recombines their blocks.
 * Pixels are then within 1e-6 x the brightest emission of a full render (no longer byte for
 * byte); at most `bytes` are held. 0 (the default) turns it off and frees it. The next whole
 * frame is computed whole either way. */
PAR2D_C_API par2d_status par2d_set_light_layer_budget(par2d_renderer* renderer, size_t bytes);
/* The budget as set, and the bytes the layers hold after the last frame (0 for a NULL renderer). */
PAR2D_C_API size_t par2d_light_layer_budget(const par2d_renderer* renderer);
PAR2D_C_API size_t par2d_light_layer_bytes(const par2d_renderer* renderer);

/* Pixel columns [x0, x1) and rows [y0, y1). */
typedef struct par2d_rect {
  int x0, y0, x1, y1;
} par2d_rect;
/* The rectangles the last successful par2d_render wrote (merged block runs, then a scroll's
 * uncovered bands; none when an incremental frame changed nothing): the parts of the buffer
 * to upload, after the shift below. Copies min(count, capacity) of them into `out` (NULL
 * allowed with capacity 0) and sets *count to how many there are. */
PAR2D_C_API par2d_status par2d_dirty_rects(const par2d_renderer* renderer, par2d_rect* out, size_t capacity,
                                           size_t* count);
/* How far the last successful par2d_render moved the buffer's pixels before writing the dirty
 * rectangles: pixel (i, j) now holds what pixel (i + dx, j + dy) held (0, 0 but for an
 * incremental frame whose view offset moved). A host whose texture holds the last frame moves
 * its pixels the same way (or uploads the whole buffer), then uploads the rectangles. */
PAR2D_C_API par2d_status par2d_frame_shift(const par2d_renderer* renderer, int* dx, int* dy);

/* ---- Long frames (docs/api.md, "Long renders"): bound, watch and stop them ---- */

/* A frame's work estimated from counts before it runs, in units of one shape or bounce piece
 * looked at for one sample (or ray), 10 to 100 nanoseconds of one core each.
 * samples = pixels computed x spp (an incremental frame: its changed blocks' pixels); lights
 * counts the directional lights too. The SIMD path's direct light is not counted (its culling
 * keeps it near what pixels need); the bounce is counted before culling. */
typedef struct par2d_work_estimate {
  double samples;
  double bounce;  /* one bounce: pieces x (samples + lights x (occluders + 1)) */
  double scalar;  /* the scalar reference's direct light: samples x lights x (occluders + 1) */
  double raycast; /* always 0 here (the ray caster is not a renderer backend) */
  double total;   /* bounce + scalar + raycast: what the work limit bounds */
} par2d_work_estimate;

/* The work limit every renderer starts with: 1e11 units (a quarter of an hour to two and a half
 * hours of one core). */
#define PAR2D_DEFAULT_WORK_LIMIT 1e11

/* The estimated work of a frame of region = {x0, y0, x1, y1} (NULL: the whole frame) with the
 * renderer's options and world of now, as par2d_render checks it. */
PAR2D_C_API par2d_status par2d_estimate_work(par2d_renderer* renderer, const int* region, par2d_work_estimate* out);
/* The most estimated work (par2d_work_estimate.total) a frame may have: a frame past it is
 * refused with PAR2D_WORK_LIMIT before any pixel is computed. Finite and >= 0; 0: no limit.
 * Default PAR2D_DEFAULT_WORK_LIMIT. Kept by par2d_set_options and par2d_set_advanced_options. */
PAR2D_C_API par2d_status par2d_set_work_limit(par2d_renderer* renderer, double limit);
PAR2D_C_API par2d_status par2d_get_work_limit(const par2d_renderer* renderer, double* limit);

/* Called during each par2d_render from the thread that called it (never from two threads at
 * once), after tiles of 16x16 pixels finish: tiles_done rises with each call, and a frame that
 * completes ends with a call where tiles_done == tiles. Return non-zero to go on, 0 to cancel
 * the frame. */
typedef int (*par2d_progress_fn)(void* user, uint64_t tiles_done, uint64_t tiles);
/* Sets the progress function (NULL: none, the default); `user` is passed back to it. */
PAR2D_C_API par2d_status par2d_set_progress(par2d_renderer* renderer, par2d_progress_fn fn, void* user);
/* Cancels the par2d_render running now on the renderer, or else the next one: it returns
 * PAR2D_CANCELLED with the pixels untouched, and the request is used up (also by a frame that
 * completes before it sees it). Safe from any thread at any time. A frame stops before its
 * next tile when it is computed in the renderer's own buffer and copied out once complete:
 * when a progress function is set or its estimated work is above 0 (a bounce, the scalar
 * reference); other frames (the SIMD path's direct light alone) see the request only before
 * they start. NULL is ignored. */
PAR2D_C_API void par2d_cancel(par2d_renderer* renderer);

/* ---- Occluders from an alpha mask (docs/api.md, "Occluders from an alpha mask") ---- */

/* The polygons par2d_outline_alpha traced: opaque, owned by the caller until destroyed. */
typedef struct par2d_outline par2d_outline;
/* Traces the solid pixels (alpha >= threshold, 0 .. 255) of a width x height alpha plane, the
 * alpha of pixel (i, j) at alpha[j * row_stride + i * pixel_stride] (an RGBA8 image: pixel
 * stride 4, alpha pointing at its fourth byte), into polygons with holes: one per 8-connected
 * group of solid pixels, within `tolerance` pixels (>= 0) of the pixels' boundary, none
 * crossing or touching another, each valid as an occluder, at most `max_vertices` (3 .. 65536)
 * vertices each (a polygon that needs more is refused naming it). `placement` = {scale x,
 * scale y, offset x, offset y} puts pixel-unit point p at offset + scale * p (NULL: {1, 1, 0,
 * 0}). On success *out holds the result; on failure *out is NULL. */
PAR2D_C_API par2d_status par2d_outline_alpha(const uint8_t* alpha, int width, int height, ptrdiff_t row_stride,
                                             int pixel_stride, int threshold, double tolerance, size_t max_vertices,
                                             const double* placement, par2d_outline** out);
/* How many polygons it holds (0 for NULL). */
PAR2D_C_API size_t par2d_outline_polygon_count(const par2d_outline* outline);
/* Polygon `index` as a shape for par2d_add_occluder: its arrays belong to `outline` and stay
 * valid until par2d_outline_destroy. */
PAR2D_C_API par2d_status par2d_outline_polygon(const par2d_outline* outline, size_t index, par2d_shape* shape);
/* Frees it; NULL is ignored. */
PAR2D_C_API void par2d_outline_destroy(par2d_outline* outline);

#ifdef __cplusplus
}
#endif

#endif /* PAR2D_PAR2D_H */
