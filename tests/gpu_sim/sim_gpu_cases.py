"""GPU kernels under numba's CUDA simulator, against the pure-Python memo engine.

Not collected by the main test run (the file name does not start with ``test_``):
``tests/test_gpu_sim.py`` runs it in a subprocess with ``NUMBA_ENABLE_CUDASIM=1``,
which must be set before numba is imported. Tiles, slices, threads and grid are
patched tiny so that n <= 40 spans many tiles, blocks and k-splits.
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

if os.environ.get("NUMBA_ENABLE_CUDASIM") != "1":  # pragma: no cover
    pytest.skip("run through tests/test_gpu_sim.py (needs the simulator)", allow_module_level=True)

# the simulator runs each CUDA thread as a Python thread; sim_harness fixes a
# race in its shared-array allocation and replaces its polling barrier
sys.path.insert(0, os.path.dirname(__file__))
import sim_harness  # noqa: E402

sim_harness.install()

from numba import cuda  # noqa: E402  (a module global: the simulator swaps those)

from optri import config  # noqa: E402
from optri.engines import gpu, memo, select_engine  # noqa: E402
from optri.engines.brute import solve as brute_solve  # noqa: E402
from optri.engines.progress import tile_work  # noqa: E402
from optri.errors import (  # noqa: E402
    EngineUnavailableError,
    TableTooLargeError,
    WeightError,
)
from optri.polygon import as_polygon  # noqa: E402
from optri.result import chords_cross_free, diagonals_of  # noqa: E402
from optri.solve import build_problem, triangulate  # noqa: E402

#: The shipped kernel settings, read before any test patches them.
SHIPPED = {name: getattr(config, name) for name in ("GPU_TILE", "GPU_K_CHUNK",
           "GPU_THREADS_PER_BLOCK", "GPU_MIN_BLOCKS")}  # fmt: skip
SMALL = {"GPU_TILE": 4, "GPU_K_CHUNK": 2, "GPU_THREADS_PER_BLOCK": 4, "GPU_MIN_BLOCKS": 6,
         "GPU_MAX_BLOCKS": 3}  # fmt: skip


@pytest.fixture(autouse=True)
def tiny_kernels(monkeypatch):
    for name, value in SMALL.items():
        monkeypatch.setattr(config, name, value)


def convex(n, seed):
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0.0, 2.0 * math.pi, n))
    r = rng.uniform(1.0, 3.0)
    return as_polygon(np.c_[r * np.cos(ang), 0.7 * r * np.sin(ang)])


def usable_chords(poly):
    """Chords (a, b) that lie inside ``poly``, by brute force with shapely."""
    from shapely.geometry import LineString
    from shapely.geometry import Polygon as ShapelyPolygon

    n, pts, shape = poly.n, poly.data, ShapelyPolygon(poly.data)
    ok = np.zeros((n, n), dtype=bool)
    for a in range(n):
        for b in range(a + 2, n):
            ok[a, b] = ok[b, a] = shape.contains(LineString([pts[a], pts[b]]))
    return ok


def comb(teeth, seed):
    """A comb (simple, non-convex): its short tip-to-tip chords lie outside it.

    Returns the polygon and its usable chords.
    """
    rng = np.random.default_rng(seed)
    top = []
    for t in range(teeth, 0, -1):
        top.append((t + rng.uniform(-0.1, 0.1), 3.0 + rng.uniform(0.0, 0.5)))  # tip
        top.append((t - 0.5 + rng.uniform(-0.1, 0.1), 0.5 + rng.uniform(0.0, 0.3)))  # valley
    poly = as_polygon(np.array([(0.0, 0.0), (teeth + 0.5, 0.0), *top]))
    assert not poly.convex
    return poly, usable_chords(poly)


def star(n, seed):
    """A random star-shaped polygon (simple, not convex) and its usable chords."""
    rng = np.random.default_rng(seed)
    ang = (np.arange(n) + rng.uniform(0.1, 0.9, n)) * (2.0 * math.pi / n)
    r = rng.uniform(0.3, 1.0, n)
    poly = as_polygon(np.c_[r * np.cos(ang), r * np.sin(ang)])
    ok = usable_chords(poly)
    if poly.convex or ok[np.triu_indices(n, 2)].all():
        return star(n, seed + 1000)  # every chord usable: not the case under test
    return poly, ok


def check_against_memo(problem, rtol=1e-9):
    """GPU cost equals memo's; GPU triangles form a triangulation attaining it."""
    got = gpu.solve(problem)
    want = memo.solve(problem)
    assert math.isclose(got.cost, want.cost, rel_tol=rtol, abs_tol=rtol), (got.cost, want.cost)
    n, tris = problem.n, got.triangles
    assert tris.shape == (n - 2, 3)
    assert ((tris[:, 0] < tris[:, 1]) & (tris[:, 1] < tris[:, 2])).all()
    diags = diagonals_of(tris, n)
    assert len(diags) == n - 3 and chords_cross_free(diags)
    if problem.allowed is not None:
        assert all(problem.allowed[a, b] for a, b in diags.tolist())
    w = problem.evaluator()
    again = problem.objective.aggregate([w(*t) for t in tris.tolist()])
    assert math.isclose(again, want.cost, rel_tol=rtol, abs_tol=rtol), (again, want.cost)
    return got, want


POINT_WEIGHTS = ["perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio"]


@pytest.mark.parametrize("objective", ["sum", "max"])
@pytest.mark.parametrize("weight", POINT_WEIGHTS)
def test_each_weight_and_objective_on_a_simple_polygon(weight, objective):
    # n = 9..14: 3 or 4 tile diagonals, so both product kernels run, under a mask;
    # convex (unmasked) polygons: the property test, the shapes below, gpu_check
    poly, ok = star(9 + len(weight) % 7, seed=3 * len(weight) + len(objective))
    check_against_memo(build_problem(poly, weight, objective, allowed=ok))


@pytest.mark.parametrize("objective", ["sum", "max"])
def test_product_values(objective):
    dims = np.random.default_rng(5).integers(2, 40, 15)
    check_against_memo(build_problem(as_polygon(dims), "product", objective))


@pytest.mark.parametrize(("weight", "objective"), [("area", "max"), ("perimeter", "sum")])
def test_3d_polygon(weight, objective):
    flat = convex(15, seed=8).data
    tilt = np.c_[flat[:, 0], 0.6 * flat[:, 1], 0.8 * flat[:, 1] + 0.3 * flat[:, 0]]
    check_against_memo(build_problem(as_polygon(tilt), weight, objective))


def test_convex_n40_many_tiles_and_splits():
    check_against_memo(build_problem(convex(40, seed=3), "perimeter", "sum"))


@pytest.mark.parametrize(("tile", "chunk", "threads"), [(8, 4, 16), (4, 4, 3), (8, 2, 5)])
def test_other_kernel_shapes(monkeypatch, tile, chunk, threads):
    monkeypatch.setattr(config, "GPU_TILE", tile)
    monkeypatch.setattr(config, "GPU_K_CHUNK", chunk)
    monkeypatch.setattr(config, "GPU_THREADS_PER_BLOCK", threads)
    check_against_memo(build_problem(convex(23, seed=tile + threads), "max_angle", "max"))


def test_shipped_settings_n130_equal_the_compiled_cpu_engine(monkeypatch):
    # the exact tile / slice / threads the engine ships with (64 / 16 / 256), on
    # 3 x 3 tiles: one min-plus product launch, finish on 3 tile diagonals; only
    # the grid is kept small (the kernels stride over blocks), to spare the
    # simulator thousands of Python threads. The slowest case (the rebuild's 128
    # steps of 10 barriers of 256 threads), so E form only.
    for name, value in SHIPPED.items():
        monkeypatch.setattr(config, name, value)
    monkeypatch.setattr(config, "GPU_MAX_BLOCKS", 2)
    got, _ = check_against_memo(build_problem(convex(130, seed=21), "perimeter", "sum"))
    assert got.stats["padded_n"] == 192 and got.stats["tiles"] == 6


@pytest.mark.parametrize(("weight", "objective"), [("perimeter", "sum"), ("max_angle", "max")])
def test_default_register_block_and_slice(monkeypatch, weight, objective):
    # T = 16 with 16 threads gives the default's 4 x 4 cells a thread and a slice
    # as deep as the tile (KC = 16, fully unrolled); n = 34 spans 3 tile diagonals
    monkeypatch.setattr(config, "GPU_TILE", 16)
    monkeypatch.setattr(config, "GPU_K_CHUNK", 16)
    monkeypatch.setattr(config, "GPU_THREADS_PER_BLOCK", 16)
    from optri.engines._gpu_kernels import thread_layout

    assert thread_layout(16, 16)[2:] == thread_layout(64, 256)[2:] == (4, 4)
    got, _ = check_against_memo(build_problem(convex(34, seed=12), weight, objective))
    assert got.stats["tiles"] == 6


@pytest.mark.parametrize(
    ("weight", "objective"), [("perimeter", "sum"), ("min_angle", "max"), ("aspect_ratio", "sum")]
)
def test_simple_polygon_mask(weight, objective):
    poly, ok = comb(7, seed=len(weight))
    _, want = check_against_memo(build_problem(poly, weight, objective, allowed=ok))
    free = memo.solve(build_problem(poly, weight, objective, allowed=np.ones_like(ok)))
    assert want.cost != pytest.approx(free.cost)  # the mask changes the optimum


@settings(max_examples=12, deadline=None, derandomize=True)
@given(
    n=st.integers(5, 22),
    seed=st.integers(0, 10_000),
    shape=st.sampled_from(["convex", "star"]),
    weight=st.sampled_from(POINT_WEIGHTS),
    objective=st.sampled_from(["sum", "max"]),
)
def test_property_random_polygons(n, seed, shape, weight, objective):
    if shape == "convex":
        problem = build_problem(convex(n, seed), weight, objective)
    else:
        poly, ok = star(n, seed)
        problem = build_problem(poly, weight, objective, allowed=ok)
    check_against_memo(problem)


def gpu_ties():
    """test_core_ties.py's exact ties the GPU takes (one objective, not a lex pair)."""
    sys.path.insert(0, os.path.dirname(os.path.dirname(__file__)))
    from test_core_ties import EXACT_TIES

    return [case for case in EXACT_TIES if isinstance(case[3], str)]


@pytest.mark.parametrize("case", gpu_ties(), ids=lambda case: case[0])
def test_exact_ties_go_to_the_smallest_split(case):
    # the rebuild's reduction must keep the smallest k among equal costs, as memo does
    _, vertices, weight, objective, expected = case
    tri = triangulate(vertices, weight, objective, method="gpu")
    assert sorted(map(tuple, tri.triangles.tolist())) == expected


@pytest.mark.parametrize("n", [6, 8, 10])
@pytest.mark.parametrize("weight", ["max_angle", "aspect_ratio"])
def test_regular_polygon_bottleneck_same_triangles_as_memo(n, weight):
    # congruent triangles: many equal sub-costs, compared exactly under "max"
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    problem = build_problem(as_polygon(np.c_[np.cos(ang), np.sin(ang)]), weight, "max")
    got, want = gpu.solve(problem), memo.solve(problem)
    assert got.cost == want.cost
    assert sorted(map(tuple, got.triangles.tolist())) == sorted(map(tuple, want.triangles.tolist()))


def test_simple_polygon_matches_brute_force():
    poly, ok = comb(4, seed=11)
    problem = build_problem(poly, "diagonal", "sum", allowed=ok)
    assert math.isclose(gpu.solve(problem).cost, brute_solve(problem).cost, rel_tol=1e-9)


def test_no_valid_triangulation_is_a_weight_error():
    ok = np.zeros((7, 7), dtype=bool)  # sides only: no chord may be drawn
    problem = build_problem(convex(7, seed=1), "perimeter", "sum", allowed=ok)
    with pytest.raises(WeightError, match="no valid triangulation"):
        gpu.solve(problem)


def test_table_equals_memo_table():
    problem = build_problem(convex(13, seed=2), "perimeter", "sum", keep_table=True)
    got, want = check_against_memo(problem)
    n = problem.n
    upper = np.triu_indices(n, 1)
    np.testing.assert_allclose(got.table[upper], want.table[upper], rtol=1e-9)
    np.testing.assert_array_equal(got.table.T[upper], want.table.T[upper])  # splits


def test_float32():
    problem = build_problem(convex(18, seed=4), "perimeter", "sum", dtype=np.float32)
    got = gpu.solve(problem)
    want = memo.solve(problem)
    assert math.isclose(got.cost, want.cost, rel_tol=1e-5)


def test_triangulate_method_gpu_and_progress():
    calls = []
    tri = triangulate(convex(12, seed=9).vertices, "perimeter", method="gpu",
                      progress=lambda d, t: calls.append((d, t)))  # fmt: skip
    tri.check()
    assert tri.method == "gpu"
    # split evaluations of tile-diagonals 0, 0-1, 0-2 of 4 x 4 tiles, out of C(12, 3)
    grid = tile_work(12, 4).reshape(3, 3)
    done = np.cumsum([np.trace(grid, d) for d in range(3)]).tolist()
    assert calls == [(d, 220) for d in done] and done[-1] == 220


def test_auto_never_picks_the_simulator(monkeypatch):
    monkeypatch.setattr(config, "GPU_AUTO_MIN_N", 3)
    assert gpu.unavailable() is None
    name, _ = select_engine("auto", build_problem(convex(8, seed=1), "perimeter", "sum"))
    assert name != "gpu"


def test_unsupported_are_clear_errors():
    poly = convex(8, seed=1)
    with pytest.raises(EngineUnavailableError, match="Python callable"):
        triangulate(poly.vertices, lambda i, k, j: 1.0, method="gpu")
    with pytest.raises(EngineUnavailableError, match="lexicographic"):
        triangulate(poly.vertices, ("max_angle", "perimeter"), ("max", "sum"), method="gpu")


def test_device_memory_ceiling(monkeypatch):
    monkeypatch.setattr(config, "GPU_MEMORY_LIMIT_BYTES", 1000)
    with pytest.raises(TableTooLargeError, match="float32"):
        gpu.solve(build_problem(convex(30, seed=1), "perimeter", "sum"))


def test_harness_barrier_shared_arrays_early_exit_and_errors():
    # sim_harness's barrier and shared arrays keep CUDA's meaning: after each
    # barrier every thread sees every other thread's write of this step, threads
    # that have returned no longer hold a barrier, and a thread's error surfaces
    @cuda.jit
    def exchange(out, steps, quit_at):
        s = cuda.shared.array(8, np.int64)
        t = cuda.threadIdx.x
        n = cuda.blockDim.x
        if t >= quit_at:
            return
        for step in range(steps):
            s[t] = step * n + t
            cuda.syncthreads()
            for u in range(quit_at):
                if s[u] != step * n + u:
                    out[t] += 1
            cuda.syncthreads()
        out[t] += 100
        if t == 1 and steps == 0:
            out[99] = 1  # out of bounds: an IndexError in thread 1

    out = np.zeros(8, dtype=np.int64)
    exchange[2, 8](out, 40, 6)
    assert out.tolist() == [200] * 6 + [0, 0]  # 2 blocks, no stale read, 2 left early
    with pytest.raises(IndexError, match="tid=.1, 0, 0."):
        exchange[1, 8](np.zeros(8, dtype=np.int64), 0, 8)
