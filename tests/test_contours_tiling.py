"""tile_contours: the compiled search against its Python twin and against brute force."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import optri
from optri import _core
from optri.contours import tile_contours
from optri.contours._reference import tile_reference
from optri.contours.tiling import weight_tables
from optri.errors import InvalidParameterError, InvalidPolygonError, WeightError


def ring(k: int, seed: int, z: float = 0.0, shift=(0.0, 0.0), scale=(1.0, 1.0)) -> np.ndarray:
    """A star-shaped contour: k jittered angles, counter-clockwise, on plane z."""
    rng = np.random.default_rng(seed)
    ang = 2 * np.pi * (np.arange(k) + 0.8 * rng.random(k)) / k
    r = 1.0 + 0.4 * rng.random(k)
    return np.c_[
        shift[0] + scale[0] * r * np.cos(ang), shift[1] + scale[1] * r * np.sin(ang), np.full(k, z)
    ]


def brute_force(wp: np.ndarray, wq: np.ndarray, is_max: bool) -> float:
    """Best over every valid tiling: every first span (i0, j0), every monotone path,
    keeping the paths that visit no span twice (a span twice is a fan: not a band)."""
    m, n = wp.shape
    best = math.inf
    for i0, j0 in itertools.product(range(m), range(n)):
        for qs in itertools.combinations(range(m + n), n):
            steps = set(qs)
            i, j, seen, terms, ok = i0, j0, {(i0, j0)}, [], True
            for s in range(m + n):
                if s in steps:
                    terms.append(wq[i % m, j % n])
                    j += 1
                else:
                    terms.append(wp[i % m, j % n])
                    i += 1
                node = (i % m, j % n)
                if s < m + n - 1 and node in seen:
                    ok = False
                    break
                seen.add(node)
            if ok:
                best = min(best, max(terms) if is_max else math.fsum(terms))
    return best


def perimeter3(p, q, r) -> float:
    return float(np.linalg.norm(p - q) + np.linalg.norm(q - r) + np.linalg.norm(r - p))


WEIGHTS = ["area", "span", "span_squared", perimeter3]


@pytest.mark.parametrize("seed", range(40))
def test_kernel_equals_reference_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    m, n = (int(x) for x in rng.integers(1, 14, 2))
    wp, wq = rng.random((m, n)), rng.random((m, n))
    if seed % 5 == 1:  # forbidden triangles
        wp[rng.random((m, n)) < 0.3] = np.inf
    if seed % 3 == 0:  # many ties
        wp, wq = np.round(wp * 3), np.round(wq * 3)
    for is_max in (False, True):
        for start in (-1, int(rng.integers(0, n))):
            got = _core.contours.tile(wp, wq, is_max, start)
            assert got == tile_reference(wp, wq, is_max, start)


def test_no_tiling_of_a_single_vertex():
    w = np.ones((1, 4))
    assert _core.contours.tile(w, w, False) == (math.inf, -1, b"") == tile_reference(w, w, False)
    with pytest.raises(WeightError):
        tile_contours(ring(4, 0), ring(5, 1, z=1), lambda p, q, r: math.inf)


@pytest.mark.parametrize("seed", range(12))
def test_optimal_over_every_tiling(seed):
    """Every valid tiling enumerated (m, n <= 6): the search finds the least weight."""
    rng = np.random.default_rng(100 + seed)
    m, n = (int(x) for x in rng.integers(3, 7, 2))
    a = ring(m, seed)
    b = ring(
        n, seed + 1000, z=float(rng.uniform(0.2, 2)), shift=rng.normal(size=2), scale=(1.4, 0.7)
    )
    for weight in WEIGHTS:
        wp, wq = weight_tables(a, b, weight)
        for objective in ("sum", "max"):
            t = tile_contours(a, b, weight, objective)
            t.check()
            assert math.isclose(t.weight, brute_force(wp, wq, objective == "max"), rel_tol=1e-12)


@pytest.mark.parametrize("seed", range(8))
def test_integer_weights_are_exact(seed):
    """Integer coordinates and squared spans: every sum is exact, so equality is exact."""
    rng = np.random.default_rng(seed)
    m, n = (int(x) for x in rng.integers(3, 7, 2))
    a = np.c_[np.round(ring(m, seed)[:, :2] * 20), np.zeros(m)]
    b = np.c_[np.round(ring(n, seed + 7)[:, :2] * 20), np.full(n, 5.0)]
    wp, wq = weight_tables(a, b, "span_squared")
    assert tile_contours(a, b, "span_squared").weight == brute_force(wp, wq, False)


def test_unit_squares_band():
    sq = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    t = optri.tile_contours(sq, sq + [0, 0, 1])
    assert t.weight == 4.0 and t.triangles.shape == (8, 3)
    t.check()
    # outward normals: a (below) and b (above) counter-clockwise
    v = t.vertices
    for tri in t.triangles:
        nrm = np.cross(v[tri[1]] - v[tri[0]], v[tri[2]] - v[tri[0]])
        centre = v[tri].mean(axis=0)
        assert nrm[:2] @ (centre[:2] - 0.5) > 0


def test_fan_is_never_returned():
    """A tiny triangle under a large contour: the fan from one vertex (one span in four
    triangles) is cheaper in area but is no band."""
    small = np.array([[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]])
    big = ring(12, 3, z=0.01, scale=(5, 5))
    for objective in ("sum", "max"):
        t = tile_contours(small, big, "area", objective)
        t.check()
        assert len(t.spans()) == 15


def test_opposite_senses_are_aligned():
    a, b = ring(7, 1), ring(9, 2, z=1.0)
    same = tile_contours(a, b)
    flipped = tile_contours(a, b[::-1])
    flipped.check()
    assert math.isclose(same.weight, flipped.weight, rel_tol=1e-12)
    twisted = tile_contours(a, b[::-1], align=False)
    assert twisted.weight > same.weight


@settings(max_examples=40, deadline=None)
@given(
    m=st.integers(3, 30),
    n=st.integers(3, 30),
    seed=st.integers(0, 2**31),
    weight=st.sampled_from(["area", "span", "span_squared"]),
    objective=st.sampled_from(["sum", "max"]),
)
def test_properties(m, n, seed, weight, objective):
    """Valid band; never worse than the closest-point start; the optimum does not
    depend on where either contour's numbering begins."""
    rng = np.random.default_rng(seed)
    a = ring(m, seed)
    b = ring(n, seed + 1, z=1.0, shift=rng.normal(scale=0.5, size=2))
    best = tile_contours(a, b, weight, objective)
    best.check()
    closest = tile_contours(a, b, weight, objective, start="closest")
    closest.check()
    assert best.weight <= closest.weight * (1 + 1e-12)
    k = int(rng.integers(0, m))
    rolled = tile_contours(np.roll(a, k, axis=0), b, weight, objective)
    assert math.isclose(rolled.weight, best.weight, rel_tol=1e-9)


def test_closest_start_is_the_closest_pair():
    a = ring(8, 4)
    b = ring(6, 5, z=0.5, shift=(0.3, 0.1))
    t = tile_contours(a, b, start="closest")
    d = ((a[:, None] - b[None]) ** 2).sum(axis=2)
    i, j = np.unravel_index(np.argmin(d), d.shape)
    assert t.start == (i, j) and t.method == "closest"


@pytest.mark.parametrize(
    ("a", "error"),
    [
        ([[0, 0, 0], [1, 0, 0]], InvalidPolygonError),
        ([[0, 0, 0], [1, 0, 0], [1, 0, 0], [0, 1, 0]], InvalidPolygonError),
        ([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], InvalidPolygonError),
        ([[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]], InvalidPolygonError),
        ("abc", InvalidPolygonError),
    ],
)
def test_bad_contours(a, error):
    with pytest.raises(error):
        tile_contours(a, ring(4, 0, z=1))


def test_bad_parameters():
    a, b = ring(4, 0), ring(5, 1, z=1)
    with pytest.raises(WeightError):
        tile_contours(a, b, "perimeter")
    with pytest.raises(InvalidParameterError):
        tile_contours(a, b, objective="mean")
    with pytest.raises(InvalidParameterError):
        tile_contours(a, b, start="first")
    with pytest.raises(WeightError):
        tile_contours(a, b, lambda p, q, r: float("nan"))


def test_check_catches_a_broken_band():
    t = tile_contours(ring(5, 0), ring(5, 1, z=1))
    t.triangles = t.triangles[:-1]
    with pytest.raises(AssertionError):
        t.check()
    t = tile_contours(ring(5, 0), ring(5, 1, z=1))
    t.weight *= 1.01
    with pytest.raises(AssertionError):
        t.check()
