-- par2d through LuaJIT's FFI: the part of include/par2d/par2d.h this example calls, declared
-- as the header has it (check_love.py holds every declaration below to the header), and a
-- thin layer that turns a failed call into a Lua error carrying par2d_last_error().
local ffi = require("ffi")

ffi.cdef[[
typedef enum par2d_status {
  PAR2D_OK = 0,
  PAR2D_INVALID_ARGUMENT = 1,
  PAR2D_INVALID_SCENE = 2,
  PAR2D_IO_ERROR = 3,
  PAR2D_OUT_OF_MEMORY = 4,
  PAR2D_UNSUPPORTED = 5,
  PAR2D_WORK_LIMIT = 6,
  PAR2D_CANCELLED = 7
} par2d_status;
typedef enum par2d_backend {
  PAR2D_BACKEND_AUTO = 0,
  PAR2D_BACKEND_SIMD = 1,
  PAR2D_BACKEND_SCALAR = 2
} par2d_backend;
typedef enum par2d_pixel_format {
  PAR2D_RGB_F32 = 0,
  PAR2D_RGBA_F32 = 1,
  PAR2D_RGBA8_SRGB = 2,
  PAR2D_BGRA8_SRGB = 3,
  PAR2D_RGBA16F = 4,
  PAR2D_RGBA8_SRGB_DITHERED = 5,
  PAR2D_BGRA8_SRGB_DITHERED = 6
} par2d_pixel_format;
typedef enum par2d_shape_kind {
  PAR2D_SHAPE_POLYGON = 0,
  PAR2D_SHAPE_CIRCLE = 1,
  PAR2D_SHAPE_SEGMENT = 2
} par2d_shape_kind;
typedef struct par2d_shape {
  par2d_shape_kind kind;
  const double* vertices;
  size_t vertex_count;
  double circle[3];
  double segment[4];
  const size_t* hole_vertex_counts;
  size_t hole_count;
} par2d_shape;
typedef struct par2d_options {
  par2d_backend backend;
  int threads;
  int spp;
  int culling;
} par2d_options;
typedef struct par2d_renderer par2d_renderer;
typedef uint64_t par2d_light;
typedef uint64_t par2d_occluder;
const char* par2d_version(void);
void par2d_version_numbers(int* major, int* minor, int* patch);
const char* par2d_last_error(void);
par2d_status par2d_renderer_create(const par2d_options* options, par2d_renderer** out);
void par2d_renderer_destroy(par2d_renderer* renderer);
par2d_status par2d_set_frame(par2d_renderer* renderer, int width, int height, const double* view);
par2d_status par2d_add_light(par2d_renderer* renderer, const par2d_shape* shape, const double color[3],
    double intensity, par2d_light* out);
par2d_status par2d_update_light(par2d_renderer* renderer, par2d_light light, const par2d_shape* shape,
    const double color[3], double intensity);
par2d_status par2d_add_occluder(par2d_renderer* renderer, const par2d_shape* shape, par2d_occluder* out);
typedef struct par2d_light_terms {
  double range;
  int has_cone;
  double cone_direction;
  double cone_half_angle;
  double cone_fade;
  uint32_t mask;
  double elevation;
  double falloff;
  double normalize;
  double shadow_strength;
  double shadow_color[3];
} par2d_light_terms;
typedef enum par2d_interior {
  PAR2D_INTERIOR_DARK = 0,
  PAR2D_INTERIOR_LIT = 1
} par2d_interior;
typedef struct par2d_occluder_terms {
  double transmittance[3];
  uint32_t mask;
  par2d_interior interior;
  double albedo[3];
} par2d_occluder_terms;
void par2d_light_terms_default(par2d_light_terms* terms);
void par2d_occluder_terms_default(par2d_occluder_terms* terms);
par2d_status par2d_set_light_terms(par2d_renderer* renderer, par2d_light light,
    const par2d_light_terms* terms);
par2d_status par2d_set_occluder_terms(par2d_renderer* renderer, par2d_occluder occluder,
    const par2d_occluder_terms* terms);
par2d_status par2d_set_ambient(par2d_renderer* renderer, const double ambient[3]);
par2d_status par2d_save_scene(const par2d_renderer* renderer, const char* path);
par2d_status par2d_render(par2d_renderer* renderer, void* pixels, par2d_pixel_format format,
    ptrdiff_t row_stride, double exposure, const int* region);
par2d_status par2d_set_incremental(par2d_renderer* renderer, int on);
typedef struct par2d_rect {
  int x0, y0, x1, y1;
} par2d_rect;
par2d_status par2d_dirty_rects(const par2d_renderer* renderer, par2d_rect* out, size_t capacity,
    size_t* count);
]]

local M = {}

-- The ABI the declarations above describe (par2d.h's PAR2D_ABI_MAJOR.PAR2D_ABI_MINOR): within
-- one ABI no struct or signature changes, so a library of another one is refused at load.
local ABI_MAJOR, ABI_MINOR = 0, 2

-- Loads libpar2d: `path` if given (as the test passes its build's), else the PAR2D_LIBRARY
-- environment variable, else the system's libpar2d.so.
function M.load(path)
  path = path or os.getenv("PAR2D_LIBRARY") or "par2d"
  local ok, lib = pcall(ffi.load, path)
  if not ok then error("par2d.lua: cannot load " .. path .. ": " .. tostring(lib), 0) end
  local v = ffi.new("int[3]")
  lib.par2d_version_numbers(v, v + 1, v + 2)
  if v[0] ~= ABI_MAJOR or v[1] ~= ABI_MINOR then
    error(string.format("par2d.lua: %s is par2d %d.%d.%d; these declarations are ABI %d.%d", path, v[0], v[1],
                        v[2], ABI_MAJOR, ABI_MINOR), 0)
  end
  M.C = lib
  return M
end

-- A failed call raises the library's message, which starts with the function's name.
local function check(status)
  if status ~= M.C.PAR2D_OK then error(ffi.string(M.C.par2d_last_error()), 0) end
end
M.check = check

function M.circle(x, y, radius)
  local s = ffi.new("par2d_shape")
  s.kind = M.C.PAR2D_SHAPE_CIRCLE
  s.circle[0], s.circle[1], s.circle[2] = x, y, radius
  return s
end

-- A shape's vertex array, kept alive as long as the shape (a cdata pointer field does not keep
-- what it points to from the garbage collector).
local anchors = setmetatable({}, {__mode = "k"})

-- An axis-aligned box as a polygon shape.
function M.box(x0, y0, x1, y1)
  local v = ffi.new("double[8]", x0, y0, x1, y0, x1, y1, x0, y1)
  local s = ffi.new("par2d_shape")
  s.kind = M.C.PAR2D_SHAPE_POLYGON
  s.vertices, s.vertex_count = v, 4
  anchors[s] = v
  return s
end

local Renderer = {}
Renderer.__index = Renderer

-- A renderer with its own thread pool (all hardware threads), destroyed with the Lua object.
function M.new_renderer()
  local out = ffi.new("par2d_renderer*[1]")
  check(M.C.par2d_renderer_create(nil, out))
  return setmetatable({ptr = ffi.gc(out[0], M.C.par2d_renderer_destroy), rect_capacity = 64,
                       rects = ffi.new("par2d_rect[?]", 64), count = ffi.new("size_t[1]"),
                       rgb = ffi.new("double[3]")}, Renderer)
end

function Renderer:set_frame(width, height) check(M.C.par2d_set_frame(self.ptr, width, height, nil)) end
function Renderer:set_incremental(on) check(M.C.par2d_set_incremental(self.ptr, on and 1 or 0)) end
function Renderer:set_ambient(r, g, b) check(M.C.par2d_set_ambient(self.ptr, ffi.new("double[3]", r, g, b))) end
function Renderer:save_scene(path) check(M.C.par2d_save_scene(self.ptr, path)) end

function Renderer:color(rgb)
  self.rgb[0], self.rgb[1], self.rgb[2] = rgb[1], rgb[2], rgb[3]
  return self.rgb
end

-- A light with a range: a game torch, whose light ends `range` units from its shape, so that
-- moving it changes only the blocks around its old and new place.
function Renderer:add_light(shape, rgb, intensity, range)
  local out = ffi.new("par2d_light[1]")
  check(M.C.par2d_add_light(self.ptr, shape, self:color(rgb), intensity, out))
  local terms = ffi.new("par2d_light_terms")
  M.C.par2d_light_terms_default(terms)
  terms.range = range
  check(M.C.par2d_set_light_terms(self.ptr, out[0], terms))
  return out[0]
end

-- Moves or recolours a light; its terms (the range) stay.
function Renderer:update_light(light, shape, rgb, intensity)
  check(M.C.par2d_update_light(self.ptr, light, shape, self:color(rgb), intensity))
end

-- interior "lit": the sprite's own pixels are lit as if it were absent; it still casts shadows.
function Renderer:add_occluder(shape, interior)
  local out = ffi.new("par2d_occluder[1]")
  check(M.C.par2d_add_occluder(self.ptr, shape, out))
  if interior == "lit" then
    local terms = ffi.new("par2d_occluder_terms")
    M.C.par2d_occluder_terms_default(terms)
    terms.interior = M.C.PAR2D_INTERIOR_LIT
    check(M.C.par2d_set_occluder_terms(self.ptr, out[0], terms))
  end
  return out[0]
end

-- Renders the whole frame as sRGB bytes in R, G, B, A order into `pixels`, rows `row_stride`
-- bytes apart; with incremental frames on, only the blocks whose inputs changed.
function Renderer:render_rgba8(pixels, row_stride, exposure)
  check(M.C.par2d_render(self.ptr, pixels, M.C.PAR2D_RGBA8_SRGB, row_stride, exposure, nil))
end

-- The rectangles the last render wrote, as an iterator of x0, y0, x1, y1 (pixels [x0, x1) x
-- [y0, y1)); the array they are copied into grows when a frame has more than it holds.
function Renderer:dirty_rects()
  check(M.C.par2d_dirty_rects(self.ptr, self.rects, self.rect_capacity, self.count))
  local n = tonumber(self.count[0])
  if n > self.rect_capacity then
    self.rect_capacity = n
    self.rects = ffi.new("par2d_rect[?]", n)
    check(M.C.par2d_dirty_rects(self.ptr, self.rects, self.rect_capacity, self.count))
  end
  local i = -1
  return function()
    i = i + 1
    if i < n then
      local r = self.rects[i]
      return r.x0, r.y0, r.x1, r.y1
    end
  end
end

return M
