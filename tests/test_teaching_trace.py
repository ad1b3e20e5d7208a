"""optri.trace: counts against the paper's formulas, the engines' stats and the naive recursion."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri import config
from optri.engines.naive import naive_calls
from optri.teaching import trace
from strategies import convex_polygons, value_sequences


def regular(n, r=10.0):
    a = 2 * np.pi * np.arange(n) / n
    return np.column_stack((r * np.cos(a), r * np.sin(a)))


def random_values(n, seed):
    return np.random.default_rng(seed).integers(1, 30, n).astype(float).tolist()


def cells(n):  # the paper's Eq. 7: (n-1)(n-2)/2 stored cells
    return (n - 1) * (n - 2) // 2


def naive_counts(n):
    """(calls, candidates, stores) of the un-memoized recursion, by its own recurrence.

    OPT on a chord spanning d sides calls itself on (d1, d - d1) for d1 = 1 .. d-1:
    calls T(d) = 1 + sum(T(a) + T(d-a)), T(1) = 1; candidates C(d) = (d-1) + sum(C(a) + C(d-a));
    stores S(d) = 1 + sum(S(a) + S(d-a)), S(1) = 0 (a side returns without storing).
    """
    T, C, S = {1: 1}, {1: 0}, {1: 0}
    for d in range(2, n):
        T[d] = 1 + sum(T[a] + T[d - a] for a in range(1, d))
        C[d] = d - 1 + sum(C[a] + C[d - a] for a in range(1, d))
        S[d] = 1 + sum(S[a] + S[d - a] for a in range(1, d))
    return T[n - 1], C[n - 1], S[n - 1]


INPUTS = [
    ("perimeter", regular),
    ("product", lambda n: random_values(n, n)),
]


@pytest.mark.parametrize("n", [3, 4, 5, 6, 8, 11])
@pytest.mark.parametrize("weight,make", INPUTS, ids=["perimeter", "product"])
def test_memo_counts_equal_formulas_and_stats(n, weight, make):
    t = trace(make(n), weight, method="memo")
    c, s = t.counts(), t.stats
    assert c["candidate"] == math.comb(n, 3) == s["weight_evaluations"]  # Eq. 6
    assert c["store"] == cells(n) == s["cells"]  # Eq. 7
    assert c["call"] == 2 * math.comb(n, 3) + 1 == s["requests"] + 1  # two per candidate, root
    # every call not computed is a side read or a hit; each computed cell reads two sides
    assert c["side"] + c["hit"] == s["lookups"] == c["call"] - c["store"]
    assert c["side"] == 2 * cells(n)
    assert c["hit"] == 2 * math.comb(n, 3) + 1 - 3 * cells(n)  # the grey leaves of Figure 3
    assert c["hit"] == sum(node.status == "hit" for node in t.recursion_tree().walk())
    assert len(t.events) == sum(c.values())


@pytest.mark.parametrize("n", [3, 4, 5, 7, 10])
@pytest.mark.parametrize("weight,make", INPUTS, ids=["perimeter", "product"])
def test_table_counts_equal_formulas_and_stats(n, weight, make):
    t = trace(make(n), weight, method="table")
    c, s = t.counts(), t.stats
    assert c["call"] == 0  # nothing recurses
    assert c["candidate"] == math.comb(n, 3) == s["weight_evaluations"]
    assert c["store"] == cells(n) == s["cells"]
    assert c["side"] + c["hit"] == 2 * math.comb(n, 3) == s["lookups"]  # every input read
    assert c["side"] == 2 * cells(n)


@pytest.mark.parametrize("n", [3, 4, 5, 6, 8, 10])
@pytest.mark.parametrize("weight,make", INPUTS, ids=["perimeter", "product"])
def test_naive_counts_follow_the_naive_recursion(n, weight, make):
    t = trace(make(n), weight, method="naive")
    c, s = t.counts(), t.stats
    calls, candidates, stores = naive_counts(n)
    assert c["call"] == calls == naive_calls(n) == 3 ** (n - 2) == s["requests"] + 1
    assert c["candidate"] == candidates == s["weight_evaluations"]
    assert c["store"] == stores == s["cells"]
    assert c["hit"] == 0 == c["side"] == s["lookups"]
    if n >= 5:  # from the pentagon on, the naive recursion repeats work memo saves
        assert c["candidate"] > math.comb(n, 3) and c["store"] > cells(n)


def test_naive_recurrence_closed_form():
    assert [naive_counts(n)[0] for n in range(3, 12)] == [3 ** (n - 2) for n in range(3, 12)]


@settings(max_examples=25, deadline=None)
@given(poly=convex_polygons(3, 9), method=st.sampled_from(["memo", "table", "naive"]))
def test_last_store_is_the_optimum(poly, method):
    t = trace(poly, "perimeter", method=method)
    last = t.events[-1]
    assert (last.kind, last.i, last.j) == ("store", 0, t.n - 1)
    oracle = optri.triangulate(poly, "perimeter", method="brute")
    assert last.value == pytest.approx(oracle.weight, rel=1e-12)
    assert last.value == t.result.weight
    t.result.check()


@settings(max_examples=25, deadline=None)
@given(values=value_sequences(3, 9))
def test_events_replay_the_recurrence_exactly(values):
    """Every candidate is cost(i,k) + cost(k,j) + p_i p_k p_j; every store the first best."""
    t = trace(values, "product", method="memo")
    p = [float(v) for v in values]
    stored, tried, hits = {}, {}, 0
    for e in t.events:
        if e.kind == "candidate":
            a = stored.get((e.i, e.k), 0.0) if e.k - e.i > 1 else 0.0
            b = stored.get((e.k, e.j), 0.0) if e.j - e.k > 1 else 0.0
            assert (e.i, e.k) in stored or e.k - e.i == 1  # inputs computed first
            assert (e.k, e.j) in stored or e.j - e.k == 1
            assert e.value == a + b + p[e.i] * p[e.k] * p[e.j]
            tried.setdefault((e.i, e.j), []).append((e.value, e.k))
        elif e.kind == "store":
            assert (e.i, e.j) not in stored  # memo stores each cell once
            best = min(tried[(e.i, e.j)])  # smallest value, then smallest k
            assert (e.value, e.k) == best
            assert [k for _, k in tried[(e.i, e.j)]] == list(range(e.i + 1, e.j))
            stored[(e.i, e.j)] = e.value
        elif e.kind in ("hit", "side"):
            hits += e.kind == "hit"
            assert (e.kind == "side") == (e.j - e.i == 1)  # a side read is never a hit
            expected = 0.0 if e.j - e.i == 1 else stored[(e.i, e.j)]
            assert e.value == expected  # a hit returns what was stored before
    assert hits == t.counts()["hit"]
    assert stored[(0, t.n - 1)] == optri.triangulate(values, "product", method="brute").weight


def test_table_stores_shortest_chords_first():
    t = trace(regular(8), method="table")
    spans = [e.j - e.i for e in t.events if e.kind == "store"]
    assert spans == sorted(spans) and spans[0] == 2 and spans[-1] == 7


def test_memo_follows_algorithm_3_1_on_the_pentagon():
    t = trace([5, 1, 5, 1, 5], "product")
    # the first requests: OPT(0,4) -> OPT(0,1) (a side, preset) -> OPT(1,4) -> OPT(1,2) ...
    assert [(e.kind, e.i, e.j) for e in t.events[:5]] == [
        ("call", 0, 4),
        ("call", 0, 1),
        ("side", 0, 1),
        ("call", 1, 4),
        ("call", 1, 2),
    ]
    # the root's three candidates are the paper's Step 4: 35, 175, 35; k = 1 kept (first best)
    root = [(e.k, e.value) for e in t.events if e.kind == "candidate" and (e.i, e.j) == (0, 4)]
    assert root == [(1, 35.0), (2, 175.0), (3, 35.0)]
    assert t.events[-1] == ("store", 0, 4, 1, 35.0)
    assert t.splits()[(0, 4)] == 1


def test_simple_polygon_counts_equal_stats_not_formulas():
    # a concave hexagon: fewer usable chords, so fewer candidates than C(6, 3)
    poly = [[0, 0], [4, 0], [4, 4], [2, 1], [0, 4], [-1, 2]]
    for method in ("memo", "table", "naive"):
        t = trace(poly, method=method)
        c, s = t.counts(), t.stats
        assert c["candidate"] == s["weight_evaluations"] < math.comb(6, 3)
        assert c["store"] == s["cells"]
        assert t.events[-1].value == pytest.approx(optri.triangulate(poly, method="brute").weight)


def test_clockwise_polygon_is_traced_counter_clockwise():
    ccw = regular(6)
    cw = ccw[::-1]
    t = trace(cw)
    assert t.result.orientation == "cw"
    assert np.allclose(t.vertices, cw[t.order])  # event indices refer to t.vertices
    assert t.events[-1].value == pytest.approx(trace(ccw).events[-1].value)


def test_max_objective_counts_and_optimum():
    t = trace(regular(7), "max_angle", "max", method="memo")
    assert t.counts()["candidate"] == math.comb(7, 3)
    assert t.events[-1].value == pytest.approx(
        optri.triangulate(regular(7), "max_angle", "max", method="brute").weight
    )


def test_trace_refuses_what_it_cannot_record(monkeypatch):
    with pytest.raises(optri.EngineUnavailableError, match="memo"):
        trace(regular(5), method="fast")
    with pytest.raises(optri.EngineUnavailableError, match="NAIVE_MAX_N"):
        trace(regular(config.NAIVE_MAX_N + 1), method="naive")
    with pytest.raises(optri.EngineUnavailableError, match="two passes"):
        trace(regular(5), ("max_angle", "perimeter"), ("max", "sum"))
    monkeypatch.setattr(config, "TRACE_MAX_N", 6)
    with pytest.raises(optri.TableTooLargeError, match="TRACE_MAX_N"):
        trace(regular(7))
    monkeypatch.setattr(config, "NAIVE_MAX_N", 4)
    with pytest.raises(optri.EngineUnavailableError, match="n <= 4"):
        optri.triangulate(regular(5), method="naive")


def test_naive_engine_solves_like_the_others():
    values = [3, 7, 4, 5, 2, 6]
    assert (
        optri.triangulate(values, "product", method="naive").weight
        == optri.triangulate(values, "product", method="brute").weight
    )


def test_recording_changes_nothing():
    poly = regular(9)
    plain = optri.triangulate(poly, method="memo")
    t = trace(poly, method="memo")
    assert t.result.weight == plain.weight
    assert np.array_equal(t.result.triangles, plain.triangles)
    assert t.stats == plain.stats
    assert np.array_equal(t.result.table, plain.table)


def test_repr_names_the_counts():
    r = repr(trace([5, 1, 5, 1, 5], "product"))
    assert (
        "calls=21" in r
        and "sides=12" in r
        and "hits=3" in r
        and "candidates=10" in r
        and "stores=6" in r
    )
