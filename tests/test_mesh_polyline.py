"""fill_polyline: exact search against brute force, planar cases, modes, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.engines.brute import all_index_triangulations
from optri.errors import InvalidPolygonError, NoTriangulationError, TableTooLargeError
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
def test_zero_area_mesh_triangles_have_no_normal_to_fold_against(seed):
    # third points on their sides: every mesh triangle is degenerate, so no side has a
    # dihedral with the mesh (key 0, not a fold of pi that every patch would share):
    # the patch is the one found without third points, in both searches
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 9)) + np.arange(9) * 1e-3
    pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.5, 9)))
    third = (pts + np.roll(pts, -1, axis=0)) / 2
    for method in ("liepa", "exact"):
        t = fill_polyline(pts, "liepa", method, third)
        free = fill_polyline(pts, "liepa", method)
        assert t.triangles.tolist() == free.triangles.tolist(), method
        assert t.weight == free.weight and t.weight[0] < math.pi


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


def test_delaunay_widens_its_candidates_before_the_cubic_search():
    # a tightly knotted polyline: its Delaunay faces hold no disc triangulation,
    # a wider candidate set does
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    knot = np.column_stack(
        (np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t))
    )
    from optri.holes.candidates import candidate_sets
    from optri.holes.search import liepa_sparse

    first = next(candidate_sets(knot))
    assert first[0] == "delaunay" and liepa_sparse(knot, 40, False, first[1]) is None
    for weight in ("area", "liepa"):
        r = fill_polyline(knot, weight, "delaunay")
        r.check()
        assert r.stats["fallback"] == 0 and r.method == "delaunay"
        assert r.stats["candidates"] not in ("delaunay", "all")
        exact = fill_polyline(knot, weight, "exact").weight
        assert np.all(np.ravel(r.weight) >= np.ravel(exact) * (1 - 1e-12))


def test_delaunay_falls_back_to_all_triangles_when_no_set_holds_a_patch(monkeypatch):
    import optri.holes.modes as modes

    monkeypatch.setattr(
        modes,
        "candidate_sets",
        lambda pts, faces=None: iter([("delaunay", np.zeros((0, 3), np.int64))]),
    )
    r = fill_polyline(_regular(9), "liepa", "delaunay")
    assert r.stats["fallback"] == 1 and r.stats["candidates"] == "all"
    assert r.method == "delaunay->exact"
    assert r.weight == fill_polyline(_regular(9), "liepa", "exact").weight


def test_delaunay_adds_triangles_on_loop_sides_missing_from_the_tetrahedralization():
    # CGAL's rule: a side that is no Delaunay edge gets every triangle on it
    from optri.holes.candidates import candidate_sets, delaunay_faces

    n = 40
    ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    pts = np.column_stack((np.cos(ang), np.sin(ang), 0.3 * np.sin(2 * ang)))
    pts += np.random.default_rng(0).normal(0, 2 * np.pi / n, pts.shape)  # a ragged scan edge
    faces = delaunay_faces(pts)
    edges = {(a, b) for t in faces.tolist() for a, b in ((t[0], t[1]), (t[1], t[2]), (t[0], t[2]))}
    missing = [(i, i + 1) for i in range(n - 1) if (i, i + 1) not in edges]
    missing += [(0, n - 1)] if (0, n - 1) not in edges else []
    assert missing  # this noisy loop has sides the tetrahedralization lacks
    name, tris = next(candidate_sets(pts))
    have = {tuple(t) for t in tris.tolist()}
    for a, b in missing:
        assert all(tuple(sorted((a, b, k))) in have for k in range(n) if k not in (a, b))
    r = fill_polyline(pts, "liepa", "delaunay")
    assert r.stats["candidates"] == "delaunay" and r.stats["fallback"] == 0


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


@pytest.mark.parametrize("tris", [[[0, 1, 4]], [[0, -1, 2]], [[0, 1]], [[0, 1, 2], [0, 2]]])
def test_liepa_objective_refuses_triangles_off_the_polyline(tris):
    # index 4 would be a third point's row, -1 the last one: neither is a polyline vertex
    third = 2 * _regular(4)
    with pytest.raises(InvalidPolygonError, match="index triples of vertices 0..3"):
        liepa_objective(_regular(4), tris, third)


def test_bad_third_points_and_method():
    sq = _regular(4)
    with pytest.raises(InvalidPolygonError, match="third_points"):
        fill_polyline(sq, third_points=np.zeros((3, 3)))
    with pytest.raises(InvalidPolygonError, match="unknown method"):
        fill_polyline(sq, method="fastest")
    with pytest.raises(optri.WeightError):
        fill_polyline(sq, weight="no_such_weight")


def test_exact_refuses_tables_that_do_not_fit(monkeypatch):
    monkeypatch.setattr(optri.config, "MEMORY_LIMIT_BYTES", 1 << 18)
    with pytest.raises(TableTooLargeError, match="method='liepa'"):
        fill_polyline(_regular(60), "liepa", "exact")
    # the exact search's states (about 0.6 MB) do not fit in 256 KiB: auto takes Liepa's
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


def _flat_sheet_border():
    # the border of a flat sheet (like a 2-D mesh loaded as 3-D): every patch folds
    # back over the sheet (180 degrees) and runs of collinear border points make
    # zero-area triangles as cheap as any other in the old objective
    pts = np.array(
        [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1], [3, 2], [2, 2], [1, 2], [0, 2], [0, 1]], float
    )
    pts3 = np.column_stack((pts, np.zeros(len(pts))))
    centre = pts3.mean(axis=0)
    mid = (pts3 + np.roll(pts3, -1, axis=0)) / 2
    third = mid + 0.3 * (centre - mid)  # the sheet's triangles lie inside the border
    return pts3, third


@pytest.mark.parametrize("method", ["exact", "liepa", "delaunay", "auto"])
def test_flat_sheet_patch_has_no_zero_area_triangle(method):
    pts, third = _flat_sheet_border()
    t = fill_polyline(pts, "liepa", method, third)
    t.check()
    assert t.stats["degenerate"] == 0
    assert math.isclose(t.weight[0], math.pi)  # the fold is unavoidable, and reported
    p = pts[t.triangles]
    cross = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    assert (cross > 1e-9).all()


def test_flat_sheet_optimum_is_the_best_patch_without_zero_area_triangles():
    pts, third = _flat_sheet_border()

    def zero_area(t):
        p = pts[np.array(t)]
        return (np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1) < 1e-9).any()

    tris = list(all_index_triangulations(len(pts)))
    clean = [t for t in tris if not zero_area(t)]
    assert len(clean) < len(tris)  # zero-area patches exist ...
    best = min(liepa_objective(pts, np.array(t), third) for t in clean)
    got = fill_polyline(pts, "liepa", "exact", third).weight
    assert got[0] == best[0] and math.isclose(got[1], best[1], rel_tol=1e-12)


@pytest.mark.parametrize("method", ["liepa", "exact", "delaunay"])
def test_l_shaped_sheet_border_takes_the_least_area_among_equal_folds(method):
    # the border of a flat L-shaped sheet, collinear runs included: every patch folds back
    # over the sheet at its sides (pi), so the area alone decides between patches, and
    # those through the notch (outside the L, wound the other way) cover more than 6
    xy = np.array([[0, 0], [4, 0], [4, 1], [3, 1], [2, 1], [1, 1], [1, 3], [0, 3], [0, 2], [0, 1]])
    pts = np.column_stack((xy, np.zeros(len(xy)))).astype(float)
    side = np.roll(pts, -1, axis=0) - pts
    inward = np.column_stack((-side[:, 1], side[:, 0], np.zeros(len(pts))))
    third = (pts + np.roll(pts, -1, axis=0)) / 2 + 0.2 * inward  # the sheet's triangles
    t = fill_polyline(pts, "liepa", method, third)
    t.check()
    assert t.weight[0] == math.pi and t.stats["degenerate"] == 0
    assert math.isclose(t.weight[1], 6.0, rel_tol=1e-12)


def test_zero_area_triangle_only_when_every_patch_needs_one():
    # 0, 1, 2 collinear; with chord (1, 3) forbidden the only patch has (0, 1, 2)
    pts = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0.5]]
    for method in ("exact", "liepa", "delaunay"):
        free = fill_polyline(pts, "liepa", method)
        assert free.stats["degenerate"] == 0 and free.triangles.tolist() == [[0, 1, 3], [1, 2, 3]]
        forced = fill_polyline(pts, "liepa", method, forbidden=[[1, 3]])
        assert forced.triangles.tolist() == [[0, 1, 2], [0, 2, 3]]
        assert forced.stats["degenerate"] == 1 and forced.stats["forbidden"] == 1


def test_triangle_weights_prefer_patches_without_zero_area_triangles():
    # area: a zero-area ear and its alternative have the same total area
    pts = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], float)
    t = fill_polyline(pts, "area", "exact")
    assert t.stats["degenerate"] == 0 and math.isclose(t.weight, 2.0, rel_tol=1e-12)


@pytest.mark.parametrize("exponent", [-500, -30, 0, 40, 500])
def test_scaling_by_a_power_of_two_changes_nothing(exponent):
    rng = np.random.default_rng(5)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 9))
    pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.4, 9)))
    third = 1.5 * (pts + np.roll(pts, -1, axis=0)) / 2
    base = fill_polyline(pts, "liepa", "exact", third)
    big = fill_polyline(np.ldexp(pts, exponent), "liepa", "exact", np.ldexp(third, exponent))
    assert big.triangles.tolist() == base.triangles.tolist()
    assert big.weight[0] == base.weight[0]
    assert big.weight[1] == math.ldexp(base.weight[1], 2 * exponent)


@pytest.mark.parametrize("scale", [1e-300, 1e-9, 1e12, 1e150])
@pytest.mark.parametrize("method", ["exact", "liepa", "delaunay"])
def test_any_scale_gives_the_same_patch(scale, method):
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0], [0.5, 0.5, 1]])
    base = fill_polyline(pts, "liepa", method).triangles.tolist()
    assert fill_polyline(pts * scale, "liepa", method).triangles.tolist() == base


def test_area_overflow_is_an_error_not_a_hang():
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]]) * 1e308
    with pytest.raises(InvalidPolygonError, match="overflows float64"):
        fill_polyline(pts)


def test_bad_forbidden_pairs():
    sq = _regular(5)
    with pytest.raises(InvalidPolygonError, match="side cannot be forbidden"):
        fill_polyline(sq, forbidden=[[0, 1]])
    with pytest.raises(InvalidPolygonError, match="forbidden pairs"):
        fill_polyline(sq, forbidden=[[0, 7]])
    with pytest.raises(InvalidPolygonError, match=r"\(m, 2\)"):
        fill_polyline(sq, forbidden=[0, 2])
    with pytest.raises(NoTriangulationError, match="forbidden chord"):
        fill_polyline(_regular(4), forbidden=[[0, 2], [1, 3]])
