"""The first call a user waits for: each entry point in a fresh process, every cache empty.

Usage: python benchmarks/bench_first_call.py [--runs 5] [--base REV] [--json OUT]

Each case runs in a new Python process with empty caches (a fresh ``NUMBA_CACHE_DIR``
and ``HOME``, no ``__pycache__`` reuse for optri's own modules), and times the call
itself inside that process (``perf_counter`` around the first call, after ``import
optri``), plus the whole process from the outside. Medians of ``--runs``.

Cases (the issue's targets: each call <= 0.5 s, the whole ``optri solve`` <= 1.5 s):

* ``convex``: ``triangulate`` of a convex 200-gon (default weight, ``method="auto"``)
* ``star``: ``triangulate`` of a simple (star-shaped) 200-gon
* ``many``: ``triangulate_many`` of 100 simple polygons of 8-40 vertices
* ``fill``: ``fill_holes`` on the bundled ``sphere_two_holes.obj`` (needs trimesh)
* ``cli``: the whole ``optri solve`` process on a 200-gon from a CSV file
* ``cdt``: for scale, a whole process that runs shapely's constrained Delaunay
  triangulation on the same star polygon (needs shapely)

With ``--base REV`` every case also runs against the package at git revision REV
(a temporary ``git worktree``, loaded with ``PYTHONPATH``), in turns with this
checkout, and the table shows both and their ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SETUP = r"""
import math, sys, time
import numpy as np

def star(n, seed=3):
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    ang = np.unique(ang)
    r = rng.uniform(0.5, 1.5, len(ang))
    return np.column_stack([r * np.cos(ang), r * np.sin(ang)])

def convex(n):
    t = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return np.column_stack([np.cos(t) * 3.0, np.sin(t) * 2.0 + 0.1 * np.cos(3 * t)])
"""

CASES = {
    "convex": "import optri\nP = convex(200)\nt = time.perf_counter()\noptri.triangulate(P)",
    "star": "import optri\nP = star(200)\nt = time.perf_counter()\noptri.triangulate(P)",
    "many": (
        "import optri\nPS = [star(int(8 + (i * 7) % 33), seed=i) for i in range(100)]\n"
        "t = time.perf_counter()\noptri.triangulate_many(PS)"
    ),
    "fill": (
        "import optri, trimesh\nm = trimesh.load(optri.data.path('sphere_two_holes.obj'))\n"
        "t = time.perf_counter()\noptri.fill_holes(m)"
    ),
    "cdt": (
        "import shapely\nP = star(200)\nt = time.perf_counter()\n"
        "shapely.constrained_delaunay_triangles(shapely.Polygon(P))"
    ),
}
TAIL = "\nprint(time.perf_counter() - t)\n"


def _env(src: Path, home: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src)
    env["HOME"] = str(home)
    env["NUMBA_CACHE_DIR"] = str(home / "numba-cache")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["MPLBACKEND"] = "Agg"
    return env


def _one(case: str, src: Path, csv: Path) -> tuple[float, float]:
    """(seconds of the call inside the process, seconds of the whole process)."""
    with tempfile.TemporaryDirectory() as home:
        env = _env(src, Path(home))
        if case == "cli":
            cmd = [sys.executable, "-m", "optri", "solve", str(csv)]
        else:
            cmd = [sys.executable, "-c", SETUP + CASES[case] + TAIL]
        t0 = time.perf_counter()
        res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
        whole = time.perf_counter() - t0
    if res.returncode != 0:
        raise RuntimeError(f"{case}: {res.stderr.strip().splitlines()[-1:]}")
    inner = whole if case == "cli" else float(res.stdout.strip().splitlines()[-1])
    return inner, whole


def _available(case: str) -> bool:
    need = {"fill": "trimesh", "cdt": "shapely"}.get(case)
    if need is None:
        return True
    import importlib.util

    return importlib.util.find_spec(need) is not None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--base", help="git revision to compare with")
    ap.add_argument("--cases", default="convex,star,many,fill,cli,cdt")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    if args.runs < 1:
        ap.error("--runs must be at least 1")
    cases = [c for c in args.cases.split(",") if c and _available(c)]
    work = Path(tempfile.mkdtemp(prefix="optri-first-"))
    versions = {"this": ROOT / "src"}
    try:
        if args.base:
            base = work / "base"
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach", str(base), args.base],
                check=True,
            )
            versions["base"] = base / "src"
        csv = work / "star.csv"
        sys.path.insert(0, str(ROOT / "src"))
        import numpy as np

        ns: dict[str, object] = {}
        exec(SETUP, ns)
        np.savetxt(csv, ns["star"](200), delimiter=",", header="x,y", comments="")  # type: ignore[operator]
        results: dict[str, dict[str, list[tuple[float, float]]]] = {
            c: {v: [] for v in versions} for c in cases
        }
        for _ in range(args.runs):
            for c in cases:
                for v, src in versions.items():
                    if c == "cdt" and v != "this":
                        continue
                    results[c][v].append(_one(c, src, csv))
        print(f"first call in a fresh process, empty caches; medians of {args.runs}")
        head = f"{'case':8} {'call s':>8} {'process s':>10}"
        if args.base:
            head += f" {'base call s':>12} {'base proc s':>12} {'call ratio':>11}"
        print(head)
        table = {}
        for c in cases:
            med = {
                v: (statistics.median(r[0] for r in rs), statistics.median(r[1] for r in rs))
                for v, rs in results[c].items()
                if rs
            }
            table[c] = med
            line = f"{c:8} {med['this'][0]:8.3f} {med['this'][1]:10.3f}"
            if "base" in med:
                b = med["base"]
                line += f" {b[0]:12.3f} {b[1]:12.3f} {med['this'][0] / b[0]:11.3f}"
            print(line)
        if args.json:
            args.json.write_text(json.dumps(table, indent=1))
    finally:
        if args.base:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(work / "base")],
                check=False,
            )
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
