"""Lexicographic objectives under ties: every engine against brute force on grid polygons.

On integer grids many triangulations share the same total perimeter in exact
arithmetic, while their float sums differ in the last bits; the secondary
component must decide those ties (optri.objective.LEX_TIE_RTOL) in every engine.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri.objective import LEX_TIE_RTOL, lex_better, lex_less, tie_ceiling
from simple_polys import simple_polygons, star_polygons

CASES = [
    (("perimeter", "max_angle"), ("sum", "max")),
    (("perimeter", "max_angle"), ("sum", "sum")),
    (("perimeter", "min_angle"), ("sum", "max")),
    (("max_angle", "perimeter"), ("max", "sum")),
    (("diagonal", "aspect_ratio"), ("sum", "sum")),
]
ENGINES = ["memo", "table", "fast"]
grid_polygons = st.one_of(star_polygons(4, 9), simple_polygons(4, 9))


def _same(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)


@settings(max_examples=120, deadline=None)
@given(grid_polygons, st.sampled_from(CASES), st.booleans())
def test_every_engine_equals_brute_force_under_ties(poly, case, reverse):
    weights, objective = case
    if reverse:
        poly = poly[::-1]
    oracle = optri.triangulate(poly, weights, objective, method="brute").weight
    for method in ENGINES:
        got = optri.triangulate(poly, weights, objective, method=method)
        assert _same(got.weight[0], oracle[0]), (method, got.weight, oracle)
        assert _same(got.weight[1], oracle[1]), (method, got.weight, oracle)
        got.check()


# grid polygons (found by search) where the primaries of two triangulations are equal
# in exact arithmetic but not as float sums: without the tie rule the DP and brute
# force pick different secondaries
TIED = [
    ([[4, 2], [2, 4], [1, 4], [3, 5], [5, 5]], CASES[1]),
    ([[2, 0], [5, 1], [1, 4], [0, 2], [1, 2]], (("diagonal", "max_angle"), ("sum", "max"))),
    ([[4, 0], [1, 2], [0, 5], [4, 4], [3, 3]], CASES[0]),
    ([[4, 0], [1, 2], [0, 5], [4, 4], [3, 3]], CASES[1]),
]


@pytest.mark.parametrize("method", ENGINES)
@pytest.mark.parametrize("poly, case", TIED)
def test_known_ties_are_broken_by_the_secondary(poly, case, method):
    weights, objective = case
    oracle = optri.triangulate(poly, weights, objective, method="brute").weight
    got = optri.triangulate(poly, weights, objective, method=method).weight
    assert _same(got[0], oracle[0]) and _same(got[1], oracle[1]), (got, oracle)
    best = min(  # the secondary of brute force is the least among exact primary ties
        (t.weight for t in optri.enumerate_triangulations(poly, weights, objective)),
        key=lambda w: (round(w[0], 9), w[1]),
    )
    assert _same(got[1], best[1])


def test_tie_rule_helpers():
    a = 10.0
    b = a * (1 + LEX_TIE_RTOL / 2)
    assert lex_better(b, 1.0, a, 2.0) and not lex_better(a, 2.0, b, 1.0)  # tie: second decides
    assert lex_better(a, 9.0, a * (1 + 4 * LEX_TIE_RTOL), 1.0)  # no tie: first decides
    assert lex_better(1.0, 5.0, math.inf, math.inf) and not lex_better(math.inf, 0.0, 1.0, 9.0)
    assert lex_less((b, 1.0), (a, 2.0)) and not lex_less((10, 1), (9, 2))  # ints: exact
    assert tie_ceiling(a) == pytest.approx(a * (1 + LEX_TIE_RTOL)) and tie_ceiling(7) == 7
