"""fill_polyline: exact search against brute force, planar cases, modes, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.engines.brute import all_index_triangulations
from optri.errors import InvalidPolygonError, TableTooLargeError
from optri.holes import fill_polyline, liepa_objective
from optri.polygon import signed_area


@st.composite
def skew_polylines(draw, min_n=3, max_n=9):
    """A wavy closed 3-D polyline (and, half the time, third points around it)."""
    n = draw(st.integers(min_n, max_n))
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, n)) + np.arange(n) * 1e-3
    pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.5, n)))
    third = None
    if draw(st.booleans()):
        mid = (pts + np.roll(pts, -1, axis=0)) / 2
        third = 1.6 * mid + rng.normal(0, 0.3, (n, 3))
    return pts, third


def _brute(pts, third, value):
    return min(value(pts, tris, third) for tris in all_index_triangulations(len(pts)))


def _liepa_key(pts, tris, third):
    # compare (angle, area) lexicographically with a tolerance on the area only
    return liepa_objective(pts, np.array(tris), third)


def _area(pts, tris, third):
    t = np.array(tris)
    cross = np.cross(pts[t[:, 1]] - pts[t[:, 0]], pts[t[:, 2]] - pts[t[:, 0]])
    return 0.5 * float(np.linalg.norm(cross, axis=1).sum())


@settings(max_examples=25, deadline=None)
@given(skew_polylines())
def test_exact_liepa_equals_brute_force(case):
    pts, third = case
    t = fill_polyline(pts, "liepa", "exact", third)
    t.check()
    best = _brute(pts, third, _liepa_key)
    assert t.weight[0] == best[0]  # the same dihedral numbers: bit-identical maxima
    assert math.isclose(t.weight[1], best[1], rel_tol=1e-9)


@settings(max_examples=15, deadline=None)
@given(skew_polylines())
def test_exact_area_equals_brute_force(case):
    pts, _ = case
    t = fill_polyline(pts, "area", "exact")
    t.check()
    assert math.isclose(t.weight, _brute(pts, None, _area), rel_tol=1e-9)


@settings(max_examples=15, deadline=None)
@given(skew_polylines())
def test_liepa_recurrence_is_never_better_than_exact(case):
    pts, third = case
    exact = fill_polyline(pts, "liepa", "exact", third).weight
    heuristic = fill_polyline(pts, "liepa", "liepa", third)
    heuristic.check()
    # the recurrence reports the true objective of its own patch
    assert heuristic.weight == liepa_objective(pts, heuristic.triangles, third)
    assert heuristic.weight[0] >= exact[0]
    if heuristic.weight[0] == exact[0]:
        assert heuristic.weight[1] >= exact[1] * (1 - 1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_area_decides_when_every_dihedral_is_the_worst(seed):
    # third points on their sides: every mesh triangle is degenerate, so every patch
    # has the worst key (pi) and the area alone decides: both searches then return the
    # minimum-area patch, which Liepa's recurrence finds exactly as the area DP does
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 9)) + np.arange(9) * 1e-3
    pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.5, 9)))
    third = (pts + np.roll(pts, -1, axis=0)) / 2
    least = fill_polyline(pts, "area", "exact").weight
    for method in ("liepa", "exact"):
        t = fill_polyline(pts, "liepa", method, third)
        assert t.weight[0] == math.pi
        assert math.isclose(t.weight[1], least, rel_tol=1e-12), method


def test_liepa_recurrence_is_a_heuristic():
    # a seeded case where Liepa's O(n^3) recurrence misses the max-dihedral optimum
    rng = np.random.default_rng(1)
    gaps = 0
    for _ in range(40):
        n = int(rng.integers(6, 9))
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.6, n)))
        third = 1.5 * (pts + np.roll(pts, -1, axis=0)) / 2 + rng.normal(0, 0.3, (n, 3))
        gaps += (
            fill_polyline(pts, "liepa", "liepa", third).weight
            > fill_polyline(pts, "liepa", "exact", third).weight
        )
    assert gaps > 0


def _regular(n, radius=1.0):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack((radius * np.cos(a), radius * np.sin(a), np.zeros(n)))


def test_planar_area_optimum_is_polygon_area():
    # an L-shaped (non-convex) planar hexagon, tilted into 3-D
    xy = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
    rot = np.array([[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]])
    pts = np.column_stack((xy, np.zeros(6))) @ rot.T + [5, -2, 1]
    area = abs(signed_area(xy))
    assert area == 4.0
    for method in ("exact", "delaunay"):
        t = fill_polyline(pts, "area", method)
        assert math.isclose(t.weight, area, rel_tol=1e-12)
    lp = fill_polyline(pts, "liepa", "exact")
    assert lp.weight[0] < 1e-6 and math.isclose(lp.weight[1], area, rel_tol=1e-12)


def test_delaunay_is_a_restriction():
    # the restricted search can only be worse: MWT is not the Delaunay triangulation
    pts = _regular(11) * [1.0, 0.6, 1.0]
    d, e = fill_polyline(pts, "perimeter", "delaunay"), fill_polyline(pts, "perimeter", "exact")
    assert d.weight >= e.weight


@pytest.mark.parametrize("weight", ["area", "liepa"])
def test_delaunay_equals_exact_on_convex_planar(weight):
    pts = _regular(11) * [1.0, 0.6, 1.0]
    d, e = fill_polyline(pts, weight, "delaunay"), fill_polyline(pts, weight, "exact")
    assert d.stats["fallback"] == 0
    d.check()
    np.testing.assert_allclose(np.ravel(d.weight), np.ravel(e.weight), rtol=1e-9, atol=1e-7)


def test_delaunay_falls_back_when_faces_hold_no_patch():
    # a tightly knotted polyline: its Delaunay faces hold no disc triangulation
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    knot = np.column_stack(
        (np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t))
    )
    for weight in ("area", "liepa"):
        r = fill_polyline(knot, weight, "delaunay")
        r.check()
        assert r.stats["fallback"] == 1 and r.stats["delaunay_faces"] > 0
        assert r.method == "delaunay->exact"
        assert r.weight == fill_polyline(knot, weight, "exact").weight


def test_triangle_weights_and_callables_agree_with_triangulate_sum():
    pts = _regular(8) + np.column_stack((np.zeros((8, 2)), np.linspace(0, 1, 8)))
    per = fill_polyline(pts, "perimeter")
    call = fill_polyline(pts, lambda v, i, k, j: liepa_objective(v, [[i, k, j]])[1])
    area = fill_polyline(pts, "area")
    assert math.isclose(call.weight, area.weight, rel_tol=1e-12)
    assert per.weight_name == "perimeter"
    exact = fill_polyline(pts, "max_angle", "exact").weight
    # for a triangle weight "liepa" is the exact recurrence; "delaunay" searches a subset
    assert math.isclose(fill_polyline(pts, "max_angle", "liepa").weight, exact, rel_tol=1e-12)
    assert fill_polyline(pts, "max_angle", "delaunay").weight >= exact * (1 - 1e-12)


def test_triangles_wound_in_polyline_order():
    t = fill_polyline(_regular(7), "area")
    assert (t.triangles[:, 0] < t.triangles[:, 1]).all()
    assert (t.triangles[:, 1] < t.triangles[:, 2]).all()


def test_two_d_input_is_lifted():
    t = fill_polyline([[0, 0], [2, 0], [2, 1], [0, 1]], "area")
    assert math.isclose(t.weight, 2.0) and t.vertices.shape == (4, 3)


@pytest.mark.parametrize(
    "pts, match",
    [
        ([[0, 0, 0], [1, 0, 0]], "at least 3"),
        ([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], "non-finite"),
        ([[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 1]], "repeats"),
        ([[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]], "collinear"),
        ([[0, 0, 0, 0]], "shape"),
    ],
)
def test_bad_polylines(pts, match):
    with pytest.raises(InvalidPolygonError, match=match):
        fill_polyline(pts)


def test_bad_third_points_and_method():
    sq = _regular(4)
    with pytest.raises(InvalidPolygonError, match="third_points"):
        fill_polyline(sq, third_points=np.zeros((3, 3)))
    with pytest.raises(InvalidPolygonError, match="unknown method"):
        fill_polyline(sq, method="fastest")
    with pytest.raises(optri.WeightError):
        fill_polyline(sq, weight="no_such_weight")


def test_exact_refuses_tables_that_do_not_fit(monkeypatch):
    monkeypatch.setattr(optri.config, "MEMORY_LIMIT_BYTES", 1 << 20)
    with pytest.raises(TableTooLargeError, match="method='liepa'"):
        fill_polyline(_regular(60), "liepa", "exact")
    # 60 * 60 * 61 * 10 bytes of exact tables do not fit in 1 MiB: auto takes Liepa's recurrence
    assert fill_polyline(_regular(60), "liepa", "auto").method == "liepa"


def test_auto_exact_search_limit_is_inclusive(monkeypatch):
    # config.HOLES_EXACT_MAX_N vertices still get the exact search, one more gets Liepa's
    monkeypatch.setattr(optri.config, "HOLES_EXACT_MAX_N", 6)
    rng = np.random.default_rng(5)
    for n, expected in ((6, "exact"), (7, "liepa")):
        pts = _regular(n) + np.column_stack((np.zeros((n, 2)), rng.normal(0, 0.3, n)))
        t = fill_polyline(pts, "liepa", "auto")
        assert t.method == expected, n
        t.check()


@pytest.mark.parametrize("method", ["exact", "liepa", "delaunay"])
def test_collinear_runs_avoid_degenerate_triangles(method):
    # a square with its edge midpoints: three collinear points on every side
    sq = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2], [0, 1]], float)
    t = fill_polyline(sq, "liepa", method)
    t.check()
    assert t.weight[0] < 1e-6  # flat, and no zero-area triangle (that would be pi)
    assert math.isclose(t.weight[1], 4.0, rel_tol=1e-12)
