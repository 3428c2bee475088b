"""An engine that re-sends every entity every frame (docs/api.md, cost model): updates with the
values an item already holds mark nothing, so the next incremental frame computes no block,
writes no pixel and reports no dirty rectangle; a real change among them is still computed.
"""
import numpy as np

import par2d

W, H = 192, 128
TORCH = {"circle": {"center": [30, 30], "radius": 2}, "range": 40, "intensity": 2, "color": [1.0, 0.7, 0.4]}
LAMP = {"circle": {"center": [150, 90], "radius": 3}, "intensity": 1.5, "color": [0.4, 0.6, 1.0]}
WALL = {"polygon": [[80, 20], [90, 20], [90, 100], [80, 100]], "transmittance": [0, 0.5, 0]}
CRATE = {"polygon": [[-4, -2], [4, -2], [4, 2], [-4, 2]]}
CRATE_AT = {"position": (120, 40), "rotation": 30, "scale": 1.5}
AMBIENT = (0.01, 0.01, 0.02)


def world():
    r = par2d.Renderer(threads=2)
    r.set_frame(W, H)
    torch, lamp = r.add_light(TORCH), r.add_light(LAMP)
    wall, crate = r.add_occluder(WALL), r.add_occluder(CRATE, transform=CRATE_AT)
    r.set_ambient(AMBIENT)
    return r, torch, lamp, wall, crate


def test_resending_every_value_marks_nothing_and_writes_nothing():
    r, torch, lamp, wall, crate = world()
    r.incremental = True
    out = np.zeros((H, W, 4), dtype=np.uint8)
    r.render_rgba8(out=out)
    assert r.dirty_rects == [(0, 0, W, H)]
    for _ in range(3):
        r.update_light(torch, TORCH)
        r.update_light(lamp, LAMP)
        r.set_light_emission(lamp, LAMP["color"], LAMP["intensity"])
        r.update_light(torch, r.light(torch))  # what the renderer reads back is what it holds
        r.update_occluder(wall, WALL)
        r.update_occluder(crate, CRATE, transform=CRATE_AT)
        r.set_ambient(AMBIENT)
        out.fill(0xA5)
        r.render_rgba8(out=out)
        assert r.dirty_rects == [] and r.frame_stats["pixels"] == 0
        assert (out == 0xA5).all()


def test_a_real_change_among_the_resent_values_is_computed():
    r, torch, lamp, wall, crate = world()
    r.incremental = True
    out = r.render()
    r.render(out=out)
    # The torch dims; everything else is re-sent as it was.
    r.update_light(torch, dict(TORCH, intensity=2.5))
    r.update_light(lamp, LAMP)
    r.update_occluder(wall, WALL)
    r.update_occluder(crate, CRATE, transform=CRATE_AT)
    r.set_ambient(AMBIENT)
    r.render(out=out)
    pixels = r.frame_stats["pixels"]
    culled = r.options["isa"] != "scalar"  # without culling any change is every block (docs/api.md)
    assert r.dirty_rects and (0 < pixels < W * H if culled else pixels == W * H)
    assert out.tobytes() == par2d.render(r.snapshot()).tobytes()
    # The ambient changes: every block.
    r.set_ambient((0.01, 0.01, 0.03))
    r.render(out=out)
    assert r.dirty_rects == [(0, 0, W, H)]
    assert out.tobytes() == par2d.render(r.snapshot()).tobytes()
