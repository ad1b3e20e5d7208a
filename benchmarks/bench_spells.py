"""The machine's spells: method="fast" on two threads and on one, beside the state of the CPUs.

Usage: python benchmarks/bench_spells.py [--n 1000] [--seconds 120] [--calls 20] [--base REV]

Over ``--seconds``, takes turns between the best of ``--calls`` solves on every
thread, the best of half as many on one thread, on the same polygon, and (where a
C compiler is found) two of optri's own yardsticks: ``crosscore.c``, the GB/s at
which one CPU reads 4 MB another has just written, and a 0.1 s run of
``minplus_peak.c`` on every CPU. Prints each turn, then the turns split by the
cross-core rate: under ``SPELL_TRANSFER`` (0.6) of its best, or not.

On the 2-core AMD EPYC of ``docs/fast-engine.md`` the cross-core rate is about 78
GB/s, or, in spells of seconds to minutes, about 28 GB/s. In those spells the
two-thread solves at n = 1000 took 6.0 ms instead of 4.8, while the one-thread solves
and the peak, whose threads share nothing, kept their speed: the host then seemingly
runs the two CPUs on cores that share no cache. (Turns in which all three slow down
are other work on the host, which the peak sees too.) ``optri bench``
interleaves its solves with the peak runs, and probes the cross-core rate after each
window, for that reason (``docs/fast-engine.md``, "Why the solves and the peak take
turns").

With ``--base REV`` it compares two versions instead: this checkout and the
package at git revision ``REV`` (``git archive``, as in ``bench_exact.py``), each in
a child process of its own that loads its kernels once (its own numba cache) and
then answers turns: the probe, then that version's best of ``--calls`` solves on
every thread, the two versions one after the other. The summary gives each
version's median best solve in spells and outside them, so a change is judged in
both states, on the same polygon and in the same minutes.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba

from optri import triangulate
from optri.bench import convex_polygon
from optri.bench.compare import SPELL_TRANSFER
from optri.bench.compiled import build, measure_peak, measure_transfer

#: a version's child: loads its kernels, prints the weight, then per line "CALLS" the best
CHILD = r"""
import json, sys
import optri
from optri.bench.compare import convex_polygon

pts = convex_polygon(int(sys.argv[1]))
weight = optri.triangulate(pts, method="fast").weight
for _ in range(10):
    optri.triangulate(pts, method="fast")
print(json.dumps(weight), flush=True)
for line in sys.stdin:
    print(min(optri.triangulate(pts, method="fast").seconds for _ in range(int(line))), flush=True)
"""


def best(pts: object, calls: int) -> float:
    return min(triangulate(pts, method="fast").seconds for _ in range(calls))


def summary(name: str, turns: list[tuple[float, float, float | None, float | None]]) -> str:
    if not turns:
        return f"{name}: no turns"
    twos, ones = [t[0] for t in turns], [t[1] for t in turns]
    peaks = [t[3] for t in turns if t[3] is not None]
    line = (
        f"{name}: {len(turns)} turns; {statistics.median(twos) * 1e3:.2f} ms on every thread "
        f"(median; {min(twos) * 1e3:.2f}-{max(twos) * 1e3:.2f}), "
        f"{statistics.median(ones) * 1e3:.2f} ms on one"
    )
    return line + (f"; peak {statistics.median(peaks):.3g} candidates/s" if peaks else "")


def by_state(turns: list[tuple[float, float]], cut: float) -> str:
    """Median best solve (ms) of the turns in spells and outside them, with their counts."""

    def med(v: list[float]) -> str:
        return f"{statistics.median(v) * 1e3:.3f} ms ({len(v)} turns)" if v else "-"

    spells = [t for t, x in turns if x < cut]
    rest = [t for t, x in turns if x >= cut]
    return f"spells {med(spells)}, outside {med(rest)}"


def compare(args: argparse.Namespace) -> None:
    """Turns of this checkout against ``args.base``, each tagged by the cross-core rate."""
    from bench_exact import ROOT, export

    with tempfile.TemporaryDirectory(prefix="optri-spells-") as tmp:
        built = build(Path(tmp))
        if built.probe is None:
            raise SystemExit(f"bench_spells: --base needs the cross-core probe ({built.note})")
        versions = {args.base: export(args.base, Path(tmp)), "checkout": ROOT / "src"}
        children = {}
        for name, src in versions.items():
            cache = Path(tmp) / f"cache-{len(children)}"
            env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
            children[name] = subprocess.Popen(
                [sys.executable, "-c", CHILD, str(args.n)],
                stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env,
            )  # fmt: skip
        weights = {name: json.loads(c.stdout.readline()) for name, c in children.items()}
        if len(set(weights.values())) != 1:
            raise SystemExit(f"bench_spells: the versions' weights differ: {weights}")
        print(f"n = {args.n}; best of {args.calls} on every thread; weight {weights[args.base]}")
        turns: dict[str, list[tuple[float, float]]] = {name: [] for name in children}
        start = time.perf_counter()
        while time.perf_counter() - start < args.seconds:
            for name, child in children.items():
                xfer = measure_transfer(built.probe)
                child.stdin.write(f"{args.calls}\n")  # type: ignore[union-attr]
                child.stdin.flush()  # type: ignore[union-attr]
                best_s = float(child.stdout.readline())  # type: ignore[union-attr]
                turns[name].append((best_s, xfer if xfer is not None else 0.0))
        for child in children.values():
            child.stdin.close()  # type: ignore[union-attr]
            child.wait()
    top = max(x for name in turns for _, x in turns[name])
    cut = SPELL_TRANSFER * top
    print(f"cross-core rate: best {top:.1f} GB/s; a spell below {cut:.1f}")
    for name, tt in turns.items():
        print(f"{name}: {by_state(tt, cut)}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=int, default=1000, help="polygon size (default 1000)")
    ap.add_argument("--seconds", type=float, default=120.0, help="how long (default 120)")
    ap.add_argument("--calls", type=int, default=20, help="solves per two-thread best (20)")
    ap.add_argument("--base", help="compare this checkout with the package at git revision REV")
    args = ap.parse_args()
    if args.base:
        compare(args)
        return
    pts = convex_polygon(args.n)
    threads = numba.get_num_threads()
    best(pts, 20)  # load the kernels, warm the memory
    turns: list[tuple[float, float, float | None, float | None]] = []
    with tempfile.TemporaryDirectory(prefix="optri-spells-") as tmp:
        built = build(Path(tmp))
        if built.note:
            print(f"bench_spells: {built.note}")
        print(f"n = {args.n}; best of {args.calls} on {threads} threads, of {args.calls // 2} on 1")
        head = f"{'s':>5} {'threads ms':>10} {'one ms':>8} {'ratio':>6}"
        print(f"{head} {'xfer GB/s':>9} {'peak':>9}")
        start = time.perf_counter()
        while time.perf_counter() - start < args.seconds:
            at = time.perf_counter() - start
            xfer = measure_transfer(built.probe) if built.probe else None
            two = best(pts, args.calls)
            numba.set_num_threads(1)
            one = best(pts, max(1, args.calls // 2))
            numba.set_num_threads(threads)
            peak = measure_peak(built.peak, 0.1, runs=1) if built.peak else None
            turns.append((two, one, xfer, peak))
            x = "-" if xfer is None else f"{xfer:.1f}"
            p = "-" if peak is None else f"{peak:.3g}"
            print(
                f"{at:>5.0f} {two * 1e3:>10.2f} {one * 1e3:>8.2f} {two / one:>6.2f} {x:>9} {p:>9}",
                flush=True,
            )
    top = max((t[2] for t in turns if t[2] is not None), default=None)
    if top is None:
        print(summary("all", turns))
        return
    cut = SPELL_TRANSFER * top
    print(f"cross-core rate: best {top:.1f} GB/s; a spell below {cut:.1f}")
    print(summary("spells", [t for t in turns if t[2] is not None and t[2] < cut]))
    print(summary("the rest", [t for t in turns if t[2] is None or t[2] >= cut]))


if __name__ == "__main__":
    main()
