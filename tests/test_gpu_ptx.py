"""Real CUDA compilation (to PTX, no GPU needed) of every GPU kernel, in a subprocess.

The compile patches numba-cuda for a driverless machine, so it runs in its own
interpreter (tests/gpu_sim/ptx_compile.py); it is skipped where libnvvm or
libdevice is missing.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from gpu_env import subprocess_env

pytest.importorskip("numba_cuda", reason="kernels compile with numba-cuda")

SCRIPT = Path(__file__).parent / "gpu_sim" / "ptx_compile.py"


def test_every_kernel_compiles_to_ptx():
    env = subprocess_env(simulator=False)
    proc = subprocess.run(
        [sys.executable, str(SCRIPT)], env=env, capture_output=True, text=True, timeout=600
    )
    if proc.returncode == 77:
        pytest.skip(proc.stdout.strip()[-300:])
    assert proc.returncode == 0, proc.stdout[-8000:] + proc.stderr[-2000:]
