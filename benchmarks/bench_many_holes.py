"""Many small holes in one mesh: the time per hole as the mesh grows, against CGAL.

A scanned mesh has thousands of small holes. The stars of well-separated vertices (six
edges each, one per 200 faces) are cut from icospheres of 20k, 80k and 320k faces; then

* optri: ``fill_holes`` (flat patches) and ``fill_holes(refine=True, fair=1)`` on the
  whole mesh, one call each;
* CGAL: ``triangulate_hole`` and ``triangulate_refine_and_fair_hole`` (the ``cgal``
  wheel) called on each hole's border halfedge in turn, found before the clock starts.

Per mesh and method: holes, time, milliseconds per hole, and optri's time as a ratio
to CGAL's in the same run. Per-hole work that grew with the mesh would show as
milliseconds per hole growing with the faces.

    PYTHONPATH=src python benchmarks/bench_many_holes.py            # levels 5 6 7, ~2 minutes
    PYTHONPATH=src python benchmarks/bench_many_holes.py --levels 5,6

Needs ``pip install cgal`` for the peer (benchmark only; left out when missing).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings

import numpy as np

from optri import fill_holes

#: One hole per this many faces.
FACES_PER_HOLE = 200


def icosphere(level: int) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=level)
    return np.asarray(s.vertices, dtype=np.float64), np.asarray(s.faces, dtype=np.int64)


def cut_stars(v: np.ndarray, f: np.ndarray, holes: int, seed: int = 1):
    """The mesh without the faces around ``holes`` vertices at least three rings apart."""
    rng = np.random.default_rng(seed)
    at = [[] for _ in range(len(v))]
    for t, face in enumerate(f.tolist()):
        for x in face:
            at[x].append(t)
    taken = np.zeros(len(v), dtype=bool)
    keep = np.ones(len(f), dtype=bool)
    cut = 0
    for p in rng.permutation(len(v)).tolist():
        ring = np.unique(f[at[p]])
        near = np.unique(f[[t for x in ring.tolist() for t in at[x]]])
        if taken[near].any():
            continue
        taken[near] = True
        keep[at[p]] = False
        cut += 1
        if cut == holes:
            break
    f2 = f[keep]
    used = np.unique(f2)
    renumber = np.full(len(v), -1)
    renumber[used] = np.arange(len(used))
    return v[used], renumber[f2], cut


def time_optri(v, f, **kw) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        _, records = fill_holes((v, f), **kw)
        seconds = time.perf_counter() - start
    assert all(r.status == "filled" for r in records)
    return seconds


def time_cgal(v, f, refine: bool) -> float | None:
    try:
        from CGAL import CGAL_Polygon_mesh_processing as pmp
        from CGAL.CGAL_Polyhedron_3 import Polyhedron_3
    except ImportError:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "in.off")
        with open(path, "w") as fh:
            fh.write(f"OFF\n{len(v)} {len(f)} 0\n")
            np.savetxt(fh, v, fmt="%.17g")
            np.savetxt(fh, np.column_stack([np.full(len(f), 3), f]), fmt="%d")
        poly = Polyhedron_3(path)
    starts, seen = [], set()
    for h in poly.halfedges():  # one border halfedge per hole
        if not h.is_border():
            continue
        key = (h.vertex().point().x(), h.vertex().point().y(), h.vertex().point().z())
        if key in seen:
            continue
        g = h
        while True:
            p = g.vertex().point()
            seen.add((p.x(), p.y(), p.z()))
            g = g.next()
            if g == h:
                break
        starts.append(h)
    start = time.perf_counter()
    for h in starts:
        if refine:
            pmp.triangulate_refine_and_fair_hole(poly, h, [], [])
        else:
            pmp.triangulate_hole(poly, h, [])
    return time.perf_counter() - start


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--levels", default="5,6,7", help="icosphere subdivision levels")
    args = ap.parse_args(argv)
    print("| faces | holes | method | optri s | ms/hole | CGAL s | ms/hole | optri/CGAL |")
    print("|---:|---:|---|---:|---:|---:|---:|---:|")
    for level in (int(x) for x in args.levels.split(",")):
        v, f = icosphere(level)
        v, f, holes = cut_stars(v, f, len(f) // FACES_PER_HOLE)
        for name, kw in (("flat", {}), ("refine, fair=1", {"refine": True, "fair": 1})):
            ours = time_optri(v, f, **kw)
            theirs = time_cgal(v, f, refine=bool(kw))
            peer = (
                f"{theirs:.2f} | {1e3 * theirs / holes:.2f} | {ours / theirs:.2f}x"
                if theirs
                else "- | - | -"
            )
            print(
                f"| {len(f)} | {holes} | {name} | {ours:.2f} | {1e3 * ours / holes:.2f} | {peer} |",
                flush=True,
            )
    load = os.getloadavg()
    print(f"\nload average {load[0]:.2f}; python {sys.version.split()[0]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
