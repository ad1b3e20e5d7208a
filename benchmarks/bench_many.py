"""Many small polygons in memory: optri.triangulate_many against shapely CDT and earcut.

For each size band, N seeded random star polygons (simple, non-convex) are
triangulated, all in the same run, by

* ``optri.triangulate_many`` on the list of vertex arrays: the compiled
  many-polygon path (``optri.batch.compiled``, one call of the compiled core
  per chunk, parallel over polygons), on all threads and on one
  (``OPTRI_NUM_THREADS=1``);
* the same with ``config.MANY_COMPILED = False``: ``optri.triangulate``
  polygon by polygon (``method="auto"`` keeps these sizes on the Python
  engine; the compiled path reproduces its results bit for bit, checked here);
* ``shapely.constrained_delaunay_triangles`` on the whole array of shapely
  Polygons at once, and ``mapbox_earcut`` polygon by polygon.

Reported: polygons per second of each, the compiled path's time over CDT's
(the target is at most 2), and how far above optri's optimum (minimum perimeter
sum, the default weight) the two heuristics land (mean and worst, in percent).
The machine's load average is printed first: timings on a shared machine are
only comparable within one run.

    python benchmarks/bench_many.py                        # 1000 polygons per band
    python benchmarks/bench_many.py --per-band 4000 --bands 8-64

``--first-call`` measures instead what a new user meets: in a fresh process
(with an empty numba cache, for a revision that still compiles kernels), the
import of optri plus the first ``triangulate_many`` of 100 star polygons of
8-64 vertices, then the best warm call on the same polygons. ``--src`` runs
that child on another checkout's ``src`` (``git archive REV src | tar -x -C DIR``
gives one), so two revisions compare in one run:

    python benchmarks/bench_many.py --first-call --repeat 5
    python benchmarks/bench_many.py --first-call --repeat 5 --src /tmp/old/src
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import optri
from optri import config


def star_polygon(rng: np.random.Generator, n: int) -> np.ndarray:
    """Sorted jittered angles, random radii: star-shaped about the origin, so simple."""
    angles = np.linspace(0, 2 * math.pi, n, endpoint=False) + rng.uniform(0, 1.5 * math.pi / n, n)
    radii = rng.uniform(0.3, 1.0, n)
    return np.column_stack((radii * np.cos(angles), radii * np.sin(angles))).round(9)


def perimeter_sum(pts: np.ndarray, tris: np.ndarray) -> float:
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    return float((np.hypot(*(a - b).T) + np.hypot(*(b - c).T) + np.hypot(*(c - a).T)).sum())


def timed(fn, *args, repeat: int = 1):
    """Result and best wall time of ``repeat`` calls (the machine may be shared)."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn(*args)
        best = min(best, time.perf_counter() - start)
    return out, best


def run_earcut(polys: list[np.ndarray]) -> list[np.ndarray]:
    import mapbox_earcut as earcut  # imported (and cached) before the clock starts

    out = []
    for pts in polys:
        idx = earcut.triangulate_float64(pts, np.array([len(pts)], dtype=np.uint32))
        out.append(np.asarray(idx, dtype=np.int64).reshape(-1, 3))
    return out


def per_polygon(polys: list[np.ndarray]) -> list:
    """``optri.triangulate`` polygon by polygon, as before the compiled path."""
    config.MANY_COMPILED = False
    try:
        return optri.triangulate_many(polys)
    finally:
        config.MANY_COMPILED = True


def one_thread(polys: list[np.ndarray]) -> list:
    previous = os.environ.get("OPTRI_NUM_THREADS")
    os.environ["OPTRI_NUM_THREADS"] = "1"
    try:
        return optri.triangulate_many(polys)
    finally:
        if previous is None:
            del os.environ["OPTRI_NUM_THREADS"]
        else:
            os.environ["OPTRI_NUM_THREADS"] = previous


FIRST_CALL = r"""
import json, math, sys, time
start = time.perf_counter()
import numpy as np
import optri
polys = []
rng = np.random.default_rng(2024)
for _ in range(100):
    n = int(rng.integers(8, 65))
    a = np.linspace(0, 2 * math.pi, n, endpoint=False) + rng.uniform(0, 1.5 * math.pi / n, n)
    r = rng.uniform(0.3, 1.0, n)
    polys.append(np.column_stack((r * np.cos(a), r * np.sin(a))).round(9))
first = optri.triangulate_many(polys)
t_first = time.perf_counter() - start
warm = float("inf")
for _ in range(int(sys.argv[1])):
    t0 = time.perf_counter()
    again = optri.triangulate_many(polys)
    warm = min(warm, time.perf_counter() - t0)
assert all(a.method == "many" and a.weight == b.weight for a, b in zip(first, again))
print(json.dumps({"first": t_first, "warm": warm, "numba": "numba" in sys.modules,
                  "cost": sum(r.weight for r in first)}))
"""


def first_call(src: Path, repeat: int) -> dict:
    """The child above in a fresh process on ``src``, with an empty numba cache."""
    with tempfile.TemporaryDirectory(prefix="optri-first-call-") as cache:
        env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=cache)
        start = time.perf_counter()
        out = subprocess.run(
            [sys.executable, "-c", FIRST_CALL, str(repeat)],
            env=env, capture_output=True, text=True, check=True,
        )  # fmt: skip
        whole = time.perf_counter() - start
    result = json.loads(out.stdout.strip().splitlines()[-1])
    result["process"] = whole
    return result


def band(lo: int, hi: int, count: int, seed: int, repeat: int, slow: int) -> dict:
    import mapbox_earcut  # noqa: F401  # import cost stays out of the timings
    import shapely

    rng = np.random.default_rng(seed)
    polys = [star_polygon(rng, int(rng.integers(lo, hi + 1))) for _ in range(count)]
    geoms = np.array([shapely.Polygon(p) for p in polys], dtype=object)
    optri.triangulate_many(polys[:4])  # load the compiled kernels first
    many, t_many = timed(optri.triangulate_many, polys, repeat=repeat)
    _, t_one = timed(one_thread, polys, repeat=repeat)
    each, t_each = timed(per_polygon, polys[:slow], repeat=1)
    cdt, t_cdt = timed(shapely.constrained_delaunay_triangles, geoms, repeat=repeat)
    ear, t_ear = timed(run_earcut, polys, repeat=repeat)
    assert all(r.method == "many" for r in many)
    for a, b in zip(many, each):  # the same optimum, bit for bit, and the same triangles
        assert a.weight == b.weight and np.array_equal(a.triangles, b.triangles)
    best = np.array([r.weight for r in many])
    cdt_cost = shapely.length(cdt)  # a collection's length: the sum of its triangles' perimeters
    ear_cost = np.array([perimeter_sum(p, t) for p, t in zip(polys, ear)])
    above = {
        "cdt": (cdt_cost / best - 1) * 100,
        "earcut": (ear_cost / best - 1) * 100,
    }
    return {
        "band": f"{lo}-{hi}",
        "count": count,
        "rate": {
            "compiled": count / t_many,
            "compiled 1 thread": count / t_one,
            "per polygon": min(slow, count) / t_each,
            "shapely CDT": count / t_cdt,
            "earcut": count / t_ear,
        },
        "compiled / CDT time": t_many / t_cdt,
        "above_mean": {k: float(v.mean()) for k, v in above.items()},
        "above_max": {k: float(v.max()) for k, v in above.items()},
        "below_zero": {k: int((v < -1e-9).sum()) for k, v in above.items()},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-band", type=int, default=1000)
    ap.add_argument("--bands", default="4-8,8-16,16-32,32-64")
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--repeat", type=int, default=3, help="rounds per timing; the best is kept")
    ap.add_argument(
        "--slow", type=int, default=1000, help="polygons timed on the per-polygon path (slow)"
    )
    ap.add_argument("--json", type=Path, help="write the results here too")
    ap.add_argument("--first-call", action="store_true", help="first call in a fresh process")
    ap.add_argument("--src", type=Path, help="with --first-call: the checkout's src to run")
    args = ap.parse_args()
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    if args.first_call:
        src = args.src or Path(__file__).resolve().parents[1] / "src"
        print(f"load average {load} on {os.cpu_count()} cores; {src}")
        r = first_call(src.resolve(), args.repeat)
        print(
            f"100 star polygons, 8-64 vertices: import + first call {r['first']:.3f} s "
            f"(whole process {r['process']:.3f} s), warm {r['warm'] * 1e3:.2f} ms; "
            f"numba imported: {r['numba']}; cost sum {r['cost']!r}"
        )
        return
    bands = [tuple(int(x) for x in b.split("-")) for b in args.bands.split(",")]
    from optri.engines.threads import available

    print(f"load average {load} on {os.cpu_count()} cores; threads {available()}")
    print(f"{args.per_band} random star polygons per band, perimeter sum; polygons/s")
    head = ["vertices", "compiled", "1 thread", "per polygon", "shapely CDT", "earcut", "vs CDT"]
    print("".join(f"{h:>12}" for h in head) + "   CDT % above opt   earcut % above opt")
    results = []
    for lo, hi in bands:
        r = band(lo, hi, args.per_band, args.seed + lo, args.repeat, args.slow)
        results.append(r)
        rates = "".join(f"{v:>12.0f}" for v in r["rate"].values())
        ratio = f"{r['compiled / CDT time']:>11.2f}x"
        mean, worst = r["above_mean"], r["above_max"]
        gaps = "".join(f"   {mean[k]:6.2f} (max {worst[k]:5.1f})" for k in ("cdt", "earcut"))
        print(f"{r['band']:>12}{rates}{ratio}{gaps}", flush=True)
        assert r["below_zero"] == {"cdt": 0, "earcut": 0}, "a heuristic beat the optimum"
    if args.json:
        args.json.write_text(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
