"""Seconds from Ctrl-C to the end of ``optri solve -m fast``, before vs after.

A child process writes a convex polygon, loads the kernels (a small solve of the same
weight and objective), prints "go" and runs ``optri solve`` on it; SIGINT comes a
different delay after "go" each run (1 s, then 0.37 s more each time), so that it
lands at different points of the fill. Timed: from the signal to the child's exit,
which must be code 130 with "optri: interrupted" on stderr. The baseline is the
package at a git revision (``git archive``, as in ``bench_exact.py``), with its own
numba cache; the versions alternate.

    python benchmarks/bench_interrupt.py [--base REV] [--n 9000] [--runs 4]
    python benchmarks/bench_interrupt.py --n 3000 --weight max_angle --objective max
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_exact import ROOT, export

CHILD = r"""
import sys
import numpy as np
import optri
from optri.bench.compare import convex_polygon
from optri.cli import main

n, weight, objective, out = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
optri.triangulate(convex_polygon(300), weight, objective, method="fast")  # kernels loaded
np.savetxt(out, convex_polygon(n), delimiter=",")
print("go", flush=True)
main(["solve", out, "-m", "fast", "-w", weight, "-O", objective, "-q"])
"""


def interrupt(src: Path, cache: Path, args: argparse.Namespace, delay: float, tmp: str) -> float:
    """Seconds from SIGINT, ``delay`` after "go", to the child's exit."""
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    csv = Path(tmp) / "polygon.csv"
    cmd = [sys.executable, "-c", CHILD, str(args.n), args.weight, args.objective, str(csv)]
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        if proc.stdout is None or proc.stdout.readline().strip() != "go":
            raise SystemExit(f"the child did not start: {proc.communicate()[1]}")
        time.sleep(delay)
        start = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=300)
        seconds = time.perf_counter() - start
    finally:
        proc.kill()
    if proc.returncode != 130 or err != "optri: interrupted\n":
        raise SystemExit(f"exit {proc.returncode}, stderr {err!r}: the fill ended before SIGINT?")
    return seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--base", default="6a2b504", help="git revision of the baseline")
    ap.add_argument("--n", type=int, default=9000)
    ap.add_argument("--weight", default="perimeter")
    ap.add_argument("--objective", default="sum")
    ap.add_argument("--runs", type=int, default=4, help="signals per version")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        versions = {"before": export(args.base, Path(tmp)), "after": ROOT / "src"}
        seconds: dict[str, list[float]] = {v: [] for v in versions}
        for run in range(args.runs):
            for v, src in versions.items():
                cache = Path(tmp) / f"cache-{v}"
                seconds[v].append(interrupt(src, cache, args, 1.0 + 0.37 * run, tmp))
    print(f"n = {args.n}, {args.weight}/{args.objective}; before = {args.base}")
    for v, s in seconds.items():
        print(f"{v:>7}: {min(s):.2f}-{max(s):.2f} s  ({', '.join(f'{x:.2f}' for x in s)})")


if __name__ == "__main__":
    main()
