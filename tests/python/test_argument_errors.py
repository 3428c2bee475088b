"""Every error the module raises is a par2d.Error naming its place: the argument, or the scene path.

Bad argument types (a float or a string region, a string view, a list where numbers go, ...)
are refused as par2d.Error with code invalid_argument and a one-line message that starts with
the argument's name, never pybind11's TypeError or cast error. Handles are any integer-like
object (NumPy integers included). A NaN or infinity anywhere in a dict is reported at its path.
"""
import pathlib

import numpy as np
import pytest

import par2d

LIGHT = {"circle": {"center": [20.0, 15.0], "radius": 3.0}, "intensity": 2.0}
WALL = {"segment": [[30, 5], [30, 25]]}


def small():
    return {"width": 48, "height": 32, "lights": [LIGHT], "occluders": [WALL]}


def raises_at(place, call, code="invalid_argument"):
    with pytest.raises(par2d.Error) as e:
        call()
    message = str(e.value)
    assert message.startswith(place + ": "), message
    assert "\n" not in message and "pybind" not in message.lower() and "C++" not in message, message
    assert e.value.code == code, message
    return message


# --- regions and views -----------------------------------------------------------------------

@pytest.mark.parametrize("region", [(0.5, 0, 4, 4), (0, 0, 4.0, 4), ("0", 0, 4, 4), "abcd", b"abcd", (0, 0, 4),
                                    (0, 0, 4, 4, 5), 7, {"x0": 0}, (0, 0, None, 4), (0, 0, 2**40, 4)])
def test_bad_region_is_a_par2d_error_naming_region(region):
    r = par2d.Renderer(small(), threads=1)
    raises_at("region", lambda: r.render(region=region))
    raises_at("region", lambda: r.render_rgba8(region=region))


def test_region_takes_any_sequence_of_integer_likes():
    r = par2d.Renderer(small(), threads=1)
    want = r.render(region=(2, 3, 20, 17))
    assert np.array_equal(r.render(region=[2, 3, 20, 17]), want)
    assert np.array_equal(r.render(region=np.array([2, 3, 20, 17], dtype=np.int64)), want)
    assert np.array_equal(r.render(region=tuple(np.uint16(v) for v in (2, 3, 20, 17))), want)


@pytest.mark.parametrize("view", [(0, 0, "a", 8), "abcd", (0, 0, 8), (0, 0, None, 8), [0, 0, [1], 8], 3.0])
def test_bad_view_is_a_par2d_error_naming_view(view):
    r = par2d.Renderer()
    raises_at("view", lambda: r.set_frame(16, 8, view=view))


def test_view_takes_any_sequence_of_numbers():
    r = par2d.Renderer()
    r.set_frame(16, 8, view=[np.float32(-2), 0, np.int64(14), 8.0])
    assert r.view == (-2.0, 0.0, 14.0, 8.0)


# --- handles ---------------------------------------------------------------------------------

class IntLike:
    """Any object with __index__ is an integer."""

    def __init__(self, value):
        self.value = value

    def __index__(self):
        return self.value


@pytest.mark.parametrize("as_type", [int, np.uint64, np.int64, IntLike])
def test_numpy_integer_handles_are_the_same_handle(as_type):
    r = par2d.Renderer(small(), threads=1)
    light, wall = r.lights[0], r.occluders[0]
    lh, wh = as_type(light), as_type(wall)
    r.update_light(lh, dict(LIGHT, intensity=3.0))
    r.set_light_emission(lh, [1.0, 0.5, 0.5], 3.0)
    r.update_occluder(wh, {"segment": [[31, 5], [31, 25]]})
    r.remove_occluder(wh)
    r.remove_light(lh)
    assert r.lights == [] and r.occluders == []
    expected = {"width": 48, "height": 32}
    assert np.array_equal(r.render(), par2d.render(expected))


def test_handles_that_are_not_integers_name_the_handle():
    r = par2d.Renderer(small(), threads=1)
    for handle in [1.0, np.float64(r.lights[0]), "1", None, True, [1]]:
        message = raises_at("handle", lambda: r.remove_light(handle))
        assert "light" in message
        raises_at("handle", lambda: r.update_occluder(handle, WALL))


# --- NaN and infinity in dicts: the scene path, not a JSON column ----------------------------

def test_nan_in_a_dict_scene_names_its_place():
    d = small()
    d["lights"] = [dict(LIGHT, intensity=float("nan"))]
    assert raises_at("<dict>", lambda: par2d.Scene.from_dict(d), "invalid_scene") == \
        "<dict>: lights[0].intensity: not a finite number (nan)"
    d = small()
    d["view"] = [0, 0, float("inf"), 32]
    assert raises_at("level", lambda: par2d.Scene.from_dict(d, name="level"), "invalid_scene") == \
        "level: view[2]: not a finite number (inf)"
    d = small()
    d["occluders"] = [{"polygon": [[0, 0], [4, 0], [4, -float("inf")]]}]
    assert raises_at("<dict>", lambda: par2d.render(d), "invalid_scene") == \
        "<dict>: occluders[0].polygon[2][1]: not a finite number (-inf)"
    d = small()
    d["lights"][0] = dict(LIGHT, circle={"center": [np.float32("nan"), 1.0], "radius": 1.0})
    assert raises_at("<dict>", lambda: par2d.Renderer(d), "invalid_scene") == \
        "<dict>: lights[0].circle.center[0]: not a finite number (nan)"
    d = small()
    d["odd key"] = {"x": [1, float("nan")]}
    assert raises_at("<dict>", lambda: par2d.Scene.from_dict(d), "invalid_scene") == \
        '<dict>: ["odd key"].x[1]: not a finite number (nan)'


def test_nan_in_a_light_occluder_or_directional_dict_names_its_place():
    r = par2d.Renderer(small(), threads=1)
    assert raises_at("add_light", lambda: r.add_light(dict(LIGHT, intensity=float("nan"))), "invalid_scene") == \
        "add_light: intensity: not a finite number (nan)"
    h = r.lights[0]
    assert raises_at(f"light {h}", lambda: r.update_light(h, dict(LIGHT, color=[1, float("inf"), 1])),
                     "invalid_scene") == f"light {h}: color[1]: not a finite number (inf)"
    assert raises_at("add_occluder", lambda: r.add_occluder({"segment": [[0, float("nan")], [1, 1]]}),
                     "invalid_scene") == "add_occluder: segment[0][1]: not a finite number (nan)"
    assert raises_at("set_directional_lights",
                     lambda: r.set_directional_lights([{"angles": [0, float("nan")]}]), "invalid_scene") == \
        "set_directional_lights: directional_lights[0].angles[1]: not a finite number (nan)"


def test_non_json_values_in_dicts_name_their_place():
    d = small()
    d["lights"][0] = dict(LIGHT, color={1, 2, 3})
    assert raises_at("<dict>", lambda: par2d.Scene.from_dict(d), "invalid_scene") == \
        "<dict>: lights[0].color: a set is not a JSON value"
    d = small()
    d["lights"][0] = {(1, 2): 3}
    assert raises_at("<dict>", lambda: par2d.Scene.from_dict(d), "invalid_scene") == \
        "<dict>: lights[0]: a key must be a string, not tuple"
    d = small()
    d["lights"].append(d["lights"])  # a cycle
    raises_at("<dict>", lambda: par2d.Scene.from_dict(d), "invalid_scene")
    # NumPy numbers are numbers: a dict built from arrays works like one of Python floats.
    d = small()
    d["lights"][0] = {"circle": {"center": list(np.array([20.0, 15.0])), "radius": np.float32(3.0)},
                      "intensity": np.int64(2)}
    assert np.array_equal(par2d.render(d), par2d.render(small()))


# --- every other argument --------------------------------------------------------------------

def bad_calls():
    """(place, call) for a wrong type in each argument of each entry point."""
    r = par2d.Renderer(small(), threads=1)
    h = r.lights[0]
    return [
        ("width", lambda: r.set_frame("48", 32)),
        ("height", lambda: r.set_frame(48, 3.5)),
        ("width", lambda: r.set_frame(2**40, 32)),
        ("exposure", lambda: r.render_rgba8("x")),
        ("out", lambda: r.render(out=[[1.0]])),
        ("out", lambda: r.render_rgba8(out="x")),
        ("color", lambda: r.set_light_emission(h, "abc", 1.0)),
        ("color", lambda: r.set_light_emission(h, [1, 1], 1.0)),
        ("intensity", lambda: r.set_light_emission(h, [1, 1, 1], "bright")),
        ("rgb", lambda: r.set_ambient("abc")),
        ("rgb", lambda: r.set_ambient(1)),
        ("rgb", lambda: r.set_ambient([0, "a", 0])),
        ("normal", lambda: r.set_normal([0, 0])),
        ("normal", lambda: r.set_normal(None)),
        ("normal_map", lambda: r.set_normal_map(5)),
        ("normal_map", lambda: r.set_normal_map(np.ones((32, 48), dtype=np.float32))),
        ("backend", lambda: r.set_options(backend=3)),
        ("threads", lambda: r.set_options(threads="x")),
        ("threads", lambda: r.set_options(threads=1.5)),
        ("isa", lambda: r.set_options(isa=2)),
        ("spp", lambda: r.set_options(spp=[1])),
        ("culling", lambda: r.set_options(culling="yes")),
        ("scene", lambda: r.set_scene([1, 2])),
        ("scene", lambda: par2d.Renderer(42)),
        ("threads", lambda: par2d.Renderer(small(), threads="x")),
        ("scene", lambda: par2d.render("scene.json")),
        ("spp", lambda: par2d.render(small(), spp="x")),
        ("rays", lambda: par2d.render(small(), rays=1.5)),
        ("shaded", lambda: par2d.render(small(), shaded=None)),
        ("out", lambda: par2d.render(small(), out=3)),
        ("text", lambda: par2d.Scene.from_json(b"{}")),
        ("name", lambda: par2d.Scene.from_json("{}", name=3)),
        ("name", lambda: par2d.Scene.from_dict(small(), name=None)),
        ("path", lambda: par2d.Scene.load(3)),
        ("path", lambda: par2d.load_scene(None)),
        ("path", lambda: par2d.Scene.from_dict(small()).save(1.5)),
        ("path", lambda: par2d.write_png(3, np.zeros((2, 2, 3), dtype=np.float32))),
        ("image", lambda: par2d.write_png("x.png", "pixels")),
        ("image", lambda: par2d.write_png("x.png", np.zeros((2, 2), dtype=np.float32))),
        ("exposure", lambda: par2d.write_png("x.png", np.zeros((2, 2, 3), dtype=np.float32), exposure="1")),
        ("light_layer_budget", lambda: setattr(r, "light_layer_budget", -1)),
        ("light_layer_budget", lambda: setattr(r, "light_layer_budget", 1.5)),
        ("light_layer_budget", lambda: setattr(r, "light_layer_budget", "10")),
        ("light_layer_budget", lambda: setattr(r, "light_layer_budget", None)),
        ("light_layer_budget", lambda: setattr(r, "light_layer_budget", 2**64)),
        ("incremental", lambda: setattr(r, "incremental", "yes")),
        ("incremental", lambda: setattr(r, "incremental", None)),
        ("incremental", lambda: setattr(r, "incremental", 2)),
    ]


@pytest.mark.parametrize("index", range(len(bad_calls())))
def test_every_bad_argument_is_a_par2d_error_naming_it(index):
    place, call = bad_calls()[index]
    raises_at(place, call)


def test_paths_may_be_pathlike(tmp_path):
    scene = par2d.Scene.from_dict(small())
    path = tmp_path / "s.json"
    scene.save(path)
    assert par2d.load_scene(path).to_json() == scene.to_json()
    assert par2d.Scene.load(pathlib.PurePath(str(path))).to_json() == scene.to_json()
    par2d.write_png(tmp_path / "s.png", par2d.render(scene))
    assert (tmp_path / "s.png").stat().st_size > 0


# --- every property setter and every argument, as a class --------------------------------------

def setters():
    """(class, property name) for each property of the module's classes that can be set."""
    found = []
    for cls in (par2d.Renderer, par2d.Scene):
        for name, value in vars(cls).items():
            if isinstance(value, property) and value.fset is not None:
                found.append((cls, name))
    return found


def test_the_settable_properties_are_found():
    assert {(c.__name__, n) for c, n in setters()} >= {("Renderer", "incremental"), ("Renderer", "light_layer_budget")}


# Settable properties that hold a real number (a work bound in units), not a count or a flag.
REAL_VALUED = {"work_limit"}


@pytest.mark.parametrize("cls, name", setters(), ids=lambda v: getattr(v, "__name__", v))
@pytest.mark.parametrize("value", ["10", None, 1.5, -1, [1], object()], ids=repr)
def test_every_setter_refuses_a_wrong_type_naming_itself_and_keeps_its_value(cls, name, value):
    target = par2d.Renderer(small(), threads=1) if cls is par2d.Renderer else par2d.Scene.from_dict(small())
    before = getattr(target, name)
    if value == 1.5 and name in REAL_VALUED:
        setattr(target, name, value)  # a real number is the right type here
        assert getattr(target, name) == 1.5
        return
    raises_at(name, lambda: setattr(target, name, value))
    assert getattr(target, name) == before


def test_setters_take_integer_likes_and_bools():
    r = par2d.Renderer(small(), threads=1)
    r.light_layer_budget = np.uint32(1 << 20)
    assert r.light_layer_budget == 1 << 20
    r.light_layer_budget = IntLike(4096)
    assert r.light_layer_budget == 4096
    r.incremental = np.bool_(True)
    assert r.incremental is True
    r.incremental = 0
    assert r.incremental is False


def bound_callables():
    """(name, pybind11 signature line) of every function, method and property setter."""
    out = []

    def add(name, fn, setter=False):
        doc = getattr(fn, "__doc__", None) or ""
        for line in doc.splitlines():
            # Overloads are listed as "1. name(...)"; a setter's signature has no name, its
            # first parameter (arg0) is the object.
            line = line.split(". ", 1)[1] if line[:1].isdigit() and ". " in line else line
            if setter and line.startswith("(arg0: "):
                out.append((name, line.replace("(arg0: ", "(self: ", 1)))
            elif line.startswith(name.rsplit(".", 1)[-1] + "("):
                out.append((name, line))

    for name, value in vars(par2d).items():
        if callable(value) and not isinstance(value, type):
            add(name, value)
    for cls in (par2d.Renderer, par2d.Scene):
        for name, value in vars(cls).items():
            if isinstance(value, property):
                if value.fset is not None:
                    add(f"{cls.__name__}.{name}", value.fset, setter=True)
            elif isinstance(value, staticmethod):
                add(f"{cls.__name__}.{name}", value.__func__)
            elif callable(value):
                add(f"{cls.__name__}.{name}", value)
    return out


def test_every_argument_is_converted_by_the_module_not_by_pybind11():
    """pybind11 refuses a typed parameter itself, with a multi-line TypeError naming no place:
    so every parameter but self is a plain object, converted with an error naming it."""
    found = bound_callables()
    names = {n for n, _ in found}
    assert {"render", "write_png", "Renderer.__init__", "Renderer.set_options", "Renderer.incremental",
            "Renderer.light_layer_budget", "Scene.from_dict"} <= names, sorted(names)
    typed = []
    for name, line in found:
        params = line[line.index("(") + 1:line.rindex(")")].split(") -> ")[0]
        for param in params.split(", "):
            if ":" not in param:
                continue  # `*` (keyword-only marker)
            pname, annotation = param.split(":", 1)
            annotation = annotation.split("=", 1)[0].strip()
            if pname.strip() != "self" and annotation != "object":
                typed.append(f"{name}: {param}")
    assert not typed, typed
