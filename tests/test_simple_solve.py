"""optri.triangulate on simple polygons equals brute force over valid diagonals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri import InvalidPolygonError, as_polygon
from optri.engines.brute import all_index_triangulations
from optri.objective import as_objective
from optri.solve import build_problem
from simple_polys import ccw_of, oracle_mask, simple_polygons, star_polygons, triangle_inside_fn

shapely = pytest.importorskip("shapely")

polygons = st.one_of(star_polygons(4, 10), simple_polygons(4, 10))
POINT_WEIGHTS = sorted(name for name, w in optri.WEIGHTS.items() if w.needs == "points")
CASES = [(w, "sum") for w in POINT_WEIGHTS] + [
    ("max_angle", "max"),
    ("min_angle", "max"),
    ("aspect_ratio", "max"),
]
# Lexicographic pairs are left out: the core DP's (max, sum) is not exact even on
# convex polygons (a sub-polygon's lexicographic optimum need not extend to the whole).


def oracle_optimum(coords, weight, objective):
    """Best cost over index triangulations whose chords shapely calls diagonals."""
    poly = as_polygon(coords)
    ok = oracle_mask(ccw_of(np.asarray(poly.vertices))).tolist()
    problem = build_problem(poly, weight, objective, allowed=np.ones((poly.n,) * 2, bool))
    w, obj = problem.evaluator(), as_objective(objective)
    costs = [obj.aggregate([w(*t) for t in tris]) for tris in all_index_triangulations(poly.n, ok)]
    best = costs[0]
    for c in costs[1:]:
        if obj.less(c, best):
            best = c
    return obj.finalize(best)


def close(a, b):
    if isinstance(a, tuple):
        return all(close(x, y) for x, y in zip(a, b))
    return a == b or math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)


def assert_inside(tri: optri.Triangulation):
    """Independent geometry: every triangle has positive area and lies in the polygon."""
    poly = shapely.Polygon(tri.vertices)
    for a, b, c in tri.triangles.tolist():
        t = shapely.Polygon(tri.vertices[[a, b, c]])
        assert t.area > 0 and poly.covers(t)
        assert t.exterior.is_ccw
    union = shapely.union_all([shapely.Polygon(tri.vertices[t]) for t in tri.triangles])
    assert math.isclose(union.area, poly.area, rel_tol=1e-9)


@pytest.mark.parametrize("case", CASES, ids=str)
@settings(max_examples=8, deadline=None)
@given(coords=polygons, reverse=st.booleans())
def test_engines_equal_oracle(case, coords, reverse):
    weight, objective = case
    if reverse:
        coords = coords[::-1]
    expected = oracle_optimum(coords, weight, objective)
    for method in ("memo", "table", "brute"):
        tri = optri.triangulate(coords, weight, objective, method=method)
        tri.check()
        assert close(tri.weight, expected), (method, tri.weight, expected)
        assert tri.stats.get("zero_area_triangles", 0) == 0
    assert_inside(tri)


@settings(max_examples=15, deadline=None)
@given(polygons)
def test_every_brute_triangulation_is_geometric(coords):
    """Each index triangulation over the mask is a real triangulation (shapely check)."""
    poly = as_polygon(coords)
    ccw = ccw_of(np.asarray(poly.vertices))
    inside = triangle_inside_fn(ccw)
    ok = optri.simple.valid_diagonals(poly).tolist()
    count = 0
    for tris in all_index_triangulations(poly.n, ok):
        count += 1
        assert all(inside(*t) for t in tris)
    assert count >= 1


@settings(max_examples=20, deadline=None)
@given(polygons)
def test_clockwise_and_counter_clockwise_agree(coords):
    a = optri.triangulate(coords, method="table")
    b = optri.triangulate(coords[::-1].copy(), method="table")
    assert math.isclose(a.weight, b.weight, rel_tol=1e-12)
    for t in (a, b):
        t.check()
        assert_inside(t)


def test_dart_has_one_triangulation():
    dart = [[0, 0], [4, 0], [1, 1], [0, 4]]
    tri = optri.triangulate(dart, method="memo")
    assert tri.diagonals.tolist() == [[0, 2]]
    assert tri.triangles.tolist() == [[0, 2, 3], [0, 1, 2]]
    assert tri.stats["valid_diagonals"] == 1 and tri.stats["mask_seconds"] >= 0


def test_straight_vertices_give_no_flat_triangles():
    # a square with two vertices on its bottom side: chord 0-3 would run along the side
    sq = [[0, 0], [1, 0], [2, 0], [3, 0], [3, 3], [0, 3]]
    for w in POINT_WEIGHTS:
        tri = optri.triangulate(sq, w, method="memo")
        tri.check()
        assert_inside(tri)
        assert tri.stats.get("zero_area_triangles", 0) == 0


def test_planar_3d_polygon_solved_in_its_plane():
    flat = np.array([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]], float)
    rot = np.array([[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]])
    pts3 = np.column_stack((flat, np.full(5, 2.0))) @ rot.T
    t2 = optri.triangulate(flat, method="table")
    t3 = optri.triangulate(pts3, method="table")
    assert math.isclose(t2.weight, t3.weight, rel_tol=1e-12)
    assert t2.diagonals.tolist() == t3.diagonals.tolist()


def test_larger_star_memo_equals_table():
    from simple_polys import random_star

    pts = random_star(60, 7)
    a = optri.triangulate(pts, method="memo")
    b = optri.triangulate(pts, "diagonal", method="table")
    a.check()
    b.check()
    assert_inside(a)
    # sum of perimeters = 2 * diagonals + boundary length
    boundary = float(np.hypot(*(np.roll(pts, -1, axis=0) - pts).T).sum())
    assert math.isclose(a.weight, 2 * b.weight + boundary, rel_tol=1e-9)


@pytest.mark.parametrize(
    "coords",
    [
        [[0, 0], [1, 1], [1, 0], [0, 1]],
        [[0, 0], [2, 0], [2, 2], [1, -1], [0, 2]],
        [[0, 0], [2, 0], [1, 1], [2, 2], [0, 2], [1, 1]],
        [[0, 0], [1, 0], [float("nan"), 1], [0, 1]],
    ],
)
def test_triangulate_refuses_non_simple(coords):
    with pytest.raises(InvalidPolygonError):
        optri.triangulate(coords)
