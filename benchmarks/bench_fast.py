"""Compiled engine vs ref_mwt.c vs naive_memo.py on the same polygons (perimeter, sum).

Usage: python benchmarks/bench_fast.py [N ...] [--quick] [--naive-max 500] [--json OUT]
Prints n, optri seconds, C seconds, optri/C, naive seconds, naive/optri and peak memory.
"""

from __future__ import annotations

import argparse
import json

from optri.bench import run_benchmark

DEFAULT_SIZES = (500, 1000, 2000, 4000)
QUICK_SIZES = (100, 200, 500)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("sizes", nargs="*", type=int, help="polygon sizes (default 500 1000 2000 4000)")
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--naive-max", type=int, default=500, help="largest n for naive_memo.py")
    ap.add_argument("--repeats", type=int, default=3, help="best of this many runs (n <= 2000)")
    ap.add_argument("--float32", action="store_true", help="float32 table")
    ap.add_argument("--json", dest="json_out", help="also write the rows to this JSON file")
    args = ap.parse_args()
    sizes = args.sizes or (QUICK_SIZES if args.quick else DEFAULT_SIZES)
    rows = run_benchmark(
        sizes,
        naive_max=args.naive_max,
        repeats=args.repeats,
        dtype="float32" if args.float32 else "float64",
        log=print,
    )
    if args.json_out:
        with open(args.json_out, "w") as fh:
            json.dump([r.to_dict() for r in rows], fh, indent=1)


if __name__ == "__main__":
    main()
