-- LÖVE settings for the par2d example: one 640x360 window, no gamma correction (the lightmap's
-- sRGB bytes multiply the sprites' bytes as they are), and none of the modules it does not use.
function love.conf(t)
  t.identity = "par2d_love_example"
  t.version = "11.4"
  t.gammacorrect = false
  t.window.title = "par2d: torches over sprites (LÖVE 11, LuaJIT FFI)"
  t.window.width = 640
  t.window.height = 360
  t.window.resizable = false
  t.modules.audio = false
  t.modules.sound = false
  t.modules.joystick = false
  t.modules.physics = false
  t.modules.touch = false
  t.modules.video = false
end
