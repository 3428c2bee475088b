"""Scrolling (docs/api.md, "Scrolling"): a camera panning by whole pixels on set_frame's pixel grid.
Each incremental frame shifts the pixels it keeps (frame_shift), writes the uncovered bands and
equals byte for byte a new renderer's frame at the same offset, in float and in 8-bit dithered
output (whose pattern follows the grid).
"""
import numpy as np
import pytest

import par2d

W, H = 160, 96
TORCH = {"circle": {"center": [30, 30], "radius": 2}, "range": 60, "intensity": 2, "color": [1.0, 0.7, 0.4]}
LAMP = {"circle": {"center": [150, 90], "radius": 3}, "intensity": 1.5, "color": [0.4, 0.6, 1.0]}
WALL = {"polygon": [[80, 20], [90, 20], [90, 100], [80, 100]]}
PATH = [(4, 0), (8, 4), (8, 9), (-20, 9), (-20, -40), (300, -40), (302, -37)]


def world(offset=(0, 0)):
    r = par2d.Renderer(threads=2)
    r.set_frame(W, H, (0, 0, 80, 48))  # half a world unit per pixel
    r.add_light(TORCH)
    r.add_light(LAMP)
    r.add_occluder(WALL)
    r.set_view_offset(*offset)
    return r


@pytest.mark.parametrize("output", ["float", "dithered"])
def test_panned_frames_equal_a_renderer_at_that_offset(output):
    r = world()
    r.incremental = True

    def frame(renderer, out=None):
        if output == "float":
            return renderer.render(out=out)
        return renderer.render_rgba8(out=out, dither=True)

    out = frame(r)
    previous_offset = (0, 0)
    for offset in PATH:
        before = out.copy()
        r.set_view_offset(*offset)
        assert r.view_offset == offset
        frame(r, out)
        fresh = frame(world(offset))
        assert np.array_equal(out.view(np.uint8), fresh.view(np.uint8))
        dx, dy = offset[0] - previous_offset[0], offset[1] - previous_offset[1]
        if abs(dx) < W and abs(dy) < H:
            assert r.frame_shift == (dx, dy)
            # Every pixel outside the dirty rectangles is the old one, shifted.
            written = np.zeros((H, W), dtype=bool)
            for x0, y0, x1, y1 in r.dirty_rects:
                written[y0:y1, x0:x1] = True
            ys, xs = np.nonzero(~written)
            assert np.array_equal(out[ys, xs], before[ys + dy, xs + dx])
            assert r.frame_stats["pixels"] < W * H
        else:
            assert r.frame_shift == (0, 0)
        previous_offset = offset
    # The visible rectangle moved with the offset: 302 and -37 pixels of half a unit.
    assert r.view == pytest.approx((151.0, -18.5, 231.0, 29.5))


def test_bad_offsets_are_refused_and_set_frame_starts_again():
    r = world((5, 6))
    with pytest.raises(par2d.Error, match="set_view_offset: .* 2\\^40"):
        r.set_view_offset(2**41, 0)
    with pytest.raises(par2d.Error, match="^x: must be an integer"):
        r.set_view_offset(1.5, 0)
    assert r.view_offset == (5, 6)
    r.set_frame(W, H, (0, 0, 80, 48))
    assert r.view_offset == (0, 0)


def test_a_ring_buffer_holds_each_grid_pixel_in_one_place():
    r = world()
    r.incremental = True
    r.buffer_layout = "ring"
    assert r.buffer_layout == "ring"
    out = r.render()
    for offset in PATH:
        before = out.copy()
        r.set_view_offset(*offset)
        r.render(out=out)
        assert r.frame_shift == (0, 0)
        # Read at the offset, the ring is the frame a renderer at that offset renders.
        shown = np.roll(out, (-(offset[1] % H), -(offset[0] % W)), axis=(0, 1))
        assert np.array_equal(shown.view(np.uint8), world(offset).render().view(np.uint8))
        written = np.zeros((H, W), dtype=bool)
        for x0, y0, x1, y1 in r.dirty_rects:
            assert not written[y0:y1, x0:x1].any()  # disjoint
            written[y0:y1, x0:x1] = True
        assert np.array_equal(out[~written], before[~written])  # nothing else moved
    with pytest.raises(par2d.Error, match="^buffer_layout: "):
        r.buffer_layout = "spiral"
