"""`par2d view` driven as a person would: real X mouse and key events (xdotool) on an Xvfb display.

The session reloads the watched file, drags a light, resizes one with the wheel, adds and deletes
lights, survives a broken save of the file, then saves (to a new file: never over the opened scene)
and reloads with R; the screenshot must equal `par2d render` of the saved scene byte for byte, and
the window capture must show the same pixels.
"""
import json
import os
import queue
import shutil
import subprocess
import threading
import time

import numpy as np
import pytest
from PIL import Image

CLI = os.environ["PAR2D_CLI"]
SOURCE_DIR = os.environ["PAR2D_SOURCE_DIR"]
TIMEOUT = 60.0  # seconds for any one step (the machine may be shared and slow)


@pytest.fixture(scope="module")
def display():
    """A private Xvfb server; its display name (":N", a free number chosen by Xvfb)."""
    read_fd, write_fd = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                              pass_fds=[write_fd], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_fd)
    with os.fdopen(read_fd) as f:
        number = f.readline().strip()
    assert number.isdigit(), "Xvfb did not report a display"
    yield ":" + number
    server.terminate()
    server.wait(timeout=10)


class Session:
    """A running viewer: its log lines arrive on a queue; xdotool talks to its window."""

    def __init__(self, display, scene_path, *args):
        self.env = dict(os.environ, DISPLAY=display)
        self.proc = subprocess.Popen([CLI, "view", scene_path, "--threads", "2", *args], env=self.env,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.lines = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        self.expect("opened ")
        found = subprocess.run(["xdotool", "search", "--sync", "--name", "^par2d view: "], env=self.env,
                               capture_output=True, text=True, timeout=TIMEOUT)
        self.window = found.stdout.split()[0]

    def _read(self):
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))

    def expect(self, prefix):
        """The next log line, which must start with `prefix` (lines are "view: ..." without the tag)."""
        deadline = time.monotonic() + TIMEOUT
        while True:
            try:
                line = self.lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                pytest.fail(f"viewer never logged {prefix!r}; stderr: {self.proc.stderr.read() if self.proc.poll() is not None else ''}")
            assert line.startswith("view: "), line
            assert line[6:].startswith(prefix), f"expected {prefix!r}, got {line!r}"
            return line[6:]

    def xdotool(self, *args):
        subprocess.run(["xdotool", *args], env=self.env, check=True, timeout=TIMEOUT)

    def move(self, x, y):
        self.xdotool("mousemove", "--window", self.window, str(x), str(y))

    def key(self, name):
        # Real key events (XTEST) to the focused window: the pointer is kept inside ours.
        self.xdotool("key", name)

    def close(self):
        self.move(10, 370)
        self.key("q")
        line = self.expect("closed")
        assert self.proc.wait(timeout=TIMEOUT) == 0
        return line


def write_atomically(path, text):
    with open(path + ".part", "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(path + ".part", path)


def png(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def test_drag_resize_add_delete_reload_and_save(display, tmp_path):
    # examples/colored_lights.json (1024x768 world units) in a 512x384 window: 2 units per pixel.
    original = json.load(open(os.path.join(SOURCE_DIR, "examples", "colored_lights.json"), encoding="utf-8"))
    original["width"], original["height"] = 512, 384
    scene_path = str(tmp_path / "scene.json")
    write_atomically(scene_path, json.dumps(original))
    session = Session(display, scene_path)

    # The watched file changes on disk: the viewer reloads it.
    edited_on_disk = json.loads(json.dumps(original))
    edited_on_disk["lights"][0]["intensity"] = 4
    time.sleep(1.1)  # a new modification time even on coarse-timestamp file systems
    write_atomically(scene_path, json.dumps(edited_on_disk))
    session.expect("reloaded " + scene_path + " (5 lights)")

    # Drag light 0 (a circle at world (230, 200), window pixel (115, 100)) by (50, 30) pixels.
    session.move(115, 100)
    session.xdotool("mousedown", "1")
    for x, y in [(125, 106), (140, 115), (165, 130)]:
        session.move(x, y)
    session.xdotool("mouseup", "1")
    assert session.expect("moved light 0: ") == "moved light 0: circle at (330, 260) radius 14"

    # One wheel notch up over light 1 (radius 12 at world (790, 190)) makes it 10 % larger.
    session.move(395, 95)
    session.xdotool("click", "4")
    line = session.expect("resized light 1: circle at (790, 190) radius ")
    assert float(line.rsplit(" ", 1)[1]) == 12 * 1.1

    # Add a light at window pixel (50, 50) (world (101, 101), radius 10 pixels = 20 units),
    # then delete the segment light 4 from (880, 420) to (930, 600) by pointing at its middle.
    session.move(50, 50)
    session.key("a")
    assert session.expect("added light 5: ") == "added light 5: circle at (101, 101) radius 20"
    session.move(452, 255)
    session.key("d")
    session.expect("deleted light 4 (5 left)")

    # Switch to the scalar path and back to SIMD at the first ISA, and raise the exposure.
    session.key("b")
    session.expect("backend scalar")
    session.key("i")
    session.expect("isa ")
    session.key("plus")

    # A broken save of the file: the error is shown, the edited scene is kept.
    write_atomically(scene_path, '{"width": 512, "height": 384, "lights": [{"circle": {"center": [1, 2]}}]}')
    assert session.expect("reload failed: ").startswith("reload failed: " + scene_path + ": lights[0].circle")

    # S without --save-to never writes the opened file: it picks the first of scene.edited.json,
    # scene.edited-2.json, ... that does not exist yet (here the first is taken).
    taken = tmp_path / "scene.edited.json"
    taken.write_text("not ours")
    saved_path = str(tmp_path / "scene.edited-2.json")
    broken = open(scene_path, encoding="utf-8").read()
    session.key("s")
    saved_line = session.expect("saved " + saved_path + " and ")
    session.expect("captured the window in ")
    assert open(scene_path, encoding="utf-8").read() == broken
    assert taken.read_text() == "not ours"
    # R reloads the opened file at once: it is still broken, so the edits stay.
    session.key("r")
    assert session.expect("reload failed: ").startswith("reload failed: " + scene_path + ": lights[0].circle")
    closed = session.close()
    # One persistent renderer: the world was prepared at opening and at the one good reload;
    # dragging, resizing, adding and deleting lights went through handles (no index rebuilt).
    counts = closed.split("(renderer: ")[1]
    frames = int(counts.split(" frames")[0])
    assert frames >= 6
    assert counts.endswith(" frames, 2 index builds, 2 full prepares)"), closed

    # The saved file holds every edit and nothing else changed.
    saved = json.load(open(saved_path, encoding="utf-8"))
    lights = saved["lights"]
    assert len(lights) == 5
    assert lights[0] == {"circle": {"center": [330, 260], "radius": 14}, "color": [1, 0.25, 0.2], "intensity": 4}
    assert lights[1]["circle"]["radius"] == 12 * 1.1
    assert lights[3] == {"segment": [[90, 700], [300, 680]], "color": [1, 0.8, 0.2], "intensity": 2.5}
    assert lights[4]["circle"] == {"center": [101, 101], "radius": 20}
    assert saved["occluders"] == original["occluders"]

    # The screenshot is `par2d render` of the saved scene with the viewer's backend, ISA and exposure.
    isa = saved_line.split("isa ")[1].split(",")[0]
    assert saved_line.split("bounce ")[1].split(",")[0] == "included"
    reference = str(tmp_path / "reference.png")
    subprocess.run([CLI, "render", saved_path, "-o", reference, "--backend", "simd", "--isa", isa,
                    "--exposure", "1.25"], check=True)
    screenshot = str(tmp_path / "scene.screenshot.png")
    with open(screenshot, "rb") as a, open(reference, "rb") as b:
        assert a.read() == b.read(), "screenshot differs from par2d render of the saved scene"

    # The window shows the same bytes below the heads-up text (top 100 rows): the viewer's
    # Renderer writes sRGB bytes as the PNG writer encodes them; and it differs from the
    # unedited scene there, so the edits are on screen.
    window = png(str(tmp_path / "scene.screenshot.window.png"))
    ref = png(reference)
    assert window.shape == ref.shape == (384, 512, 3)
    assert np.array_equal(window[100:], ref[100:])
    unedited_scene = str(tmp_path / "unedited.json")
    write_atomically(unedited_scene, json.dumps(original))
    unedited = str(tmp_path / "unedited.png")
    subprocess.run([CLI, "render", unedited_scene, "-o", unedited, "--exposure", "1.25"], check=True)
    assert np.abs(png(unedited)[100:] - window[100:]).max() > 50


def test_unloadable_scene_is_refused_before_any_window(display, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"width": 0, "height": 4}')
    result = subprocess.run([CLI, "view", str(bad)], env=dict(os.environ, DISPLAY=display),
                            capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 1
    assert result.stderr.startswith(f"par2d: {bad}: width") and result.stderr.count("\n") == 1
    assert result.stdout == ""


def test_no_display_is_one_line_error(tmp_path):
    scene = tmp_path / "ok.json"
    scene.write_text('{"width": 8, "height": 8}')
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    result = subprocess.run([CLI, "view", str(scene)], env=env, capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 1
    assert result.stderr.startswith("par2d: cannot open a window: ") and result.stderr.count("\n") == 1


def test_the_bounce_key_cycles_the_terms_and_the_screenshot_follows(display, tmp_path):
    # examples/bounce_corner.json's kind of scene: a lamp and a red reflecting wall.
    scene = {"width": 512, "height": 384, "view": [0, 0, 160, 120],
             "lights": [{"circle": {"center": [40, 40], "radius": 6}, "intensity": 4}],
             "occluders": [{"polygon": [[100, 10], [110, 10], [110, 110], [100, 110]], "albedo": [0.9, 0.2, 0.1]}]}
    scene_path = str(tmp_path / "bounce.json")
    write_atomically(scene_path, json.dumps(scene))
    session = Session(display, scene_path)
    session.move(100, 300)
    session.key("g")
    session.expect("bounce excluded")
    session.key("g")
    session.expect("bounce only")
    session.key("s")
    saved_line = session.expect("saved ")
    assert ", bounce only," in saved_line
    session.expect("captured the window in ")
    session.close()
    saved_path = saved_line.split("saved ")[1].split(" and ")[0]
    isa = saved_line.split("isa ")[1].split(",")[0]
    reference = str(tmp_path / "reference.png")
    subprocess.run([CLI, "render", saved_path, "-o", reference, "--backend", "simd", "--isa", isa,
                    "--bounce", "only"], check=True)
    with open(str(tmp_path / "bounce.screenshot.png"), "rb") as a, open(reference, "rb") as b:
        assert a.read() == b.read(), "screenshot differs from par2d render --bounce only"
    # Only the bounce: the light the red wall throws back, red over green over blue.
    shot = png(reference)
    r, g, b = shot[192, 288]  # world (90, 60), between the lamp and the wall
    assert r > g > b
