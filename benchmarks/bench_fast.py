"""Compiled engine vs its yardsticks on the same polygons (perimeter, sum), in one run.

Usage: python benchmarks/bench_fast.py [N ...] [--quick] [--naive-max 500] [--json OUT]
                                       [--shared ../shared/bench]
Prints n, optri seconds (its best solve; solves and peak runs take turns, --rounds
windows each), fraction of the min-plus peak, C seconds, optri/C, naive seconds,
naive/optri, peak memory, the load average, the number of timed solves and whether
optri's optimum equals the C reference's. The yardsticks live in src/optri/bench/yardsticks (C,
built with gcc at run time) and optri.bench.naive (plain Python); see optri.bench.
"""

from __future__ import annotations

import argparse
import json

from optri.bench import run_benchmark
from optri.errors import InvalidParameterError

DEFAULT_SIZES = (500, 1000, 2000, 4000)
QUICK_SIZES = (100, 200, 500)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("sizes", nargs="*", type=int, help="polygon sizes (default 500 1000 2000 4000)")
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument(
        "--naive-max", type=int, default=500, help="largest n for the plain-Python recursion"
    )
    ap.add_argument(
        "--repeats", type=int, default=3, help="at least this many timed solves (the best counts)"
    )
    ap.add_argument("--float32", action="store_true", help="float32 table")
    ap.add_argument("--json", dest="json_out", help="also write the rows to this JSON file")
    ap.add_argument("--shared", help="also build and run DIR/ref_mwt.c and DIR/minplus_peak.c")
    ap.add_argument(
        "--peak-seconds", type=float, default=1.0, help="seconds of each peak kernel, all turns"
    )
    ap.add_argument("--rounds", type=int, default=3, help="turns of peak runs and solves (3)")
    args = ap.parse_args()
    sizes = args.sizes or (QUICK_SIZES if args.quick else DEFAULT_SIZES)
    try:
        rows = run_benchmark(
            sizes,
            naive_max=args.naive_max,
            repeats=args.repeats,
            dtype="float32" if args.float32 else "float64",
            log=print,
            shared=args.shared,
            peak_seconds=args.peak_seconds,
            rounds=args.rounds,
        )
    except InvalidParameterError as exc:  # e.g. --rounds 0: one line and status 2
        ap.error(str(exc))
    if args.json_out:
        with open(args.json_out, "w") as fh:
            json.dump([r.to_dict() for r in rows], fh, indent=1)


if __name__ == "__main__":
    main()
