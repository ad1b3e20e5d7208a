"""Time method="gpu" on large random convex polygons (a script, never run by pytest).

For each n: seconds of the GPU engine (kernel compilation excluded: a warm-up
solve compiles first and is reported on its own line), the GPU model, and the
compiled CPU engine (method="fast") on the same polygon in the same run where
it exists and n <= --cpu-max-n, with the ratio and the relative cost difference.

Targets on one H100 (issue 9): n = 20,000 in <= 2 s, n = 50,000 in <= 30 s.

Usage (on a machine with an NVIDIA GPU and `pip install 'optri[gpu]'`)::

    python benchmarks/bench_gpu.py                       # n = 2000 5000 10000 20000 50000
    python benchmarks/bench_gpu.py 20000 --cpu-max-n 20000 --json gpu.json
    python benchmarks/bench_gpu.py 20000 --dtype float32
    python benchmarks/bench_gpu.py 20000 --tile 32 --threads 128   # a tuning point

Under NUMBA_ENABLE_CUDASIM=1 it only runs with --allow-simulator (a smoke test
of the script; the simulator's timings mean nothing).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import sys
import time

import numpy as np

import gpu_settings
import optri
from optri import config
from optri.engines import gpu

TARGETS = {20000: 2.0, 50000: 30.0}


def convex_polygon(n: int, seed: int = 1) -> np.ndarray:
    """n random angles on a 1000 x 600 ellipse (as ../shared/bench/gen.py)."""
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0.0, 2.0 * math.pi, n))
    return np.c_[1000.0 * np.cos(ang), 600.0 * np.sin(ang)]


def gpu_model() -> str:
    from numba import cuda

    if gpu.simulated():
        return "CUDA simulator (not a GPU)"
    name = cuda.get_current_device().name
    return name.decode() if isinstance(name, bytes) else str(name)


def timed(pts: np.ndarray, method: str, args: argparse.Namespace) -> tuple[float, float]:
    start = time.perf_counter()
    tri = optri.triangulate(pts, args.weight, args.objective, method=method, dtype=args.dtype)
    return time.perf_counter() - start, float(tri.weight)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("n", nargs="*", type=int, default=[2000, 5000, 10000, 20000, 50000])
    ap.add_argument("--weight", default="perimeter")
    ap.add_argument("--objective", default="sum")
    ap.add_argument("--dtype", default="float64", choices=["float64", "float32"])
    ap.add_argument("--cpu-max-n", type=int, default=10000, help="largest n timed on the CPU")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", help="also write the rows to this JSON file")
    ap.add_argument("--allow-simulator", action="store_true")
    gpu_settings.add_arguments(ap)
    args = ap.parse_args()
    refused = gpu_settings.apply(args, args.dtype)
    if refused:
        print(refused, file=sys.stderr)
        return 2
    if gpu.simulated() and not args.allow_simulator:
        print("NUMBA_ENABLE_CUDASIM is set: timings would be meaningless", file=sys.stderr)
        return 2
    has_cpu = importlib.util.find_spec("optri.engines.jit") is not None
    model = gpu_model()
    print(f"GPU: {model}   {gpu_settings.describe()}, dtype {args.dtype}")
    if not has_cpu:
        print("CPU column skipped: optri.engines.jit (method='fast') is not in this build")

    warm_n = min(4 * config.GPU_TILE + 3, min(args.n))
    compile_s, _ = timed(convex_polygon(max(warm_n, 5), args.seed), "gpu", args)
    print(f"warm-up (kernel compilation + n = {warm_n}): {compile_s:.2f} s, excluded below")

    rows = []
    print(f"{'n':>7} {'gpu s':>9} {'cpu s':>9} {'cpu/gpu':>8} {'rel diff':>9}  target")
    for n in args.n:
        pts = convex_polygon(n, args.seed)
        gpu_s, gpu_cost = timed(pts, "gpu", args)
        cpu_s = cpu_cost = None
        if has_cpu and n <= args.cpu_max_n:
            cpu_s, cpu_cost = timed(pts, "fast", args)
        target = TARGETS.get(n)
        row = {"n": n, "gpu_seconds": gpu_s, "gpu_model": model, "cpu_seconds": cpu_s,
               "gpu_cost": gpu_cost, "cpu_cost": cpu_cost, "dtype": args.dtype,
               "weight": args.weight, "objective": args.objective,
               "compile_seconds": compile_s, "target_seconds": target}  # fmt: skip
        rows.append(row)
        ratio = f"{cpu_s / gpu_s:8.1f}" if cpu_s else f"{'-':>8}"
        cpu_col = f"{cpu_s:9.3f}" if cpu_s else f"{'-':>9}"
        diff = abs(gpu_cost - cpu_cost) / max(1.0, abs(cpu_cost)) if cpu_cost is not None else None
        diff_col = f"{diff:9.1e}" if diff is not None else f"{'-':>9}"
        met = "met" if target is not None and gpu_s <= target else "MISSED"
        verdict = "" if target is None else f"<= {target:g} s: {met}"
        print(f"{n:7d} {gpu_s:9.3f} {cpu_col} {ratio} {diff_col}  {verdict}", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
