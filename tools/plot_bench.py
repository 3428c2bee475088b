#!/usr/bin/env python3
"""Plots the scaling benchmark (Google Benchmark JSON) as a PNG: frame time against occluder and light count.

Usage: tools/plot_bench.py BENCH.json OUT.png
BENCH.json is the output of
  par2d_bench --benchmark_filter='^scaling/' --benchmark_out=BENCH.json --benchmark_out_format=json
whose run names are scaling/<sweep>/occluders:<N>/lights:<M>/<culled|unculled>[/skipped:...]/real_time.
"""
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no display needed (CI, Xvfb-less machines)
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FixedLocator, FuncFormatter, LogLocator, NullFormatter  # noqa: E402

NAME = re.compile(
    r"^scaling/(?P<sweep>\w+)/occluders:(?P<occ>\d+)/lights:(?P<lights>\d+)/"
    r"(?P<mode>culled|unculled)(?P<skipped>/skipped:[\w]+)?(/real_time)?$")
TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def fail(message):
    print(f"plot_bench.py: {message}", file=sys.stderr)
    sys.exit(1)


def read_results(path):
    """Returns ({(sweep, mode): {x: ms}}, {(sweep, mode): skipped count}, label)."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")
    runs = doc.get("benchmarks") if isinstance(doc, dict) else None
    if not isinstance(runs, list):
        fail(f"{path}: no \"benchmarks\" array (not Google Benchmark JSON)")
    series, skipped, label = {}, {}, ""
    for run in runs:
        m = NAME.match(str(run.get("name", "")))
        # Repetition aggregates (mean, median, ...) would duplicate points; plot the median if present.
        if not m or run.get("run_type", "iteration") == "aggregate" and run.get("aggregate_name") != "median":
            continue
        key = (m["sweep"], m["mode"])
        if m["skipped"]:
            skipped[key] = skipped.get(key, 0) + 1
            continue
        x = int(m["occ"]) if m["sweep"] == "occluder_sweep" else int(m["lights"])
        if m["sweep"] == "target":
            x = (int(m["lights"]), int(m["occ"]))
        series.setdefault(key, {})[x] = float(run["real_time"]) * TO_MS[run.get("time_unit", "ns")]
        label = run.get("label", label)
    if not any(k[0] in ("occluder_sweep", "light_sweep") for k in series):
        fail(f"{path}: no scaling/occluder_sweep or scaling/light_sweep results "
             "(run par2d_bench --benchmark_filter=^scaling/)")
    return series, skipped, label


def plot(series, skipped, label, out_path):
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2), sharey=True, constrained_layout=True)
    panels = [("occluder_sweep", "occluders (16 lights)", "Occluder sweep"),
              ("light_sweep", "lights (256 occluders)", "Light sweep")]
    for ax, (sweep, xlabel, title) in zip(axes, panels):
        xs_all = set()
        for mode, color, marker in (("culled", "tab:blue", "o"), ("unculled", "tab:orange", "s")):
            pts = sorted(series.get((sweep, mode), {}).items())
            n_skip = skipped.get((sweep, mode), 0)
            if not pts and not n_skip:
                continue
            name = mode + (f" ({n_skip} runs over 3 s skipped)" if n_skip else "")
            if pts:
                xs, ys = zip(*pts)
                xs_all.update(xs)
                ax.plot(xs, ys, marker=marker, color=color, label=name)
                for x, y in pts:
                    ax.annotate(f"{y:.0f}" if y >= 100 else f"{y:.3g}", (x, y), textcoords="offset points", xytext=(0, 7),
                                ha="center", fontsize=8, color=color)
            else:
                ax.plot([], [], marker=marker, color=color, label=name)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.xaxis.set_major_locator(FixedLocator(sorted(xs_all)))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_locator(LogLocator(base=10))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.set_xlabel(xlabel)
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.4)
        ax.grid(True, which="minor", axis="y", alpha=0.15)
        ax.legend(loc="lower right")
    # Whole decades on the shared time axis, so both panels read at a glance and labels fit.
    all_ms = [ms for (sweep, _), pts in series.items() if sweep != "target" for ms in pts.values()]
    axes[0].set_ylim(10 ** math.floor(math.log10(min(all_ms))), 10 ** math.ceil(math.log10(max(all_ms)) + 0.05))
    axes[0].set_ylabel("ms per frame (log scale)")
    targets = sorted(series.get(("target", "culled"), {}).items())
    suptitle = "par2d frame time" + (f" ({label})" if label else "")
    if targets:
        suptitle += "\ntargets (culled): " + ",  ".join(
            f"{l} lights + {o} occluders = {ms:.4g} ms" for (l, o), ms in targets)
    fig.suptitle(suptitle)
    # Written next to the destination and renamed, so a failed write leaves no partial PNG.
    tmp = out_path + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=110)
        os.replace(tmp, out_path)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        fail(f"{out_path}: cannot write PNG: {e.strerror}")


def main(argv):
    if len(argv) != 3:
        print("usage: tools/plot_bench.py BENCH.json OUT.png", file=sys.stderr)
        return 2
    plot(*read_results(argv[1]), argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
