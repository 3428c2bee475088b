"""What NumPy users pass is accepted, errors are the natural Python exceptions, write_png stores render_rgba8.

NumPy scalars, 0-d arrays and arrays where lists of numbers or points go (scene dicts, light and
occluder dicts, directional lights, regions, views, colors, options) give exactly what the same
plain Python values give. Every par2d.Error is also the built-in exception of its kind: a bad
argument or scene is a ValueError, a file that cannot be read or written an OSError.
"""
import os

import numpy as np
import pytest

import par2d
from test_renderer import read_png_rgb

PLAIN = {
    "width": 48, "height": 32, "view": [0, 0, 96, 64],
    "lights": [{"circle": {"center": [20.0, 15.0], "radius": 3.0}, "color": [1.0, 0.5, 0.25], "intensity": 2.0,
                "mask": 3},
               {"polygon": [[70, 40], [76, 40], [76, 46]], "intensity": 1.5}],
    "occluders": [{"polygon": [[30, 10], [40, 10], [40, 30], [30, 30]]},
                  {"segment": [[50, 5], [60, 20]], "transmittance": [0.5, 0.25, 0.0]}],
    "ambient": [0.01, 0.02, 0.03],
    "directional_lights": [{"angles": [80, 100], "intensity": 0.25}],
}


def with_numpy():
    """PLAIN with NumPy everywhere a number or a list of numbers or points goes."""
    return {
        "width": np.int64(48), "height": np.array(32), "view": np.array([0, 0, 96, 64], dtype=np.float32),
        "lights": [{"circle": {"center": np.array([20.0, 15.0]), "radius": np.float32(3.0)},
                    "color": np.array([1.0, 0.5, 0.25]), "intensity": np.array(2.0), "mask": np.uint32(3)},
                   {"polygon": np.array([[70, 40], [76, 40], [76, 46]], dtype=np.int32),
                    "intensity": np.float64(1.5)}],
        "occluders": [
            {"polygon": np.array([[30.0, 10.0], [40.0, 10.0], [40.0, 30.0], [30.0, 30.0]])},
            {"segment": np.array([[50, 5], [60, 20]]), "transmittance": np.array([0.5, 0.25, 0.0])}],
        "ambient": np.array([0.01, 0.02, 0.03]),
        "directional_lights": [{"angles": np.array([80, 100]), "intensity": np.array(0.25)}],
    }


# --- NumPy values in dicts ----------------------------------------------------------------------

def test_scene_dict_with_numpy_values_is_the_plain_dict():
    want = par2d.render(PLAIN, threads=1)
    assert np.array_equal(par2d.render(with_numpy(), threads=1), want)
    scene = par2d.Scene.from_dict(with_numpy())
    assert scene.to_json() == par2d.Scene.from_dict(PLAIN).to_json()
    assert np.array_equal(par2d.Renderer(with_numpy(), threads=1).render(), want)


def test_numpy_bool_in_a_dict_is_a_bool():
    d = dict(PLAIN, lights=[dict(PLAIN["lights"][0], intensity=np.bool_(True))])
    with pytest.raises(par2d.InvalidSceneError) as e:
        par2d.Scene.from_dict(d)
    assert str(e.value).startswith("<dict>: lights[0].intensity: "), str(e.value)


def test_nan_inside_a_numpy_array_is_reported_at_its_path():
    d = with_numpy()
    d["lights"][0]["circle"]["center"] = np.array([np.nan, 15.0])
    with pytest.raises(par2d.Error) as e:
        par2d.render(d)
    assert str(e.value) == "<dict>: lights[0].circle.center[0]: not a finite number (nan)"
    assert e.value.code == "invalid_scene"


def test_complex_numbers_are_not_json_values():
    d = with_numpy()
    d["ambient"] = np.array([1j, 0, 0])
    with pytest.raises(par2d.Error) as e:
        par2d.render(d)
    assert str(e.value) == "<dict>: ambient[0]: a complex is not a JSON value"


def test_light_and_occluder_dicts_with_numpy_values():
    plain = par2d.Renderer(PLAIN, threads=1)
    numpy = par2d.Renderer(PLAIN, threads=1)
    light = {"circle": {"center": [10, 20], "radius": 2}, "color": [0.5, 1, 1], "cone": {"direction": 90,
             "half_angle": 60}}
    light_np = {"circle": {"center": np.array([10, 20]), "radius": np.int16(2)}, "color": np.array([0.5, 1, 1]),
                "cone": {"direction": np.array(90.0), "half_angle": np.float32(60)}}
    occluder = {"polygon": [[5, 40], [15, 40], [15, 50]], "mask": 1}
    occluder_np = {"polygon": np.array([[5, 40], [15, 40], [15, 50]], dtype=np.float64), "mask": np.array(1)}
    plain.update_light(plain.lights[0], light)
    numpy.update_light(np.array(numpy.lights[0], dtype=np.uint64), light_np)
    plain.add_occluder(occluder)
    numpy.add_occluder(occluder_np)
    plain.add_light(light)
    numpy.add_light(light_np)
    plain.set_directional_lights([{"angles": [10, 30], "elevation": 20}])
    numpy.set_directional_lights([{"angles": np.array([10.0, 30.0]), "elevation": np.int64(20)}])
    assert np.array_equal(numpy.render(), plain.render())
    assert numpy.snapshot().to_json() == plain.snapshot().to_json()


# --- NumPy scalars, 0-d arrays and arrays as arguments ------------------------------------------

def test_arguments_take_numpy_scalars_0d_arrays_and_arrays():
    plain = par2d.Renderer(PLAIN, threads=1, spp=2)
    r = par2d.Renderer(PLAIN, threads=np.array(1), spp=np.int8(2), culling=np.array(True), backend="auto")
    assert np.array_equal(r.render(), plain.render())
    region = (2, 3, 20, 17)
    want = plain.render(region=region)
    for given in (np.array(region), [np.int64(2), np.array(3), 20, np.uint16(17)], np.array(region, dtype=np.uint8)):
        assert np.array_equal(r.render(region=given), want)
    assert np.array_equal(r.render_rgba8(exposure=np.array(1.5), region=np.array(region)),
                          plain.render_rgba8(exposure=1.5, region=region))
    handle = r.lights[0]
    for rr, h, color, intensity in ((plain, handle, (0.25, 0.5, 1.0), 3.0),
                                    (r, np.array(handle), np.array([0.25, 0.5, 1.0]), np.array(3.0))):
        rr.set_light_emission(h, color, intensity)
    plain.set_ambient((0.1, 0.0, 0.2))
    r.set_ambient(np.array([0.1, 0.0, 0.2]))
    plain.set_normal((0.0, 0.5, 1.0))
    r.set_normal(np.array([np.float32(0.0), 0.5, 1.0]))
    plain.set_frame(32, 24, (0, 0, 64, 48))
    r.set_frame(np.int64(32), np.array(24), np.array([0, 0, 64, 48]))
    assert r.view == (0.0, 0.0, 64.0, 48.0)
    assert np.array_equal(r.render(), plain.render())
    assert np.array_equal(par2d.render(PLAIN, threads=np.array(1), spp=np.array(2), rays=np.int32(16)),
                          par2d.render(PLAIN, threads=1, spp=2))


def test_a_0d_float_array_is_no_integer():
    with pytest.raises(par2d.InvalidArgumentError) as e:
        par2d.render(PLAIN, threads=np.array(1.5))
    assert str(e.value) == "threads: must be an integer, not ndarray"
    r = par2d.Renderer(PLAIN, threads=1)
    with pytest.raises(ValueError) as e:
        r.render(region=np.array([0.0, 0.0, 4.0, 4.0]))
    assert str(e.value).startswith("region: needs (x0, y0, x1, y1) integers"), str(e.value)


# --- Errors are the natural Python exceptions ---------------------------------------------------

def test_error_classes_derive_from_par2d_error_and_the_builtin_of_their_kind():
    assert issubclass(par2d.Error, Exception)
    for name, builtin in (("InvalidArgumentError", ValueError), ("InvalidSceneError", ValueError),
                          ("FileError", OSError), ("OutOfMemoryError", MemoryError),
                          ("UnsupportedError", NotImplementedError)):
        cls = getattr(par2d, name)
        assert issubclass(cls, par2d.Error) and issubclass(cls, builtin), name
        assert cls.__module__ == "par2d" and cls.__name__ == name


def test_a_bad_argument_is_a_value_error():
    with pytest.raises(ValueError) as e:
        par2d.render(PLAIN, spp=0)
    assert isinstance(e.value, par2d.InvalidArgumentError) and e.value.code == "invalid_argument"
    with pytest.raises(ValueError) as e:
        par2d.Renderer(PLAIN).remove_light(12345)
    assert isinstance(e.value, par2d.Error) and "12345" in str(e.value)


def test_a_bad_scene_is_a_value_error():
    try:
        par2d.Scene.from_dict({"width": 8, "height": 8, "lights": [{"circle": {"center": [0, 0], "radius": -1}}]})
    except ValueError as e:
        assert type(e) is par2d.InvalidSceneError and e.code == "invalid_scene"
        assert str(e).startswith("<dict>: lights[0].circle.radius"), str(e)
    else:
        pytest.fail("no error")


def test_a_file_failure_is_an_os_error(tmp_path):
    with pytest.raises(OSError) as e:
        par2d.load_scene(tmp_path / "missing.json")
    assert type(e.value) is par2d.FileError and e.value.code == "io_error"
    assert str(e.value).startswith(str(tmp_path / "missing.json")), str(e.value)
    with pytest.raises(OSError) as e:
        par2d.write_png(tmp_path / "no" / "such" / "dir.png", np.zeros((2, 2, 3), np.float32))
    assert isinstance(e.value, par2d.Error) and e.value.code == "io_error"
    assert e.value.args == (str(e.value),)  # OSError keeps the one line as its only argument


# --- write_png stores render_rgba8's array --------------------------------------------------------

def test_write_png_stores_render_rgba8_as_the_float_frame_with_its_exposure(tmp_path):
    r = par2d.Renderer(PLAIN, threads=1)
    rgba = r.render_rgba8(exposure=1.5)
    assert rgba.dtype == np.uint8 and rgba.shape == (32, 48, 4)
    par2d.write_png(tmp_path / "bytes.png", rgba)
    par2d.write_png(tmp_path / "floats.png", r.render(), exposure=1.5)
    assert (tmp_path / "bytes.png").read_bytes() == (tmp_path / "floats.png").read_bytes()
    par2d.write_png(str(tmp_path / "rgb.png"), np.ascontiguousarray(rgba[:, :, :3]))
    assert (tmp_path / "rgb.png").read_bytes() == (tmp_path / "bytes.png").read_bytes()


def test_write_png_keeps_every_byte_value(tmp_path):
    codes = np.arange(256, dtype=np.uint8).reshape(16, 16)
    image = np.stack([codes, codes[::-1], codes.T, np.full_like(codes, 7)], axis=2)  # alpha is not stored
    par2d.write_png(tmp_path / "codes.png", image[:, ::-1])  # strided views too
    assert np.array_equal(read_png_rgb(tmp_path / "codes.png"), image[:, ::-1, :3])


def test_write_png_refuses_an_exposure_for_bytes_and_odd_arrays(tmp_path):
    rgba = np.zeros((4, 4, 4), np.uint8)
    with pytest.raises(par2d.InvalidArgumentError) as e:
        par2d.write_png(tmp_path / "x.png", rgba, exposure=2.0)
    assert str(e.value).startswith("exposure: applies to float images"), str(e.value)
    for bad in (np.zeros((4, 4, 4), np.uint16), np.zeros((4, 4, 2), np.uint8), np.zeros((4, 4), np.float32)):
        with pytest.raises(ValueError) as e:
            par2d.write_png(tmp_path / "x.png", bad)
        assert str(e.value).startswith("image: needs a float32 array of shape (height, width, 3) or a uint8"), str(e.value)
    assert not os.path.exists(tmp_path / "x.png")
