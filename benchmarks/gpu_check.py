"""Real-GPU correctness: method="gpu" against a CPU engine (a script, never run by pytest).

Random convex polygons (every built-in weight, "sum" and "max", float64 and a
float32 spot check) and random comb-shaped simple polygons (chord mask built by
brute force with shapely) are solved on the GPU and by a CPU engine: the compiled
one (method="fast") where this build has it, else the pure-Python "table" engine
(then sizes stay small). Costs must agree to 1e-9 relative (1e-4 for float32)
and the GPU's triangles must form a triangulation that attains the cost.
Exits 1 on any mismatch, 2 when no GPU is available.

Usage::

    python benchmarks/gpu_check.py              # default sizes
    python benchmarks/gpu_check.py --sizes 5 17 64 300 2000 --seed 3
    python benchmarks/gpu_check.py --tile 32 --threads 128    # a tuning point
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
from collections.abc import Iterator

import numpy as np

import gpu_settings
from optri.engines import gpu, select_engine
from optri.engines.problem import Problem
from optri.errors import OptriError
from optri.polygon import Polygon, as_polygon
from optri.result import chords_cross_free, diagonals_of
from optri.solve import build_problem

POINT_WEIGHTS = ["perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio"]


def convex(n: int, rng: np.random.Generator) -> np.ndarray:
    ang = np.sort(rng.uniform(0.0, 2.0 * math.pi, n))
    return np.c_[1000.0 * np.cos(ang), 600.0 * np.sin(ang)]


def comb(n: int, rng: np.random.Generator) -> tuple[Polygon, np.ndarray]:
    """Comb-shaped simple polygon (tip-to-tip chords lie outside) and its usable chords.

    The chord mask is found by brute force with shapely, O(n^2) containment tests.
    """
    from shapely.geometry import LineString
    from shapely.geometry import Polygon as ShapelyPolygon
    from shapely.prepared import prep

    teeth = max(1, (n - 2) // 2)
    top = []
    for t in range(teeth, 0, -1):
        top.append((t + rng.uniform(-0.1, 0.1), 3.0 + rng.uniform(0.0, 0.5)))
        top.append((t - 0.5 + rng.uniform(-0.1, 0.1), 0.5 + rng.uniform(0.0, 0.3)))
    poly = as_polygon(np.array([(0.0, 0.0), (teeth + 0.5, 0.0), *top]))
    m, pts, shape = poly.n, poly.data, prep(ShapelyPolygon(poly.data))
    ok = np.zeros((m, m), dtype=bool)
    for a in range(m):
        for b in range(a + 2, m):
            ok[a, b] = ok[b, a] = shape.contains(LineString([pts[a], pts[b]]))
    return poly, ok


def compare(problem: Problem, cpu_method: str, rtol: float) -> str | None:
    """None when the GPU agrees with the CPU engine, else what went wrong."""
    try:
        got = gpu.solve(problem)
    except OptriError as exc:
        return f"GPU raised {exc!r}"
    _, cpu_solve = select_engine(cpu_method, problem)
    want = cpu_solve(problem)
    if not math.isclose(got.cost, want.cost, rel_tol=rtol, abs_tol=rtol):
        return f"cost {got.cost!r} != CPU {want.cost!r}"
    n, tris = problem.n, got.triangles
    diags = diagonals_of(tris, n)
    if tris.shape != (n - 2, 3) or len(diags) != n - 3 or not chords_cross_free(diags):
        return "GPU triangles are not a triangulation"
    if problem.allowed is not None and not all(problem.allowed[a, b] for a, b in diags.tolist()):
        return "GPU used a chord outside the polygon"
    w = problem.evaluator()
    again = problem.objective.aggregate([w(*t) for t in tris.tolist()])
    if not math.isclose(again, want.cost, rel_tol=max(rtol, 1e-9), abs_tol=rtol):
        return f"GPU triangles cost {again!r}, optimum {want.cost!r}"
    return None


def cases(
    sizes: list[int], rng: np.random.Generator, python_max_n: int
) -> Iterator[tuple[str, Problem]]:
    for n in sizes:
        poly = as_polygon(convex(n, rng))
        for weight in POINT_WEIGHTS:
            for objective in ("sum", "max"):
                yield f"convex n={n} {weight}/{objective}", build_problem(poly, weight, objective)
        values = as_polygon(rng.integers(1, 50, n).astype(float))
        for objective in ("sum", "max"):
            yield f"values n={n} product/{objective}", build_problem(values, "product", objective)
        yield (
            f"convex n={n} perimeter/sum float32",
            build_problem(poly, "perimeter", "sum", dtype=np.float32),
        )
        if n <= min(python_max_n, 400):
            spoly, ok = comb(n, rng)
            for weight, objective in (("perimeter", "sum"), ("min_angle", "max")):
                yield (
                    f"simple n={spoly.n} {weight}/{objective}",
                    build_problem(spoly, weight, objective, allowed=ok),
                )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", nargs="*", type=int, default=[5, 17, 64, 65, 130, 300, 1000])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument(
        "--cpu-method",
        choices=["fast", "table"],
        default="fast",
        help="CPU engine to compare with (table: pure Python, sizes <= 130)",
    )
    gpu_settings.add_arguments(ap)
    args = ap.parse_args()
    refused = gpu_settings.apply(args)
    if refused:
        print(refused, file=sys.stderr)
        return 2
    if gpu.simulated():
        print("note: NUMBA_ENABLE_CUDASIM is set, this checks the simulator, not a GPU")
    print(f"kernel settings: {gpu_settings.describe()}")
    fast = importlib.util.find_spec("optri.engines.jit") is not None
    if args.cpu_method == "table":
        fast = False
    cpu_method, python_max_n = ("fast", 10**9) if fast else ("table", 130)
    sizes = [n for n in args.sizes if fast or n <= python_max_n]
    if sizes != args.sizes:
        print(f"CPU engine 'table' (pure Python): sizes cut to {sizes}")
    rng = np.random.default_rng(args.seed)
    bad = total = 0
    for label, problem in cases(sizes, rng, python_max_n):
        rtol = 1e-4 if problem.dtype == np.float32 else 1e-9
        err = compare(problem, cpu_method, rtol)
        total += 1
        if err:
            bad += 1
            print(f"MISMATCH {label}: {err}", flush=True)
    print(f"{total - bad}/{total} cases agree with method={cpu_method!r}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
