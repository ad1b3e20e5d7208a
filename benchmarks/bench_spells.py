"""The machine's spells: method="fast" on two threads and on one, in turns, for a while.

Usage: python benchmarks/bench_spells.py [--n 1000] [--seconds 120] [--calls 20]

Over ``--seconds``, takes turns between the best of ``--calls`` solves on every
thread and the best of half as many on one thread, on the same polygon, and
prints each pair with its ratio (two threads' time / one thread's). On a quiet
machine the ratio holds near 0.5; where a virtual machine's CPU is taken away
for a while, the two-thread solves, whose threads wait for each other's tiles,
slow down while the one-thread ones do not. The summary counts the pairs whose
two-thread time is over 1.2x the best seen. ``optri bench`` interleaves its
solves with the peak runs for that reason (``docs/fast-engine.md``, "Why the
solves and the peak take turns").
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba

from optri import triangulate
from optri.bench import convex_polygon


def best(pts: object, calls: int) -> float:
    return min(triangulate(pts, method="fast").seconds for _ in range(calls))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=int, default=1000, help="polygon size (default 1000)")
    ap.add_argument("--seconds", type=float, default=120.0, help="how long (default 120)")
    ap.add_argument("--calls", type=int, default=20, help="solves per two-thread best (20)")
    args = ap.parse_args()
    pts = convex_polygon(args.n)
    threads = numba.get_num_threads()
    best(pts, 20)  # load the kernels, warm the memory
    pairs = []
    print(f"n = {args.n}; best of {args.calls} on {threads} threads, of {args.calls // 2} on 1")
    print(f"{'s':>5} {'threads ms':>10} {'one ms':>8} {'ratio':>6}")
    start = time.perf_counter()
    while time.perf_counter() - start < args.seconds:
        at = time.perf_counter() - start
        two = best(pts, args.calls)
        numba.set_num_threads(1)
        one = best(pts, max(1, args.calls // 2))
        numba.set_num_threads(threads)
        pairs.append((two, one))
        print(f"{at:>5.0f} {two * 1e3:>10.2f} {one * 1e3:>8.2f} {two / one:>6.2f}", flush=True)
    twos = [p[0] for p in pairs]
    ones = [p[1] for p in pairs]
    slow2 = sum(t > 1.2 * min(twos) for t in twos)
    slow1 = sum(t > 1.2 * min(ones) for t in ones)
    print(
        f"{len(pairs)} pairs; {threads} threads: best {min(twos) * 1e3:.2f} ms, median "
        f"{statistics.median(twos) * 1e3:.2f}, max {max(twos) * 1e3:.2f}, over 1.2x the best "
        f"in {slow2}; one thread: best {min(ones) * 1e3:.2f} ms, median "
        f"{statistics.median(ones) * 1e3:.2f}, max {max(ones) * 1e3:.2f}, over 1.2x in {slow1}"
    )


if __name__ == "__main__":
    main()
