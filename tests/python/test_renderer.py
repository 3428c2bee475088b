"""par2d.Renderer: frames equal one-shot renders bit for bit, handles, refused updates, sRGB bytes, regions."""
import copy
import os
import struct
import threading
import time
import zlib

import numpy as np
import pytest

import par2d
from gil_check import assert_releases_gil

SOURCE_DIR = os.environ["PAR2D_SOURCE_DIR"]
EXAMPLE = os.path.join(SOURCE_DIR, "examples", "colored_lights.json")


def small_example_dict():
    """examples/colored_lights.json at 256x192 (same view), as a dict."""
    d = par2d.load_scene(EXAMPLE).to_dict()
    d["width"], d["height"] = 256, 192
    return d


def read_png_rgb(path):
    """An 8-bit RGB, non-interlaced PNG (what write_png stores) as a uint8 (H, W, 3) array."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert (depth, color, interlace) == (8, 2, 0)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = 3 * width
    out = np.zeros((height, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, dtype=np.int32)
        for x in range(stride):
            a = cur[x - 3] if x >= 3 else 0
            b = prev[x]
            c = prev[x - 3] if x >= 3 else 0
            if kind == 0:
                pred = 0
            elif kind == 1:
                pred = a
            elif kind == 2:
                pred = b
            elif kind == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (line[x] + pred) & 0xFF
        out[y] = cur
        prev = cur
    return out.reshape(height, width, 3).astype(np.uint8)


def test_frame_equals_one_shot_render_bit_for_bit():
    d = small_example_dict()
    for backend in ["simd", "scalar"]:
        r = par2d.Renderer(d, backend=backend, threads=2)
        frame = r.render()
        assert frame.dtype == np.float32 and frame.shape == (192, 256, 3)
        assert np.array_equal(frame, par2d.render(d, backend=backend, threads=1)), backend
        assert r.stats["frames"] == 1


def test_moved_light_equals_fresh_render_of_moved_scene_without_index_builds():
    d = small_example_dict()
    r = par2d.Renderer(par2d.Scene.from_dict(d))
    lights, occluders = r.lights, r.occluders
    assert len(lights) == len(d["lights"]) and len(occluders) == len(d["occluders"])
    r.render()
    builds = r.stats["index_builds"]
    moved = copy.deepcopy(d)
    for step in range(3):
        light = moved["lights"][0]
        assert "circle" in light
        light["circle"]["center"][0] += 7.5
        light["circle"]["center"][1] -= 3.25
        r.update_light(lights[0], light)
        assert np.array_equal(r.render(), par2d.render(moved)), step
    assert r.stats["index_builds"] == builds  # moving lights never rebuilds the occluder index
    assert r.stats["frames"] == 4


def test_add_and_remove_by_handle_match_fresh_renders():
    d = small_example_dict()
    r = par2d.Renderer(d)
    extra = {"circle": {"center": [100.0, 50.0], "radius": 6.0}, "color": [0.2, 1.0, 0.4], "intensity": 5.0}
    h = r.add_light(extra)
    assert r.lights[-1] == h
    with_extra = dict(d, lights=d["lights"] + [extra])
    assert np.array_equal(r.render(), par2d.render(with_extra))
    r.remove_light(h)
    assert h not in r.lights
    assert np.array_equal(r.render(), par2d.render(d))
    wall = {"polygon": [[60, 60], [90, 60], [90, 70], [60, 70]]}
    o = r.add_occluder(wall)
    with_wall = dict(d, occluders=d["occluders"] + [wall])
    assert np.array_equal(r.render(), par2d.render(with_wall))
    r.remove_occluder(o)
    assert np.array_equal(r.render(), par2d.render(d))
    with pytest.raises(par2d.Error, match=str(h)) as e:  # a removed handle is never valid again
        r.update_light(h, extra)
    assert e.value.code == "invalid_argument"


def test_bad_updates_raise_and_keep_the_world():
    d = small_example_dict()
    r = par2d.Renderer(d)
    before = r.render()
    stats = r.stats
    h = r.lights[0]
    with pytest.raises(par2d.Error) as e:
        r.update_light(h, {"circle": {"center": [10, 10], "radius": -1}})
    assert e.value.code == "invalid_scene"
    assert str(e.value).startswith(f"light {h}: circle")
    assert "\n" not in str(e.value)
    with pytest.raises(par2d.Error, match=r"^add_light: ") as e:
        r.add_light({"segment": [[0, 0]]})
    with pytest.raises(par2d.Error, match=r"^add_occluder: must be a dict"):
        r.add_occluder([1, 2])
    with pytest.raises(par2d.Error):
        r.update_light(h, {"circle": {"center": [float("nan"), 10], "radius": 1}})
    with pytest.raises(par2d.Error):
        r.set_light_emission(h, [1.0, 1.0, 1.0], -2.0)
    with pytest.raises(par2d.Error) as e:
        r.set_options(backend="raycast")
    assert str(e.value) == 'backend: "raycast" is the baseline of par2d.render, not a Renderer backend (auto, simd, scalar)'
    assert r.options["backend"] != "raycast"
    with pytest.raises(par2d.Error, match="backend"):
        r.set_options(backend="fast")
    with pytest.raises(par2d.Error) as e:
        r.remove_light(12345)
    assert e.value.code == "invalid_argument"
    assert len(r.lights) == len(d["lights"])
    s = r.stats
    assert (s["index_builds"], s["index_updates"], s["frames"]) == (stats["index_builds"], stats["index_updates"], stats["frames"])
    assert np.array_equal(r.render(), before)
    assert np.array_equal(par2d.render(r.snapshot()), before)


def test_set_light_emission_matches_fresh_render():
    d = small_example_dict()
    r = par2d.Renderer(d)
    r.set_light_emission(r.lights[1], [0.5, 0.25, 1.0], 3.0)
    changed = copy.deepcopy(d)
    changed["lights"][1]["color"] = [0.5, 0.25, 1.0]
    changed["lights"][1]["intensity"] = 3.0
    assert np.array_equal(r.render(), par2d.render(changed))


def test_empty_renderer_with_set_frame_and_view():
    r = par2d.Renderer()
    r.set_frame(64, 48, view=(-10.0, -5.0, 54.0, 43.0))
    assert r.shape == (48, 64, 3) and r.view == (-10.0, -5.0, 54.0, 43.0)
    light = {"circle": {"center": [20.0, 20.0], "radius": 3.0}, "intensity": 2.0}
    r.add_light(light)
    scene = {"width": 64, "height": 48, "view": [-10.0, -5.0, 54.0, 43.0], "lights": [light]}
    assert np.array_equal(r.render(), par2d.render(scene))


def test_render_into_out_and_regions():
    d = small_example_dict()
    r = par2d.Renderer(d)
    full = r.render()
    padded = np.zeros((192, 300, 3), dtype=np.float32)
    out = padded[:, :256, :]
    assert r.render(out=out) is out
    assert np.array_equal(padded[:, :256], full)
    assert not padded[:, 256:].any()  # bytes past the row are never written
    region = r.render(region=(30, 40, 130, 90))
    assert region.shape == (50, 100, 3)
    assert np.array_equal(region, full[40:90, 30:130])
    rgba = r.render_rgba8(1.5)
    part = r.render_rgba8(1.5, region=(5, 7, 21, 19))
    assert np.array_equal(part, rgba[7:19, 5:21])
    with pytest.raises(par2d.Error, match="region"):
        r.render(region=(0, 0, 257, 10))
    with pytest.raises(par2d.Error, match="out: needs"):
        r.render(out=np.zeros((192, 256, 3), dtype=np.float64))
    with pytest.raises(par2d.Error, match="out: needs"):
        r.render_rgba8(out=np.zeros((192, 256, 3), dtype=np.uint8))


@pytest.mark.parametrize("exposure", [1.0, 2.5])
def test_rgba8_equals_the_png_writers_srgb_bytes(tmp_path, exposure):
    d = small_example_dict()
    r = par2d.Renderer(d)
    frame = r.render()
    rgba = r.render_rgba8(exposure)
    assert rgba.dtype == np.uint8 and rgba.shape == (192, 256, 4)
    assert (rgba[:, :, 3] == 255).all()
    png = tmp_path / "frame.png"
    par2d.write_png(str(png), frame, exposure=exposure)
    expected = read_png_rgb(str(png))
    assert np.array_equal(rgba[:, :, :3], expected)
    assert len(np.unique(expected)) > 20  # a real image, not a flat one


def test_render_releases_the_gil():
    d = small_example_dict()
    r = par2d.Renderer(d, backend="scalar", threads=1, spp=4)
    assert_releases_gil(r.render)


@pytest.mark.parametrize("handle", [-1, 0, 2**64, 2**70, "1", 1.0, True, None])
def test_handles_that_name_nothing_raise_par2d_error(handle):
    r = par2d.Renderer(small_example_dict())
    light = {"circle": {"center": [10, 10], "radius": 2}}
    for call in [lambda: r.update_light(handle, light), lambda: r.remove_light(handle),
                 lambda: r.set_light_emission(handle, [1, 1, 1], 1.0),
                 lambda: r.update_occluder(handle, light), lambda: r.remove_occluder(handle)]:
        with pytest.raises(par2d.Error) as e:
            call()
        assert e.value.code == "invalid_argument"
        assert "handle" in str(e.value)


def test_calls_from_two_threads_are_serialized():
    # One thread renders while another moves a light: every frame is one of the scenes that
    # existed (the renderer is one-thread-at-a-time in C++; the binding serializes calls).
    d = small_example_dict()
    r = par2d.Renderer(d, threads=1)
    h = r.lights[0]
    positions = [[100.0 + 10 * k, 300.0] for k in range(6)]
    expected = []
    for p in positions:
        moved = copy.deepcopy(d)
        moved["lights"][0]["circle"]["center"] = p
        expected.append(par2d.render(moved))
    r.update_light(h, dict(d["lights"][0], circle={"center": positions[0], "radius": d["lights"][0]["circle"]["radius"]}))
    frames = []

    def work():
        for _ in range(8):
            frames.append(r.render())

    worker = threading.Thread(target=work)
    worker.start()
    for p in positions[1:]:
        r.update_light(h, dict(d["lights"][0], circle={"center": p, "radius": d["lights"][0]["circle"]["radius"]}))
        time.sleep(0.002)
    worker.join()
    assert len(frames) == 8
    for f in frames:
        assert any(np.array_equal(f, e) for e in expected)
    assert np.array_equal(r.render(), expected[-1])


def test_light_and_occluder_read_back_what_the_handles_name():
    r = par2d.Renderer(small_example_dict(), threads=1)
    light = {"circle": {"center": [40, 30], "radius": 5}, "color": [1, 0.5, 0.25], "intensity": 2, "range": 80,
             "cone": {"direction": 45, "half_angle": 30, "fade": 10}, "mask": 5}
    occluder = {"polygon": [[10, 10], [20, 10], [20, 20]], "transmittance": [0.5, 0.5, 0.5], "interior": "lit"}
    h = r.add_light(light)
    o = r.add_occluder(occluder)
    assert r.light(h) == light
    assert r.occluder(o) == occluder
    # The scene's own handles too, and what is read back adds the same light again.
    first = r.light(r.lights[0])
    assert first == small_example_dict()["lights"][0]
    assert r.light(r.add_light(first)) == first
    with pytest.raises(par2d.InvalidArgumentError):
        r.light(h + 12345)
    with pytest.raises(par2d.InvalidArgumentError):
        r.occluder(h)  # a light's handle names no occluder


def test_options_and_frame_stats():
    r = par2d.Renderer(small_example_dict(), threads=1, spp=2, isa="scalar", shaded=False)
    o = r.options
    assert o == {"backend": "auto", "threads": 1, "isa": "scalar", "spp": 2, "culling": True, "shaded": False,
                 "sample_needs": False, "bounce": "included"}
    assert r.frame_stats["pixels"] == 0
    r.render()
    s = r.frame_stats
    assert s == {"pixels": 256 * 192, "tiles": 16 * 12, "layer_tiles_reused": 0, "layer_tiles_filled": 0,
                 "bounce_pieces": 0, "bounce_lit_sources": 0}
    diagnostics = r.frame_diagnostics
    assert diagnostics["scalar_tiles"] == 16 * 12 and diagnostics["blocks"] == 0  # the scalar reference's tiles
    assert not set(s) & set(diagnostics) and set(diagnostics) >= {"samples", "tile_pairs", "umbra_hits"}
    r.render(region=(0, 0, 32, 16))
    assert r.frame_stats["pixels"] == 32 * 16
    r.set_options(threads=1, backend="scalar")
    assert r.options["backend"] == "scalar" and r.options["shaded"] is True


def test_sampled_needs_on_request_equal_the_one_shot_counts():
    d = small_example_dict()
    r = par2d.Renderer(d, threads=1, backend="simd", isa="avx2")
    r.render()
    assert r.frame_diagnostics["sampled_pixels"] == 0  # off by default
    r.set_options(threads=1, backend="simd", isa="avx2", sample_needs=True)
    assert r.options["sample_needs"] is True
    r.render()
    s = r.frame_diagnostics
    if r.options["isa"] == "scalar":  # a CPU with no SIMD level: the reference counts no needs
        assert s["sampled_pixels"] == 0
    else:
        # One sampled pixel per tile; culling at work on the small example's walls.
        assert s["sampled_pixels"] == r.frame_stats["tiles"] and s["sampled_visible_lights"] > 0
        assert s["blocks"] > 0 and s["block_proofs_tried"] > 0 and s["tile_pairs"] > 0


def test_incremental_frames_write_only_dirty_rects_and_equal_full_renders():
    d = {"width": 256, "height": 192,
         "lights": [{"circle": {"center": [30, 30], "radius": 2}, "range": 20, "intensity": 2},
                    {"circle": {"center": [200, 150], "radius": 3}, "range": 25}],
         "occluders": [{"polygon": [[100, 20], [110, 20], [110, 170], [100, 170]]}]}
    r = par2d.Renderer(d, threads=2)
    assert r.incremental is False
    r.incremental = True
    assert r.incremental is True
    out = np.zeros((192, 256, 3), dtype=np.float32)
    r.render(out=out)
    assert r.dirty_rects == [(0, 0, 256, 192)]
    # Nothing changed: nothing written (canaries stay), no rectangle.
    saved = out.copy()
    out.fill(12345.0)
    r.render(out=out)
    assert r.dirty_rects == []
    assert r.frame_stats["pixels"] == 0
    assert np.all(out == 12345.0)
    out[...] = saved
    # One torch flickers: only its block is computed, and the frame equals a full render.
    torch = r.lights[0]
    r.set_light_emission(torch, (1.0, 0.5, 0.25), 3.0)
    r.render(out=out)
    assert r.dirty_rects == [(0, 0, 64, 64)]
    assert r.frame_stats["pixels"] == 64 * 64
    assert out.tobytes() == par2d.render(r.snapshot()).tobytes()
    # Without out= every pixel is computed (a new array holds no earlier frame).
    r.render()
    assert r.dirty_rects == [(0, 0, 256, 192)]
    r.force_full_frame()
    r.render(out=out)
    assert r.frame_stats["pixels"] == 256 * 192


def test_light_layer_cache_recombines_a_flicker_within_its_bound():
    d = {"width": 256, "height": 192,
         "lights": [{"circle": {"center": [30, 30], "radius": 2}, "range": 40, "intensity": 2},
                    {"circle": {"center": [200, 150], "radius": 3}, "range": 25}],
         "occluders": [{"polygon": [[50, 10], [54, 10], [54, 60], [50, 60]]}]}
    r = par2d.Renderer(d, threads=2)
    assert r.light_layer_budget == 0
    with pytest.raises(par2d.Error, match="^light_layer_budget: must be >= 0, got -1$"):
        r.light_layer_budget = -1
    r.incremental = True
    r.light_layer_budget = 8 << 20
    assert r.light_layer_budget == 8 << 20
    out = np.zeros((192, 256, 3), dtype=np.float32)
    r.render(out=out)
    simd = r.options["isa"] != "scalar"
    assert (r.frame_stats["layer_tiles_filled"] > 0) == simd
    assert 0 <= r.light_layer_bytes <= 8 << 20
    torch = r.lights[0]
    r.set_light_emission(torch, (1.0, 0.5, 0.25), 3.0)
    r.render(out=out)
    s = r.frame_stats
    assert (s["layer_tiles_reused"] > 0) == simd and s["layer_tiles_filled"] == 0
    full = par2d.render(r.snapshot())
    assert np.max(np.abs(out - full)) <= 1e-6 * 3.0
    r.light_layer_budget = 0
    assert r.light_layer_bytes == 0
    r.render(out=out)
    assert out.tobytes() == par2d.render(r.snapshot()).tobytes()


def test_transforms_place_local_shapes_like_placed_dicts():
    """A crate and a lamp moved by transforms render what the same shapes placed by hand render."""
    by_transform = par2d.Renderer({"width": 48, "height": 32})
    by_hand = par2d.Renderer({"width": 48, "height": 32})
    crate = {"polygon": [[-4, -2], [4, -2], [4, 2], [-4, 2]]}
    h = by_transform.add_occluder(crate, transform={"position": (30, 24), "rotation": 90})
    by_hand.add_occluder({"polygon": [[32, 20], [32, 28], [28, 28], [28, 20]]})
    lamp = by_transform.add_light({"circle": {"center": [0, 0], "radius": 1.5}, "intensity": 2},
                                  transform={"position": np.array([12.0, 10.0]), "scale": 2})
    by_hand.add_light({"circle": {"center": [12, 10], "radius": 3}, "intensity": 2})
    np.testing.assert_array_equal(by_transform.render(), by_hand.render())
    assert by_transform.occluder(h)["polygon"] == [[32, 20], [32, 28], [28, 28], [28, 20]]
    by_transform.update_occluder(h, crate, transform={"position": [20, 30], "scale": (-0.5, 0.5)})
    assert by_transform.occluder(h)["polygon"] == [[22, 29], [18, 29], [18, 31], [22, 31]]
    by_transform.update_light(lamp, {"circle": {"center": [0, 0], "radius": 1.5}, "intensity": 2},
                              transform={"position": (40, 10)})
    assert by_transform.light(lamp)["circle"] == {"center": [40, 10], "radius": 1.5}
    with pytest.raises(par2d.Error) as e:
        by_transform.update_occluder(h, crate, transform={"scale": (1, 0)})
    assert str(e.value) == f"occluder {h}: transform.scale[1]: must be non-zero, got 0"
    with pytest.raises(par2d.Error) as e:
        by_transform.update_light(lamp, {"circle": {"center": [0, 0], "radius": 1}}, transform={"scale": (1, 2)})
    assert "transform.scale: a circle takes the same scale on both axes, got [1, 2]" in str(e.value)
    with pytest.raises((TypeError, ValueError)) as e:
        by_transform.add_occluder(crate, transform={"angle": 3})
    assert "unknown key 'angle' (expected position, rotation, scale)" in str(e.value)
    with pytest.raises((TypeError, ValueError)) as e:
        by_transform.add_occluder(crate, transform={"position": (1,)})
    assert "transform.position" in str(e.value)
    assert by_transform.occluder(h)["polygon"] == [[22, 29], [18, 29], [18, 31], [22, 31]]
