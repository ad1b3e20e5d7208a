"""The min-plus fill of the compiled core against another version's, in the same run.

Usage: python benchmarks/bench_core.py --base REV [--sizes 500 1000 2000 4000 8000]
       [--rounds 5] [--calls 3] [--dtype float64] [--threads N]

``method="fast"`` on convex polygons (perimeter, sum: the min-plus fill) in child
processes: this checkout (``src/``, with its built ``optri._core``) and the package
at git revision ``REV`` (``git archive``, as in ``bench_exact.py``; its kernels are
compiled or loaded once per child and not timed). Each round runs one child of each
version, alternately (A, B, then B, A the next round), each answering every size with
its best of ``--calls`` solves. The summary gives, per size, each version's median
best time over the rounds and the ratio base / this: a fraction of the peak measured
in the same run scales with it, so 0.95 or more meets "at least 0.95x of the base's
fraction of peak". The weights must agree to rounding: a base whose edge lengths were
compiled with fused multiply-adds may differ in the last bits.

Against the numba engine, e.g. ``--base 8cfecf8`` (the last version whose min-plus
fill was numba's).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

from bench_exact import ROOT, export, run_child

CHILD = r"""
import json, sys, time
import optri
from optri.bench.compare import convex_polygon

sizes, calls, dtype = [int(s) for s in sys.argv[1].split(",")], int(sys.argv[2]), sys.argv[3]
threads = int(sys.argv[4])
opts = {} if threads <= 0 else {"threads": threads}
optri.triangulate(convex_polygon(300), method="fast", dtype=dtype, **opts)  # load kernels
out = {}
for n in sizes:
    pts = convex_polygon(n)
    weight = optri.triangulate(pts, method="fast", dtype=dtype, **opts).weight
    best = float("inf")
    for _ in range(calls):
        t0 = time.perf_counter()
        optri.triangulate(pts, method="fast", dtype=dtype, **opts)
        best = min(best, time.perf_counter() - t0)
    out[n] = (best, weight)
print(json.dumps(out))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--base", default="8cfecf8", help="git revision of the other version")
    ap.add_argument("--sizes", type=int, nargs="+", default=[500, 1000, 2000, 4000, 8000])
    ap.add_argument("--rounds", type=int, default=5, help="alternating child runs per version")
    ap.add_argument("--calls", type=int, default=3, help="timed solves per size and child")
    ap.add_argument("--dtype", default="float64", choices=["float64", "float32"])
    ap.add_argument("--threads", type=int, default=0, help="0: the engine's default")
    args = ap.parse_args()
    sizes = ",".join(map(str, args.sizes))
    with tempfile.TemporaryDirectory() as tmp:
        versions = {"base": export(args.base, Path(tmp)), "this": ROOT / "src"}
        times: dict[str, dict[str, list[float]]] = {v: {} for v in versions}
        weights: dict[str, dict[str, float]] = {v: {} for v in versions}
        names = list(versions)
        for r in range(args.rounds):
            for v in names if r % 2 == 0 else names[::-1]:
                cache = Path(tmp) / f"cache-{v}"
                got = run_child(CHILD, versions[v], cache, sizes, args.calls, args.dtype,
                                args.threads)  # fmt: skip
                for n, (t, w) in got.items():
                    times[v].setdefault(n, []).append(t)
                    weights[v][n] = w
                    print(f"round {r + 1} {v:>4} n = {n:>5}: {t * 1e3:9.2f} ms", flush=True)
    print(f"\nmedian of {args.rounds} rounds (best of {args.calls} solves each), {args.dtype}; "
          f"base = {args.base}")  # fmt: skip
    print(f"{'n':>6} {'base':>11} {'this':>11} {'base/this':>10}  weight rel. diff")
    for n in times["this"]:
        b, a = statistics.median(times["base"][n]), statistics.median(times["this"][n])
        wb, wa = weights["base"][n], weights["this"][n]
        diff = abs(wa - wb) / max(abs(wb), 1e-300)
        print(f"{n:>6} {b * 1e3:>9.2f}ms {a * 1e3:>9.2f}ms {b / a:>10.3f}  {diff:.1e}")


if __name__ == "__main__":
    main()
