-- LÖVE 11 example: par2d lights a sprite scene through LuaJIT's FFI (par2d.lua). Each frame
-- three torches move, par2d renders the lightmap as sRGB bytes straight into an ImageData's
-- memory (incremental frames: only the blocks whose inputs changed), only the rectangles it
-- wrote are uploaded into the lightmap Image, and the Image is drawn over the sprites with the
-- "multiply" blend mode: screen = sprite x light, the light's exposure applied by par2d.
--
-- Run: love examples/love [--library PATH] [--frames N --screenshot OUT.ppm --sprites OUT.ppm
--      --scene OUT.json]
-- --library names libpar2d (default: $PAR2D_LIBRARY, else the system's libpar2d.so). With
-- --frames it stops after N frames and saves the last one as shown (--screenshot), its sprite
-- layer alone (--sprites) and the world as a scene file (--scene); check_love.py compares the
-- screenshot with `par2d render` of that scene multiplied over those sprites.
local ffi = require("ffi")
local par2d = require("par2d")

local W, H = 640, 360
local EXPOSURE = 1.5

local options = {}
local renderer, torches, crates, pillars, wall
local light_data, light_image -- par2d's buffer (an ImageData) and its texture
local scratch = {}            -- one ImageData per dirty-rectangle size, reused
local floor_image, crate_image
local frame, time, uploaded = 0, 0.0, 0

-- An error stops the program with one line on stderr and exit status 1 (no error screen:
-- the test runs it unattended).
function love.errorhandler(message)
  io.stderr:write("par2d love example: " .. tostring(message) .. "\n")
  return nil
end

local function parse_arguments(args)
  local i = 1
  while i <= #args do
    local name, value = args[i], args[i + 1]
    local key = ({["--library"] = "library", ["--frames"] = "frames", ["--screenshot"] = "screenshot",
                  ["--sprites"] = "sprites", ["--scene"] = "scene"})[name]
    if not key then error("unknown argument " .. tostring(name) .. " (see the top of main.lua)", 0) end
    if value == nil then error(name .. " needs a value", 0) end
    options[key] = value
    i = i + 2
  end
  if options.frames then
    options.frames = tonumber(options.frames)
    if not options.frames or options.frames < 1 or options.frames % 1 ~= 0 then
      error("--frames must be a whole number >= 1", 0)
    end
  end
end

-- Binary PPM (P6) of an RGBA8 ImageData, top row first, written whole or not at all.
local function write_ppm(path, image)
  local w, h = image:getDimensions()
  local src = ffi.cast("const uint8_t*", image:getFFIPointer())
  local rgb = ffi.new("uint8_t[?]", w * h * 3)
  for i = 0, w * h - 1 do
    rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2] = src[4 * i], src[4 * i + 1], src[4 * i + 2]
  end
  local f, err = io.open(path .. ".part", "wb")
  if not f then error("cannot write " .. path .. ": " .. err, 0) end
  local ok = f:write(string.format("P6\n%d %d\n255\n", w, h)) and f:write(ffi.string(rgb, w * h * 3))
  if not f:close() or not ok or not os.rename(path .. ".part", path) then
    os.remove(path .. ".part")
    error("cannot write " .. path, 0)
  end
end

-- The floor: stone tiles with mortar lines and a tint per tile (sRGB bytes, as drawn).
local function make_floor()
  local data = love.image.newImageData(W, H, "rgba8")
  data:mapPixel(function(x, y)
    if x % 32 == 0 or y % 32 == 0 then return 90 / 255, 85 / 255, 80 / 255, 1 end
    local tint = (math.floor(x / 32) * 37 + math.floor(y / 32) * 91) % 40
    return (170 + tint) / 255, (160 + math.floor(tint / 2)) / 255, 140 / 255, 1
  end)
  return love.graphics.newImage(data)
end

-- A 40x40 wooden crate: a dark frame, planks and a diagonal brace.
local function make_crate()
  local data = love.image.newImageData(40, 40, "rgba8")
  data:mapPixel(function(x, y)
    if x < 3 or y < 3 or x > 36 or y > 36 or math.abs(x - y) < 3 then return 110 / 255, 70 / 255, 35 / 255, 1 end
    local seam = y % 9 == 0 and 0.8 or 1.0
    return seam * (190 + (x * 7) % 20) / 255, seam * 135 / 255, seam * 80 / 255, 1
  end)
  return love.graphics.newImage(data)
end

-- Where each torch is at `t` seconds: one circles the pillar, one paces along the bottom, one
-- traces a figure eight on the right.
local TORCH_PATHS = {
  function(t) return 330 + 85 * math.cos(0.9 * t + 2.6), 150 + 85 * math.sin(0.9 * t + 2.6) end,
  function(t) return 320 + 230 * math.sin(0.5 * t), 318 end,
  function(t) return 500 + 70 * math.sin(0.7 * t), 150 + 50 * math.sin(1.4 * t) end,
}

local function build_world()
  renderer = par2d.new_renderer()
  renderer:set_frame(W, H)      -- one lightmap pixel per screen pixel, the view at (0, 0)
  renderer:set_incremental(true)
  renderer:set_ambient(0.02, 0.02, 0.03)
  -- Crates, pillars and a wall, seen from above: their tops are lit (interior "lit") and they
  -- cast shadows.
  crates = {{x = 230, y = 70}, {x = 420, y = 240}, {x = 90, y = 260}, {x = 132, y = 260}}
  for _, c in ipairs(crates) do renderer:add_occluder(par2d.box(c.x, c.y, c.x + 40, c.y + 40), "lit") end
  pillars = {{x = 330, y = 150, r = 16}, {x = 560, y = 270, r = 14}}
  for _, p in ipairs(pillars) do renderer:add_occluder(par2d.circle(p.x, p.y, p.r), "lit") end
  wall = {x0 = 280, y0 = 210, x1 = 400, y1 = 226}
  renderer:add_occluder(par2d.box(wall.x0, wall.y0, wall.x1, wall.y1), "lit")
  torches = {
    {color = {1.0, 0.75, 0.45}, intensity = 22, range = 115, radius = 5},
    {color = {0.55, 0.7, 1.0}, intensity = 20, range = 125, radius = 4},
    {color = {1.0, 0.55, 0.25}, intensity = 16, range = 100, radius = 6},
  }
  for i, torch in ipairs(torches) do
    local x, y = TORCH_PATHS[i](0)
    torch.shape = par2d.circle(x, y, torch.radius)
    torch.handle = renderer:add_light(torch.shape, torch.color, torch.intensity, torch.range)
  end
end

function love.load(args)
  parse_arguments(args)
  par2d.load(options.library)
  love.graphics.setDefaultFilter("nearest", "nearest")
  floor_image, crate_image = make_floor(), make_crate()
  build_world()
  -- par2d writes into the ImageData's memory: PAR2D_RGBA8_SRGB is LÖVE's rgba8 byte order.
  light_data = love.image.newImageData(W, H, "rgba8")
  light_image = love.graphics.newImage(light_data)
end

-- Copies rectangle [x0, x1) x [y0, y1) of the buffer into the texture: Image:replacePixels
-- uploads a whole ImageData at a position, so the rectangle goes through one of its size.
local function upload(x0, y0, x1, y1)
  local w, h = x1 - x0, y1 - y0
  local key = w * 65536 + h
  local part = scratch[key]
  if not part then
    part = love.image.newImageData(w, h, "rgba8")
    scratch[key] = part
  end
  part:paste(light_data, 0, 0, x0, y0, w, h)
  light_image:replacePixels(part, 1, 1, x0, y0)
  uploaded = uploaded + w * h
end

function love.update(dt)
  frame = frame + 1
  time = time + (options.frames and 1 / 60 or dt) -- the test steps a fixed time per frame
  for i, torch in ipairs(torches) do
    torch.shape.circle[0], torch.shape.circle[1] = TORCH_PATHS[i](time)
    -- A flicker in the intensity; the position and the intensity go in one call.
    local flicker = 0.9 + 0.1 * math.sin(11 * time + 2 * i)
    renderer:update_light(torch.handle, torch.shape, torch.color, torch.intensity * flicker)
  end
  renderer:render_rgba8(light_data:getFFIPointer(), W * 4, EXPOSURE)
  for x0, y0, x1, y1 in renderer:dirty_rects() do upload(x0, y0, x1, y1) end
end

local function draw_sprites()
  love.graphics.setColor(1, 1, 1, 1)
  love.graphics.draw(floor_image, 0, 0)
  love.graphics.setColor(0.35, 0.33, 0.38, 1)
  love.graphics.rectangle("fill", wall.x0, wall.y0, wall.x1 - wall.x0, wall.y1 - wall.y0)
  love.graphics.setColor(0.55, 0.55, 0.6, 1)
  for _, p in ipairs(pillars) do love.graphics.circle("fill", p.x, p.y, p.r) end
  love.graphics.setColor(1, 1, 1, 1)
  for _, c in ipairs(crates) do love.graphics.draw(crate_image, c.x, c.y) end
  for _, torch in ipairs(torches) do -- the flames, lit by their own light
    love.graphics.setColor(1, 0.95, 0.7, 1)
    love.graphics.circle("fill", torch.shape.circle[0], torch.shape.circle[1], torch.radius)
  end
  love.graphics.setColor(1, 1, 1, 1)
end

local function finish()
  if options.sprites then -- the sprite layer alone, drawn the same way into a canvas
    local canvas = love.graphics.newCanvas(W, H)
    love.graphics.setCanvas(canvas)
    love.graphics.clear(0, 0, 0, 1)
    draw_sprites()
    love.graphics.setCanvas()
    write_ppm(options.sprites, canvas:newImageData())
  end
  if options.scene then renderer:save_scene(options.scene) end
  love.graphics.captureScreenshot(function(shown)
    if options.screenshot then write_ppm(options.screenshot, shown) end
    print(string.format("par2d love example: %d frames, %.1f %% of their texels uploaded", frame,
                        100 * uploaded / (frame * W * H)))
    love.event.quit(0)
  end)
end

function love.draw()
  if options.frames and frame == options.frames then finish() end
  love.graphics.clear(0, 0, 0, 1)
  draw_sprites()
  love.graphics.setBlendMode("multiply", "premultiplied") -- destination x lightmap
  love.graphics.draw(light_image, 0, 0)
  love.graphics.setBlendMode("alpha")
end
