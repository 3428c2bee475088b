"""tools/plot_bench.py: plots the committed scaling results, refuses bad input without writing."""
import os
import subprocess
import sys

SOURCE_DIR = os.environ["PAR2D_SOURCE_DIR"]
SCRIPT = os.path.join(SOURCE_DIR, "tools", "plot_bench.py")


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def test_plots_the_committed_results_as_png(tmp_path):
    out = tmp_path / "scaling.png"
    result = run(os.path.join(SOURCE_DIR, "docs", "bench_scaling.json"), str(out))
    assert result.returncode == 0, result.stderr
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    # The IHDR chunk: width and height big-endian at bytes 16..24.
    width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    assert width >= 1000 and height >= 400
    assert os.listdir(tmp_path) == ["scaling.png"]  # no temporary left behind


def test_input_without_scaling_runs_is_refused_in_one_line(tmp_path):
    bench = tmp_path / "other.json"
    bench.write_text('{"benchmarks": [{"name": "scenes/paper", "real_time": 1, "time_unit": "ms"}]}')
    out = tmp_path / "out.png"
    result = run(str(bench), str(out))
    assert result.returncode == 1
    assert result.stderr.startswith(f"plot_bench.py: {bench}: no scaling/")
    assert result.stderr.count("\n") == 1
    assert not out.exists()


def test_unreadable_json_is_refused_in_one_line(tmp_path):
    bench = tmp_path / "broken.json"
    bench.write_text("{not json")
    result = run(str(bench), str(tmp_path / "out.png"))
    assert result.returncode == 1
    assert result.stderr.startswith(f"plot_bench.py: {bench}: ")
    assert result.stderr.count("\n") == 1
    assert os.listdir(tmp_path) == ["broken.json"]


def test_size_grid_ratios_are_tabled_and_plotted(tmp_path):
    runs = []
    for occ_band, light_band, small, large in (("1.5-4", "3-5", 10.0, 200.0), ("4-12", "3-5", 20.0, 100.0),
                                               ("1.5-4", "6-12", 5.0, 50.0)):
        for (lights, occluders), ms in (((16, 256), small), ((256, 4096), large)):
            runs.append({"name": f"scaling/size_grid/occluder_size:{occ_band}/light_size:{light_band}/"
                                 f"occluders:{occluders}/lights:{lights}/culled/real_time",
                         "real_time": ms * 1e6, "time_unit": "ns"})
    # An incomplete cell (no 256 + 4096 run) is left out of the table.
    runs.append({"name": "scaling/size_grid/occluder_size:12-40/light_size:3-5/occluders:256/lights:16/culled/real_time",
                 "real_time": 3.0, "time_unit": "ms"})
    bench = tmp_path / "sizes.json"
    bench.write_text(__import__("json").dumps({"benchmarks": runs}))
    out, sizes = tmp_path / "unused.png", tmp_path / "sizes.png"
    result = run(str(bench), str(out), str(sizes))
    assert result.returncode == 0, result.stderr
    rows = [line for line in result.stdout.splitlines() if line.startswith("| 1") or line.startswith("| 4")]
    assert rows == ["| 1.5-4 | 3-5 | 10 | 200 | 20.0x (over 16x) |",
                    "| 1.5-4 | 6-12 | 5 | 50 | 10.0x |",
                    "| 4-12 | 3-5 | 20 | 100 | 5.0x |"]
    assert sizes.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not out.exists()  # no occluder or light sweep in the input: nothing to plot there
