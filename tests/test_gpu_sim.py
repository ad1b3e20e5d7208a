"""Run the GPU kernels and the GPU scripts under numba's CUDA simulator, in a subprocess.

``NUMBA_ENABLE_CUDASIM`` is read when numba is imported, so the simulator cases
(tests/gpu_sim/sim_gpu_cases.py) and the script smoke tests
(tests/gpu_sim/sim_scripts.py) run in a fresh interpreter with it set; the rest
of the suite keeps running in normal mode. Two such processes of about equal
length, which xdist runs side by side: the shipped kernel settings, and the rest.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from gpu_env import subprocess_env

pytest.importorskip("numba_cuda", reason="the CUDA simulator comes with numba-cuda")

SIM = Path(__file__).parent / "gpu_sim"
FILES = [str(SIM / "sim_gpu_cases.py"), str(SIM / "sim_scripts.py")]


@pytest.mark.parametrize(
    "selection",
    ["not shipped", "shipped"],
    ids=["small-tiles-and-scripts", "shipped-settings"],
)
def test_gpu_kernels_under_the_simulator(tmp_path, selection):
    env = subprocess_env(simulator=True)
    cmd = [sys.executable, "-m", "pytest", "-q", "-o", "addopts=", "-p", "no:cacheprovider",
           "--rootdir", str(tmp_path), "-k", selection, *FILES]  # fmt: skip
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-2000:]
    assert " passed" in proc.stdout and "skipped" not in proc.stdout
