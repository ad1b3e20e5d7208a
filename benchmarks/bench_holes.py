"""Polygons with holes: N vs seconds to a proven optimum, and how far earcut and CDT are.

For 1, 3 and 10 holes, random polygons with holes (``optri.domains.random_domain``:
a star-shaped exterior, about half the vertices on small holes) of growing N are
solved with ``optri.triangulate(..., time_limit=LIMIT)`` until a size is not
proven optimal within the limit. Each row reports the wall time, its ratio to
the DP of a simple polygon of the same N timed in the same run (the baseline:
what holes cost), the program's size, and the weight of mapbox-earcut's and
shapely's constrained Delaunay triangulations of the same polygon, as a
percentage above the optimum (all weights evaluated by optri's own evaluator).

    PYTHONPATH=src python benchmarks/bench_holes.py [--quick] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import optri
from optri.domains import as_domain, random_domain
from optri.domains.weighing import DomainWeight
from optri.weights import get_weight

SIZES = (20, 30, 40, 60, 80, 120, 160, 240, 320, 480, 640, 800, 960, 1280, 1600, 2000)


def earcut_triangles(ext: np.ndarray, holes: list[np.ndarray]) -> np.ndarray:
    import mapbox_earcut as earcut

    pts = np.concatenate([ext, *holes])
    ends = np.cumsum([len(ext), *map(len, holes)]).astype(np.uint32)
    idx = earcut.triangulate_float64(pts, ends)
    return np.asarray(idx, dtype=np.int64).reshape(-1, 3)


def cdt_triangles(ext: np.ndarray, holes: list[np.ndarray]) -> np.ndarray:
    import shapely

    pts = np.concatenate([ext, *holes])
    index = {tuple(p): k for k, p in enumerate(pts.tolist())}
    tris = shapely.constrained_delaunay_triangles(shapely.Polygon(ext, holes))
    out = [[index[tuple(c)] for c in np.asarray(g.exterior.coords)[:3].tolist()]
           for g in tris.geoms]  # fmt: skip
    return np.array(out, dtype=np.int64).reshape(-1, 3)


def total(weight: DomainWeight, tris: np.ndarray, n_expected: int) -> float:
    assert len(tris) == n_expected, f"{len(tris)} triangles, expected {n_expected}"
    return float(np.sum(weight.many(tris)))


def simple_dp_seconds(n: int, weight: str, seed: int) -> float:
    """The baseline: optri's DP on a simple polygon of n vertices (star-shaped)."""
    ext, _ = random_domain(n, 0, seed=seed)
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        optri.triangulate(ext, weight=weight)
        best = min(best, time.perf_counter() - start)
    return best


def run(holes: int, sizes, weight: str, limit: float, seed: int) -> list[dict]:
    rows = []
    for n in sizes:
        if n < 3 * holes + 8:
            continue
        ext, hs = random_domain(n, holes, seed=seed)
        start = time.perf_counter()
        tri = optri.triangulate((ext, hs), weight=weight, time_limit=limit)
        seconds = time.perf_counter() - start
        tri.check()
        w = DomainWeight(as_domain(ext, hs), get_weight(weight))
        count = n + 2 * holes - 2
        opt = float(tri.weight)
        row = dict(
            holes=holes, n=n, seconds=seconds, optimality=tri.optimality, gap=tri.gap,
            method=tri.method, weight=opt,
            candidates=tri.stats.get("candidate_triangles"),
            ip_blocks=tri.stats.get("ip_blocks", 0), dp_blocks=tri.stats.get("dp_blocks", 0),
            baseline_seconds=simple_dp_seconds(n, weight, seed),
            earcut_pct=100 * (total(w, earcut_triangles(ext, hs), count) / opt - 1),
            cdt_pct=100 * (total(w, cdt_triangles(ext, hs), count) / opt - 1),
        )  # fmt: skip
        row["ratio"] = seconds / row["baseline_seconds"]
        rows.append(row)
        print(
            f"h={holes:2d} N={n:5d} {seconds:8.2f} s  x{row['ratio']:8.1f} of the simple DP  "
            f"{tri.optimality:9s} T={row['candidates']:7d}  earcut +{row['earcut_pct']:5.1f}%  "
            f"CDT +{row['cdt_pct']:5.1f}%",
            flush=True,
        )
        if tri.optimality != "proven" or seconds > limit:
            break
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--holes", type=int, nargs="+", default=[1, 3, 10])
    ap.add_argument("--weight", default="diagonal", help="a sum weight (default: MWT)")
    ap.add_argument("--limit", type=float, default=60.0, help="seconds per polygon")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--quick", action="store_true", help="sizes up to 120, limit 10 s")
    ap.add_argument("--json", help="write the rows to this file")
    args = ap.parse_args()
    sizes = [s for s in SIZES if s <= 120] if args.quick else SIZES
    limit = 10.0 if args.quick else args.limit
    # warm-up: imports, compiled kernels (the mask's, the DP's), HiGHS
    optri.triangulate(random_domain(30, 1, seed=1))
    for n in (60, 200):
        optri.triangulate(random_domain(n, 0, seed=1)[0], weight=args.weight)
    rows = []
    for h in args.holes:
        rows += run(h, sizes, args.weight, limit, args.seed)
    for h in args.holes:
        mine = [r for r in rows if r["holes"] == h and r["optimality"] == "proven"]
        mine = [r for r in mine if r["seconds"] <= limit]
        if mine:
            best = max(mine, key=lambda r: r["n"])
            print(f"{h} hole(s): largest N proven optimal within {limit:g} s: {best['n']} "
                  f"({best['seconds']:.1f} s)")  # fmt: skip
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
