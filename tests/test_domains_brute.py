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


@SETTINGS
@given(small_domains(), st.sampled_from(SUM_WEIGHTS))
def test_floors_are_lower_bounds(dom, name):
    from optri.domains import as_domain, find_candidates
    from optri.domains.bounds import max_floor, sum_floor
    from optri.domains.reduce import blocks
    from optri.domains.weighing import DomainWeight
    from optri.weights import get_weight

    ext, holes = dom
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


def test_max_is_proven_where_an_exact_block_holds_the_maximum():
    # found by hypothesis: the bridged block's bound is below its value, but the maximum
    # comes from a block the DP solved exactly, so the whole answer is proven
    ext = [
        [0.92389948, 0.16177549],
        [0.4703455, 0.58363801],
        [-0.4738874, 0.68217634],
        [-0.81312559, 0.14511649],
        [-0.48294862, -0.7689661],
        [0.15440862, -0.98593242],
    ]
    holes = [
        [[0.51285579, -0.05958531], [0.27798894, -0.31051117], [0.27794525, 0.03280629]],
        [[-0.03188118, 0.10247251], [-0.21383255, 0.05239338], [-0.12608362, 0.28761137]],
    ]
    brute = BruteDomain(ext, holes)
    best = brute.best(brute.triangulations(), "max_angle", "max")
    t = optri.triangulate((ext, holes), weight="max_angle", objective="max", method="bridge")
    assert t.method == "bridge+dp" and _close(t.weight, best)
    assert t.optimality == "proven" and t.gap == 0.0
