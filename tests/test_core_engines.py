"""Every Python engine against the brute-force oracle, and result invariants."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.engines import memo
from optri.engines.brute import all_index_triangulations
from optri.polygon import as_polygon
from optri.solve import build_problem
from strategies import (
    MAX_LED_EDGE_PAIRS,
    POINT_WEIGHTS,
    TWO_PHASE_CASES,
    convex_polygons,
    ellipse_polygon,
    value_sequences,
)

ENGINES = ["memo", "table"]


def close(a, b):
    if isinstance(a, tuple):
        return all(close(x, y) for x, y in zip(a, b))
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    poly=convex_polygons(3, 10),
    weight=st.sampled_from(POINT_WEIGHTS),
    objective=st.sampled_from(["sum", "max"]),
    cw=st.booleans(),
)
def test_dp_engines_equal_brute_force(poly, weight, objective, cw):
    if cw:
        poly = poly[::-1]
    oracle = optri.triangulate(poly, weight, objective, method="brute")
    for method in ENGINES:
        t = optri.triangulate(poly, weight, objective, method=method)
        assert close(t.weight, oracle.weight), (method, t.weight, oracle.weight)
        t.check()


@settings(max_examples=20, deadline=None)
@given(poly=convex_polygons(3, 9))
def test_lexicographic_objective_matches_brute(poly):
    spec = dict(weight=("max_angle", "perimeter"), objective=("max", "sum"))
    oracle = optri.triangulate(poly, **spec, method="brute")
    for method in ENGINES:
        t = optri.triangulate(poly, **spec, method=method)
        assert close(t.weight, oracle.weight)
        t.check()


@pytest.mark.parametrize("n, seed", TWO_PHASE_CASES)
@pytest.mark.parametrize("pair", MAX_LED_EDGE_PAIRS)
def test_max_led_pair_is_solved_in_two_phases(n, seed, pair):
    """("max", "sum") is not monotone: one lexicographic pass misses the optimum here."""
    pts = ellipse_polygon(n, seed)
    oracle = optri.triangulate(pts, pair, ("max", "sum"), method="brute")
    one_pass = memo.solve(build_problem(as_polygon(pts), pair, ("max", "sum")))
    assert one_pass.cost > oracle.weight and not close(one_pass.cost, oracle.weight)
    for method in ENGINES:
        t = optri.triangulate(pts, pair, ("max", "sum"), method=method)
        assert close(t.weight, oracle.weight), (method, t.weight, oracle.weight)
        t.check()


@settings(max_examples=30, deadline=None)
@given(values=value_sequences(3, 9))
def test_integer_max_led_pair_in_two_phases_keeps_the_bottleneck(values):
    """Integer costs tie only when equal: the gate is the bottleneck itself, not loosened,
    so a gate that excludes its own threshold leaves no triangulation."""
    spec = (("product", "product"), ("max", "sum"))
    oracle = optri.triangulate(values, *spec, method="brute").weight
    assert all(isinstance(v, int) for v in oracle)  # exact: no tie tolerance applies
    for method in ENGINES:
        assert optri.triangulate(values, *spec, method=method).weight == oracle


@settings(max_examples=30, deadline=None)
@given(values=value_sequences(3, 10))
def test_product_weight_equals_brute(values):
    oracle = optri.triangulate(values, "product", method="brute").weight
    for method in ENGINES:
        assert optri.triangulate(values, "product", method=method).weight == oracle


def test_max_objective_with_negative_weights():
    # "min_angle" is minus the smallest angle: negative, so a side must count as -inf
    tri = [[0, 0], [3, 0], [0, 4]]
    for method in ENGINES + ["brute"]:
        t = optri.triangulate(tri, "min_angle", "max", method=method)
        assert t.weight == pytest.approx(-math.asin(0.6))  # the angle opposite side 3
        poly = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]
        worst = optri.triangulate(poly, lambda i, k, j: -1.0 - i, "max", method=method)
        assert worst.weight == -1.0  # every triangulation has a triangle at vertex 0


def test_max_table_sides_are_zero_not_minus_infinity():
    poly = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3], [-2, 1]]
    for method in ENGINES:
        t = optri.triangulate(poly, "max_angle", "max", method=method, keep_table=True)
        n = t.n
        assert np.all(t.table[np.arange(n - 1), np.arange(1, n)] == 0.0)  # sides: no triangle
        assert t.table[0, n - 1] == t.weight and np.isfinite(t.table).all()


def test_brute_enumerates_catalan_many():
    for n in range(3, 11):
        assert sum(1 for _ in all_index_triangulations(n)) == math.comb(2 * (n - 2), n - 2) // (
            n - 1
        )


@pytest.mark.parametrize("method", ENGINES + ["brute"])
def test_published_product_values(method):
    assert optri.triangulate([1, 2, 3], "product", method=method).weight == 6
    assert optri.triangulate([3, 7, 4, 5], "product", method=method).weight == 144
    assert optri.triangulate([1, 3, 1, 4, 1, 5], "product", method=method).weight == 13
    assert optri.triangulate([5, 1, 5, 1, 5], "product", method=method).weight == 35


def test_unit_square_by_hand():
    t = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], method="memo")
    assert t.weight == pytest.approx(2 * (2 + math.sqrt(2)))
    d = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], "diagonal", method="table")
    assert d.weight == pytest.approx(math.sqrt(2))
    assert d.diagonals.shape == (1, 2)


def test_perimeter_and_diagonal_share_the_optimum():
    rng = np.random.default_rng(3)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 12))
    poly = np.column_stack((np.cos(ang), np.sin(ang)))
    p = optri.triangulate(poly, "perimeter", method="table")
    d = optri.triangulate(poly, "diagonal", method="table")
    boundary = np.linalg.norm(poly - np.roll(poly, -1, axis=0), axis=1).sum()
    assert p.weight == pytest.approx(2 * d.weight + boundary)


def test_area_sum_is_polygon_area():
    poly = np.array([[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]], float)
    t = optri.triangulate(poly, "area", method="memo")
    assert t.weight == pytest.approx(abs(optri.polygon.signed_area(poly)))


def test_triangle_has_no_diagonal():
    t = optri.triangulate([[0, 0], [1, 0], [0, 1]], method="memo")
    assert t.triangles.tolist() == [[0, 1, 2]]
    assert t.diagonals.shape == (0, 2)
    t.check()


def test_clockwise_input_is_normalized():
    ccw = np.array([[0, 0], [3, 0], [4, 2], [2, 4], [0, 3]], float)
    a = optri.triangulate(ccw, method="memo")
    b = optri.triangulate(ccw[::-1], method="memo")
    assert a.orientation == "ccw" and b.orientation == "cw"
    assert b.order.tolist() == [0, 4, 3, 2, 1]  # internal: counter-clockwise from input 0
    assert a.weight == pytest.approx(b.weight)
    b.check()  # triangles counter-clockwise in input indices
    pts = ccw[::-1]
    for i, k, j in b.triangles:
        u, v = pts[k] - pts[i], pts[j] - pts[i]
        assert u[0] * v[1] - u[1] * v[0] > 0


def test_closing_vertex_dropped():
    t = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]])
    assert t.n == 4


def test_memo_counts_on_full_convex_table():
    # on a convex polygon memoization reaches every cell: C(n,3) weights, C(n-1,2) cells
    for n in range(5, 12):
        ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
        poly = np.column_stack((np.cos(ang), np.sin(ang)))
        s = optri.triangulate(poly, method="memo").stats
        assert s["weight_evaluations"] == math.comb(n, 3)
        assert s["cells"] == (n - 1) * (n - 2) // 2
        assert s["requests"] == 2 * math.comb(n, 3)
        assert s["lookups"] == s["requests"] - (s["cells"] - 1)
        assert optri.triangulate(poly, method="table").stats["weight_evaluations"] == math.comb(
            n, 3
        )


def test_memo_deep_recursion_without_recursion_limit():
    # a fan-only chord mask makes the memo recursion n deep while staying O(n) work
    n = 2000
    poly = optri.as_polygon(
        np.column_stack((np.cos(np.linspace(0, 6, n)), np.sin(np.linspace(0, 6, n))))
    )
    allowed = np.zeros((n, n), bool)
    allowed[0, :] = allowed[:, 0] = True
    from optri.engines import memo
    from optri.solve import build_problem

    prob = build_problem(poly, "perimeter", "sum", allowed=allowed, keep_table=False)
    sol = memo.solve(prob)
    assert len(sol.triangles) == n - 2
    assert all(t[0] == 0 for t in sol.triangles.tolist())


def test_custom_callable_weight_gets_input_indices():
    seen = set()
    poly = np.array([[0, 0], [0, 2], [2, 2], [2, 0]], float)  # clockwise

    def w(i, k, j):
        seen.add((i, k, j))
        return 1.0

    t = optri.triangulate(poly, w, method="table")
    assert t.weight == 2.0
    assert all(max(tri) <= 3 for tri in seen)

    def area(v, i, k, j):
        u, w = v[k] - v[i], v[j] - v[i]
        return 0.5 * abs(u[0] * w[1] - u[1] * w[0])

    assert optri.triangulate(poly, area, method="memo").weight == pytest.approx(4.0)


@pytest.mark.parametrize("method", ["memo", "table", "fast"])
def test_progress_counts_split_evaluations_up_to_the_total(method: str) -> None:
    # progress(done, total) counts split evaluations (chord (i, j) takes j - i - 1), so
    # that done / total moves with the time: rising, about 200 reports at most, the last
    # the total, also where a chord mask leaves chords (and their splits) out
    n = 30
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack((np.cos(ang), np.sin(ang)))
    star = ring * np.where(np.arange(n) % 2, 1.0, 0.5)[:, None]
    total = n * (n - 1) * (n - 2) // 6
    seen = {}
    for name, pts in (("convex", ring), ("star", star)):
        calls: list[tuple[int, int]] = []
        optri.triangulate(pts, method=method, progress=lambda d, t, c=calls: c.append((d, t)))
        assert calls and calls[-1] == (total, total) and all(t == total for _, t in calls)
        assert all(a < b for (a, _), (b, _) in zip(calls, calls[1:])) and len(calls) <= 202
        seen[name] = [d for d, _ in calls]
    if method != "fast":  # one report per 1/200 of the work (the fast fill is too short)
        assert len(seen["convex"]) > 150
    if method == "table":  # the convex polygon's chords by length: each report a prefix
        work = np.cumsum([d - 1 for d in range(2, n) for _ in range(n - d)])
        assert set(seen["convex"]) <= set(work.tolist())


def test_table_layout_upper_costs_lower_splits():
    t = optri.triangulate([5, 1, 5, 1, 5], "product", method="table")
    tab = t.table
    assert tab[0, 2] == 25 and tab[0, 3] == 10 and tab[0, 4] == 35
    assert tab[1, 3] == 5 and tab[1, 4] == 10 and tab[2, 4] == 25
    assert np.all(np.diag(tab) == 0)
    assert tab[4, 1] == 3  # chord (1, 4) splits at vertex 3


def test_engine_without_gate_support_refuses_gated_problem(monkeypatch):
    import types

    from optri.engines import ENGINES, EngineSpec, register_engine

    fake = types.ModuleType("fake_engine")
    from optri.engines import memo

    def solve(problem):
        assert not problem.gates, "a gated problem reached an engine without gate support"
        return memo.solve(problem)

    fake.solve = solve
    monkeypatch.setitem(__import__("sys").modules, "fake_engine", fake)
    monkeypatch.setitem(ENGINES, "fake", ENGINES["memo"])
    register_engine(EngineSpec("fake", "fake_engine", "test double"))
    square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(optri.EngineUnavailableError, match="gates"):
        optri.triangulate(square, ("max_angle", "area"), ("max", "sum"), method="fake")
