"""Time per ``optri.triangulate`` call on small polygons, before vs after: the per-call setup.

A 20-vertex polygon's table fills in microseconds, so what a call costs is its setup:
checking the polygon, the memory check, starting the kernel, building the result. The
baseline is the package at a git revision (default ``e52817c``), exported with ``git
archive`` as in ``bench_exact.py``; both versions run in child processes, alternately,
on the same convex polygons (``method="fast"``, perimeter), each with its own numba
cache (compiled once, not timed). Prints the best time per call of each and the ratio
after / before.

    python benchmarks/bench_calls.py [--base REV] [--sizes 8 20 100 1000] [--rounds 5]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from bench_exact import ROOT, export, run_child

CHILD = r"""
import json, sys, time
import optri
from optri.bench.compare import convex_polygon

sizes, calls = [int(s) for s in sys.argv[1].split(",")], int(sys.argv[2])
out = {}
for n in sizes:
    pts = convex_polygon(n)
    weight = optri.triangulate(pts, method="fast").weight  # compile or load the kernels
    number = max(1, calls // max(1, n // 20))
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(number):
            optri.triangulate(pts, method="fast")
        best = min(best, (time.perf_counter() - t0) / number)
    out[n] = (best, weight)
print(json.dumps(out))
"""


def run(src: Path, cache: Path, sizes: list[int], calls: int) -> dict[str, list[float]]:
    return run_child(CHILD, src, cache, ",".join(map(str, sizes)), calls)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--base", default="e52817c", help="git revision of the baseline")
    ap.add_argument("--sizes", type=int, nargs="+", default=[8, 20, 100, 1000])
    ap.add_argument("--rounds", type=int, default=5, help="alternating child runs per version")
    ap.add_argument("--calls", type=int, default=400, help="calls per timing at n <= 20")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        versions = {"before": export(args.base, Path(tmp)), "after": ROOT / "src"}
        best: dict[str, dict[str, float]] = {v: {} for v in versions}
        weights: dict[str, dict[str, float]] = {v: {} for v in versions}
        for _ in range(args.rounds):
            for v, src in versions.items():
                for n, (t, w) in run(src, Path(tmp) / f"cache-{v}", args.sizes, args.calls).items():
                    best[v][n] = min(best[v].get(n, float("inf")), t)
                    weights[v][n] = w
    print(f"best of {args.rounds} rounds x 5 timings; before = {args.base}")
    print(f"{'n':>6} {'before':>10} {'after':>10} {'after/before':>13}  same weight")
    for n in best["after"]:
        b, a = best["before"][n], best["after"][n]
        same = weights["before"][n] == weights["after"][n]
        print(f"{n:>6} {b * 1e6:>8.0f}us {a * 1e6:>8.0f}us {a / b:>13.2f}  {same}")


if __name__ == "__main__":
    main()
