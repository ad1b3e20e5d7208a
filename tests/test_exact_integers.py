"""Exact integers: matrix chains and the product weight, against a pure-Python exact DP."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri import EngineUnavailableError


def exact_chain(d: list[int]) -> int:
    """The textbook DP (CLRS 15.2) in Python ints: the oracle."""
    m = len(d) - 1
    cost = [[0] * (m + 1) for _ in range(m + 1)]
    for length in range(2, m + 1):
        for i in range(1, m - length + 2):
            j = i + length - 1
            cost[i][j] = min(
                cost[i][k] + cost[k + 1][j] + d[i - 1] * d[k] * d[j] for k in range(i, j)
            )
    return cost[1][m]


@pytest.mark.parametrize("m", [5, 8, 25, 60])
@pytest.mark.parametrize("seed", range(3))
def test_chain_near_1e6_is_exact(m, seed):
    rng = random.Random(seed)
    dims = [rng.randint(999_000, 1_001_000) for _ in range(m + 1)]
    c = optri.matrix_chain(dims)
    assert type(c.cost) is int and c.cost == exact_chain(dims)
    assert c.cost > 2**53 or m < 8  # beyond float64's integers: rounding would show


def test_chain_beyond_int64_uses_python_ints():
    dims = [10**12 + 7 * i for i in range(12)]
    t = optri.triangulate(dims, "product")
    assert t.method == "integer" and t.stats["int64"] == 0
    assert t.weight == exact_chain(dims) and t.weight > 2**63
    small = optri.triangulate([30, 35, 15, 5, 10, 20, 25], "product")
    assert small.stats["int64"] == 1 and small.weight == 15125


@pytest.mark.parametrize("method", ["memo", "table", "brute", "integer"])
def test_every_exact_engine_gives_the_exact_int(method):
    dims = [999_999, 1_000_003, 999_983, 1_000_033, 999_979, 1_000_037, 999_961, 1_000_039]
    t = optri.triangulate(dims, "product", method=method)
    assert type(t.weight) is int and t.weight == exact_chain(dims)
    t.check()


def test_float_tables_are_refused_where_they_would_round():
    dims = [1_000_003] * 12  # (n - 2) max^3 > 2**53
    with pytest.raises(EngineUnavailableError, match="exactly"):
        optri.triangulate(dims, "product", method="fast")
    with pytest.raises(EngineUnavailableError, match="exactly"):
        optri.matrix_chain(dims, method="fast")
    ok = optri.triangulate([30, 35, 15, 5, 10, 20, 25], "product", method="fast")
    assert type(ok.weight) is int and ok.weight == 15125  # below 2**53 floats are exact


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.integers(-(10**6), 10**6), min_size=3, max_size=9),
    st.sampled_from(["sum", "max"]),
)
def test_integer_engine_equals_brute_force(values, objective):
    brute = optri.triangulate(values, "product", objective, method="brute")
    fast = optri.triangulate(values, "product", objective, method="integer")
    assert fast.weight == brute.weight and type(fast.weight) is int
    fast.check()


def test_non_integer_values_stay_floats():
    t = optri.triangulate([1.5, 3, 1, 4, 1, 5], "product")
    assert isinstance(t.weight, float) and t.method != "integer"


def _brute_product(values: list[int], objective: str = "sum") -> int:
    """Exact optimum by enumeration, in Python ints (the oracle)."""
    from optri.engines.brute import all_index_triangulations

    agg = sum if objective == "sum" else max
    n = len(values)
    return min(
        agg(values[i] * values[k] * values[j] for i, k, j in tris)
        for tris in all_index_triangulations(n)
    )


@pytest.mark.parametrize("base", [2**31, 2**53, 2**62, 2**63, 2**64, 2**100])
@pytest.mark.parametrize("offsets", [(5, 9), (0, 1), (-3, 7)])
def test_mixed_small_and_huge_ints_stay_exact(base, offsets):
    # small and huge Python ints in one list: numpy would make floats of them
    values = [base + offsets[0], 3, base + offsets[1], 7, base - 1]
    want = _brute_product(values)
    for method in ("auto", "integer"):
        got = optri.triangulate(values, "product", method=method)
        assert type(got.weight) is int and got.weight == want
