import math

import numpy as np
import pytest

import optri


def _poly(n, seed):
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0, 2 * np.pi, n)) + np.linspace(0, 1e-3, n)
    return np.column_stack((np.cos(a), 0.6 * np.sin(a)))


@pytest.mark.parametrize("n", [4, 5, 6, 7, 8])
@pytest.mark.parametrize("objective", ["sum", "max"])
def test_kbest_equals_sorted_enumeration(n, objective):
    poly = _poly(n, n)
    every = sorted(t.weight for t in optri.enumerate_triangulations(poly, "perimeter", objective))
    best = optri.best_triangulations(poly, "perimeter", k=len(every) + 5, objective=objective)
    got = [t.weight for t in best]
    assert len(got) == len(every)
    assert all(a <= b + 1e-12 for a, b in zip(got, got[1:]))
    assert all(math.isclose(a, b, rel_tol=1e-9) for a, b in zip(got, every))
    assert len({tuple(map(tuple, t.triangles.tolist())) for t in best}) == len(best)
    for t in best:
        t.check()


def test_kbest_first_is_optimum_and_k_limits():
    poly = _poly(12, 0)
    best = optri.best_triangulations(poly, "diagonal", k=7)
    assert len(best) == 7
    assert math.isclose(best[0].weight, optri.triangulate(poly, "diagonal").weight)
    assert [t.weight for t in best] == sorted(t.weight for t in best)


def test_kbest_pentagon_product_ties():
    got = [t.weight for t in optri.best_triangulations([5, 1, 5, 1, 5], "product", k=10)]
    assert got == [35.0, 35.0, 75.0, 75.0, 175.0]


def test_kbest_lexicographic():
    poly = _poly(7, 11)  # irregular: a regular one ties up to rounding and reorders
    best = optri.best_triangulations(
        poly, ("max_angle", "perimeter"), k=50, objective=("max", "sum")
    )
    every = sorted(
        t.weight
        for t in optri.enumerate_triangulations(poly, ("max_angle", "perimeter"), ("max", "sum"))
    )
    assert len(best) == 42
    for a, b in zip((t.weight for t in best), every):
        assert all(math.isclose(x, y, rel_tol=1e-9) for x, y in zip(a, b))


def test_kbest_rejects_bad_k():
    with pytest.raises(ValueError):
        optri.best_triangulations(5, "perimeter", k=0)
