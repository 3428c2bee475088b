"""Compositing par2d's light with a sprite layer in NumPy: multiply, additive and HDR with a
tone curve, the same three ways a GPU shader does it (docs/compositing.md).

Run: PYTHONPATH=build/python python3 examples/python_compositing.py [OUT_PREFIX]
Writes OUT_PREFIX-multiply.png, -additive.png and -hdr.png when OUT_PREFIX is given.
"""
import sys

import numpy as np

import par2d

W, H = 320, 180
scene = {
    "width": W, "height": H,
    "lights": [
        {"circle": {"center": [80, 60], "radius": 4}, "color": [1.0, 0.75, 0.45], "intensity": 3},
        {"circle": {"center": [250, 130], "radius": 3}, "color": [0.5, 0.7, 1.0], "intensity": 2},
    ],
    "occluders": [
        {"polygon": [[150, 0], [166, 0], [166, 70], [150, 70]]},
        {"polygon": [[150, 110], [166, 110], [166, 180], [150, 180]]},
        {"circle": {"center": [220, 90], "radius": 10}},
    ],
}

# The sprite layer: sRGB bytes (H, W, 3), floor tiles with mortar lines.
y, x = np.mgrid[0:H, 0:W]
mortar = (x % 16 == 0) | (y % 16 == 0)
tint = ((x // 16) * 37 + (y // 16) * 91) % 40
sprites = np.stack([np.where(mortar, 90, 170 + tint), np.where(mortar, 85, 160 + tint // 2),
                    np.where(mortar, 80, 140)], axis=-1).astype(np.uint8)


def to_linear(c):
    """sRGB-encoded values in [0, 1] to linear."""
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def to_srgb(c):
    """Linear values in [0, 1] to sRGB encoding."""
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


renderer = par2d.Renderer(scene)
E = renderer.render()                             # float32 (H, W, 3): linear irradiance, unbounded
light8 = renderer.render_rgba8(exposure=1.5)      # uint8 (H, W, 4): sRGB(clamp(1.5 E, 0, 1))
exposure = 2.0

# Multiply, as most 2D engines composite a lightmap: sprite bytes x light bytes. Cheap, but the
# light saturates at 1 (a lit sprite is never brighter than its texture).
multiply = np.rint(sprites * (light8[..., :3] / 255.0)).astype(np.uint8)

# Additive: the light's colour added to the sprite (glows, fog); clamps at white.
additive = np.clip(sprites.astype(np.int32) + light8[..., :3], 0, 255).astype(np.uint8)

# HDR: in linear light, sprite albedo x exposure x E, then a tone curve (Reinhard x / (1 + x))
# so highlights roll off instead of clipping, then sRGB encoding for the display.
lit = to_linear(sprites / 255.0) * E * exposure
hdr = np.rint(255.0 * to_srgb(lit / (1.0 + lit))).astype(np.uint8)

# Checks a reader can trust: the one-shot render and the Renderer agree bit for bit; the
# multiply composite is the sprite where the light is white and black in the walls' shadow.
assert np.array_equal(E, par2d.render(scene))
inside_wall = (5, 158)  # row, column inside the top wall
assert multiply[inside_wall].max() == 0 and hdr[inside_wall].max() == 0
print(f"E max {E.max():.3f}; lit pixels {np.mean(E.max(axis=2) > 1e-3) * 100:.1f} %; "
      f"multiply mean {multiply.mean():.1f}, additive mean {additive.mean():.1f}, hdr mean {hdr.mean():.1f}")

if len(sys.argv) > 1:
    for name, image in (("multiply", multiply), ("additive", additive), ("hdr", hdr)):
        path = f"{sys.argv[1]}-{name}.png"
        par2d.write_png(path, image)  # uint8 arrays are stored byte for byte
        print("wrote", path)
