"""The real-GPU scripts run end to end under the CUDA simulator (smoke tests).

``benchmarks/gpu_check.py`` and ``benchmarks/bench_gpu.py`` are meant for a GPU
machine, where device time is scarce: a broken option or report must show up
here first. Not collected by the main test run: ``tests/test_gpu_sim.py`` runs
this file in the simulator process with ``sim_gpu_cases.py``, and each script
runs there as ``__main__`` (as ``python benchmarks/NAME.py ...`` would), its exit
status and output captured. Tiny kernel settings (``--tile 4 ...``) keep the
simulator quick.
"""

from __future__ import annotations

import json
import os
import runpy
import sys
from pathlib import Path

import pytest

if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":  # pragma: no cover
    pytest.skip("run through tests/test_gpu_sim.py (needs the simulator)", allow_module_level=True)

sys.path.insert(0, os.path.dirname(__file__))
import sim_harness  # noqa: E402

sim_harness.install()

from optri import config  # noqa: E402

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
TINY = ["--tile", "4", "--k-chunk", "2", "--threads", "4", "--min-blocks", "6"]


@pytest.fixture
def run_script(monkeypatch, capsys):
    """``run(name, *args) -> (exit status, stdout, stderr)`` of a script in benchmarks/."""
    monkeypatch.syspath_prepend(str(BENCH))  # the scripts import gpu_settings from there

    def run(name, *args):
        path = str(BENCH / name)
        monkeypatch.setattr(sys, "argv", [path, *args])
        try:
            runpy.run_path(path, run_name="__main__")
            status = 0
        except SystemExit as exc:
            status = exc.code
        out = capsys.readouterr()
        return status, out.out, out.err

    yield run
    config.reset()  # the scripts set config.GPU_* from their options


def test_gpu_check_agrees_under_the_simulator(run_script):
    status, out, err = run_script("gpu_check.py", "--sizes", "5", "9", "--cpu-method", "table",
                                  *TINY)  # fmt: skip
    assert status == 0, out[-4000:] + err[-2000:]
    assert "tile 4, k-slice 2, 4 threads/block" in out
    assert "34/34 cases agree with method='table'" in out


def test_bench_gpu_report_and_json(run_script, tmp_path):
    out_json = tmp_path / "gpu.json"
    status, out, err = run_script(
        "bench_gpu.py", "9", "12", "--allow-simulator", "--cpu-max-n", "0", "--json", str(out_json),
        *TINY,
    )  # fmt: skip
    assert status == 0, out[-4000:] + err[-2000:]
    assert "CUDA simulator (not a GPU)" in out and "warm-up" in out
    rows = json.loads(out_json.read_text())
    assert [r["n"] for r in rows] == [9, 12]
    assert all(r["gpu_cost"] > 0 and r["gpu_seconds"] > 0 for r in rows)


def test_scripts_refuse_settings_the_kernels_cannot_take(run_script):
    status, _, err = run_script("gpu_check.py", "--tile", "6", "--k-chunk", "4")
    assert status == 2
    assert "bad kernel settings" in err and "GPU_K_CHUNK must divide" in err
