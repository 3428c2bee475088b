"""Shared check that a par2d call releases the GIL while it renders."""
import threading
import time


def assert_releases_gil(render_call):
    # The call must take 0.05 s or more on one thread; meanwhile this thread keeps running
    # Python. Were the GIL held, no tick could fall inside the call's interval.
    span = {}

    def work():
        span["start"] = time.perf_counter()
        render_call()
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    inside = [t for t in ticks if span["start"] < t < span["end"]]
    assert span["end"] - span["start"] > 0.05
    assert len(inside) >= 10, f"{len(inside)} ticks during a {span['end'] - span['start']:.3f} s render"
