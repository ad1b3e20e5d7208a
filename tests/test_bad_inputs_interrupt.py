"""Ctrl-C inside a compiled kernel (the chord mask, the CPU DP) ends as KeyboardInterrupt.

A real SIGINT is sent to a subprocess while a long kernel runs; numba notices it
only when the kernel returns, which used to surface as ``SystemError: ...
returned a result with an exception set``. The library must raise a plain
``KeyboardInterrupt``; the CLI must print "optri: interrupted" and exit 130.
(The Liepa 3-D kernel's SIGINT test is in test_mesh_cli.py.)
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest

from cli_run import checkout_env

pytest.importorskip("numba")

STAR = """
import numpy as np
def star(n):
    a = 2 * np.pi * np.arange(n) / n
    r = np.where(np.arange(n) % 2 == 0, 1.0, 0.6)
    return np.column_stack((r * np.cos(a), r * np.sin(a)))
"""

MASK = (
    STAR
    + """
from optri.simple import valid_diagonals
valid_diagonals(star(200))  # kernels loaded (compiled or from the cache)
print("go", flush=True)
valid_diagonals(star(14000))  # several seconds inside one kernel call
print("finished", flush=True)
"""
)

CLI = (
    STAR
    + """
import optri
optri.triangulate(star(200), method="fast")  # kernels loaded
np.savetxt("star.csv", star(6000), delimiter=",")
from optri.cli import main
print("go", flush=True)
main(["solve", "star.csv", "-m", "fast", "-q"])
"""
)


def _interrupt(code, tmp_path, delay):
    proc = subprocess.Popen(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=checkout_env(),
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        assert proc.stdout.readline().strip() == "go", proc.stderr.read()
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=300)
    finally:
        proc.kill()
    return proc.returncode, out, err


def test_ctrl_c_in_the_mask_kernel_is_keyboard_interrupt(tmp_path):
    code, out, err = _interrupt(MASK, tmp_path, 1.5)
    assert "finished" not in out
    assert "SystemError:" not in err
    assert err.strip().splitlines()[-1] == "KeyboardInterrupt", err


def test_ctrl_c_in_the_cli_dp_exits_130(tmp_path):
    code, out, err = _interrupt(CLI, tmp_path, 3.0)
    assert code == 130, err
    assert err.strip().splitlines() == ["optri: interrupted"], err
