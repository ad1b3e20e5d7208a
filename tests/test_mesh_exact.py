"""The exact Liepa search: same optimum as the textbook search, pruned or chunked; limits."""

from __future__ import annotations

import math
import tracemalloc

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import optri
from holes_naive import exact_liepa as naive_exact
from optri.engines.brute import all_index_triangulations
from optri.errors import NoTriangulationError, TableTooLargeError
from optri.holes import fill_polyline, liepa_objective, search
from optri.holes.liepa import power_of_two_scale, with_third_points


@st.composite
def holes(draw, min_n=3, max_n=10):
    """A wavy closed 3-D polyline, maybe third points, maybe forbidden chords."""
    n = draw(st.integers(min_n, max_n))
    rng = np.random.default_rng(draw(st.integers(0, 2**31 - 1)))
    ang = np.sort(rng.uniform(0, 2 * np.pi, n)) + np.arange(n) * 1e-3
    pts = np.column_stack((np.cos(ang), np.sin(ang), rng.normal(0, 0.5, n)))
    third = None
    if draw(st.booleans()):
        mid = (pts + np.roll(pts, -1, axis=0)) / 2
        third = 1.6 * mid + rng.normal(0, 0.3, (n, 3))
    chords = [(i, j) for i in range(n) for j in range(i + 2, n) if (i, j) != (0, n - 1)]
    share = draw(st.sampled_from([0.0, 0.2, 0.5]))
    forbidden = [c for c in chords if rng.random() < share]
    return pts, third, forbidden


def _inputs(pts, third, forbidden):
    n = len(pts)
    Q, has_third = with_third_points(pts, third)
    allowed = np.ones((n, n), dtype=bool)
    for a, b in forbidden:
        allowed[a, b] = allowed[b, a] = False
    return power_of_two_scale(Q)[0], n, has_third, allowed


@settings(max_examples=40, deadline=None)
@given(holes())
def test_exact_equals_the_textbook_search(case):
    pts, third, forbidden = case
    Q, n, has_third, allowed = _inputs(pts, third, forbidden)
    want = naive_exact(Q, n, has_third, allowed)
    if want is None:
        with pytest.raises(NoTriangulationError, match="forbidden"):
            fill_polyline(pts, "liepa", "exact", third, forbidden=forbidden or None)
        return
    got = fill_polyline(pts, "liepa", "exact", third, forbidden=forbidden or None)
    got.check()
    assert got.triangles.tolist() == want[2].tolist()  # the same patch, ties included
    assert got.weight == liepa_objective(pts, want[2], third)


@settings(max_examples=25, deadline=None)
@given(holes(max_n=8))
def test_forbidden_chords_never_used_and_optimum_over_the_rest(case):
    pts, third, forbidden = case
    bad = {frozenset(c) for c in forbidden}
    allowed = [
        t
        for t in all_index_triangulations(len(pts))
        if not any(frozenset(e) in bad for tri in t for e in (tri[:2], tri[1:], tri[::2]))
    ]
    assume(allowed)
    best = min(liepa_objective(pts, np.array(t), third) for t in allowed)
    for method in ("exact", "liepa", "delaunay"):
        got = fill_polyline(pts, "liepa", method, third, forbidden=forbidden or None)
        edges = {
            frozenset(e) for tri in got.triangles.tolist() for e in (tri[:2], tri[1:], tri[::2])
        }
        assert not edges & bad
        if method == "exact":
            assert got.weight[0] == best[0]
            assert math.isclose(got.weight[1], best[1], rel_tol=1e-9)


@settings(max_examples=20, deadline=None)
@given(holes(min_n=5, max_n=12))
def test_bound_and_chunks_change_nothing(case):
    pts, third, forbidden = case
    Q, n, has_third, allowed = _inputs(pts, third, forbidden)
    plain = search.exact_search(Q, n, has_third, allowed)  # no bound
    liepa = search.liepa_dense(Q, n, has_third, allowed)
    assume(plain is not None and liepa is not None)
    from optri.holes.liepa import liepa_keys

    bound = liepa_keys(Q, n, has_third, liepa)[0]
    optri.config.HOLES_CHUNK_WORK = 1  # one chord length per kernel call
    try:
        bounded = search.exact_search(Q, n, has_third, allowed, bound)
    finally:
        optri.config.reset()
    assert bounded is not None
    assert sorted(map(tuple, bounded.tolist())) == sorted(map(tuple, plain.tolist()))


def test_memory_is_checked_before_anything_is_allocated(monkeypatch):
    ang = np.linspace(0, 2 * np.pi, 1000, endpoint=False)
    loop = np.column_stack((np.cos(ang), np.sin(ang), 0.1 * np.sin(5 * ang)))
    monkeypatch.setattr(optri.config, "MEMORY_LIMIT_BYTES", 10**9)
    tracemalloc.start()
    try:
        with pytest.raises(TableTooLargeError, match=r"exact Liepa search of a 1000-vertex.*MB"):
            fill_polyline(loop, "liepa", "exact")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert search.exact_bytes(1000) > 10**9
    assert peak < 50 * 10**6  # refused before its 2.7 GB (or Liepa's 45 MB) were taken


def test_exact_memory_is_about_eight_thirds_n_cubed():
    for n in (50, 400, 1000):
        assert search.exact_bytes(n) < 8 * n**3 / 3 + 30 * n * n
    assert search.exact_bytes(1000) < 3e9  # the old layout took 10 bytes per n^3: 10 GB


def test_core_kernels_check_their_arrays():
    from optri._core import holes as core

    Q = np.eye(3)
    allowed = np.ones((3, 3), dtype=bool)
    K = np.full((3, 3), -1, dtype=np.int32)
    MN = np.zeros((1, 4))
    with pytest.raises(ValueError, match=r"T must be \(n, 5, n\)"):
        core.dense_rows(Q, 3, False, MN, allowed, np.zeros((3, 5, 2)), K, 0, 0)
    with pytest.raises(TypeError):  # an output in another layout is refused, not copied
        core.dense_rows(Q, 3, False, MN, allowed, np.zeros((3, 3, 5)).transpose(0, 2, 1), K, 0, 0)
    with pytest.raises(ValueError, match="rows"):
        core.dense_rows(Q, 3, False, MN, allowed, np.zeros((3, 5, 3)), K, 1, 0)
    off = core.state_offsets(5)
    with pytest.raises(ValueError, match="state_count"):
        core.bottleneck_lengths(
            np.eye(5, 3), 5, False, MN, np.zeros((5, 5)), np.ones((5, 5), bool), off,
            np.zeros(8), np.inf, 2, 5,
        )  # fmt: skip
    with pytest.raises(ValueError, match="triangle index"):
        core.triangle_normals(Q, np.array([[0, 1, 3]]))
