"""What the module reads from files: a normal-map PNG's size is checked against the frame from
its header before a pixel is decoded, and a scene's normal_map path stays in the scene's folder
unless allow_any_path=True (docs/contract.md section 6)."""
import json
import struct
import zlib

import numpy as np
import pytest

import par2d


def chunk(kind, data=b""):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, rgb=None):
    """An 8-bit RGB PNG declaring width x height; without `rgb` it has no pixel data at all (45 bytes)."""
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    if rgb is not None:
        rows = b"".join(b"\x00" + np.ascontiguousarray(row, dtype=np.uint8).tobytes() for row in rgb)
        data += chunk(b"IDAT", zlib.compress(rows))
    return data + chunk(b"IEND")


def facing_viewer(width, height):
    """RGB bytes of a map whose every normal is (0, 0, 1): decodes to (0.0039, 0.0039, 1)."""
    rgb = np.full((height, width, 3), 128, dtype=np.uint8)
    rgb[..., 2] = 255
    return rgb


# --- Normal maps: the PNG's declared size before anything is decoded --------------------------

def test_png_declaring_16000x16000_is_refused_from_its_header_naming_both_sizes(tmp_path):
    huge = tmp_path / "huge.png"
    huge.write_bytes(png(16000, 16000))
    assert huge.stat().st_size == 45
    r = par2d.Renderer(threads=1)
    r.set_frame(6, 4)
    for path in (str(huge), huge):  # str and os.PathLike
        with pytest.raises(par2d.Error) as e:
            r.set_normal_map(path)
        assert str(e.value) == (f"{huge}: is 16000x16000 but the image is 6x4 "
                                "(it must be exactly the image's size)")
        assert e.value.code == "invalid_scene"
    assert r.snapshot().normal_map is None


def test_png_of_the_frames_size_loads(tmp_path):
    good = tmp_path / "good.png"
    good.write_bytes(png(6, 4, facing_viewer(6, 4)))
    r = par2d.Renderer(threads=1)
    r.set_frame(6, 4)
    r.set_normal_map(good)
    snap = r.snapshot().normal_map
    assert snap.shape == (4, 6, 3)
    np.testing.assert_allclose(snap[..., 2], 1.0)
    r.set_frame(6, 4, view=(0, 0, 12, 8))  # same size, other view: the map stays
    wrong = tmp_path / "wrong.png"
    wrong.write_bytes(png(4, 6, facing_viewer(4, 6)))
    with pytest.raises(par2d.Error) as e:
        r.set_normal_map(wrong)
    assert str(e.value) == f"{wrong}: is 4x6 but the image is 6x4 (it must be exactly the image's size)"
    np.testing.assert_array_equal(r.snapshot().normal_map, snap)  # the refused map changed nothing


def test_without_a_frame_only_the_largest_image_side_is_checked(tmp_path):
    beyond = tmp_path / "beyond.png"
    beyond.write_bytes(png(20000, 16))
    r = par2d.Renderer(threads=1)
    with pytest.raises(par2d.Error) as e:
        r.set_normal_map(beyond)
    assert str(e.value) == f"{beyond}: is 20000x16, larger than any image"
    good = tmp_path / "good.png"
    good.write_bytes(png(6, 4, facing_viewer(6, 4)))
    r.set_normal_map(good)  # any size before the first set_frame
    assert r.snapshot().normal_map.shape == (4, 6, 3)


# --- Scene paths: normal_map confined to the scene's folder unless allow_any_path ------------

@pytest.fixture
def scenes(tmp_path):
    """inner/up.json names ../map.png, inner/abs.json names it by its absolute path."""
    (tmp_path / "map.png").write_bytes(png(6, 4, facing_viewer(6, 4)))
    inner = tmp_path / "inner"
    inner.mkdir()
    up = {"width": 6, "height": 4, "normal_map": "../map.png"}
    absolute = {"width": 6, "height": 4, "normal_map": str(tmp_path / "map.png")}
    (inner / "up.json").write_text(json.dumps(up))
    (inner / "abs.json").write_text(json.dumps(absolute))
    return inner, up, absolute


LEAVES = "normal_map: path leaves the scene's folder"
ABSOLUTE = "normal_map: path is absolute; it must be relative to the scene's folder"


def refused(call, message):
    with pytest.raises(par2d.Error) as e:
        call()
    assert str(e.value) == message and e.value.code == "invalid_scene"


def test_scene_files_refuse_paths_out_of_their_folder_by_default(scenes):
    inner, _, _ = scenes
    for name, what in (("up.json", LEAVES), ("abs.json", ABSOLUTE)):
        path = inner / name
        refused(lambda: par2d.Scene.load(path), f"{path}: {what}")
        refused(lambda: par2d.Scene.load(str(path), allow_any_path=False), f"{path}: {what}")
        refused(lambda: par2d.load_scene(path), f"{path}: {what}")


def test_scene_files_take_any_path_when_allowed(scenes):
    inner, _, _ = scenes
    for name in ("up.json", "abs.json"):
        for load in (par2d.Scene.load, par2d.load_scene):
            scene = load(inner / name, allow_any_path=True)
            assert scene.normal_map.shape == (4, 6, 3)
            np.testing.assert_allclose(scene.normal_map[..., 2], 1.0)


def test_json_text_and_dicts_follow_the_same_policy_from_their_names_folder(scenes):
    inner, up, absolute = scenes
    name = str(inner / "scene.json")
    for d, what in ((up, LEAVES), (absolute, ABSOLUTE)):
        refused(lambda: par2d.Scene.from_json(json.dumps(d), name), f"{name}: {what}")
        refused(lambda: par2d.Scene.from_dict(d, name), f"{name}: {what}")
        refused(lambda: par2d.render(d), f"<dict>: {what}")  # its folder: the current one
        assert par2d.Scene.from_json(json.dumps(d), name, allow_any_path=True).normal_map_path == d["normal_map"]
        assert par2d.Scene.from_dict(d, name, allow_any_path=True).normal_map_path == d["normal_map"]


@pytest.mark.parametrize("value", ["yes", 2, None, 1.0])
def test_allow_any_path_must_be_a_bool(scenes, value):
    inner, up, _ = scenes
    for call in (lambda: par2d.Scene.load(inner / "up.json", allow_any_path=value),
                 lambda: par2d.load_scene(inner / "up.json", allow_any_path=value),
                 lambda: par2d.Scene.from_json(json.dumps(up), allow_any_path=value),
                 lambda: par2d.Scene.from_dict(up, allow_any_path=value)):
        with pytest.raises(par2d.Error) as e:
            call()
        assert str(e.value).startswith("allow_any_path: must be True or False, not ")
        assert e.value.code == "invalid_argument"
