"""Environment for a subprocess that runs optri's GPU code (simulated or compiled)."""

from __future__ import annotations

import os
from pathlib import Path

import optri


def subprocess_env(simulator: bool) -> dict[str, str]:
    """This environment with optri's source first on PYTHONPATH.

    ``NUMBA_ENABLE_CUDASIM`` is read when numba is imported, so the choice of
    simulator or real CUDA compilation must be made for a fresh interpreter.
    """
    src = str(Path(optri.__file__).resolve().parents[1])
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    if simulator:
        env["NUMBA_ENABLE_CUDASIM"] = "1"
    env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env
