"""Port check: this checkout's compiled paths against another revision's, hash by hash.

Usage: python benchmarks/check_port.py [--rev REV] [--paths generic,minplus,many]
                                       [--sizes 5 6 ... 300] [--quick] [--keep]

Checks out REV (default 8cfecf8, the last numba-only engine) into a temporary git
worktree, then runs this script twice as a worker, once with ``PYTHONPATH`` on
that worktree's ``src`` and once on this checkout's, each solving the same cases
and writing a SHA-256 per case of what it got: the optimum (its float's bits),
the triangles and, where kept, the exported table (costs and splits). Then it
prints how many cases each path has, how many agree, and the first that do not.

Paths (``--paths``):

``generic``
    ``method="fast"`` on every case outside the min-plus table: every built-in
    weight with ``"max"``, the non-edge weights with ``"sum"``, the
    lexicographic pairs (``("max", "sum")`` solved in two phases through a
    gate, ``("sum", "max")``), a user's ``numba.njit`` weight; float64 and
    float32 tables; convex polygons, star-shaped ones (a chord mask), 3-D ones,
    1-D values (``"product"``).
``minplus``
    ``method="fast"`` with ``"perimeter"`` and ``"diagonal"`` under ``"sum"``.
``many``
    the many-polygon path (:func:`optri.batch.compiled.solve_compiled`), one
    chunk a size, methods ``"auto"`` and ``"fast"``.

The exit status is 1 when any case differs. The worker's cases are fixed by the
seed, so both sides solve the same inputs.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

DEFAULT_REV = "8cfecf8"
PATHS = ("generic", "minplus", "many")
SIZES = (5, 6, 7, 8, 9, 10, 11, 13, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200, 250, 300)
QUICK_SIZES = (5, 6, 7, 9, 13, 20, 40, 64, 100)
POINT_WEIGHTS = ("perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio")
EDGE_WEIGHTS = ("perimeter", "diagonal")
PAIRS = (
    (("max_angle", "area"), ("max", "sum")),
    (("area", "perimeter"), ("max", "sum")),
    (("perimeter", "aspect_ratio"), ("sum", "max")),
    (("min_angle", "max_angle"), ("sum", "max")),
)
MANY_WEIGHTS = ("perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio")
REPO = Path(__file__).resolve().parents[1]


# --- the cases -----------------------------------------------------------------------


def shapes(n: int, seed: int) -> dict[str, np.ndarray]:
    """The polygons of size ``n``: convex, star-shaped (non-convex: a chord mask), 3-D."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
    t[0] = 0.0
    convex = np.column_stack((2.0 * np.cos(t), np.sin(t))) * 3.7 + [11.0, -5.0]
    radius = rng.uniform(0.4, 1.0, n)
    star = np.column_stack((radius * np.cos(t), radius * np.sin(t))) * 100.0
    spatial = np.column_stack(
        (np.cos(t), np.sin(t), 0.3 * np.sin(3.0 * t) + rng.normal(0, 0.01, n))
    )
    return {"convex": convex, "star": star, "spatial": spatial}


def user_weight() -> Any:
    """A user's ``numba.njit`` weight over the caller's vertex array."""
    import math

    import numba

    @numba.njit(cache=False)
    def sides(v, i, k, j):  # type: ignore[no-untyped-def]
        total = 0.0
        for a, b in ((i, k), (k, j), (j, i)):
            s = 0.0
            for c in range(v.shape[1]):
                s += (v[a, c] - v[b, c]) ** 2
            total += math.sqrt(s) * (1.0 + 0.001 * (a % 7))
        return total

    return sides


def cases(path: str, sizes: list[int]) -> list[tuple[str, Any, Any, Any, str, np.ndarray]]:
    """``(key, weight, objective, dtype, method, vertices)`` of every case of ``path``."""
    out = []
    user = user_weight() if path == "generic" else None
    for n in sizes:
        polys = shapes(n, seed=n)
        for dtype in ("float64", "float32"):
            for name, v in polys.items():
                runs: list[tuple[Any, Any]] = []
                if path == "minplus":
                    runs = [(w, "sum") for w in EDGE_WEIGHTS]
                elif path == "generic":
                    runs = [(w, "max") for w in POINT_WEIGHTS]
                    runs += [(w, "sum") for w in POINT_WEIGHTS if w not in EDGE_WEIGHTS]
                    runs += list(PAIRS)
                    runs += [(user, "sum"), (user, "max"), ((user, "max_angle"), ("sum", "max"))]
                for w, obj in runs:
                    label = _label(w)
                    key = f"n={n} {name} {label} {obj} {dtype}"
                    out.append((key, w, obj, dtype, "fast", v))
            if path == "generic":
                values = np.random.default_rng(n + 1).uniform(0.5, 40.0, n)
                for obj in ("sum", "max"):
                    out.append(
                        (
                            f"n={n} values product {obj} {dtype}",
                            "product",
                            obj,
                            dtype,
                            "fast",
                            values,
                        )
                    )
    return out


def _label(w: Any) -> str:
    if isinstance(w, tuple):
        return "+".join(_label(x) for x in w)
    return w if isinstance(w, str) else "user"


def digest(*parts: Any) -> str:
    h = hashlib.sha256()
    for p in parts:
        if isinstance(p, np.ndarray):
            h.update(str(p.dtype).encode() + str(p.shape).encode())
            h.update(np.ascontiguousarray(p).tobytes())
        else:
            h.update(repr(p).encode())
    return h.hexdigest()[:20]


def _cost_bits(cost: Any) -> Any:
    if isinstance(cost, tuple):
        return tuple(_cost_bits(c) for c in cost)
    return np.float64(cost).tobytes().hex()


def run_fast(path: str, sizes: list[int]) -> dict[str, str]:
    import optri

    out = {}
    for key, w, obj, dtype, method, v in cases(path, sizes):
        try:
            t = optri.triangulate(v, w, obj, method=method, dtype=dtype, keep_table=True)
            out[key] = digest(_cost_bits(t.weight), t.triangles, t.table)
        except Exception as exc:  # noqa: BLE001 - an error is a result to compare too
            out[key] = digest(type(exc).__name__, str(exc))
    return out


def run_many(sizes: list[int]) -> dict[str, str]:
    from optri.batch.compiled import solve_compiled
    from optri.batch.each import SolveOptions

    out = {}
    for n in sizes:
        polys = [p for p in shapes(n, seed=n).values() if p.shape[1] == 2]
        polys += [shapes(n, seed=n + 1000 * s)["star"] for s in range(1, 4)]
        for method in ("auto", "fast"):
            for w in MANY_WEIGHTS:
                for obj in ("sum", "max"):
                    key = f"n={n} many {w} {obj} {method}"
                    try:
                        res = solve_compiled(polys, SolveOptions(w, obj, method))
                        parts = []
                        for r in res:
                            tri = getattr(r, "triangles", None)
                            cost = getattr(r, "weight", None)
                            parts += [
                                type(r).__name__,
                                tri,
                                _cost_bits(cost) if cost is not None else None,
                            ]
                        out[key] = digest(*parts)
                    except Exception as exc:  # noqa: BLE001
                        out[key] = digest(type(exc).__name__, str(exc))
    return out


def worker(paths: list[str], sizes: list[int], dest: str) -> None:
    result: dict[str, dict[str, str]] = {}
    for path in paths:
        start = time.perf_counter()
        result[path] = run_many(sizes) if path == "many" else run_fast(path, sizes)
        print(
            f"  {path}: {len(result[path])} cases in {time.perf_counter() - start:.1f} s",
            file=sys.stderr,
        )
    Path(dest).write_text(json.dumps(result))


# --- the driver ----------------------------------------------------------------------


def run_side(src: Path, paths: list[str], sizes: list[int], dest: Path, cache: Path) -> None:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    cmd = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--worker",
        str(dest),
        "--paths",
        ",".join(paths),
        "--sizes",
        *map(str, sizes),
    ]
    subprocess.run(cmd, env=env, check=True, cwd=str(src.parent))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument(
        "--rev", default=DEFAULT_REV, help=f"the revision to compare with ({DEFAULT_REV})"
    )
    ap.add_argument("--paths", default=",".join(PATHS), help="comma-separated: " + ", ".join(PATHS))
    ap.add_argument("--sizes", nargs="*", type=int, help="polygon sizes (default 5 ... 300)")
    ap.add_argument("--quick", action="store_true", help="fewer sizes")
    ap.add_argument("--keep", action="store_true", help="keep the temporary worktree")
    ap.add_argument("--cache", help="keep numba's caches of both sides in this folder")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    paths = [p for p in args.paths.split(",") if p]
    unknown = [p for p in paths if p not in PATHS]
    if unknown:
        ap.error(f"unknown path(s) {unknown}; choose from {', '.join(PATHS)}")
    sizes = args.sizes or list(QUICK_SIZES if args.quick else SIZES)
    if args.worker:
        worker(paths, sizes, args.worker)
        return 0
    tmp = Path(tempfile.mkdtemp(prefix="optri-port-"))
    old = tmp / "old"
    try:
        subprocess.run(
            ["git", "-C", str(REPO), "worktree", "add", "--detach", "-q", str(old), args.rev],
            check=True,
        )
        print(f"old: {args.rev} in {old}", file=sys.stderr)
        cache = Path(args.cache) if args.cache else tmp
        run_side(old / "src", paths, sizes, tmp / "old.json", cache / "numba-cache-old")
        print("new: this checkout", file=sys.stderr)
        run_side(REPO / "src", paths, sizes, tmp / "new.json", cache / "numba-cache-new")
        want = json.loads((tmp / "old.json").read_text())
        got = json.loads((tmp / "new.json").read_text())
    finally:
        if not args.keep:
            subprocess.run(
                ["git", "-C", str(REPO), "worktree", "remove", "--force", str(old)], check=False
            )
            shutil.rmtree(tmp, ignore_errors=True)
    failed = False
    for path in paths:
        a, b = want.get(path, {}), got.get(path, {})
        same = sum(1 for k in a if b.get(k) == a[k])
        differ = sorted(k for k in a if k in b and b[k] != a[k])
        missing = sorted(set(a) ^ set(b))
        print(f"{path}: {len(a)} cases, {same} equal, {len(differ)} differ, {len(missing)} missing")
        for k in differ[:10]:
            print(f"  differs: {k}")
        failed = failed or bool(differ or missing)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
