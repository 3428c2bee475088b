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
