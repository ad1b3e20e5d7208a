"""The real-GPU scripts run end to end under the CUDA simulator (smoke tests).

``benchmarks/gpu_check.py`` and ``benchmarks/bench_gpu.py`` are meant for a GPU
machine, where device time is scarce: a broken option or report must show up
here first. Tiny kernel settings (``--tile 4 ...``) keep the simulator quick.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from gpu_env import subprocess_env

pytest.importorskip("numba_cuda", reason="the CUDA simulator comes with numba-cuda")

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
TINY = ["--tile", "4", "--k-chunk", "2", "--threads", "4", "--min-blocks", "6"]


#: Runs a script as __main__ after fixing the simulator's shared-array race
#: (tests/gpu_sim/sim_shared.py), with the script's folder on sys.path.
LAUNCH = """
import runpy, sys
sys.path[:0] = [sys.argv[1], sys.argv[2]]
import sim_shared
sim_shared.install()
sys.argv = sys.argv[3:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""


def run_script(name, *args):
    env = subprocess_env(simulator=True)
    harness = str(Path(__file__).parent / "gpu_sim")
    return subprocess.run(
        [sys.executable, "-c", LAUNCH, str(BENCH), harness, str(BENCH / name), *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_gpu_check_agrees_under_the_simulator():
    proc = run_script("gpu_check.py", "--sizes", "5", "9", "--cpu-method", "table", *TINY)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert "tile 4, k-slice 2, 4 threads/block" in proc.stdout
    assert "34/34 cases agree with method='table'" in proc.stdout


def test_bench_gpu_report_and_json(tmp_path):
    out = tmp_path / "gpu.json"
    proc = run_script(
        "bench_gpu.py", "9", "12", "--allow-simulator", "--cpu-max-n", "0", "--json", str(out),
        *TINY,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert "CUDA simulator (not a GPU)" in proc.stdout and "warm-up" in proc.stdout
    rows = json.loads(out.read_text())
    assert [r["n"] for r in rows] == [9, 12]
    assert all(r["gpu_cost"] > 0 and r["gpu_seconds"] > 0 for r in rows)


def test_scripts_refuse_settings_the_kernels_cannot_take():
    proc = run_script("gpu_check.py", "--tile", "6", "--k-chunk", "4")
    assert proc.returncode == 2
    assert "bad kernel settings" in proc.stderr and "GPU_K_CHUNK must divide" in proc.stderr
