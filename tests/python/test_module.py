"""The Python module: scenes from dicts, JSON and files; arrays equal to the CLI's; errors; the GIL."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import par2d
from gil_check import assert_releases_gil

SOURCE_DIR = os.environ["PAR2D_SOURCE_DIR"]
CLI = os.environ["PAR2D_CLI"]
EXAMPLE = os.path.join(SOURCE_DIR, "examples", "colored_lights.json")


def one_circle_light(x=40.0, y=30.0, radius=4.0, intensity=2.0, size=(64, 48)):
    return {"width": size[0], "height": size[1],
            "lights": [{"circle": {"center": [x, y], "radius": radius}, "intensity": intensity}]}


def small_example(tmp_path):
    """examples/colored_lights.json at 256x192 (same view), saved to a file: (Scene, path)."""
    d = par2d.load_scene(EXAMPLE).to_dict()
    d["width"], d["height"] = 256, 192
    scene = par2d.Scene.from_dict(d)
    path = tmp_path / "small.json"
    scene.save(str(path))
    return scene, str(path)


def read_pfm(path):
    """A PF file as an (H, W, 3) float32 array, top row first (PFM stores bottom row first)."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)[::-1]


def test_render_returns_float32_height_width_3():
    image = par2d.render(par2d.Scene.from_dict(one_circle_light()))
    assert image.dtype == np.float32
    assert image.shape == (48, 64, 3)
    assert image.flags.c_contiguous


def test_circle_light_matches_closed_form():
    # docs/contract.md section 1: a circle of radius r at distance d gives e * 2 asin(r/d) / (2 pi).
    image = par2d.render(one_circle_light(), backend="scalar")
    for i, j in [(0, 0), (63, 47), (10, 30), (40, 5)]:
        d = math.hypot(i + 0.5 - 40.0, j + 0.5 - 30.0)
        expected = 2.0 * 2.0 * math.asin(4.0 / d) / (2.0 * math.pi)
        assert image[j, i] == pytest.approx([expected] * 3, rel=1e-6)


def test_render_equals_cli_pfm_for_every_backend(tmp_path):
    scene, path = small_example(tmp_path)
    for backend in ["auto", "simd", "scalar"]:
        pfm = tmp_path / f"{backend}.pfm"
        subprocess.run([CLI, "render", path, "--pfm", str(pfm), "--backend", backend], check=True)
        # The same library call on the same scene: bit-identical, whatever the thread count.
        image = par2d.render(scene, backend=backend, threads=1)
        assert np.array_equal(image, read_pfm(pfm)), backend


def test_dict_file_and_json_scenes_are_the_same():
    from_file = par2d.Scene.load(EXAMPLE)
    with open(EXAMPLE, encoding="utf-8") as f:
        text = f.read()
    from_json = par2d.Scene.from_json(text)
    from_dict = par2d.Scene.from_dict(json.loads(text))
    reference = par2d.render(from_file)
    assert np.array_equal(par2d.render(from_json), reference)
    assert np.array_equal(par2d.render(from_dict), reference)
    assert from_dict.to_json() == from_file.to_json()
    assert (from_file.width, from_file.height) == (1024, 768)
    assert from_file.shape == (768, 1024, 3)
    assert from_file.light_count == 5


def test_to_dict_round_trips_and_edits_move_the_light():
    scene = par2d.Scene.from_dict(one_circle_light())
    d = scene.to_dict()
    assert d["lights"][0]["color"] == [1, 1, 1]  # defaults are written out
    assert par2d.Scene.from_dict(d).to_json() == scene.to_json()
    d["lights"][0]["circle"]["center"] = [10.0, 10.0]
    moved = par2d.render(d, backend="scalar")
    # The pixels inside the light get its full emission (2); their centroid is the new center.
    rows, cols = np.nonzero(moved[:, :, 0] == np.float32(2.0))
    assert len(rows) > 30
    assert abs(np.mean(cols + 0.5) - 10.0) < 0.1 and abs(np.mean(rows + 0.5) - 10.0) < 0.1


def test_save_writes_a_file_the_cli_renders(tmp_path):
    path = tmp_path / "saved.json"
    scene = par2d.Scene.from_dict(one_circle_light())
    scene.save(str(path))
    assert par2d.Scene.load(str(path)).to_json() == scene.to_json()
    pfm = tmp_path / "saved.pfm"
    subprocess.run([CLI, "render", str(path), "--pfm", str(pfm)], check=True)
    assert np.array_equal(par2d.render(scene, threads=1), read_pfm(pfm))


def test_render_into_out_with_padded_rows():
    scene = par2d.Scene.from_dict(one_circle_light())
    storage = np.full((48, 70, 3), -1.0, dtype=np.float32)
    out = storage[:, :64, :]  # rows padded by 6 pixels
    result = par2d.render(scene, out=out)
    assert result is out
    assert np.array_equal(out, par2d.render(scene))
    assert np.all(storage[:, 64:, :] == -1.0)  # the padding is untouched


@pytest.mark.parametrize("out", [
    np.zeros((48, 64, 3), dtype=np.float64),
    np.zeros((48, 63, 3), dtype=np.float32),
    np.zeros((48, 64, 4), dtype=np.float32),
    np.zeros((48, 64, 3), dtype=np.float32)[:, ::2, :].repeat(2, axis=1)[:, ::-1, :],
])
def test_render_into_a_wrong_array_raises(out):
    with pytest.raises(par2d.Error) as e:
        par2d.render(one_circle_light(), out=out)
    assert e.value.code == "invalid_argument"
    assert str(e.value).startswith("out: needs a writable float32 array of shape (48, 64, 3)")


def test_isa_option_and_names(tmp_path):
    assert par2d.detect_isa() in ["scalar", "sse4", "avx2", "avx512"]
    scene, _ = small_example(tmp_path)
    reference = par2d.render(scene, backend="scalar")
    e_max = 5.0 + 5.0 + 5.0 + 2.5 + 2.5  # sum of each light's largest channel
    for isa in ["scalar", "sse4", "avx2", "avx512"]:
        image = par2d.render(scene, backend="simd", isa=isa)
        # docs/contract.md section 5 bound, away from boundaries: checked on the median pixel error.
        assert np.median(np.abs(image - reference)) <= 1e-4 * e_max, isa


def test_bad_scene_raises_with_the_loaders_one_line_message():
    bad = one_circle_light()
    bad["lights"].append({"polygon": [[0, 0], [10, 10], [10, 0], [0, 10]]})
    with pytest.raises(par2d.Error) as e:
        par2d.Scene.from_dict(bad, name="level")
    assert str(e.value) == "level: lights[1].polygon: edges 0 and 2 cross"
    assert e.value.code == "invalid_scene"
    with pytest.raises(par2d.Error) as e:
        par2d.render(dict(bad, colour=[1, 1, 1]))
    assert str(e.value).startswith("<dict>: ")
    assert "\n" not in str(e.value)


def test_non_finite_and_non_json_values_are_refused():
    nan = one_circle_light(radius=float("nan"))
    with pytest.raises(par2d.Error) as e:
        par2d.Scene.from_dict(nan)
    assert str(e.value).startswith("<dict>: ") and "\n" not in str(e.value)
    with pytest.raises(par2d.Error) as e:
        par2d.Scene.from_dict({"width": 4, "height": 4, "lights": {1, 2}})
    assert e.value.code == "invalid_scene"
    with pytest.raises(par2d.Error) as e:
        par2d.Scene.from_dict([1, 2])
    assert str(e.value) == "<dict>: a scene must be a dict, not list"


def test_missing_file_and_bad_options_raise():
    with pytest.raises(par2d.Error) as e:
        par2d.load_scene("/nonexistent/scene.json")
    assert e.value.code == "io_error"
    assert str(e.value).startswith("/nonexistent/scene.json: ")
    with pytest.raises(par2d.Error) as e:
        par2d.render(one_circle_light(), backend="gpu")
    assert str(e.value) == 'backend: unknown name "gpu" (auto, simd, scalar, raycast)'
    # The one-shot render still has the ray-casting baseline (par2d::render_raycast): near the
    # exact image, not equal to it, and it checks its rays.
    rays = par2d.render(one_circle_light(), backend="raycast", rays=256)
    exact = par2d.render(one_circle_light())
    assert rays.shape == exact.shape and np.all(np.isfinite(rays)) and rays.max() > 0
    assert np.max(np.abs(rays - exact)) <= 0.05 * exact.max() and not np.array_equal(rays, exact)
    with pytest.raises(par2d.Error, match="^render_raycast: rays must be in 1..1048576$"):
        par2d.render(one_circle_light(), backend="raycast", rays=0)
    with pytest.raises(par2d.Error) as e:
        par2d.render(one_circle_light(), isa="neon2")
    assert e.value.code == "invalid_argument"
    with pytest.raises(par2d.Error) as e:
        par2d.render(one_circle_light(), spp=0)
    assert e.value.code == "invalid_argument" and "\n" not in str(e.value)


def test_write_png_writes_what_the_cli_writes(tmp_path):
    scene = par2d.Scene.load(EXAMPLE)
    ours = tmp_path / "ours.png"
    par2d.write_png(str(ours), par2d.render(scene, threads=1), exposure=2.0)
    cli = tmp_path / "cli.png"
    subprocess.run([CLI, "render", EXAMPLE, "-o", str(cli), "--exposure", "2"], check=True)
    assert ours.read_bytes() == cli.read_bytes()
    with pytest.raises(par2d.Error) as e:
        par2d.write_png(str(tmp_path / "no" / "x.png"), par2d.render(scene))
    assert e.value.code == "io_error"


def test_render_releases_the_gil(tmp_path):
    # A scalar render of ~0.2 s or more on one thread; meanwhile this thread keeps running
    # Python. Were the GIL held, no tick could fall inside the render's interval.
    scene, _ = small_example(tmp_path)
    assert_releases_gil(lambda: par2d.render(scene, backend="scalar", threads=1))
