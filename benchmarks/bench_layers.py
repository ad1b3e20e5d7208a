"""GIS layers end to end: optri batch, Dask and triangulate_many against a hand-written pipeline.

The baseline, timed in the same run, is what a GIS user writes by hand:
``geopandas.read_parquet`` -> ``shapely.constrained_delaunay_triangles`` ->
``GeoDataFrame.to_parquet``. Every configuration runs in a fresh process (its
imports, its reading and writing included), and each result is reported with
its ratio to that pipeline, the process tree's peak RSS and CPU seconds (the
process and its children, sampled with psutil; without psutil the largest
reaped child's ``ru_maxrss`` and no CPU) and the machine's load
(``os.getloadavg``) before and after.

Sections (``--sections a,b,c``):

a. real OSM building footprints (``benchmarks/data/osm_buildings.geojson``,
   projected to UTM zone 32N) copied ``--footprints`` times, each copy rotated
   and shifted: ``batch -j 1``, ``-j 2``, ``--scheduler dask`` (2 workers) and
   ``triangulate_many`` + read/write, each against the pipeline; and the solve
   alone, ``triangulate_many(gs)`` against ``constrained_delaunay_triangles(gs)``.
b. ``--stars`` star polygons of 8-64 vertices: ``batch -j 2`` against the
   pipeline, ``-j 2`` against ``-j 1``, Dask against the local pool (``-j 2``).

Dask is timed both ways in (a) and (b): ``--scheduler dask`` starts (and
stops) a LocalCluster inside the timed run, as a one-off command does; and
``--scheduler tcp://...`` sends the run to a cluster that is already running,
as a Dask user's is: a LocalCluster of single-threaded worker processes started
by this script before the clock (its scheduler then runs in this process, not
in the timed one), timed twice, its workers cold (their first optri task) and
then warm. Its CPU seconds include the cluster's (scheduler and workers), its
peak RSS only the client's.
c. memory: ``batch -j 2`` on ``--rows`` footprints and on a tenth of them (flat
   memory: about equal peaks); ``--rows 10000000`` for the large run.

    python benchmarks/bench_layers.py                       # a and b, a few minutes
    python benchmarks/bench_layers.py --sections c --rows 1000000
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FOOTPRINTS = ROOT / "benchmarks" / "data" / "osm_buildings.geojson"
#: The footprints' UTM zone (10.07 degrees east).
UTM = "EPSG:32632"

PIPELINE = """
import sys, geopandas, shapely
g = geopandas.read_parquet(sys.argv[1])
g = g.set_geometry(shapely.constrained_delaunay_triangles(g.geometry.values))
g.to_parquet(sys.argv[2])
"""
MANY = """
import sys, geopandas, optri
g = geopandas.read_parquet(sys.argv[1])
optri.triangulate_many(g).to_parquet(sys.argv[2])
"""
SOLVE_ONLY = """
import json, sys, time, geopandas, optri, shapely
gs = geopandas.read_parquet(sys.argv[1]).geometry
t = time.perf_counter()
shapely.constrained_delaunay_triangles(gs.values)
cdt = time.perf_counter() - t
t = time.perf_counter()
optri.triangulate_many(gs)
many = time.perf_counter() - t
print(json.dumps({"cdt": cdt, "many": many}))
"""


def footprints(count: int, seed: int = 0):
    """``count`` rotated, shifted copies of the real (valid) footprints, in metres (UTM 32N)."""
    import geopandas
    import shapely

    base = geopandas.read_file(FOOTPRINTS).to_crs(UTM)
    base = base[base.is_valid].reset_index(drop=True)  # CDT refuses the one that crosses itself
    rng = np.random.default_rng(seed)
    which = rng.integers(0, len(base), count)
    angle = rng.uniform(0, 2 * np.pi, count)
    side = int(np.ceil(np.sqrt(count)))
    shift = np.column_stack((np.arange(count) % side, np.arange(count) // side)) * 60.0
    shift += base.total_bounds[:2]
    geoms = np.empty(count, dtype=object)
    for b, poly in enumerate(base.geometry):
        rows = np.flatnonzero(which == b)
        ring = shapely.get_coordinates(poly.exterior)
        ring = ring - ring[:-1].mean(axis=0)
        c, s = np.cos(angle[rows])[:, None], np.sin(angle[rows])[:, None]
        x = ring[None, :, 0] * c - ring[None, :, 1] * s + shift[rows, :1]
        y = ring[None, :, 0] * s + ring[None, :, 1] * c + shift[rows, 1:]
        geoms[rows] = shapely.polygons(np.stack((x, y), axis=-1))
    ids = [f"b{i}" for i in range(count)]
    osm = base["osm_id"].to_numpy()[which]
    return geopandas.GeoDataFrame({"id": ids, "osm_id": osm}, geometry=geoms, crs=UTM)


def stars(count: int, seed: int = 1):
    """``count`` star-shaped polygons of 8-64 vertices, spread over a grid (metres)."""
    import geopandas
    import shapely

    rng = np.random.default_rng(seed)
    sizes = rng.integers(8, 65, count)
    geoms = np.empty(count, dtype=object)
    side = int(np.ceil(np.sqrt(count)))
    for n in np.unique(sizes):
        rows = np.flatnonzero(sizes == n)
        angles = np.linspace(0, 2 * np.pi, n, endpoint=False)[None, :]
        angles = angles + rng.uniform(0, 1.5 * np.pi / n, (len(rows), n))
        radii = rng.uniform(3.0, 10.0, (len(rows), n))
        cx = (rows % side * 25.0)[:, None]
        cy = (rows // side * 25.0)[:, None]
        ring = np.stack((cx + radii * np.cos(angles), cy + radii * np.sin(angles)), axis=-1)
        geoms[rows] = shapely.polygons(np.concatenate((ring, ring[:, :1]), axis=1))
    ids = [f"s{i}" for i in range(count)]
    return geopandas.GeoDataFrame({"id": ids}, geometry=geoms, crs=UTM)


def run(cmd: list[str], out: Path) -> dict:
    """Run ``cmd`` in a fresh process; its seconds, tree peak RSS (MB) and the load around it."""
    for p in (out, out.parent / f".{out.name}.lock"):
        if p.is_dir():
            import shutil

            shutil.rmtree(p)
        elif p.exists():
            p.unlink()
    load = os.getloadavg()[0]
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak, cpu = _watch(proc)
    stdout, stderr = proc.communicate()
    seconds = time.perf_counter() - start
    if proc.returncode:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{stderr[-2000:]}")
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return {
        "seconds": seconds,
        "peak_mb": peak if peak is not None else children,
        "cpu": cpu,
        "load": (load, os.getloadavg()[0]),
        "stdout": stdout,
    }


def _watch(proc: subprocess.Popen) -> tuple[float | None, float | None]:
    """Peak summed RSS (MB) and CPU seconds of ``proc`` and its descendants (psutil).

    Sampled every 50 ms: the CPU time is each process's last sample, summed (a
    process's last 50 ms may be missed). On a loaded machine CPU seconds compare
    configurations better than wall time.
    """
    try:
        import psutil
    except ImportError:
        return None, None
    peak = 0.0
    cpu: dict[int, float] = {}
    stop = threading.Event()

    def sample() -> None:
        nonlocal peak
        try:
            root = psutil.Process(proc.pid)
        except psutil.NoSuchProcess:
            return
        while not stop.is_set():
            total = 0
            try:
                for p in [root, *root.children(recursive=True)]:
                    try:
                        total += p.memory_info().rss
                        times = p.cpu_times()
                        cpu[p.pid] = times.user + times.system
                    except psutil.NoSuchProcess:
                        pass
            except psutil.NoSuchProcess:
                return
            peak = max(peak, total / 2**20)
            stop.wait(0.05)

    t = threading.Thread(target=sample, daemon=True)
    t.start()
    proc.wait()
    stop.set()
    t.join()
    return peak, sum(cpu.values())


def optri_batch(src: Path, out: Path, *args: str) -> list[str]:
    exe = [sys.executable, "-m", "optri", "batch", str(src), "-o", str(out), "-q", *args]
    return exe


@contextlib.contextmanager
def running_cluster(workers: int):
    """The address of a LocalCluster of ``workers`` single-threaded processes, started now."""
    import distributed

    with distributed.LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    ) as cluster:
        yield cluster.scheduler_address


def dask_both_ways(src: Path, out: Path, workers: int, base: dict, what: str) -> None:
    """Dask with the cluster started in the run, then on a running cluster (cold, warm)."""
    r = run(optri_batch(src, out, "-j", str(workers), "--scheduler", "dask"), out)
    report(f"optri batch --scheduler dask ({workers} workers)", r, base, what)
    with running_cluster(workers) as address:
        for state in ("cold", "warm"):
            before = _cluster_cpu()
            r = run(optri_batch(src, out, "--scheduler", address), out)
            if r["cpu"] is not None:  # the cluster's work counts too
                r["cpu"] += _cluster_cpu() - before
            report(f"  on a running cluster, workers {state}", r, base, what)


def _cluster_cpu() -> float:
    """CPU seconds so far of this process (the running cluster's scheduler) and its workers."""
    try:
        import psutil
    except ImportError:
        return 0.0
    total = 0.0
    me = psutil.Process()
    for p in [me, *me.children(recursive=True)]:
        with contextlib.suppress(psutil.NoSuchProcess):
            times = p.cpu_times()
            total += times.user + times.system
    return total


def report(name: str, r: dict, base: dict | None, what: str = "pipeline") -> None:
    ratio = f"{r['seconds'] / base['seconds']:6.2f}x {what}" if base else " " * 8 + "baseline"
    print(
        f"{name:<40} {r['seconds']:8.2f} s  {ratio:<22} peak {r['peak_mb']:7.0f} MB  "
        f"cpu {r['cpu'] or float('nan'):6.2f} s  load {r['load'][0]:.2f}->{r['load'][1]:.2f}",
        flush=True,
    )


def section_a(d: Path, count: int, workers: int) -> None:
    src = d / "footprints.parquet"
    gdf = footprints(count)
    verts = gdf.geometry.count_coordinates().to_numpy() - 1
    gdf.to_parquet(src, row_group_size=max(1, count // (4 * workers)))
    print(f"\n(a) {count:,} real OSM footprints (median {np.median(verts):.0f} vertices), {UTM}")
    py = sys.executable
    base = run([py, "-c", PIPELINE, str(src), str(d / "cdt.parquet")], d / "cdt.parquet")
    report("hand-written CDT pipeline", base, None)
    out = d / "out.parquet"
    report("optri batch -j 1", run(optri_batch(src, out, "-j", "1"), out), base)
    report(f"optri batch -j {workers}", run(optri_batch(src, out, "-j", str(workers)), out), base)
    dask_both_ways(src, out, workers, base, "pipeline")
    report(
        "triangulate_many(gdf) + read/write", run([py, "-c", MANY, str(src), str(out)], out), base
    )
    solve = json.loads(run([py, "-c", SOLVE_ONLY, str(src)], out)["stdout"])
    print(
        f"{'solve alone: triangulate_many(gs) / CDT':<40} {solve['many']:8.2f} s  "
        f"{solve['many'] / solve['cdt']:6.2f}x CDT ({solve['cdt']:.2f} s)"
    )


def section_b(d: Path, count: int, workers: int) -> None:
    src = d / "stars.parquet"
    stars(count).to_parquet(src, row_group_size=max(1, count // (4 * workers)))
    print(f"\n(b) {count:,} star polygons of 8-64 vertices")
    py = sys.executable
    base = run([py, "-c", PIPELINE, str(src), str(d / "cdt.parquet")], d / "cdt.parquet")
    report("hand-written CDT pipeline", base, None)
    out = d / "out.parquet"
    one = run(optri_batch(src, out, "-j", "1"), out)
    report("optri batch -j 1", one, base)
    pool = run(optri_batch(src, out, "-j", str(workers)), out)
    report(f"optri batch -j {workers}", pool, base)
    report(f"optri batch -j {workers} against -j 1", pool, one, "-j 1")
    dask_both_ways(src, out, workers, pool, "local pool")


def section_c(d: Path, rows: int, workers: int) -> None:
    print(f"\n(c) memory: optri batch -j {workers} into GeoParquet, peak RSS of the process tree")
    small = None
    for count in (max(1, rows // 10), rows):
        src = d / f"fp{count}.parquet"
        footprints(count).to_parquet(src, row_group_size=max(1, min(100_000, count // 4)))
        out = d / "out.parquet"
        r = run(optri_batch(src, out, "-j", str(workers)), out)
        report(f"{count:,} footprints", r, small, "a tenth")
        src.unlink()
        if small is None:
            small = r
        else:
            print(f"peak RSS {r['peak_mb'] / small['peak_mb']:.2f}x that of a tenth of the rows")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sections", default="a,b", help="which of a, b, c to run (default a,b)")
    ap.add_argument("--footprints", type=int, default=100_000, help="copies in (a)")
    ap.add_argument("--stars", type=int, default=30_000, help="star polygons in (b)")
    ap.add_argument("--rows", type=int, default=1_000_000, help="footprints in (c)")
    ap.add_argument("--workers", type=int, default=2, help="processes / Dask workers")
    ap.add_argument("--dir", type=Path, help="work folder (default: a temporary one)")
    args = ap.parse_args()
    import optri

    print(f"optri {optri.__version__}, {os.cpu_count()} CPUs, load {os.getloadavg()}")
    with tempfile.TemporaryDirectory(dir=args.dir) as tmp:
        d = Path(tmp)
        sections = set(args.sections.split(","))
        if "a" in sections:
            section_a(d, args.footprints, args.workers)
        if "b" in sections:
            section_b(d, args.stars, args.workers)
        if "c" in sections:
            section_c(d, args.rows, args.workers)


if __name__ == "__main__":
    main()
