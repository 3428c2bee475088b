"""par2d.occluders_from_alpha: NumPy alpha planes and RGBA images to the scene's occluder dicts."""
import numpy as np
import pytest

import par2d


def ring(size=6):
    a = np.full((size, size), 255, np.uint8)
    a[2:4, 2:4] = 0
    return a


def area(points):
    p = np.asarray(points, float)
    q = np.roll(p, -1, axis=0)
    return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]))


def test_a_ring_is_one_occluder_with_a_hole_that_a_scene_accepts_and_renders():
    occluders = par2d.occluders_from_alpha(ring(), tolerance=0)
    assert len(occluders) == 1
    assert len(occluders[0]["polygon"]) == 4 and len(occluders[0]["holes"]) == 1
    assert area(occluders[0]["polygon"]) == 36.0 and area(occluders[0]["holes"][0]) == -4.0
    scene = par2d.Scene.from_dict({"width": 6, "height": 6, "occluders": occluders,
                                   "lights": [{"circle": {"center": [3, 3], "radius": 0.5}}]})
    image = par2d.render(scene, backend="scalar")
    assert image[2, 2, 0] > 0.0  # inside the hole, with the light
    assert image[0, 0, 0] == 0.0  # behind the ring


def test_rgba_reads_the_alpha_channel_and_placement_scales_and_offsets():
    alpha = ring()
    rgba = np.zeros(alpha.shape + (4,), np.uint8)
    rgba[..., :3] = 77
    rgba[..., 3] = alpha
    assert par2d.occluders_from_alpha(rgba) == par2d.occluders_from_alpha(alpha)
    placed = par2d.occluders_from_alpha(alpha, tolerance=0, scale=(2, 0.5), offset=(10, -4))
    assert area(placed[0]["polygon"]) == 36.0
    xs = [p[0] for p in placed[0]["polygon"]]
    ys = [p[1] for p in placed[0]["polygon"]]
    assert (min(xs), max(xs), min(ys), max(ys)) == (10, 22, -4, -1)
    # A non-contiguous view is read as the array it shows.
    wide = np.zeros((6, 12), np.uint8)
    wide[:, ::2] = alpha
    assert par2d.occluders_from_alpha(wide[:, ::2]) == par2d.occluders_from_alpha(alpha)


@pytest.mark.parametrize("seed", range(20))
def test_noise_masks_give_scenes_the_validator_accepts_with_exact_area_at_tolerance_0(seed):
    rng = np.random.default_rng(seed)
    alpha = (rng.random((17, 23)) < 0.55).astype(np.uint8) * 255
    for tolerance in (0.0, 0.5, 2.0):
        occluders = par2d.occluders_from_alpha(alpha, tolerance=tolerance)
        par2d.Scene.from_dict({"width": 23, "height": 17, "occluders": occluders})  # raises if invalid
        if tolerance == 0.0:
            total = sum(abs(area(o["polygon"])) - sum(abs(area(h)) for h in o.get("holes", [])) for o in occluders)
            assert total == np.count_nonzero(alpha)


def test_bad_arguments_raise_naming_them():
    with pytest.raises(par2d.InvalidArgumentError, match="alpha: needs a uint8 array"):
        par2d.occluders_from_alpha(ring().astype(np.float32))
    with pytest.raises(par2d.InvalidArgumentError, match="alpha: needs a uint8 array"):
        par2d.occluders_from_alpha(np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(par2d.InvalidArgumentError, match="tolerance"):
        par2d.occluders_from_alpha(ring(), tolerance=-1)
    with pytest.raises(par2d.InvalidArgumentError, match="threshold"):
        par2d.occluders_from_alpha(ring(), threshold=300)
    with pytest.raises(par2d.InvalidArgumentError, match="scale"):
        par2d.occluders_from_alpha(ring(), scale="big")
    with pytest.raises(par2d.InvalidArgumentError, match=r"polygon 0 \(from pixel \(0, 0\)\) needs 8 vertices"):
        par2d.occluders_from_alpha(ring(), max_vertices=7)
