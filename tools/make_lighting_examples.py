#!/usr/bin/env python3
"""Writes the game-lighting example scenes (examples/lighting_*.json) and the brick normal map
they use (examples/brick_normals_*.png). Deterministic: running it again gives the same files.

    python3 tools/make_lighting_examples.py            # needs python3-numpy, python3-pil

Each scene shows one term of the lighting model (docs/contract.md section 6); lighting_game.json
combines them all.
"""
import json
import math
import os
import sys

import numpy as np
from PIL import Image

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
EXAMPLES = os.path.join(ROOT, "examples")


def box(x0, y0, x1, y1):
    return {"polygon": [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]}


def circle(cx, cy, r):
    return {"circle": {"center": [cx, cy], "radius": r}}


def write_scene(name, scene):
    path = os.path.join(EXAMPLES, name)
    with open(path, "w") as f:
        f.write("{\n")
        keys = list(scene.keys())
        for i, key in enumerate(keys):
            value = scene[key]
            comma = "," if i + 1 < len(keys) else ""
            if isinstance(value, list) and value and isinstance(value[0], dict):
                f.write(f'  "{key}": [\n')
                for j, item in enumerate(value):
                    f.write("    " + json.dumps(item) + ("," if j + 1 < len(value) else "") + "\n")
                f.write(f"  ]{comma}\n")
            else:
                f.write(f'  "{key}": {json.dumps(value)}{comma}\n')
        f.write("}\n")
    print("wrote", os.path.relpath(path, ROOT))


def brick_normal_map(width, height, brick_w=64, brick_h=32, mortar=3, bevel=5):
    """A running-bond brick wall seen from the front: mortar grooves and bevelled brick edges,
    with a little deterministic surface noise. Returns uint8 RGB in the common 2D convention
    (R = image +x, G = image up, B = toward the viewer)."""
    rng = np.random.default_rng(7)
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    row = np.floor(ys / brick_h)
    xs_shifted = xs + (row % 2) * (brick_w / 2)
    u = np.mod(xs_shifted, brick_w)  # position inside the brick
    v = np.mod(ys, brick_h)
    # Height field: bricks raised, mortar low, bevels ramping between.
    dist_edge = np.minimum.reduce([u - mortar / 2, brick_w - mortar / 2 - u, v - mortar / 2, brick_h - mortar / 2 - v])
    height_field = np.clip(dist_edge / bevel, 0.0, 1.0)
    # Per-brick tilt and fine noise make the bricks catch the light differently.
    brick_id = (row * 1000 + np.floor(xs_shifted / brick_w)).astype(np.int64)
    tilt = np.sin(brick_id * 12.9898) * 0.5
    noise = rng.normal(0.0, 0.015, size=(height, width))
    height_field = height_field * (1.0 + 0.08 * tilt) + noise * (height_field > 0.99)
    # Normal from the height gradient (image y grows downward; G stores image up).
    gy, gx = np.gradient(height_field * 3.0)
    nx = -gx
    ny = gy  # d/d(image down) -> the up component flips sign
    nz = np.ones_like(nx)
    length = np.sqrt(nx * nx + ny * ny + nz * nz)
    n = np.stack([nx / length, ny / length, nz / length], axis=-1)
    return np.clip(np.round((n + 1.0) * 127.5), 0, 255).astype(np.uint8)


def torch(cx, cy, r=5, intensity=14, color=(1.0, 0.62, 0.30), **extra):
    light = {**circle(cx, cy, r), "color": list(color), "intensity": intensity}
    light.update(extra)
    return light


def main():
    os.makedirs(EXAMPLES, exist_ok=True)

    # Range: torches light only their surroundings (smooth window), so each costs only there.
    lights = []
    occluders = []
    for k, (cx, cy) in enumerate([(70, 70), (250, 60), (440, 80), (120, 240), (330, 220), (470, 330), (200, 340)]):
        lights.append(torch(cx, cy, intensity=12, range=95 + 20 * (k % 3)))
    for cx, cy in [(160, 120), (300, 130), (390, 270), (90, 320), (260, 280)]:
        occluders.append(box(cx - 12, cy - 12, cx + 12, cy + 12))
    write_scene("lighting_range.json", {"width": 512, "height": 384, "lights": lights, "occluders": occluders})

    # Spot lights: emission cones with soft (fade) and hard edges, cut by occluders.
    write_scene("lighting_spot.json", {
        "width": 512, "height": 384,
        "lights": [
            {**circle(60, 50, 6), "color": [1.0, 0.9, 0.7], "intensity": 40,
             "cone": {"direction": 40, "half_angle": 25, "fade": 10}},
            {**circle(460, 40, 5), "color": [0.4, 0.6, 1.0], "intensity": 40,
             "cone": {"direction": 120, "half_angle": 15, "fade": 0}},
            {"segment": [[200, 370], [260, 370]], "color": [1.0, 0.4, 0.3], "intensity": 6,
             "cone": {"direction": 270, "half_angle": 60, "fade": 30}},
        ],
        "occluders": [box(180, 160, 230, 200), circle(360, 200, 18), {"segment": [[300, 300], [340, 270]]}],
    })

    # Cookies: angular emission profiles over the brick floor's normals. A beacon with three
    # soft beams of different strengths; a small lamp whose grille throws bars (weights
    # stepping between 0 and 1 over half a degree).
    beams = []
    for centre, peak in [(0, 1.0), (120, 0.7), (240, 0.4)]:
        beams += [[centre - 12, 0.0], [centre - 5, peak], [centre + 5, peak], [centre + 12, 0.0]]
    grille = []
    for k in range(8):  # 32 knots, the most a cookie takes
        start = 64 + 6.5 * k
        grille += [[start, 0.0], [start + 0.5, 1.0], [start + 3.5, 1.0], [start + 4.0, 0.0]]
    write_scene("lighting_cookie.json", {
        "width": 512, "height": 384,
        "normal_map": "brick_normals_512x384.png",
        "ambient": [0.01, 0.01, 0.015],
        "lights": [
            {**circle(150, 230, 4), "color": [1.0, 0.85, 0.55], "intensity": 60, "elevation": 20,
             "cookie": {"rotation": -20, "knots": beams}},
            {"segment": [[378, 16], [384, 16]], "color": [0.55, 0.75, 1.0], "intensity": 60, "elevation": 35,
             "cookie": {"knots": grille}},
        ],
        "occluders": [circle(250, 300, 12), circle(420, 250, 10)],
    })

    # Shadow strength and colour: the same lamp and pillar three times, with full shadows, half
    # shadows (strength 0.5), and shadows coloured deep blue (the blue of the light passes).
    # Ranges keep the three apart: a partial shadow lets light through every occluder.
    lamps, pillars = [], []
    for k, shadow in enumerate([None, {"strength": 0.5}, {"strength": 1, "color": [0.1, 0.2, 0.85]}]):
        x = 128 + 256 * k
        lamp = torch(x, 60, r=7, intensity=5, color=(1.0, 0.9, 0.75), range=125, falloff=1)
        if shadow:
            lamp["shadow"] = shadow
        lamps.append(lamp)
        pillars.append(box(x - 20, 110, x + 20, 135))
    write_scene("lighting_shadow.json", {
        "width": 768, "height": 256,
        "ambient": [0.01, 0.01, 0.012],
        "lights": lamps,
        "occluders": pillars,
    })

    # Sun through windows: a directional light at infinity; penumbrae widen with distance.
    wall = [box(0, 90, 90, 106), box(130, 90, 230, 106), box(270, 90, 370, 106), box(410, 90, 512, 106)]
    write_scene("lighting_sun.json", {
        "width": 512, "height": 384,
        "ambient": [0.015, 0.018, 0.03],
        "directional_lights": [{"angles": [238, 250], "color": [1.0, 0.93, 0.8], "intensity": 18}],
        "occluders": wall + [circle(200, 260, 22), box(330, 230, 370, 300)],
    })

    # Stained glass: translucent occluders multiply where they overlap.
    write_scene("lighting_glass.json", {
        "width": 512, "height": 384,
        "lights": [{**circle(256, 30, 10), "color": [1, 1, 1], "intensity": 12}],
        "occluders": [
            {**circle(210, 150, 45), "transmittance": [0.95, 0.2, 0.15]},
            {**circle(300, 150, 45), "transmittance": [0.15, 0.9, 0.2]},
            {**circle(256, 215, 45), "transmittance": [0.2, 0.3, 0.95]},
            {**box(90, 120, 130, 200)},
            {**box(380, 120, 420, 200), "transmittance": [0.6, 0.6, 0.6]},
        ],
    })

    # Sprites and masks: lit-interior occluders cast shadows without going black inside; a
    # light with its own mask passes through occluders of another layer.
    write_scene("lighting_sprites.json", {
        "width": 512, "height": 384,
        "ambient": [0.02, 0.02, 0.025],
        "lights": [
            torch(120, 190, r=8, intensity=20, color=(1.0, 0.8, 0.55), mask=1),
            torch(400, 190, r=8, intensity=20, color=(0.5, 0.7, 1.0), mask=2),
        ],
        "occluders": [
            {**circle(200, 150, 20), "interior": "lit"},
            {**box(180, 230, 215, 275), "interior": "lit"},
            {**circle(320, 140, 18), "mask": 1},
            {**box(300, 240, 340, 270), "mask": 2},
            {**box(250, 60, 262, 330)},
        ],
    })

    # Normal map: a brick floor shaded by torches above the plane (elevation).
    w, h = 512, 384
    Image.fromarray(brick_normal_map(w, h)).save(os.path.join(EXAMPLES, "brick_normals_512x384.png"))
    print("wrote examples/brick_normals_512x384.png")
    write_scene("lighting_normals.json", {
        "width": w, "height": h,
        "normal_map": "brick_normals_512x384.png",
        "lights": [
            torch(130, 120, intensity=30, range=260, elevation=25),
            torch(380, 260, intensity=30, range=260, elevation=25, color=(0.5, 0.75, 1.0)),
        ],
        "occluders": [box(240, 170, 275, 205)],
    })

    # Everything together: a torch-lit hall with a brick floor, a spot lamp, sun through
    # windows with stained glass, sprites and a ghost light on its own mask.
    w, h = 960, 540
    Image.fromarray(brick_normal_map(w, h)).save(os.path.join(EXAMPLES, "brick_normals_960x540.png"))
    print("wrote examples/brick_normals_960x540.png")
    occluders = [
        # North wall with windows; two panes are stained glass.
        box(0, 100, 150, 118), box(200, 100, 380, 118), box(430, 100, 610, 118), box(660, 100, 960, 118),
        {**box(150, 104, 200, 114), "transmittance": [0.9, 0.25, 0.2]},
        {**box(380, 104, 430, 114), "transmittance": [0.25, 0.5, 0.95]},
        # Pillars.
        box(260, 250, 290, 280), box(520, 250, 550, 280), box(780, 250, 810, 280),
        box(260, 420, 290, 450), box(520, 420, 550, 450),
        # Sprites (lit inside) and a translucent curtain.
        {**circle(400, 330, 14), "interior": "lit"}, {**circle(690, 380, 12), "interior": "lit"},
        {**box(860, 300, 868, 470), "transmittance": [0.55, 0.45, 0.35]},
        # Only the ghost light's layer: the ghost passes through everything else.
        {**circle(150, 420, 16), "mask": 2},
    ]
    lights = [
        torch(120, 200, intensity=24, range=330, elevation=30),
        torch(420, 200, intensity=24, range=330, elevation=30),
        torch(700, 200, intensity=24, range=330, elevation=30),
        torch(880, 480, intensity=20, range=280, elevation=30),
        {**circle(620, 480, 7), "color": [1.0, 0.95, 0.85], "intensity": 90, "elevation": 35,
         "cone": {"direction": 200, "half_angle": 22, "fade": 8}},
        {**circle(60, 470, 6), "color": [0.45, 1.0, 0.6], "intensity": 22, "range": 220, "mask": 2,
         "elevation": 20},
    ]
    write_scene("lighting_game.json", {
        "width": w, "height": h,
        "ambient": [0.01, 0.012, 0.02],
        "normal_map": "brick_normals_960x540.png",
        "directional_lights": [{"angles": [245, 258], "color": [1.0, 0.92, 0.78], "intensity": 9, "elevation": 40}],
        "lights": lights,
        "occluders": occluders,
    })


if __name__ == "__main__":
    sys.exit(main())
