"""Evaluate the CUDA weight device functions under numba's CUDA simulator (a script).

``tests/test_weights.py`` runs it in a fresh interpreter with
``NUMBA_ENABLE_CUDASIM=1`` (read when numba is imported). The simulator makes
``cuda.jit(device=True)`` functions callable from Python, so the very device
functions the GPU kernels inline are evaluated here, not a copy.

Usage: ``weights_twin.py JOBS.npz OUT.npz``. ``JOBS.npz`` holds, for each job
``j``: ``kind_j`` (``"triangle"`` or ``"edge"``), ``code_j``, ``data_j`` (vertex
data as the engines see it: ``(n,)`` values or ``(n, d)`` points) and ``idx_j``
(rows of ``(i, k, j)`` or ``(a, b)``). ``OUT.npz`` gets one value array per job.
"""

from __future__ import annotations

import os
import sys

import numpy as np


def padded(data: np.ndarray) -> tuple[int, np.ndarray]:
    """The GPU engine's view of vertex data: dimension and ``(n, 3)`` float64."""
    n = len(data)
    dim = 1 if data.ndim == 1 else data.shape[1]
    pts = np.zeros((n, 3), dtype=np.float64)
    pts[:, :dim] = data.reshape(n, dim)
    return dim, pts


def main(jobs_path: str, out_path: str) -> int:
    if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":
        print("run with NUMBA_ENABLE_CUDASIM=1", file=sys.stderr)
        return 2
    from optri.engines._gpu_device import device_functions

    dev = device_functions()
    jobs = np.load(jobs_path)
    count = sum(name.startswith("kind_") for name in jobs.files)
    out = {}
    for j in range(count):
        kind, code = str(jobs[f"kind_{j}"]), int(jobs[f"code_{j}"])
        dim, pts = padded(jobs[f"data_{j}"])
        n = len(pts)
        rows = jobs[f"idx_{j}"].tolist()
        if kind == "triangle":
            values = [dev.weight(code, dim, n, pts, i, k, m) for i, k, m in rows]
        else:
            values = [dev.edge(code, n, pts, a, b) for a, b in rows]
        out[f"out_{j}"] = np.array(values, dtype=np.float64)
    np.savez(out_path, **out)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
