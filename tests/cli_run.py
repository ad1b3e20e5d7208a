"""Run this checkout's optri in a subprocess: ``python -m optri`` with its ``src`` first.

A bare ``optri`` command or an inherited ``PYTHONPATH`` could reach another
installed copy; these helpers always put this repository's ``src`` first.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

SRC = Path(__file__).resolve().parents[1] / "src"


def checkout_env(**extra: str) -> dict[str, str]:
    """This process's environment with the checkout's ``src`` first on ``PYTHONPATH``."""
    env = {**os.environ, **extra}
    rest = os.environ.get("PYTHONPATH", "")
    env["PYTHONPATH"] = os.pathsep.join([str(SRC), rest]) if rest else str(SRC)
    return env


def run_python(*args: Any, timeout: float = 120, **kwargs: Any) -> subprocess.CompletedProcess:
    """``python ARGS`` with the checkout first on the path; text output captured."""
    return subprocess.run(
        [sys.executable, *map(str, args)],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=checkout_env(),
        **kwargs,
    )


def run_optri(*args: Any, **kwargs: Any) -> subprocess.CompletedProcess:
    """``python -m optri ARGS`` from this checkout."""
    return run_python("-m", "optri", *args, **kwargs)
