"""par2d.Renderer under concurrent Python calls: every call reads the world under its lock.

Threads render (whole frames, regions, sRGB bytes, snapshots) while others resize the frame,
add and remove a light and move an occluder. The world only ever takes a few states, all
rendered beforehand, so every result must equal the render of one of them, with the shape
of a frame size that existed; the only error allowed is a region outside the frame of the
moment, reported for exactly the region the caller passed.
"""
import itertools
import os
import subprocess
import sys
import random
import threading
import time

import numpy as np
import pytest

import par2d

# (width, height) -> view: every frame the world ever has. The views differ, so a frame
# rendered with the other frame's size is wrong in content as well as in shape.
FRAMES = {(128, 96): (0.0, 0.0, 64.0, 48.0), (80, 60): (-4.0, -3.0, 36.0, 27.0)}
SIZES = list(FRAMES)
MUTATIONS = 1000000  # the most calls a changing thread makes; they stop once the renders are done
BASE_LIGHT = {"circle": {"center": [12.0, 10.0], "radius": 3.0}, "color": [1.0, 0.8, 0.6], "intensity": 4.0}
EXTRA_LIGHT = {"circle": {"center": [30.0, 22.0], "radius": 2.0}, "color": [0.3, 0.5, 1.0], "intensity": 6.0}
OCCLUDER_AT = [{"polygon": [[18, 14], [26, 14], [26, 20], [18, 20]]},
               {"polygon": [[8, 18], [16, 18], [16, 26], [8, 26]]}]
WIDE = (0, 0, 120, 90)    # inside the 128x96 frame only
INNER = (3, 2, 70, 55)    # inside both frames


# Enough lights and occluders that a frame takes a while, so calls overlap.
MORE_LIGHTS = [{"circle": {"center": [6.0 + 7 * k, 40.0 - 3 * k], "radius": 1.5}, "intensity": 1.0} for k in range(6)]
FIXED_OCCLUDERS = [{"circle": {"center": [5.0 + 9 * k, 30.0], "radius": 1.5}} for k in range(6)]


class Yielding:
    """An integer-like region coordinate whose __index__ lets other threads run."""

    def __init__(self, value):
        self.value = value

    def __index__(self):
        time.sleep(0.0002)
        return self.value


def scene(size, extra, at):
    lights = [BASE_LIGHT] + MORE_LIGHTS + ([EXTRA_LIGHT] if extra else [])
    return {"width": size[0], "height": size[1], "view": list(FRAMES[size]), "lights": lights,
            "occluders": [OCCLUDER_AT[at]] + FIXED_OCCLUDERS}


def all_states():
    """Every (size, extra light present, occluder position) the threads below can produce."""
    return list(itertools.product(SIZES, [False, True], [0, 1]))


def test_concurrent_calls_see_consistent_states():
    states = all_states()
    floats = {s: par2d.render(scene(*s), threads=1) for s in states}
    rgba = {}
    for s in states:
        fresh = par2d.Renderer(scene(*s), threads=1)
        rgba[s] = fresh.render_rgba8(1.5)
        assert np.array_equal(fresh.render(), floats[s])  # the expectations agree with the Renderer

    def matches(result, table, region):
        x0, y0, x1, y1 = region if region is not None else (0, 0, None, None)
        for s in states:
            want = table[s]
            if region is None:
                if result.shape == want.shape and np.array_equal(result, want):
                    return True
            elif x1 <= s[0][0] and y1 <= s[0][1] and np.array_equal(result, want[y0:y1, x0:x1]):
                return True
        return False

    r = par2d.Renderer(scene(SIZES[0], False, 0), threads=1)
    occluder = r.occluders[0]
    assert len(r.lights) == 1 + len(MORE_LIGHTS)
    problems = []
    stop = threading.Event()          # a problem was found: everyone stops
    renders_done = threading.Event()  # the changing threads stop too

    def record(what):
        problems.append(what)
        stop.set()

    def renderer_thread(seed):
        rng = random.Random(seed)
        for i in range(100):
            if stop.is_set():
                return
            kind = rng.choice(["full", "inner", "wide", "wide_yield", "rgba", "rgba_wide", "snapshot"])
            try:
                if kind == "full":
                    out = r.render()
                    if not matches(out, floats, None):
                        record(f"render() gave a {out.shape} array equal to no state")
                elif kind == "inner":
                    out = r.render(region=INNER)
                    if not matches(out, floats, INNER):
                        record(f"render(region={INNER}) gave a {out.shape} array equal to no state")
                elif kind == "wide":
                    out = r.render(region=WIDE)
                    if not matches(out, floats, WIDE):
                        record(f"render(region={WIDE}) gave a {out.shape} array equal to no state")
                elif kind == "wide_yield":
                    out = r.render(region=tuple(Yielding(v) for v in WIDE))
                    if not matches(out, floats, WIDE):
                        record(f"render(region=Yielding {WIDE}) gave a {out.shape} array equal to no state")
                elif kind == "rgba":
                    out = r.render_rgba8(1.5)
                    if not matches(out, rgba, None):
                        record(f"render_rgba8() gave a {out.shape} array equal to no state")
                elif kind == "rgba_wide":
                    out = r.render_rgba8(1.5, region=WIDE)
                    if not matches(out, rgba, WIDE):
                        record(f"render_rgba8(region={WIDE}) gave a {out.shape} array equal to no state")
                else:
                    snap = r.snapshot()
                    h, w, _ = snap.shape
                    if (w, h) not in SIZES or snap.occluder_count != 1 + len(FIXED_OCCLUDERS) or \
                            snap.light_count - len(MORE_LIGHTS) not in (1, 2):
                        record(f"snapshot() gave {snap!r}")
                    elif not matches(par2d.render(snap, threads=1), floats, None):
                        record("render(snapshot()) equal to no state")
            except par2d.Error as e:
                # Only a region outside the 80x60 frame may be refused, and for that region.
                expected = (f"region: {WIDE} is not a non-empty rectangle inside the 80x60 frame")
                if kind not in ("wide", "wide_yield", "rgba_wide") or str(e) != expected or e.code != "invalid_argument":
                    record(f"{kind}: par2d.Error {str(e)!r}")
            except Exception as e:  # noqa: BLE001 - any other error is a failure
                record(f"{kind}: {type(e).__name__}: {e}")

    def frame_thread():
        rng = random.Random(11)
        for _ in range(MUTATIONS):
            if stop.is_set() or renders_done.is_set():
                return
            try:
                size = rng.choice(SIZES)
                r.set_frame(*size, view=FRAMES[size])
                shape = r.shape
                if (shape[1], shape[0]) not in SIZES:
                    record(f"shape {shape}")
            except Exception as e:  # noqa: BLE001
                record(f"set_frame: {type(e).__name__}: {e}")

    def light_thread():
        rng = random.Random(12)
        handle = None
        for _ in range(MUTATIONS):
            if stop.is_set() or renders_done.is_set():
                return
            try:
                if handle is None:
                    handle = r.add_light(EXTRA_LIGHT)
                else:
                    if rng.random() < 0.5:
                        r.set_light_emission(handle, EXTRA_LIGHT["color"], EXTRA_LIGHT["intensity"])
                    r.remove_light(handle)
                    handle = None
                if len(r.lights) - len(MORE_LIGHTS) not in (1, 2):
                    record(f"lights {r.lights}")
            except Exception as e:  # noqa: BLE001
                record(f"light: {type(e).__name__}: {e}")

    def occluder_thread():
        rng = random.Random(13)
        for _ in range(MUTATIONS):
            if stop.is_set() or renders_done.is_set():
                return
            try:
                r.update_occluder(occluder, OCCLUDER_AT[rng.randrange(2)])
                r.stats  # noqa: B018 - a read of the world like any other
            except Exception as e:  # noqa: BLE001
                record(f"occluder: {type(e).__name__}: {e}")

    renderers = [threading.Thread(target=renderer_thread, args=(seed,)) for seed in (1, 2, 3)]
    changers = [threading.Thread(target=f) for f in (frame_thread, light_thread, occluder_thread)]
    for t in renderers + changers:
        t.start()
    for t in renderers:
        t.join(timeout=60)
    renders_done.set()
    for t in changers:
        t.join(timeout=60)
    assert not any(t.is_alive() for t in renderers + changers), "a call never returned (deadlock?)"
    assert not problems, problems[:5]


@pytest.mark.parametrize("seed", [5, 6])
def test_properties_read_under_the_lock_while_the_frame_changes(seed):
    # shape, view and repr are one consistent frame each, never a mix.
    r = par2d.Renderer({"width": 64, "height": 48, "lights": [BASE_LIGHT]}, threads=1)
    frames = FRAMES
    problems = []
    done = threading.Event()

    def change():
        rng = random.Random(seed)
        for _ in range(300):
            size = rng.choice(list(frames))
            r.set_frame(*size, view=frames[size])
            r.render()
        done.set()

    worker = threading.Thread(target=change)
    worker.start()
    while not done.is_set() and len(problems) < 5:
        h, w, _ = r.shape
        if (w, h) not in frames:
            problems.append(("shape", (h, w)))
        rep = repr(r)
        if not any(f"{fw}x{fh}," in rep for fw, fh in frames):
            problems.append(("repr", rep))
        if r.view not in frames.values():
            problems.append(("view", r.view))
    worker.join(timeout=60)
    assert not worker.is_alive()
    assert not problems, problems


def test_a_frame_changed_while_arguments_convert_is_the_frame_rendered():
    # Converting `region` runs Python code (__index__); here it has another thread shrink the
    # frame. The world must be read after the arguments, under the lock: the region is then
    # refused for the 80x60 frame it no longer fits, in the words of the region passed.
    r = par2d.Renderer(scene(SIZES[0], False, 0), threads=1)

    class ShrinksTheFrame:
        def __index__(self):
            worker = threading.Thread(target=lambda: r.set_frame(*SIZES[1], view=FRAMES[SIZES[1]]))
            worker.start()
            worker.join(timeout=10)
            assert not worker.is_alive(), "set_frame blocked while render converted its arguments"
            return 0

    with pytest.raises(par2d.Error) as e:
        r.render(region=(ShrinksTheFrame(), 0, 120, 90))
    assert str(e.value) == "region: (0, 0, 120, 90) is not a non-empty rectangle inside the 80x60 frame"
    with pytest.raises(par2d.Error) as e:
        r.render_rgba8(region=(0, 0, 120, 90))
    assert str(e.value) == "region: (0, 0, 120, 90) is not a non-empty rectangle inside the 80x60 frame"
    r.set_frame(*SIZES[0], view=FRAMES[SIZES[0]])
    out = r.render(region=(ShrinksTheFrame(), 0, 70, 55))
    assert np.array_equal(out, par2d.render(scene(SIZES[1], False, 0), threads=1)[0:55, 0:70])


FIRST_USE = """
import threading, par2d
r = par2d.Renderer({"width": 32, "height": 24, "lights": [{"circle": {"center": [5, 5], "radius": 2}}]}, threads=1)
barrier = threading.Barrier(4)
def work():
    barrier.wait()
    for _ in range(20):
        r.render()
        par2d.render({"width": 8, "height": 8})
threads = [threading.Thread(target=work) for _ in range(4)]
for t in threads: t.start()
for t in threads: t.join()
print("ok")
"""


def test_first_arrays_from_several_threads_at_once_do_not_deadlock():
    # The first NumPy arrays a fresh interpreter makes come from four threads at once; this
    # used to hang in pybind11's first-use setup of its NumPy table.
    for _ in range(4):
        done = subprocess.run([sys.executable, "-c", FIRST_USE], env=dict(os.environ), capture_output=True,
                              text=True, timeout=20)
        assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]
