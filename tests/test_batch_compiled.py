"""The compiled many-polygon path equals optri.triangulate, polygon by polygon, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import optri
from optri import config
from optri.batch import iter_records
from optri.batch.compiled import STATUS, many_plan, mode_of, solve_compiled
from optri.batch.each import SolveOptions, solve_each
from optri.batch.solver import chunk_solver, solve_polygons
from optri.engines import select_engine
from optri.polygon import as_polygon
from optri.solve import build_problem
from simple_polys import random_star, simple_polygons, star_polygons
from strategies import convex_polygons

numba = pytest.importorskip("numba")

#: (weight, objective, method): every arithmetic the kernel reproduces.
SETTINGS = [
    ("perimeter", "sum", "auto"),  # Python engines, edge table
    ("perimeter", "sum", "fast"),  # the compiled engine's min-plus table
    ("diagonal", "sum", "table"),
    ("diagonal", "sum", "fast"),
    ("area", "sum", "memo"),  # best_split cells
    ("max_angle", "max", "auto"),
    ("min_angle", "max", "fast"),
    ("aspect_ratio", "sum", "auto"),
    ("perimeter", "max", "fast"),
]


def bits(cost: object) -> object:
    """A cost's exact bits (each component's, for a lexicographic pair)."""
    if isinstance(cost, tuple):
        return tuple(float(c).hex() for c in cost)
    return float(cost).hex()  # type: ignore[arg-type]


def same(got: object, want: object) -> None:
    """Equal results: the same error text, or the same triangles and cost bits."""
    if isinstance(want, optri.OptriError):
        assert type(got) is type(want) and str(got) == str(want), (got, want)
        return
    assert isinstance(got, optri.Triangulation), got
    assert bits(got.weight) == bits(want.weight), (got.weight, want.weight)
    assert np.array_equal(got.triangles, want.triangles)
    assert got.triangles.dtype == np.int64
    assert np.array_equal(got.vertices, want.vertices)
    assert np.array_equal(got.order, want.order) and got.orientation == want.orientation
    assert got.stats.get("warnings") == want.stats.get("warnings")


def both(arrays: list, options: SolveOptions) -> tuple[list, list]:
    got = solve_compiled(arrays, options)
    want = solve_each(arrays, options)
    assert len(got) == len(want) == len(arrays)
    for g, w in zip(got, want):
        same(g, w)
    return got, want


def near_collinear(poly: np.ndarray, eps: float) -> np.ndarray:
    """A vertex added just off the middle of the first edge (or exactly on it, eps = 0)."""
    a, b = poly[0], poly[1]
    mid = (a + b) / 2 + eps * np.array([-(b - a)[1], (b - a)[0]])
    return np.vstack([a, mid, poly[1:]])


shapes = st.one_of(
    star_polygons(4, 12), simple_polygons(4, 10), convex_polygons(3, 14).map(np.asarray)
)


@st.composite
def variants(draw: st.DrawFn) -> np.ndarray:
    """A polygon as a user might give it: offset, reversed, near-collinear, closed."""
    poly = np.asarray(draw(shapes), dtype=np.float64)
    if draw(st.booleans()):
        poly = near_collinear(poly, draw(st.sampled_from([0.0, 1e-12, -1e-12, 1e-3])))
    if draw(st.booleans()):
        poly = poly + np.array([500000.0, 4600000.0])  # UTM-like offsets
    if draw(st.booleans()):
        poly = poly[::-1].copy()  # clockwise
    if draw(st.booleans()):
        poly = np.vstack([poly, poly[:1]])  # a closing vertex
    return poly


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(variants(), min_size=1, max_size=6), st.sampled_from(SETTINGS))
def test_equals_triangulate_polygon_by_polygon(polys: list, setting: tuple) -> None:
    got, want = both(polys, SolveOptions(*setting))
    taken = [g for g in got if isinstance(g, optri.Triangulation) and g.method == "many"]
    ok = [w for w in want if isinstance(w, optri.Triangulation)]
    assume(ok)  # some polygon was solvable: the comparison is not all fallbacks
    assert len(taken) == len(ok)  # every solvable polygon went through the kernel
    for t in taken:
        t.check()


@pytest.mark.parametrize("setting", SETTINGS)
def test_star_polygons_of_many_sizes(setting: tuple) -> None:
    polys = [random_star(n, seed) for seed, n in enumerate(range(3, 70, 3))]
    got, _ = both(polys, SolveOptions(*setting))
    assert all(g.method == "many" for g in got)


def test_ties_go_to_the_smallest_split() -> None:
    # regular polygons and grid rectangles: every triangulation ties or nearly so
    regular = [
        np.c_[np.cos(t), np.sin(t)] for t in (np.arange(n) * 2 * np.pi / n for n in (6, 8, 12))
    ]
    grid = [np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], dtype=float)]
    square = [np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)]
    for setting in SETTINGS:
        both(regular + grid + square, SolveOptions(*setting))


BAD = [
    [[0, 0], [1, 1], [1, 0], [0, 1]],  # bow-tie
    [[0, 0], [2, 0], [1, 0], [1, 1]],  # folds back onto an edge
    [[0, 0], [1, 0], [0, 0], [0, 1]],  # repeated vertex
    [[0, 0], [1, 0], [2, 0]],  # collinear
    [[0, 0], [1, 0]],  # too few
    [[0, 0], [1, 0], [0, 0]],  # too few once closed
    [[0, 0], [1, 0], [np.nan, 1]],  # not finite
    [[0, 0], [1, 0], [np.inf, 1]],
    [[0, 0], [4, 0], [4, 4], [2, 0.0], [0, 4]],  # touches an edge
    [[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]],  # optimum overflows
    [[0, 0, 0], [1, 0, 0], [0, 1, 1]],  # 3-D: per polygon
    [0, 1, 2, 3],  # values: refused by the batch's reader of vertices
    "not a polygon",
    None,
]


@pytest.mark.parametrize("method", ["auto", "fast"])
def test_bad_rows_keep_their_exact_errors(method: str) -> None:
    good = random_star(9, 1)
    rows = [good, *BAD, good[::-1]]
    options = SolveOptions(method=method)
    assert chunk_solver(options) is solve_compiled
    got = solve_polygons(rows, options)
    config.MANY_COMPILED = False
    try:
        want = solve_polygons(rows, options)
    finally:
        config.reset()
    for g, w in zip(got, want):
        same(g, w)
    assert got[0].method == got[-1].method == "many"
    assert sum(isinstance(g, optri.OptriError) for g in got) == len(BAD) - 1  # 3-D is solved
    assert "edges 0-1 and 2-3 cross" in str(got[1])


def test_options_the_kernel_cannot_take_go_polygon_by_polygon() -> None:
    polys = [random_star(8, s) for s in range(3)]
    for options in (
        SolveOptions(weight=lambda i, k, j: float(j - i)),  # a user weight
        SolveOptions(weight=("max_angle", "perimeter"), objective=("max", "sum")),
        SolveOptions(method="brute"),
    ):
        assert many_plan(options) is None and chunk_solver(options) is solve_each
        out = solve_compiled(polys, options)  # called anyway: it hands everything on
        for g, w in zip(out, solve_each(polys, options)):
            assert g.method != "many"
            same(g, w)


def test_chunk_boundaries_and_large_polygons(monkeypatch: pytest.MonkeyPatch) -> None:
    polys = [random_star(n, n) for n in (3, 4, 5, 11, 17, 30, 7)]
    want = solve_each(polys, SolveOptions())
    for chunk in (1, 2, 3, 7, 100):
        monkeypatch.setattr(config, "MANY_KERNEL_CHUNK", chunk)
        for g, w in zip(solve_compiled(polys, SolveOptions()), want):
            same(g, w)
    monkeypatch.setattr(config, "MANY_MAX_N", 10)  # above it: triangulate, one by one
    got = solve_compiled(polys, SolveOptions())
    assert [g.method for g in got] == ["many", "many", "many", "table", "table", "table", "many"]
    for g, w in zip(got, want):
        same(g, w)


def test_empty_input_and_threads() -> None:
    assert solve_compiled([], SolveOptions()) == []
    assert optri.triangulate_many([]) == []
    polys = [random_star(n, n) for n in range(3, 40)]
    one = solve_compiled(polys, SolveOptions(threads=1))
    two = solve_compiled(polys, SolveOptions(threads=2))
    for a, b in zip(one, two):
        same(a, b)


def test_results_own_their_vertices() -> None:
    poly = random_star(12, 3)
    tri = solve_compiled([poly], SolveOptions())[0]
    assert tri.method == "many" and not np.shares_memory(tri.vertices, poly)
    tri.check()
    assert tri.stats["wall_seconds"] >= 0


def test_triangulate_many_and_batch_records_use_it(tmp_path) -> None:
    from batch_polys import mixed_polygons, write_ndjson

    rows = mixed_polygons(20, seed=5)
    out = optri.triangulate_many([r["coordinates"] for r in rows])
    assert all(t.method == "many" for t in out)
    for t, r in zip(out, rows):
        same(t, optri.triangulate(r["coordinates"]))
    src = write_ndjson(tmp_path / "in.ndjson", rows)
    optri.batch(src, tmp_path / "out.ndjson", workers=1)
    recs = list(iter_records(tmp_path / "out.ndjson"))
    assert [r["cost"] for r in recs] == [t.weight for t in out]
    assert [r["triangles"] for r in recs] == [t.triangles.tolist() for t in out]


@pytest.mark.parametrize("method", ["auto", "fast", "table", "memo"])
def test_mode_mirrors_select_engine(method: str) -> None:
    for n in range(3, config.MANY_MAX_N + 1):
        pts = np.c_[np.cos(np.arange(n) * 2 * np.pi / n), np.sin(np.arange(n) * 2 * np.pi / n)]
        problem = build_problem(as_polygon(pts), "perimeter", "sum")
        name, _ = select_engine(method, problem)
        assert mode_of(method, n) == {"table": 1, "memo": 1, "fast": 2}[name], (method, n)


def test_kernel_statuses_name_the_check_that_failed() -> None:
    # the core's columnar answer: one status per polygon, its triangles from row first[p]
    from optri._core import many

    rows = {
        "ok": [[0, 0], [2, 0], [2, 1], [0, 1], [0, 0]],  # closed: the closing row dropped
        "non-finite": [[0, 0], [1, 0], [np.nan, 1]],
        "too few vertices": [[0, 0], [1, 0]],
        "repeated vertex": [[0, 0], [1, 0], [0, 0]],  # closing rows go only down to 3
        "no turn at the lowest vertex": [[0, 0], [1, 0], [2, 0]],
        "not simple": [[0, 0], [1, 1], [1, 0], [0, 1]],
        "size not taken": random_star(12, 0).tolist(),
        "no finite optimum": [[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]],
    }
    arrays = [np.array(r, dtype=np.float64) for r in rows.values()]
    counts = np.array([len(a) for a in arrays], dtype=np.int64)
    starts = np.concatenate(([0], np.cumsum(counts)[:-1])).astype(np.int64)
    modes = np.array([mode_of("auto", n) if n < 10 else 0 for n in range(20)], dtype=np.int64)
    status, sizes, cw, costs, tris, first = many.solve(
        np.concatenate(arrays), starts, counts, modes, 0, False, True, 2
    )
    assert [STATUS_NAMES[s] for s in status.tolist()] == list(rows)
    assert sizes.tolist()[:3] == [4, 3, 2]
    rows_each = np.maximum(counts - 2, 0)  # n - 2 triangles at most, closing rows included
    assert first.tolist() == np.concatenate(([0], np.cumsum(rows_each)[:-1])).tolist()
    assert tris.shape == (int(rows_each.sum()), 3)
    want = optri.triangulate(arrays[0])
    assert costs[0] == want.weight and not cw[0]
    assert np.array_equal(tris[:2], want.triangles)
    assert np.isnan(costs[1:]).all()


STATUS_NAMES = {code: name for name, code in STATUS.items()}
