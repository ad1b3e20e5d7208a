import math
import random

import numpy as np
import pytest

import optri
from optri.enumeration import catalan, regular_polygon


def test_catalan_closed_form_big():
    c38 = optri.count_triangulations(40)
    assert isinstance(c38, int)
    # C(38) = 176,733,862,787,006,701,400 (the guess 1.697e21 was off)
    assert c38 == math.comb(76, 38) // 39 == 176733862787006701400
    assert optri.count_triangulations(1000) == math.comb(1996, 998) // 999


@pytest.mark.parametrize("n", [3, 4, 5, 10, 16])
def test_count_of_polygon_equals_count_of_n(n):
    assert optri.count_triangulations(regular_polygon(n)) == catalan(n - 2)


def test_count_rejects_too_few():
    with pytest.raises(optri.InvalidPolygonError):
        optri.count_triangulations(2)


def test_count_dp_over_mask(monkeypatch):
    import optri.enumeration.builder

    n = 7
    rng = np.random.default_rng(3)
    mask = rng.random((n, n)) < 0.6
    mask = mask | mask.T
    monkeypatch.setattr(optri.enumeration.builder, "allowed_chords", lambda polygon: mask)
    from optri.engines.brute import all_index_triangulations
    from optri.enumeration.builder import usable_chords

    poly = optri.as_polygon(regular_polygon(n))
    expected = sum(1 for _ in all_index_triangulations(n, usable_chords(poly)))
    assert optri.count_triangulations(regular_polygon(n)) == expected


def test_uniform_sampler_chi_square():
    scipy_stats = pytest.importorskip("scipy.stats")
    keys = [
        tuple(sorted(map(tuple, t.triangles.tolist()))) for t in optri.enumerate_triangulations(6)
    ]
    index = {k: i for i, k in enumerate(keys)}
    rng = random.Random(12345)
    draws = 2800
    counts = [0] * len(keys)
    for _ in range(draws):
        t = optri.random_triangulation(6, seed=rng)
        counts[index[tuple(sorted(map(tuple, t.triangles.tolist())))]] += 1
    assert len(counts) == 14 and all(c > 0 for c in counts)
    p = scipy_stats.chisquare(counts).pvalue
    assert p > 0.001


def test_sampler_is_seeded_and_valid():
    a = optri.random_triangulation(30, seed=7, weight="perimeter")
    b = optri.random_triangulation(30, seed=7, weight="perimeter")
    assert a.triangles.tolist() == b.triangles.tolist()
    assert a.method == "random"
    a.check()


def test_sampler_rejects_biased_split():
    # A sampler picking k uniformly would favour fans; at n = 5 each of the 5 is 1/5.
    rng = random.Random(1)
    fan0 = sum(
        optri.random_triangulation(5, seed=rng).diagonals.tolist() == [[0, 2], [0, 3]]
        for _ in range(5000)
    )
    assert 850 < fan0 < 1150


def test_non_convex_polygon_uses_valid_diagonals():
    pytest.importorskip("optri.simple")  # the simple-polygon support supplies the mask
    poly = [[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [4, 3], [4, 4], [0, 4]]
    items = list(optri.enumerate_triangulations(poly, "perimeter"))
    assert len(items) == optri.count_triangulations(poly) == 8
    for t in items:
        t.check()
    best = optri.triangulate(poly, "perimeter", method="memo").weight
    assert math.isclose(min(t.weight for t in items), best)
    kbest = [t.weight for t in optri.best_triangulations(poly, "perimeter", k=20)]
    assert all(math.isclose(a, b) for a, b in zip(kbest, sorted(t.weight for t in items)))
    optri.random_triangulation(poly, seed=0).check()
