"""The game lighting model from Python: dict keys, Scene properties, Renderer setters, refused values."""
import numpy as np
import pytest

import par2d


def lit_scene():
    """A 6x4 scene using every lighting-model key except normal_map."""
    return {
        "width": 6, "height": 4,
        "ambient": [0.1, 0.2, 0.3],
        "directional_lights": [{"angles": [-30, 45], "color": [1, 0.5, 0.25], "intensity": 2, "mask": 6,
                                "elevation": 30}],
        "normal": [0, 0, 2],
        "lights": [{"circle": {"center": [1, 1], "radius": 0.5}, "range": 50,
                    "cone": {"direction": 90, "half_angle": 40, "fade": 10}, "mask": 5, "elevation": 15}],
        "occluders": [{"segment": [[3, 0], [3, 2]], "transmittance": [0.5, 0.25, 1], "mask": 4, "interior": "lit"},
                      {"circle": {"center": [5, 3], "radius": 0.5}}],
    }


def test_every_key_reaches_the_scene_and_back():
    scene = par2d.Scene.from_dict(lit_scene())
    assert scene.ambient == (0.1, 0.2, 0.3)
    assert scene.directional_lights == [{"angles": (-30.0, 45.0), "color": (1.0, 0.5, 0.25), "intensity": 2.0,
                                         "mask": 6, "elevation": 30.0}]
    assert scene.normal == (0.0, 0.0, 2.0)
    assert scene.normal_map is None and scene.normal_map_path is None
    d = scene.to_dict()
    light = d["lights"][0]
    assert light["range"] == 50 and light["mask"] == 5 and light["elevation"] == 15
    assert light["cone"] == {"direction": 90, "half_angle": 40, "fade": 10}
    glass, wall = d["occluders"]
    assert glass["transmittance"] == [0.5, 0.25, 1] and glass["mask"] == 4 and glass["interior"] == "lit"
    # Defaults are not written.
    assert set(wall) == {"circle"}
    assert par2d.Scene.from_dict(d).to_json() == scene.to_json()


def test_normal_map_array_and_shaded_flag(tmp_path):
    d = lit_scene()
    del d["normal"]
    normals = np.zeros((4, 6, 3), dtype=np.float32)
    normals[..., 2] = 1.0
    normals[0, 5] = (1.0, -1.0, 0.5)
    r = par2d.Renderer(d)
    r.set_normal_map(normals)
    snap = r.snapshot()
    assert snap.normal is None
    np.testing.assert_array_equal(snap.normal_map, normals)
    assert snap.normal_map.shape == (4, 6, 3) and snap.normal_map.dtype == np.float32
    # shaded=False gives the plain irradiance: the same scene's without its normal source.
    tilted = dict(d, normal=[1, 0, 0.2])
    np.testing.assert_array_equal(par2d.render(tilted, shaded=False), par2d.render(d))
    r.clear_normal_source()
    assert r.snapshot().normal_map is None


def test_renderer_setters_refuse_bad_values_and_keep_the_old_ones():
    r = par2d.Renderer(lit_scene())
    r.set_ambient([0.5, 0.5, 0.5])
    with pytest.raises(par2d.Error) as e:
        r.set_ambient([0.5, -1, 0])
    assert str(e.value) == "set_ambient: ambient[1]: must be >= 0, got -1"
    assert e.value.code == "invalid_scene"
    assert r.snapshot().ambient == (0.5, 0.5, 0.5)

    r.set_directional_lights([{"angles": [0, 90]}, {"angles": [100, 120], "mask": 1}])
    with pytest.raises(par2d.Error) as e:
        r.set_directional_lights([{"angles": [0, 90], "elevation": 95}])
    assert str(e.value) == ("set_directional_lights: directional_lights[0].elevation: "
                            "must be between 0 and 90, got 95")
    assert [x["mask"] for x in r.snapshot().directional_lights] == [0xFFFFFFFF, 1]

    with pytest.raises(par2d.Error) as e:
        r.set_normal([0, 0, 0])
    assert str(e.value) == "set_normal: normal: must have a non-zero length"
    assert r.snapshot().normal == (0.0, 0.0, 2.0)
    with pytest.raises(par2d.Error) as e:
        r.set_normal_map(np.ones((3, 6, 3), dtype=np.float32))
    assert "is 6x3 but the image is 6x4" in str(e.value)
    with pytest.raises(par2d.Error):
        r.set_normal_map(np.ones((4, 6), dtype=np.float32))
    assert r.snapshot().normal == (0.0, 0.0, 2.0)


def test_light_and_occluder_dicts_carry_their_terms_with_placed_errors():
    r = par2d.Renderer({"width": 4, "height": 4})
    h = r.add_light({"circle": {"center": [1, 1], "radius": 1}, "range": 3, "mask": 1})
    with pytest.raises(par2d.Error) as e:
        r.update_light(h, {"circle": {"center": [1, 1], "radius": 1}, "cone": {"direction": 0, "half_angle": 30,
                                                                               "fade": 40}})
    assert str(e.value) == f"light {h}: cone.fade: must be between 0 and half_angle, got 40"
    with pytest.raises(par2d.Error) as e:
        r.add_occluder({"segment": [[0, 0], [1, 1]], "mask": 1.5})
    assert str(e.value) == "add_occluder: mask: must be an integer from 0 to 4294967295, got 1.5"
    with pytest.raises(par2d.Error) as e:
        r.add_occluder({"segment": [[0, 0], [1, 1]], "interior": "glass"})
    assert str(e.value) == 'add_occluder: interior: must be "dark" or "lit", got "glass"'
    r.add_occluder({"segment": [[0, 0], [1, 1]], "transmittance": [1, 1, 1], "mask": 2})
    snap = r.snapshot().to_dict()
    assert snap["lights"][0]["range"] == 3 and snap["lights"][0]["mask"] == 1
    assert snap["occluders"][0]["transmittance"] == [1, 1, 1] and snap["occluders"][0]["mask"] == 2


def test_falloff_shapes_the_range_window_and_is_refused_out_of_range():
    def scene(falloff):
        light = {"circle": {"center": [4.5, 8.5], "radius": 1}, "range": 40}
        if falloff is not None:
            light["falloff"] = falloff
        return {"width": 48, "height": 16, "lights": [light]}
    default, two = par2d.render(scene(None)), par2d.render(scene(2))
    assert default.tobytes() == two.tobytes()
    assert "falloff" not in par2d.Scene.from_dict(scene(2)).to_dict()["lights"][0]
    assert par2d.Scene.from_dict(scene(0.5)).to_dict()["lights"][0]["falloff"] == 0.5
    # The pixel 20 units right of the light's edge: window (1 - (d/R)^2)^falloff times the plain value.
    plain = par2d.render({"width": 48, "height": 16,
                          "lights": [{"circle": {"center": [4.5, 8.5], "radius": 1}}]})[8, 25, 0]
    d = 25.5 - 4.5 - 1.0
    for falloff in (0.0, 1.0, 3.5):
        got = par2d.render(scene(falloff))[8, 25, 0]
        assert got == pytest.approx(plain * (1 - (d / 40) ** 2) ** falloff, rel=1e-5)
    r = par2d.Renderer(scene(1))
    with pytest.raises(par2d.Error) as e:
        r.update_light(r.lights[0], {"circle": {"center": [1, 1], "radius": 1}, "range": 5, "falloff": 17})
    assert str(e.value) == f"light {r.lights[0]}: falloff: must be between 0 and 16, got 17"


def test_shadow_strength_and_colour_blend_the_lit_and_shadowed_images():
    def scene(shadow=None, occluded=True):
        light = {"circle": {"center": [8, 2], "radius": 1.5}, "color": [1, 0.5, 0.25], "intensity": 2}
        if shadow is not None:
            light["shadow"] = shadow
        occluders = [{"segment": [[4, 6], [12, 6]]}] if occluded else []
        return {"width": 16, "height": 12, "lights": [light], "occluders": occluders}
    full, bare = par2d.render(scene()), par2d.render(scene(occluded=False))
    assert np.array_equal(par2d.render(scene({"strength": 1})), full)
    assert "shadow" not in par2d.Scene.from_dict(scene({"strength": 1, "color": [0, 0, 0]})).to_dict()["lights"][0]
    shadow = {"strength": 0.6, "color": [1.0, 0.5, 0.0]}
    assert par2d.Scene.from_dict(scene(shadow)).to_dict()["lights"][0]["shadow"] == shadow
    k = 0.6 * (1 - np.array([1.0, 0.5, 0.0]))
    expected = (1 - k) * bare + k * full
    got = par2d.render(scene(shadow))
    assert np.allclose(got, expected, rtol=0, atol=1e-6 * 2)
    assert np.allclose(got[:, :, 0], bare[:, :, 0], rtol=0, atol=1e-6 * 2)  # red passes wholly: k = 0
    assert not np.allclose(got[:, :, 2], bare[:, :, 2], rtol=0, atol=1e-3)  # blue is shadowed (k = 0.6)
    r = par2d.Renderer(scene())
    with pytest.raises(par2d.Error) as e:
        r.update_light(r.lights[0], {"circle": {"center": [1, 1], "radius": 1}, "shadow": {"strength": 2}})
    assert str(e.value) == f"light {r.lights[0]}: shadow.strength: must be between 0 and 1, got 2"


def test_normalize_sets_brightness_apart_from_size():
    # Torches of radius 1, 3 and 6 normalized at 20: the pixel centre 20 units from each
    # center gets intensity * color from it, whatever the radius.
    for radius in (1.0, 3.0, 6.0):
        d = {"width": 48, "height": 16,
             "lights": [{"circle": {"center": [40.5 - 20.0, 8.5], "radius": radius}, "intensity": 2,
                         "color": [1, 0.5, 0.25], "normalize": 20}]}
        e = par2d.render(d)[8, 40]
        assert e == pytest.approx([2.0, 1.0, 0.5], rel=1e-5)
        assert par2d.Scene.from_dict(d).to_dict()["lights"][0]["normalize"] == 20
    with pytest.raises(par2d.Error) as e:
        par2d.render({"width": 4, "height": 4, "lights": [{"circle": {"center": [1, 1], "radius": 1},
                                                           "normalize": 0}]})
    assert "lights[0].normalize: must be > 0, got 0" in str(e.value)


def test_cookie_dicts_with_numpy_knots_render_and_read_back():
    """A cookie from NumPy arrays reads as from lists; a constant one scales the light; refusals are placed."""
    light = {"circle": {"center": [3, 2], "radius": 0.5}, "intensity": 2}
    plain = {"width": 8, "height": 6, "lights": [light]}
    quarter = dict(plain, lights=[dict(light, cookie={"knots": [[30, 0.25]]})])
    np.testing.assert_allclose(par2d.render(quarter), 0.25 * par2d.render(plain), rtol=1e-5, atol=1e-7)
    knots = np.array([[-20.0, 1.0], [45.5, 0.25], [200.0, 0.0]])
    patterned = dict(plain, lights=[dict(light, cookie={"rotation": np.float64(15), "knots": knots})])
    listed = dict(plain, lights=[dict(light, cookie={"rotation": 15, "knots": knots.tolist()})])
    np.testing.assert_array_equal(par2d.render(patterned), par2d.render(listed))
    back = par2d.Scene.from_dict(patterned).to_dict()["lights"][0]["cookie"]
    assert back == {"rotation": 15, "knots": [[-20, 1], [45.5, 0.25], [200, 0]]}
    r = par2d.Renderer(plain)
    h = r.lights[0]
    r.update_light(h, dict(light, cookie={"rotation": 15, "knots": knots}))
    assert r.light(h)["cookie"] == back
    np.testing.assert_array_equal(r.render(), par2d.render(listed))
    with pytest.raises(par2d.Error) as e:
        r.update_light(h, dict(light, cookie={"knots": [[0, 1.5]]}))
    assert str(e.value) == f"light {h}: cookie.knots[0][1]: weight must be between 0 and 1, got 1.5"
    assert r.light(h)["cookie"] == back
    with pytest.raises(par2d.Error) as e:
        par2d.render(dict(plain, lights=[dict(light, cookie={"knots": [[0, 1], [0, 0.5]]})]))
    assert "lights[0].cookie.knots[1][0]: directions must increase, got 0 after 0" in str(e.value)
    with pytest.raises(par2d.Error) as e:
        par2d.render(dict(plain, lights=[dict(light, cookie={"knots": [[0, 1]]},
                                              cone={"direction": 0, "half_angle": 20})]))
    assert "lights[0].cookie: a light takes a cone or a cookie, not both" in str(e.value)


def test_bounce_piece_and_albedo_from_a_renderer():
    """set_bounce changes the piece length like a scene's bounce key; refusals keep the old one."""
    scene = {"width": 24, "height": 16,
             "lights": [{"circle": {"center": [4, 4], "radius": 1.5}, "intensity": 3}],
             "occluders": [{"polygon": [[10, 2], [12, 2], [12, 12], [10, 12]], "albedo": [0.8, 0.4, 0.2]}]}
    r = par2d.Renderer(scene)
    assert r.bounce_piece == 4.0
    r.set_bounce(0.5)
    assert r.bounce_piece == 0.5
    np.testing.assert_array_equal(r.render(), par2d.render(dict(scene, bounce={"piece": 0.5})))
    with pytest.raises(par2d.Error) as e:
        r.set_bounce(0)
    assert str(e.value) == "set_bounce: bounce.piece: must be > 0, got 0"
    assert r.bounce_piece == 0.5
    # The coarse step, set alone (the piece length kept), like a scene's bounce.step.
    assert r.bounce_step == 1
    r.set_bounce(step=4)
    assert (r.bounce_piece, r.bounce_step) == (0.5, 4)
    np.testing.assert_array_equal(r.render(), par2d.render(dict(scene, bounce={"piece": 0.5, "step": 4})))
    assert not np.array_equal(r.render(), par2d.render(dict(scene, bounce={"piece": 0.5})))
    with pytest.raises(par2d.Error) as e:
        r.set_bounce(step=65)
    assert str(e.value) == "set_bounce: bounce.step: must be an integer from 1 to 64, got 65"
    assert r.bounce_step == 4


def test_the_direct_and_bounce_terms_apart():
    """bounce="excluded" is the scene without albedo, "only" what albedo adds; counted in frame_stats."""
    scene = {"width": 24, "height": 16,
             "lights": [{"circle": {"center": [4, 4], "radius": 1.5}, "intensity": 3}],
             "occluders": [{"polygon": [[10, 2], [12, 2], [12, 12], [10, 12]], "albedo": [0.8, 0.4, 0.2]}]}
    dark = dict(scene, occluders=[{"polygon": scene["occluders"][0]["polygon"]}])
    total = par2d.render(scene)
    direct = par2d.render(scene, bounce="excluded")
    bounce = par2d.render(scene, bounce="only")
    np.testing.assert_array_equal(direct, par2d.render(dark))
    assert bounce[10, 8, 0] > 0.0
    assert np.allclose(direct + bounce, total, rtol=0, atol=1e-6 * 3)
    r = par2d.Renderer(scene, bounce="only")
    assert r.options["bounce"] == "only"
    np.testing.assert_array_equal(r.render(), bounce)
    stats = r.frame_stats
    assert stats["bounce_pieces"] == 8 and stats["bounce_lit_sources"] == 1
    r.set_options(bounce="excluded")
    np.testing.assert_array_equal(r.render(), direct)
    with pytest.raises(par2d.Error) as e:
        par2d.render(scene, bounce="indirect")
    assert str(e.value) == 'bounce: unknown name "indirect" (included, excluded, only)'


def test_a_concave_occluder_is_one_occluder_and_shadows_as_its_pieces():
    ell = [[4, 2], [12, 2], [12, 10], [10, 10], [10, 4], [4, 4]]
    pieces = [[[4, 2], [12, 2], [12, 4], [4, 4]], [[10, 4], [12, 4], [12, 10], [10, 10]]]
    light = {"circle": {"center": [2, 11], "radius": 1}, "intensity": 3}
    whole = par2d.render({"width": 16, "height": 12, "lights": [light], "occluders": [{"polygon": ell}]})
    by_hand = par2d.render({"width": 16, "height": 12, "lights": [light],
                            "occluders": [{"polygon": p} for p in pieces]})
    assert np.allclose(whole, by_hand, rtol=0, atol=1e-6 * 3)
    assert whole[3, 8, 0] == 0.0  # inside the wall
    r = par2d.Renderer({"width": 16, "height": 12, "lights": [light], "occluders": [{"polygon": ell}]})
    assert len(r.occluders) == 1
    assert r.snapshot().to_dict()["occluders"][0]["polygon"] == ell
    with pytest.raises(par2d.Error) as e:
        r.update_light(r.lights[0], {"polygon": ell, "range": 5})
    assert str(e.value) == (f"light {r.lights[0]}: range: a concave light takes no range or normalize "
                            "(split it into convex lights)")
    r.update_light(r.lights[0], {"polygon": ell, "intensity": 2})  # a concave light
    assert r.light(r.lights[0])["polygon"] == ell


def test_polygons_with_holes_as_lights_and_occluders():
    """A ring light lights its hole from every side; an occluder's hole is read back as given."""
    scene = {"width": 16, "height": 12,
             "lights": [{"polygon": [[0, 0], [6, 0], [6, 6], [0, 6]], "holes": [[[2, 2], [4, 2], [4, 4], [2, 4]]]}],
             "occluders": [{"polygon": [[8, 0], [16, 0], [16, 8], [8, 8]], "holes": [[[9, 1], [11, 1], [11, 3]]]}]}
    image = par2d.render(scene, backend="scalar")
    # The hole's centre sees the ring in every direction, entered once: e exactly (to 1e-6).
    assert abs(float(image[3, 3, 0]) - 1.0) <= 1e-6
    r = par2d.Renderer(scene)
    assert r.occluder(r.occluders[0])["holes"] == [[[9, 1], [11, 1], [11, 3]]]
    assert r.light(r.lights[0])["holes"] == [[[2, 2], [4, 2], [4, 4], [2, 4]]]
    with pytest.raises(par2d.Error) as e:
        r.add_occluder({"circle": {"center": [2, 2], "radius": 1}, "holes": []})
    assert "holes: only a polygon has holes" in str(e.value)

