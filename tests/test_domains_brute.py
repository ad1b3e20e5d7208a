"""Polygons with holes against brute force: every triangulation enumerated exactly."""

from __future__ import annotations

import math

import pytest

shapely = pytest.importorskip("shapely")
pytest.importorskip("scipy")

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import optri  # noqa: E402
from domain_polys import SUM_WEIGHTS, BruteDomain, small_domains  # noqa: E402

SETTINGS = settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.filter_too_much]
)


def _close(a, b):
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9)


def _in_brute(brute_set, tri):
    return frozenset(map(tuple, tri.triangles.tolist())) in brute_set


def _solve(ext, holes, **kw):
    t = optri.triangulate((ext, holes), **kw)
    t.check()
    assert t.optimality == "proven" and t.gap == 0.0
    return t


@SETTINGS
@given(small_domains(), st.sampled_from(["auto", "ip"]))
def test_every_sum_weight_matches_brute_force(dom, method):
    ext, holes = dom
    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()
    assert all_tr, "a polygon with holes always has a triangulation"
    seen = {frozenset(tr) for tr in all_tr}
    assert len(seen) == len(all_tr)  # each enumerated once
    for name in SUM_WEIGHTS:
        t = _solve(ext, holes, weight=name, method=method)
        assert _close(t.weight, brute.best(all_tr, name)), name
        assert _in_brute(seen, t)


@SETTINGS
@given(small_domains(), st.sampled_from(["max_angle", "min_angle", "aspect_ratio", "perimeter"]))
def test_max_objective_matches_brute_force(dom, name):
    ext, holes = dom
    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()
    for method in ("auto", "ip"):
        t = _solve(ext, holes, weight=name, objective="max", method=method)
        assert _close(t.weight, brute.best(all_tr, name, "max"))


@SETTINGS
@given(small_domains())
def test_lexicographic_max_then_sum(dom):
    ext, holes = dom
    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()
    t = _solve(ext, holes, weight=("max_angle", "perimeter"), objective=("max", "sum"))
    bottleneck = brute.best(all_tr, "max_angle", "max")
    gated = [tr for tr in all_tr if max(brute.weight("max_angle", x) for x in tr) <= bottleneck]
    assert _close(t.weight[0], bottleneck)
    assert _close(t.weight[1], brute.best(gated, "perimeter"))


@SETTINGS
@given(small_domains(n_max=10))
def test_custom_weight_matches_brute_force(dom):
    ext, holes = dom
    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()

    def w(i, k, j):  # arbitrary, by index: no geometry shortcut can help
        assert i < k < j
        return float((7 * i + 3 * k + j) % 11) + 0.1 * j

    t = _solve(ext, holes, weight=w)
    assert _close(t.weight, brute.best(all_tr, w))


def test_the_count_of_a_square_annulus():
    # a 3x3 square around a unit square hole: 4 trapezoids, 2 ways each
    ext = [[0, 0], [3, 0], [3, 3], [0, 3]]
    hole = [[1, 1], [2, 1], [2, 2], [1, 2]]
    assert len(BruteDomain(ext, [hole]).triangulations()) == 16
    t = _solve(ext, [hole], weight="diagonal")
    assert len(t.triangles) == 8 + 2 - 2
    assert _close(t.weight, 4 * math.sqrt(2) + 4 * math.sqrt(5))  # corners, then trapezoids


@SETTINGS
@given(small_domains())
def test_bridged_heuristic_is_a_triangulation_with_a_valid_bound(dom):
    ext, holes = dom
    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()
    seen = {frozenset(tr) for tr in all_tr}
    for name, objective in (("perimeter", "sum"), ("max_angle", "max")):
        t = optri.triangulate((ext, holes), weight=name, objective=objective, method="bridge")
        t.check()
        assert _in_brute(seen, t)
        best = brute.best(all_tr, name, objective)
        assert t.bound <= best + 1e-9 and best <= t.weight + 1e-9
        assert (t.optimality == "proven") == (t.gap <= 1e-9)
        if t.optimality == "proven":
            assert _close(t.weight, best)
