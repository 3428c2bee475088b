"""Long renders: the work estimate and limit, progress callbacks, cancelling by the callback and by Ctrl-C."""
import math
import os
import signal
import threading

import numpy as np
import pytest

import par2d

SENTINEL = np.float32(-7.25)


def bounce_dict(width=64, height=48, radius=6.0, piece=0.5):
    """One light beside a white circle wall cut into ceil(2 pi radius / piece) pieces."""
    return {"width": width, "height": height, "bounce": {"piece": piece},
            "lights": [{"circle": {"center": [10, 10], "radius": 3}, "color": [1, 1, 1], "intensity": 2}],
            "occluders": [{"circle": {"center": [36, 28], "radius": radius}, "albedo": [1, 1, 1]}]}


def plain_dict(width=96, height=64):
    return {"width": width, "height": height,
            "lights": [{"circle": {"center": [12, 12], "radius": 3}, "color": [1, 1, 1], "intensity": 1}],
            "occluders": [{"polygon": [[40, 20], [52, 20], [46, 40]]}]}


def tiles(width, height):
    return ((width + 15) // 16) * ((height + 15) // 16)


def sentinel_image(width, height, channels=3):
    return np.full((height, width, channels), SENTINEL, dtype=np.float32)


class Recorder:
    """A progress callback keeping (tiles_done, tiles, thread) of every call; False once at cancel_at."""

    def __init__(self, cancel_at=None):
        self.calls = []
        self.cancel_at = cancel_at

    def __call__(self, done, total):
        self.calls.append((done, total, threading.get_ident()))
        if self.cancel_at is not None and done >= self.cancel_at:
            return False
        return None

    def check(self, total):
        assert self.calls
        dones = [c[0] for c in self.calls]
        assert all(b > a for a, b in zip(dones, dones[1:]))
        assert {c[1] for c in self.calls} == {total}
        assert {c[2] for c in self.calls} == {threading.get_ident()}


def test_estimate_by_counts_and_the_limit_refuses_before_rendering():
    scene = bounce_dict()
    pieces = math.ceil(2 * math.pi * 6.0 / 0.5)
    e = par2d.estimate_work(scene, backend="scalar", bounce="only")
    assert e["samples"] == 64 * 48
    assert e["bounce"] == pieces * (64 * 48 + 1 * (1 + 1))
    assert e["scalar"] == 0 and e["total"] == e["bounce"]
    e = par2d.estimate_work(plain_dict(), backend="scalar", spp=2)
    assert e["scalar"] == 96 * 64 * 2 * 1 * (1 + 1)
    e = par2d.estimate_work(plain_dict(), backend="raycast", rays=32)
    assert e["raycast"] == 32 * (96 * 64) * (1 + 1)

    total = par2d.estimate_work(scene, backend="scalar")["total"]
    out = sentinel_image(64, 48)
    with pytest.raises(par2d.WorkLimitError) as error:
        par2d.render(scene, backend="scalar", work_limit=total * 0.99, out=out)
    assert error.value.code == "work_limit" and isinstance(error.value, RuntimeError)
    assert "work limit" in str(error.value)
    assert (out == SENTINEL).all()
    par2d.render(scene, backend="scalar", work_limit=total, out=out)
    assert not (out == SENTINEL).all()
    with pytest.raises(par2d.InvalidArgumentError):
        par2d.render(scene, work_limit=-1.0)


def test_renderer_estimate_and_work_limit_property():
    r = par2d.Renderer(bounce_dict(), backend="scalar")
    assert r.work_limit == 1e11
    e = r.estimate_work()
    assert e["samples"] == 64 * 48 and e["total"] == e["bounce"] + e["scalar"]
    assert r.estimate_work(region=(0, 0, 16, 16))["samples"] == 256
    with pytest.raises(par2d.InvalidArgumentError):
        r.estimate_work(region=(0, 0, 65, 48))
    r.work_limit = e["total"] / 2
    out = sentinel_image(64, 48)
    with pytest.raises(par2d.WorkLimitError):
        r.render(out=out)
    assert (out == SENTINEL).all()
    r.work_limit = 0  # no limit
    r.render(out=out)
    assert not (out == SENTINEL).all()
    with pytest.raises(par2d.InvalidArgumentError):
        r.work_limit = float("nan")


def test_progress_from_the_calling_thread_rising_to_the_total():
    scene = plain_dict()
    reference = par2d.render(scene, threads=2)
    rec = Recorder()
    image = par2d.render(scene, threads=2, progress=rec)
    rec.check(tiles(96, 64))
    assert rec.calls[-1][0] == tiles(96, 64)
    assert np.array_equal(image, reference)

    r = par2d.Renderer(scene, threads=2)
    rec = Recorder()
    assert np.array_equal(r.render(progress=rec), reference)
    rec.check(tiles(96, 64))
    assert rec.calls[-1][0] == tiles(96, 64)
    rec = Recorder()
    r.render_rgba8(progress=rec, region=(16, 0, 48, 32))
    rec.check(4)
    with pytest.raises(par2d.InvalidArgumentError):
        r.render(progress=3)


def test_progress_returning_false_cancels_with_out_untouched():
    scene = plain_dict()
    r = par2d.Renderer(scene, threads=1)
    out = sentinel_image(96, 64)
    rec = Recorder(cancel_at=2)
    with pytest.raises(par2d.CancelledError) as error:
        r.render(out=out, progress=rec)
    assert error.value.code == "cancelled"
    assert (out == SENTINEL).all()
    assert rec.calls[-1][0] == 2
    r.render(out=out)  # the next frame renders whole
    assert np.array_equal(out, par2d.render(scene))

    out = sentinel_image(96, 64)
    with pytest.raises(par2d.CancelledError):
        par2d.render(scene, threads=1, out=out, progress=Recorder(cancel_at=1))
    assert (out == SENTINEL).all()


def test_an_exception_in_the_callback_cancels_and_propagates():
    out = sentinel_image(96, 64)

    def failing(done, total):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        par2d.Renderer(plain_dict(), threads=1).render(out=out, progress=failing)
    assert (out == SENTINEL).all()


def test_ctrl_c_during_a_render_raises_keyboard_interrupt_with_out_untouched():
    out = sentinel_image(96, 64)
    calls = []

    def interrupt_once(done, total):
        calls.append(done)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)  # what Ctrl-C sends; seen at the next tile

    with pytest.raises(KeyboardInterrupt):
        par2d.Renderer(plain_dict(), threads=1).render(out=out, progress=interrupt_once)
    assert (out == SENTINEL).all()
    assert len(calls) == 1
    with pytest.raises(KeyboardInterrupt):
        calls.clear()
        par2d.render(plain_dict(), threads=1, out=out, progress=interrupt_once)
    assert (out == SENTINEL).all()
