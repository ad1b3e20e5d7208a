"""Polygons with holes against brute force: every triangulation enumerated exactly."""

from __future__ import annotations

import math

import numpy as np
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


def _floors_below_optima(ext, holes, name):
    from optri.domains import as_domain, find_candidates
    from optri.domains.bounds import max_floor, sum_floor
    from optri.domains.reduce import blocks
    from optri.domains.weighing import DomainWeight
    from optri.weights import get_weight

    brute = BruteDomain(ext, holes)
    all_tr = brute.triangulations()
    d = as_domain(ext, holes)
    cand = find_candidates(d)
    values = DomainWeight(d, get_weight(name)).many(cand.triangles)
    fixed = ~cand.is_diagonal  # no forced diagonal: the blocks are the domain's faces
    floors_sum, floors_max = 0.0, -math.inf
    for block in blocks(cand, np.ones(len(values), dtype=bool), fixed):
        floors_sum += sum_floor(cand, block, fixed, values)
        floors_max = max(floors_max, max_floor(cand, block, fixed, values))
    assert floors_sum <= brute.best(all_tr, name) + 1e-9
    assert floors_max <= brute.best(all_tr, name, "max") + 1e-9


@SETTINGS
@given(small_domains(), st.sampled_from(SUM_WEIGHTS))
def test_floors_are_lower_bounds(dom, name):
    _floors_below_optima(*dom, name)


def test_sum_floor_on_a_polygon_with_ears():
    # ears (two boundary sides) take one share per side: counted whole, the floor of
    # min_angle would exceed the optimum here
    ext = [
        [-1, 19],
        [-10, 15],
        [-17, 8],
        [-15, -5],
        [-6, -17],
        [4, -14],
        [14, -11],
        [14, -1],
        [11, 15],
    ]
    _floors_below_optima(ext, [[[2, -2], [2, -5], [-2, -3]]], "min_angle")


def _anti_bridge(domain):
    """Heavy where a triangle has a short diagonal: the bridges' own weakness."""
    nxt, p = domain.nxt.tolist(), domain.vertices

    def w(i, k, j):
        worst = 0.0
        for a, b in ((i, k), (k, j), (i, j)):
            if nxt[a] != b and nxt[b] != a:
                worst = max(worst, 1.0 / math.dist(p[a], p[b]))
        return worst

    return w


@SETTINGS
@given(small_domains())
def test_max_bisection_beats_the_bridges_exactly(dom):
    from optri.domains import as_domain

    ext, holes = dom
    brute = BruteDomain(ext, holes)
    w = _anti_bridge(as_domain(ext, holes))
    best = brute.best(brute.triangulations(), w, "max")
    for method in ("auto", "ip"):
        t = _solve(ext, holes, weight=w, objective="max", method=method)
        assert _close(t.weight, best)


def test_max_bisection_goes_below_the_heuristic():
    from optri.domains import as_domain, find_candidates, random_domain
    from optri.domains.program import solve_program
    from optri.domains.reduce import blocks, prune

    d = as_domain(*random_domain(30, 2, seed=1))
    w = _anti_bridge(d)
    heur = optri.triangulate(d, weight=w, objective="max", method="bridge")
    t = optri.triangulate(d, weight=w, objective="max", method="ip")
    t.check()
    assert t.optimality == "proven" and t.weight < heur.weight - 1.0
    # nothing lighter than the optimum triangulates the polygon
    cand = find_candidates(d)
    keep = prune(cand, np.array([w(*sorted(x)) < t.weight for x in cand.triangles.tolist()]))
    if keep is not None:
        fixed = ~cand.is_diagonal
        outs = [
            solve_program(cand, b.triangles, fixed, None, None) for b in blocks(cand, keep, fixed)
        ]
        assert any(o.status == "infeasible" for o in outs)


def test_time_limited_max_bound_stays_below_the_optimum(monkeypatch):
    # a bisection cut short at once: its bound is the lowest level it has not ruled out,
    # below the optimum even where the incumbent (the bridges) is far above it
    from optri import config
    from optri.domains import as_domain, random_domain

    d = as_domain(*random_domain(30, 2, seed=1))
    w = _anti_bridge(d)
    exact = optri.triangulate(d, weight=w, objective="max", method="ip")
    assert exact.optimality == "proven"
    monkeypatch.setattr(config, "DOMAIN_MIN_SOLVER_SECONDS", 1e-6)
    for method in ("ip", "auto"):
        t = optri.triangulate(d, weight=w, objective="max", method=method, time_limit=1e-9)
        t.check()
        assert t.optimality == "heuristic" and t.weight > exact.weight + 1.0
        assert t.bound <= exact.weight + 1e-9
        assert t.gap == pytest.approx((t.weight - t.bound) / abs(t.weight))
