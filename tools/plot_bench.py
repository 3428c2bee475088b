#!/usr/bin/env python3
"""Plots the scaling benchmark (Google Benchmark JSON) as a PNG: frame time against occluder and light count.

Usage: tools/plot_bench.py BENCH.json OUT.png [SIZES.png]
BENCH.json is the output of
  par2d_bench --benchmark_filter='^scaling/' --benchmark_out=BENCH.json --benchmark_out_format=json
whose run names are scaling/<sweep>/occluders:<N>/lights:<M>/<culled|unculled>[/skipped:...]/real_time
(plotted to OUT.png) and
scaling/size_grid/occluder_size:<A-B>/light_size:<C-D>/occluders:<N>/lights:<M>/culled/real_time:
the ratio of 256 lights + 4096 occluders to 16 + 256 per size band, plotted to SIZES.png and
printed as a Markdown table.
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
SIZE_NAME = re.compile(
    r"^scaling/size_grid/occluder_size:(?P<occ_band>[\d.]+-[\d.]+)/light_size:(?P<light_band>[\d.]+-[\d.]+)/"
    r"occluders:(?P<occ>\d+)/lights:(?P<lights>\d+)/culled(/real_time)?$")
TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
SIZE_TARGET = 16.0  # 256 lights + 4096 occluders at most 16x the cost of 16 + 256


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
    series, skipped, label, sizes = {}, {}, "", {}
    for run in runs:
        # Repetition aggregates (mean, median, ...) would duplicate points; plot the median if present.
        if run.get("run_type", "iteration") == "aggregate" and run.get("aggregate_name") != "median":
            continue
        name = str(run.get("name", ""))
        if run.get("run_type") == "aggregate":
            name = name.rsplit("_median", 1)[0]
        sm = SIZE_NAME.match(name)
        if sm and not run.get("error_occurred"):
            key = (sm["occ_band"], sm["light_band"])
            sizes.setdefault(key, {})[(int(sm["lights"]), int(sm["occ"]))] = \
                float(run["real_time"]) * TO_MS[run.get("time_unit", "ns")]
            label = run.get("label", label)
            continue
        m = NAME.match(name)
        if not m:
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
    if not sizes and not any(k[0] in ("occluder_sweep", "light_sweep") for k in series):
        fail(f"{path}: no scaling/ sweep or size_grid results "
             "(run par2d_bench --benchmark_filter=^scaling/)")
    return series, skipped, label, sizes


def band_key(band):
    return tuple(float(v) for v in band.split("-"))


def size_ratios(sizes):
    """[(occluder band, light band, ms 16+256, ms 256+4096, ratio)] for the complete cells."""
    rows = []
    for (occ_band, light_band), pts in sorted(sizes.items(), key=lambda kv: (band_key(kv[0][0]), band_key(kv[0][1]))):
        small, large = pts.get((16, 256)), pts.get((256, 4096))
        if small and large:
            rows.append((occ_band, light_band, small, large, large / small))
    return rows


def print_size_table(rows):
    print("| occluder size (px) | light size (px) | 16 lights + 256 occluders (ms) | 256 + 4096 (ms) | ratio |")
    print("|---|---|---|---|---|")
    for occ_band, light_band, small, large, ratio in rows:
        mark = "" if ratio <= SIZE_TARGET else " (over 16x)"
        print(f"| {occ_band} | {light_band} | {small:.4g} | {large:.4g} | {ratio:.1f}x{mark} |")


def save(fig, out_path):
    # Written next to the destination and renamed, so a failed write leaves no partial PNG.
    tmp = out_path + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=110)
        os.replace(tmp, out_path)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        fail(f"{out_path}: cannot write PNG: {e.strerror}")


def plot_sizes(rows, label, out_path):
    light_bands = sorted({r[1] for r in rows}, key=band_key)
    occ_bands = sorted({r[0] for r in rows}, key=band_key)
    fig, ax = plt.subplots(figsize=(8, 4.8), constrained_layout=True)
    width = 0.8 / max(1, len(light_bands))
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
    for li, light_band in enumerate(light_bands):
        xs, ys = [], []
        for oi, occ_band in enumerate(occ_bands):
            for r in rows:
                if r[0] == occ_band and r[1] == light_band:
                    xs.append(oi + (li - (len(light_bands) - 1) / 2) * width)
                    ys.append(r[4])
        bars = ax.bar(xs, ys, width=width * 0.95, color=colors[li % len(colors)], label=f"lights {light_band} px")
        for bar, y in zip(bars, ys):
            ax.annotate(f"{y:.1f}x", (bar.get_x() + bar.get_width() / 2, y), textcoords="offset points",
                        xytext=(0, 3), ha="center", fontsize=8)
    ax.axhline(SIZE_TARGET, color="black", linestyle="--", linewidth=1, label="goal: 16x")
    ax.set_xticks(range(len(occ_bands)))
    ax.set_xticklabels([f"occluders {b} px" for b in occ_bands])
    ax.set_ylabel("cost of 256 lights + 4096 occluders\nover 16 lights + 256 occluders")
    ax.set_title("par2d: cost ratio per size band" + (f" ({label})" if label else ""))
    ax.legend(loc="upper right")
    ax.grid(True, axis="y", alpha=0.4)
    save(fig, out_path)


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
    save(fig, out_path)


def main(argv):
    if len(argv) not in (3, 4):
        print("usage: tools/plot_bench.py BENCH.json OUT.png [SIZES.png]", file=sys.stderr)
        return 2
    series, skipped, label, sizes = read_results(argv[1])
    if any(k[0] in ("occluder_sweep", "light_sweep") for k in series):
        plot(series, skipped, label, argv[2])
    rows = size_ratios(sizes)
    if rows:
        print_size_table(rows)
        if len(argv) == 4:
            plot_sizes(rows, label, argv[3])
    elif len(argv) == 4:
        fail(f"{argv[1]}: no complete scaling/size_grid cells to plot")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
