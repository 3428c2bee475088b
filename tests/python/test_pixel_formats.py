"""The Renderer's pixel formats from Python: render_rgba, render_rgba8 (dither=), render_bgra8 and
render_rgba16f against render's floats and each other, the ordered dither's definition and what it
does to a dark gradient, the half's rounding and saturation, regions, out= checks and incremental
frames into each format.
"""
import os

import numpy as np
import pytest

import par2d

SOURCE_DIR = os.environ["PAR2D_SOURCE_DIR"]
EXAMPLE = os.path.join(SOURCE_DIR, "examples", "colored_lights.json")
W, H = 256, 192


def small_example_dict():
    """examples/colored_lights.json at 256x192 (same view), as a dict."""
    d = par2d.load_scene(EXAMPLE).to_dict()
    d["width"], d["height"] = W, H
    return d


def srgb(v):
    """The sRGB transfer function of linear values in [0, 1]."""
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)


def bayer8():
    """The 8x8 Bayer matrix by its recursion M(2n) = [[4M, 4M + 2], [4M + 3, 4M + 1]], indexed [y, x]."""
    m = np.zeros((1, 1), dtype=np.int64)
    for _ in range(3):
        m = np.block([[4 * m, 4 * m + 2], [4 * m + 3, 4 * m + 1]])
    return m


def encoded(frame, exposure):
    """255 * srgb(clamp(exposure * E, 0, 1)) of a float32 frame's RGB, in double as the library does."""
    return 255.0 * srgb(np.clip(exposure * frame[:, :, :3].astype(np.float64), 0.0, 1.0))


# Every format a Renderer renders, by its call; (dtype, channels) of the array each returns.
CALLS = {
    "render": (lambda r, **k: r.render(**k), np.float32, 3),
    "render_rgba": (lambda r, **k: r.render_rgba(**k), np.float32, 4),
    "render_rgba8": (lambda r, **k: r.render_rgba8(1.5, **k), np.uint8, 4),
    "render_rgba8_dither": (lambda r, **k: r.render_rgba8(1.5, dither=True, **k), np.uint8, 4),
    "render_bgra8": (lambda r, **k: r.render_bgra8(1.5, **k), np.uint8, 4),
    "render_bgra8_dither": (lambda r, **k: r.render_bgra8(1.5, dither=True, **k), np.uint8, 4),
    "render_rgba16f": (lambda r, **k: r.render_rgba16f(**k), np.float16, 4),
}


def test_the_formats_hold_the_float_frame_and_agree_with_each_other():
    r = par2d.Renderer(small_example_dict(), threads=2)
    rgb = r.render()
    rgba = r.render_rgba()
    assert rgba.dtype == np.float32 and rgba.shape == (H, W, 4)
    assert rgba[:, :, :3].tobytes() == rgb.tobytes() and (rgba[:, :, 3] == 1.0).all()

    rgba8 = r.render_rgba8(1.5)
    assert np.array_equal(r.render_rgba8(1.5, dither=False), rgba8)
    bgra8 = r.render_bgra8(1.5)
    assert bgra8.dtype == np.uint8 and bgra8.shape == (H, W, 4)
    assert np.array_equal(bgra8, rgba8[:, :, [2, 1, 0, 3]])
    dithered = r.render_rgba8(1.5, dither=True)
    assert np.array_equal(r.render_bgra8(1.5, dither=True), dithered[:, :, [2, 1, 0, 3]])
    assert (dithered[:, :, 3] == 255).all() and not np.array_equal(dithered, rgba8)

    half = r.render_rgba16f()
    assert half.dtype == np.float16 and half.shape == (H, W, 4)
    assert rgba.max() <= 65504.0  # no saturation here: NumPy's conversion (nearest even) is the reference
    assert half.tobytes() == rgba.astype(np.float16).tobytes()
    assert len(np.unique(half)) > 100  # a real image, not a flat one


def test_the_dithered_codes_are_the_definition_keyed_to_the_frame_pixel():
    r = par2d.Renderer(small_example_dict(), threads=2)
    frame = r.render()
    for exposure in (1.0, 2.5):
        dithered = r.render_rgba8(exposure, dither=True)
        v = encoded(frame, exposure)
        t = ((bayer8() + 0.5) / 64.0)[np.arange(H)[:, None] % 8, np.arange(W)[None, :] % 8][:, :, None]
        want = np.floor(v + t)
        # Where v + t is within rounding error of a whole code the two evaluations may differ.
        exact = np.abs(v + t - np.rint(v + t)) > 1e-9
        assert exact.mean() > 0.99
        assert np.array_equal(dithered[:, :, :3][exact], want[exact])
        rounded = r.render_rgba8(exposure)
        assert np.abs(dithered.astype(int) - rounded.astype(int)).max() <= 1


def test_the_dither_keeps_a_dark_gradients_block_means_where_rounding_bands():
    # A dim light off the left edge: E falls slowly across the frame, a few dozen sRGB codes in all.
    d = {"width": 256, "height": 64,
         "lights": [{"circle": {"center": [-60, 32], "radius": 10}, "intensity": 0.17}]}
    r = par2d.Renderer(d, threads=2)
    frame = r.render()
    dithered = r.render_rgba8(dither=True)[:, :, :3].astype(np.float64)
    rounded = r.render_rgba8()[:, :, :3].astype(np.float64)
    v = encoded(frame, 1.0)
    assert 2.0 < v.min() and v.max() < 40.0 and v.max() - v.min() > 5.0  # dark, and a gradient
    assert len(np.unique(rounded)) < 40  # bands: few codes over 256 columns

    def block_means(a):
        return a.reshape(64 // 8, 8, 256 // 8, 8, 3).mean(axis=(1, 3))

    want = block_means(v)
    dither_error = np.abs(block_means(dithered) - want)
    rounding_error = np.abs(block_means(rounded) - want)
    assert np.abs(dithered - rounded).max() <= 1
    # The 64 thresholds of a block average out to within a small fraction of a code (1/128 for a
    # flat block); rounding is off by up to half a code where a block lies within one band.
    assert dither_error.mean() < 0.25 * rounding_error.mean()
    assert dither_error.max() < 0.15 and rounding_error.max() > 0.3
    assert (dither_error < rounding_error).mean() > 0.75


def test_half_rounds_to_nearest_even_and_saturates_past_the_largest_half():
    # A bright light: E from 1e6 inside it down to a few units in the far corner.
    d = {"width": 128, "height": 96,
         "lights": [{"circle": {"center": [20, 20], "radius": 6}, "intensity": 1e6}],
         "occluders": [{"polygon": [[60, 40], [70, 40], [70, 80], [60, 80]]}]}
    r = par2d.Renderer(d, threads=2)
    rgba = r.render_rgba()
    half = r.render_rgba16f()
    over = rgba > 65504.0
    assert over.any() and (~over & (rgba > 1000.0)).any() and (rgba[:, :, :3] == 0.0).any()
    assert np.isfinite(half).all()
    assert (half[over] == np.float16(65504.0)).all()
    # Everywhere else, NumPy's float16 conversion (nearest even) bit for bit.
    assert half[~over].tobytes() == rgba[~over].astype(np.float16).tobytes()


@pytest.mark.parametrize("name", sorted(CALLS))
def test_regions_equal_the_whole_frames_pixels(name):
    call, dtype, channels = CALLS[name]
    r = par2d.Renderer(small_example_dict(), threads=2)
    whole = call(r)
    assert whole.dtype == dtype and whole.shape == (H, W, channels)
    for region in [(5, 7, 133, 90), (0, 0, W, H), (255, 191, 256, 192), (61, 3, 70, 189)]:
        x0, y0, x1, y1 = region
        part = call(r, region=region)
        assert part.dtype == dtype and part.shape == (y1 - y0, x1 - x0, channels)
        assert part.tobytes() == np.ascontiguousarray(whole[y0:y1, x0:x1]).tobytes(), region


@pytest.mark.parametrize("name", sorted(CALLS))
def test_out_is_filled_in_place_with_padded_rows_and_checked(name):
    call, dtype, channels = CALLS[name]
    r = par2d.Renderer(small_example_dict(), threads=2)
    want = call(r)
    padded = np.zeros((H, W + 9, channels), dtype=dtype)
    out = padded[:, :W]
    assert call(r, out=out) is out
    assert np.array_equal(out, want) and not padded[:, W:].any()  # bytes past a row stay
    wrong = np.float64 if dtype == np.float32 else (np.float32 if dtype == np.float16 else np.float16)
    want_message = (f"out: needs a writable {np.dtype(dtype).name} array of shape ({H}, {W}, {channels}) "
                    "with packed pixels (rows may be padded)")
    for bad in [np.zeros((H, W, channels), dtype=wrong), np.zeros((H, W, 5 - channels + 2), dtype=dtype),
                np.zeros((H, W + 1, channels), dtype=dtype), np.zeros((H, W, channels), dtype=dtype)[:, ::-1],
                np.zeros((H, W, channels), dtype=np.dtype(dtype).newbyteorder()) if dtype != np.uint8 else "x"]:
        with pytest.raises(par2d.InvalidArgumentError) as e:
            call(r, out=bad)
        assert str(e.value) == want_message
    readonly = np.zeros((H, W, channels), dtype=dtype)
    readonly.flags.writeable = False
    with pytest.raises(par2d.InvalidArgumentError, match="^out: needs a writable"):
        call(r, out=readonly)
    assert not readonly.any()


@pytest.mark.parametrize("name", sorted(CALLS))
def test_incremental_frames_into_each_format_equal_a_fresh_render(name):
    call, dtype, channels = CALLS[name]
    d = {"width": W, "height": H,
         "lights": [{"circle": {"center": [30, 30], "radius": 2}, "range": 20, "intensity": 2},
                    {"circle": {"center": [200, 150], "radius": 3}, "range": 25, "intensity": 0.02}],
         "occluders": [{"polygon": [[100, 20], [110, 20], [110, 170], [100, 170]]}],
         "ambient": [0.001, 0.002, 0.003]}
    r = par2d.Renderer(d, threads=2)
    r.incremental = True
    out = np.zeros((H, W, channels), dtype=dtype)
    call(r, out=out)
    assert r.dirty_rects == [(0, 0, W, H)]
    culled = r.options["isa"] != "scalar"  # without culling any change is every block (docs/api.md)
    torch = r.lights[0]
    for step in range(3):
        r.update_light(torch, {"circle": {"center": [34 + 3 * step, 30], "radius": 2}, "range": 20, "intensity": 2})
        call(r, out=out)
        pixels = r.frame_stats["pixels"]
        assert 0 < pixels < W * H if culled else pixels == W * H  # only the torch's blocks
        fresh = call(par2d.Renderer(r.snapshot(), threads=1))
        assert out.tobytes() == fresh.tobytes(), step


@pytest.mark.parametrize("name", ["render_rgba", "render_bgra8_dither", "render_rgba16f"])
def test_a_cancelled_frame_leaves_out_untouched(name):
    call, dtype, channels = CALLS[name]
    r = par2d.Renderer(small_example_dict(), threads=2)
    out = np.full((H, W, channels), 7, dtype=dtype)
    calls = []

    def stop_at_the_first(done, total):
        calls.append((done, total))
        return False

    with pytest.raises(par2d.CancelledError):
        call(r, out=out, progress=stop_at_the_first)
    assert len(calls) == 1 and (out == 7).all()
    done = []
    call(r, out=out, progress=lambda k, n: done.append((k, n)) or True)
    assert done[-1][0] == done[-1][1] and np.array_equal(out, call(r))


def test_bad_arguments_name_their_place():
    r = par2d.Renderer(small_example_dict(), threads=1)
    for place, bad in [("dither", lambda: r.render_rgba8(dither="yes")),
                       ("dither", lambda: r.render_bgra8(1.0, dither=None)),
                       ("exposure", lambda: r.render_bgra8("x")),
                       ("out", lambda: r.render_rgba(out="x")),
                       ("out", lambda: r.render_rgba16f(out=np.zeros((H, W, 4), dtype=np.uint16))),
                       ("region", lambda: r.render_rgba16f(region=(0, 0, 0.5, 4))),
                       ("region", lambda: r.render_bgra8(region=(0, 0, W + 1, 4))),
                       ("progress", lambda: r.render_rgba(progress=3))]:
        with pytest.raises(par2d.Error) as e:
            bad()
        message = str(e.value)
        assert message.startswith(place + ": ") and "\n" not in message, message
        assert e.value.code == "invalid_argument", message


def test_write_png_dithers_a_float_frame_as_render_rgba8_does(tmp_path):
    from test_renderer import read_png_rgb

    r = par2d.Renderer(small_example_dict(), threads=2)
    frame = r.render()
    path = tmp_path / "frame.png"
    par2d.write_png(path, frame, exposure=1.5, dither=True)
    dithered = r.render_rgba8(1.5, dither=True)
    assert np.array_equal(read_png_rgb(str(path)), dithered[:, :, :3])
    par2d.write_png(path, frame, exposure=1.5)
    assert np.array_equal(read_png_rgb(str(path)), r.render_rgba8(1.5)[:, :, :3])
    # Bytes are stored as they are: a dither belongs to the call that made them.
    with pytest.raises(par2d.InvalidArgumentError, match="^dither: applies to float images"):
        par2d.write_png(path, dithered, dither=True)
    assert np.array_equal(read_png_rgb(str(path)), r.render_rgba8(1.5)[:, :, :3])
