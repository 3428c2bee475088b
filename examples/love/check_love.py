#!/usr/bin/env python3
"""Runs the LÖVE example (examples/love) for a number of frames on the X display in $DISPLAY
(the CI gate gives it Xvfb with Mesa's software GL) and checks its last frame as shown against
`par2d render` of the world it saved, multiplied over the sprite layer it saved the way the
GPU's "multiply" blend does: round(sprite x light / 255) per channel. Also holds every
declaration of par2d.lua's ffi.cdef to include/par2d/par2d.h, so the FFI cannot drift from
the header.
Usage: check_love.py LOVE PAR2D_CLI LIBPAR2D (LOVE: the love program; LIBPAR2D: libpar2d.so)"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = os.path.join(HERE, "..", "..", "include", "par2d", "par2d.h")
FRAMES = 30
EXPOSURE = 1.5  # main.lua's: the lightmap's bytes are round(255 srgb(clamp(1.5 E, 0, 1)))
# The GPU's blend multiplies two 8-bit values and stores 8 bits. Exact rounding gives
# round(s l / 255); Mesa's llvmpipe computes it in floats, and a product a hair above a half
# (196 x 188 / 255 = 144.502) can come out one step lower: 1/255 at most. Nothing else is
# interpolated (the lightmap is drawn 1:1 with nearest filtering), so a wrong or stale texel
# shows as more than that.
TOLERANCE = 1


def normalized_c(text):
    """C declarations without comments, preprocessor lines, PAR2D_C_API or layout whitespace."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"^\s*#.*$", " ", text, flags=re.M)
    text = text.replace("PAR2D_C_API", " ")
    text = re.sub(r"\s+", " ", text)
    return re.sub(r"\s*([(),;{}\[\]*=])\s*", r"\1", text).strip()


def check_cdef():
    """Every top-level declaration of par2d.lua's ffi.cdef appears in par2d.h as written."""
    lua = open(os.path.join(HERE, "par2d.lua"), encoding="utf-8").read()
    match = re.search(r"ffi\.cdef\[\[(.*?)\]\]", lua, flags=re.S)
    if not match:
        return ["par2d.lua: no ffi.cdef[[ ... ]] block"]
    header = normalized_c(open(HEADER, encoding="utf-8").read())
    declarations, depth, start = [], 0, 0
    cdef = normalized_c(match.group(1))
    for i, c in enumerate(cdef):
        depth += {"{": 1, "}": -1}.get(c, 0)
        if c == ";" and depth == 0:
            declarations.append(cdef[start:i + 1])
            start = i + 1
    missing = [d for d in declarations if d not in header]
    print(f"cdef: {len(declarations)} declarations of par2d.lua, {len(declarations) - len(missing)} found in par2d.h")
    return [f"par2d.lua declares what par2d.h does not: {d}" for d in missing] + (
        ["par2d.lua: the cdef block holds no declaration"] if not declarations else [])


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(maxsplit=4)
    if parts[0] != b"P6" or parts[3] != b"255":
        sys.exit(f"check_love: {path}: not an 8-bit binary PPM")
    width, height = int(parts[1]), int(parts[2])
    return np.frombuffer(parts[4], dtype=np.uint8).reshape(height, width, 3)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    love, cli, library = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
    if not os.environ.get("DISPLAY"):
        sys.exit("check_love: DISPLAY is not set (run it under xvfb-run)")
    failures = check_cdef()
    work = tempfile.mkdtemp(prefix="par2d_love_")
    try:
        shot, sprites, scene, light = (os.path.join(work, name)
                                       for name in ("shot.ppm", "sprites.ppm", "scene.json", "light.png"))
        env = dict(os.environ, LIBGL_ALWAYS_SOFTWARE="1")
        run = subprocess.run([love, HERE, "--library", library, "--frames", str(FRAMES), "--screenshot", shot,
                              "--sprites", sprites, "--scene", scene],
                             env=env, stdout=subprocess.PIPE, text=True, timeout=240)
        sys.stdout.write(run.stdout)
        if run.returncode != 0:
            sys.exit(f"check_love: {love} {HERE} exited with status {run.returncode}")
        subprocess.run([cli, "render", scene, "-o", light, "--exposure", str(EXPOSURE)], check=True)
        shown = read_ppm(shot).astype(np.int64)
        s = read_ppm(sprites).astype(np.int64)
        l = np.asarray(Image.open(light).convert("RGB")).astype(np.int64)
        if not shown.shape == s.shape == l.shape:
            sys.exit(f"check_love: sizes differ: screenshot {shown.shape}, sprites {s.shape}, par2d render {l.shape}")
        expected = (2 * s * l + 255) // 510  # round(s l / 255); s l / 255 is never halfway
        diff = np.abs(shown - expected)
        # Lit by the torches: a light byte of 96 or more (the ambient alone gives 48).
        lit = float((l >= 96).mean())
        print(f"love: max |screenshot - composite| = {diff.max()} / 255, {(diff > 0).mean() * 100:.3f} % of "
              f"channels differ, {lit * 100:.1f} % of channels lit by the torches")
        if diff.max() > TOLERANCE:
            y, x, c = np.unravel_index(np.argmax(diff), diff.shape)
            failures.append(f"pixel ({x}, {y}) channel {c}: shown {shown[y, x, c]}, composite {expected[y, x, c]} "
                            f"(sprite {s[y, x, c]} x light {l[y, x, c]}); {(diff > TOLERANCE).sum()} channels "
                            f"differ by more than {TOLERANCE}")
        if lit < 0.15:
            failures.append(f"only {lit * 100:.1f} % of channels lit by the torches: the scene is not what the "
                            "check expects")
        # The texture must have been built from partial uploads (what the check is about): more
        # than the first frame's whole upload, less than every frame's.
        m = re.search(r"([0-9.]+) % of their texels uploaded", run.stdout)
        share = float(m.group(1)) if m else -1.0
        if not 100.0 / FRAMES < share < 100.0:
            failures.append(f"uploaded {share} % of the texels: not a run of partial uploads")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print("check_love: " + f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
