#!/usr/bin/env python3
"""Runs the SDL2 + OpenGL example under Xvfb with Mesa's software GL for a number of frames
and checks its last frame, read back from the GPU, against `par2d render` of the world it
saved, composited on the CPU the way the example's shader does (multiply and hdr modes, and
multiply with the camera panning: the lightmap on the world's pixel grid, sampled bilinearly
at the camera's sub-pixel remainder).
Usage: check_lightmap_gl.py EXAMPLE PAR2D_CLI"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(maxsplit=4)
    assert parts[0] == b"P6" and parts[3] == b"255", path
    width, height = int(parts[1]), int(parts[2])
    return np.frombuffer(parts[4], dtype=np.uint8).reshape(height, width, 3)


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        pixels = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return pixels.reshape(height, width, 3)[::-1]  # PFM rows are stored bottom first


def to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def to_srgb(c):
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def start_xvfb():
    for display in range(90, 140):
        if os.path.exists(f"/tmp/.X11-unix/X{display}") or os.path.exists(f"/tmp/.X{display}-lock"):
            continue
        server = subprocess.Popen(["Xvfb", f":{display}", "-screen", "0", "800x600x24", "-nolisten", "tcp"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(100):
            if os.path.exists(f"/tmp/.X11-unix/X{display}"):
                return server, f":{display}"
            if server.poll() is not None:
                break
            time.sleep(0.05)
        server.kill()
    sys.exit("check_lightmap_gl: could not start Xvfb")


def main():
    example, cli = sys.argv[1], sys.argv[2]
    work = tempfile.mkdtemp(prefix="par2d_gl_")
    server, display = start_xvfb()
    env = dict(os.environ, DISPLAY=display, SDL_VIDEODRIVER="x11", LIBGL_ALWAYS_SOFTWARE="1")
    env.pop("WAYLAND_DISPLAY", None)
    failures = []
    try:
        # The scroll run's tolerance covers the GPU's bilinear weights (8 bits in Mesa's llvmpipe).
        for mode, exposure, tolerance in (("multiply", 1.5, 1), ("hdr", 2.0, 2), ("scroll", 1.5, 2)):
            shot, sprites, scene, camera = (os.path.join(work, f"{mode}.{ext}")
                                            for ext in ("shot.ppm", "sprites.ppm", "json", "camera.json"))
            flags = ["--mode", "multiply", "--scroll", "--lightmap", camera] if mode == "scroll" else ["--mode", mode]
            subprocess.run([example, *flags, "--frames", "30", "--exposure", str(exposure), "--screenshot", shot,
                            "--sprites", sprites, "--scene", scene], env=env, check=True, timeout=240)
            shown = read_ppm(shot).astype(np.int32)
            s = read_ppm(sprites).astype(np.float64) / 255.0
            if mode in ("multiply", "scroll"):
                light_png = os.path.join(work, "light.pfm")
                subprocess.run([cli, "render", scene, "--pfm", light_png], check=True)
                e = read_pfm(light_png).astype(np.float64)
                # par2d's rgba8_srgb bytes: round(255 * srgb(clamp(exposure * E, 0, 1))).
                light8 = np.rint(255.0 * to_srgb(np.clip(exposure * e, 0.0, 1.0)))
                if mode == "scroll":
                    # The scene's view is the last lightmap's (one pixel more than the screen each
                    # way); screen pixel (x, y) reads it between pixels (x, y) and (x + 1, y + 1).
                    fx, fy = json.load(open(camera))["remainder"]
                    h, w = shown.shape[:2]
                    light8 = ((1 - fx) * (1 - fy) * light8[:h, :w] + fx * (1 - fy) * light8[:h, 1:w + 1] +
                              (1 - fx) * fy * light8[1:h + 1, :w] + fx * fy * light8[1:h + 1, 1:w + 1])
                expected = np.rint(s * light8)  # the shader's sprite x light, stored as bytes
            else:
                pfm = os.path.join(work, "light.pfm")
                subprocess.run([cli, "render", scene, "--pfm", pfm], check=True)
                x = to_linear(s) * read_pfm(pfm).astype(np.float64) * exposure
                expected = np.rint(255.0 * to_srgb(x / (1.0 + x)))
            diff = np.abs(shown - expected.astype(np.int32))
            lit = float((expected > 8).mean())
            print(f"{mode}: max |screenshot - composite| = {diff.max()} / 255, "
                  f"{(diff > 0).mean() * 100:.3f} % of channels differ, {lit * 100:.1f} % of channels lit")
            if diff.max() > tolerance:
                failures.append(f"{mode}: a channel differs by {diff.max()} (> {tolerance}) at "
                                f"{np.unravel_index(np.argmax(diff), diff.shape)}")
            if lit < 0.2:
                failures.append(f"{mode}: only {lit * 100:.1f} % of channels lit: the scene is not what the check expects")
    finally:
        server.terminate()
        server.wait()
        shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print("check_lightmap_gl: " + f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
