import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import optri
from optri.engines.brute import all_index_triangulations
from optri.enumeration import catalan, index_triangulations, regular_polygon
from optri.enumeration.hurtado_noy import hn_index_triangulations, hn_operation_counts


def _key(tri):
    return tuple(sorted(map(tuple, tri.triangles.tolist())))


@pytest.mark.parametrize("n", range(3, 12))
def test_hn_yields_every_triangulation_once(n):
    seen = {tuple(sorted(map(tuple, tris))) for tris in hn_index_triangulations(n)}
    oracle = {tuple(sorted(t)) for t in all_index_triangulations(n)}
    assert len(seen) == catalan(n - 2)
    assert seen == oracle


@pytest.mark.parametrize("n", range(3, 10))
def test_enumerate_items_are_valid_and_distinct(n):
    items = list(optri.enumerate_triangulations(n, weight="perimeter"))
    assert len(items) == optri.count_triangulations(n)
    assert len({_key(t) for t in items}) == len(items)
    for t in items:
        assert t.method == "enumerate"
        t.check()


def test_enumerate_without_weight_has_nan_weight():
    items = list(optri.enumerate_triangulations([[0, 0], [1, 0], [1, 1], [0, 1]]))
    assert len(items) == 2 and all(math.isnan(t.weight) for t in items)
    for t in items:
        t.check()


def test_enumerate_respects_input_order_and_orientation():
    cw = [[0, 0], [0, 2], [1, 3], [2, 2], [2, 0]]  # clockwise pentagon
    items = list(optri.enumerate_triangulations(cw, weight="perimeter"))
    assert len(items) == 5
    for t in items:
        t.check()
    best = min(t.weight for t in items)
    assert math.isclose(best, optri.triangulate(cw, method="brute").weight)


def test_hn_children_order_is_fixed():
    # Children of the triangle in order s = 0, 1: ear at the new vertex first.
    got = [[tuple(t) for t in tris] for tris in hn_index_triangulations(4)]
    assert got == [[(0, 1, 2), (0, 2, 3)], [(0, 1, 3), (1, 2, 3)]]


def test_hn_is_lazy():
    gen = hn_index_triangulations(40)  # C(38) ~ 1.7e21 triangulations: never materialized
    first = [list(t) for t in next(gen)]
    assert len(first) == 38


@pytest.mark.parametrize("n", range(4, 12))
def test_hn_operation_counts_match_eq5(n):
    c = hn_operation_counts(n)
    assert c.parents == catalan(n - 3) and c.children == catalan(n - 2)
    assert c.edge_checks == (2 * n - 5) * catalan(n - 3)
    assert c.edges_written == (2 * n - 3) * catalan(n - 2)
    assert c.scratch_evaluations == (n - 2) * catalan(n - 2)


def _convex(angles):
    a = np.sort(np.asarray(angles))
    return np.column_stack((np.cos(a), 1.7 * np.sin(a)))


def _memo_or_none(poly, weight, objective):
    try:
        return optri.triangulate(poly, weight, objective, method="memo")
    except optri.InvalidPolygonError:
        return None


@settings(max_examples=25, deadline=None)
@given(
    st.lists(
        st.floats(0, 2 * math.pi, exclude_max=True), min_size=4, max_size=8, unique=True
    ).filter(lambda a: min(np.diff(np.sort(a)), default=1) > 1e-3),
    st.sampled_from(["perimeter", "diagonal", "max_angle"]),
    st.sampled_from(["sum", "max"]),
)
def test_min_over_enumeration_is_dp_optimum(angles, weight, objective):
    poly = _convex(angles)
    opt = _memo_or_none(poly, weight, objective)
    assume(opt is not None)  # three nearly collinear points: refused as not simple
    best = min(t.weight for t in optri.enumerate_triangulations(poly, weight, objective))
    assert math.isclose(best, opt.weight, rel_tol=1e-9, abs_tol=1e-12)


def test_index_triangulations_uses_mask(monkeypatch):
    # With a mask forbidding chord (0, 2) the square keeps one triangulation.
    import optri.enumeration.builder

    mask = np.ones((4, 4), dtype=bool)
    mask[0, 2] = mask[2, 0] = False
    monkeypatch.setattr(optri.enumeration.builder, "allowed_chords", lambda polygon: mask)
    poly = optri.as_polygon(regular_polygon(4))
    got = [sorted(map(tuple, t)) for t in index_triangulations(poly)]
    assert got == [[(0, 1, 3), (1, 2, 3)]]
    assert optri.count_triangulations(regular_polygon(4)) == 1
    t = optri.random_triangulation(regular_polygon(4), seed=0)
    assert t.diagonals.tolist() == [[1, 3]]
