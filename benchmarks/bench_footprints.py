"""A layer of building footprints in memory: ``optri.triangulate_many(gdf)`` against shapely CDT.

Footprint-like polygons (seeded): rotated rectangles (4 vertices, most of
them), L-shapes (6) and irregular convex outlines (5-8), 5-40 m across, in
projected metres (EPSG:32633 coordinates around Berlin), as one GeoDataFrame
with an id and a name column. In the same process, best of ``--repeat``:

* ``shapely.constrained_delaunay_triangles`` on the GeoSeries' array (the
  hand-written way: a GeometryCollection per row, no attributes);
* ``optri.triangulate_many(gdf)`` (the optimum; a GeoDataFrame with the
  attributes, status, cost, reason and a GeometryCollection per row);
* ``optri.triangulate_many(gdf, explode=True)`` (a row per triangle).

Reported: seconds of each, optri's time over CDT's (the target is at most
2.0 for the default call), and the machine's load average first (timings on a
shared machine are only comparable within one run). ``--profile`` prints
cProfile's top functions of one ``triangulate_many`` call.

    python benchmarks/bench_footprints.py                  # 100,000 footprints
    python benchmarks/bench_footprints.py --count 20000 --profile
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

import numpy as np

import optri


def footprints(count: int, seed: int = 0) -> list:
    """``count`` footprint polygons (shapely), median 4 vertices."""
    import shapely

    rng = np.random.default_rng(seed)
    kind = rng.choice(3, size=count, p=[0.7, 0.2, 0.1])
    out = []
    for k in kind:
        w, h = rng.uniform(5, 40, 2)
        if k == 0:
            ring = np.array([[0, 0], [w, 0], [w, h], [0, h]])
        elif k == 1:
            a, b = rng.uniform(0.3, 0.7, 2)
            ring = np.array([[0, 0], [w, 0], [w, b * h], [a * w, b * h], [a * w, h], [0, h]])
        else:
            m = int(rng.integers(5, 9))
            ang = np.sort(rng.uniform(0, 2 * np.pi, m))
            ring = np.column_stack((w * np.cos(ang), h * np.sin(ang)))
        t = rng.uniform(0, np.pi)
        rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
        origin = rng.uniform([385_000, 5_810_000], [400_000, 5_830_000])
        out.append(shapely.Polygon((ring @ rot.T + origin).round(2)))
    return out


def best(fn, repeat: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    import geopandas as gpd
    import shapely

    print("load average:", ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    polys = footprints(args.count)
    gdf = gpd.GeoDataFrame(
        {"id": np.arange(args.count), "name": [f"b{i}" for i in range(args.count)]},
        geometry=polys,
        crs="EPSG:32633",
    )
    median = np.median(shapely.get_num_coordinates(polys)) - 1
    print(f"{args.count} footprints, median {median:.0f} vertices")
    optri.triangulate_many(gdf.iloc[:100])  # loads the compiled core
    cdt, _ = best(lambda: shapely.constrained_delaunay_triangles(gdf.geometry.values), args.repeat)
    many, out = best(lambda: optri.triangulate_many(gdf), args.repeat)
    exploded, _ = best(lambda: optri.triangulate_many(gdf, explode=True), args.repeat)
    ok = out["status"] == "ok"  # a few random outlines repeat a vertex once rounded
    assert ok.mean() > 0.99 and out.geometry[ok].is_valid.all()
    print(f"shapely CDT                   {cdt:8.3f} s")
    print(f"triangulate_many(gdf)         {many:8.3f} s   {many / cdt:5.2f}x CDT")
    print(f"triangulate_many(explode)     {exploded:8.3f} s   {exploded / cdt:5.2f}x CDT")
    if args.profile:
        prof = cProfile.Profile()
        prof.runcall(optri.triangulate_many, gdf)
        pstats.Stats(prof).sort_stats("cumulative").print_stats(25)


if __name__ == "__main__":
    main()
