"""How evenly ``progress(done, total)`` moves with the time of a solve, before vs after.

A progress bar (and its time estimate) reads ``done / total``: it should be near 25 %
a quarter of the way through a fill. For each engine this solves one convex polygon
(memo and table at n = 160, fast at n = 7000), records ``(seconds, done / total)`` at
every report, and prints what the bar read at 25, 50 and 75 % of the solve's time, for
the package at a git revision (``--base``, default ``da565c8``: progress counted in
chords) and for this tree, in child processes, alternately. Each child solves its
polygon once first, so that the kernels are loaded and the table's memory is the
process's own (a fresh virtual machine's first use of memory is much slower).

    python benchmarks/bench_progress.py [--base REV] [--rounds 2]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from bench_exact import ROOT, export, run_child

CHILD = r"""
import json, time
import numpy as np
import optri
from optri import config
from optri.bench.compare import convex_polygon

config.FAST_PROGRESS_SECONDS = 0.01
out = {}
for method, n in (("memo", 160), ("table", 160), ("fast", 7000)):
    pts = convex_polygon(n)
    optri.triangulate(pts, method=method)
    seen = []
    start = time.perf_counter()
    optri.triangulate(
        pts, method=method, progress=lambda d, t: seen.append((time.perf_counter() - start, d / t))
    )
    whole = time.perf_counter() - start
    at = np.array(seen)
    read = []
    for q in (0.25, 0.5, 0.75):
        k = int(np.searchsorted(at[:, 0], q * whole))
        read.append(float(at[k - 1, 1]) if k > 0 else 0.0)
    out[method] = [whole, *read]
print(json.dumps(out))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--base", default="da565c8", help="git revision of the baseline")
    ap.add_argument("--rounds", type=int, default=2, help="alternating child runs per version")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        versions = {"before": export(args.base, Path(tmp)), "after": ROOT / "src"}
        runs: dict[str, list[dict[str, list[float]]]] = {v: [] for v in versions}
        for _ in range(args.rounds):
            for v, src in versions.items():
                runs[v].append(run_child(CHILD, src, Path(tmp) / f"cache-{v}"))
    print(f"what the bar read at 25 / 50 / 75 % of the solve's time; before = {args.base}")
    for method in ("memo", "table", "fast"):
        for v in versions:
            reads = [r[method] for r in runs[v]]
            lows = [min(x[q] for x in reads) for q in (1, 2, 3)]
            highs = [max(x[q] for x in reads) for q in (1, 2, 3)]
            cols = " ".join(f"{lo:4.0%}-{hi:4.0%}" for lo, hi in zip(lows, highs))
            secs = min(x[0] for x in reads)
            print(f"  {method:5s} {v:6s} {secs:6.2f} s   {cols}")


if __name__ == "__main__":
    main()
