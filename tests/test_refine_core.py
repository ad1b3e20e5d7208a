"""The compiled refinement and crossing check equal their Python references bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

import optri
from optri.errors import InvalidPolygonError
from optri.holes import intersect, mesh, refine


def _disc(rng: np.random.Generator, n: int, bump: float) -> tuple[np.ndarray, np.ndarray]:
    """A bumpy star-shaped loop of ``n`` points and its fan patch from point 0."""
    th = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(0.5, 2.0, n)
    v = np.column_stack([r * np.cos(th), r * np.sin(th), rng.normal(0, bump, n)])
    return v, np.array([[0, i, i + 1] for i in range(1, n - 1)], dtype=np.int64)


@pytest.mark.parametrize("seed", range(6))
def test_compiled_refinement_equals_the_python_reference(seed):
    rng = np.random.default_rng(seed)
    blocked = 0
    for _ in range(12):
        n = int(rng.integers(3, 40))
        v, patch = _disc(rng, n, float(rng.choice([0.0, 0.05, 0.4])))
        loop = np.arange(n)
        scales = rng.uniform(0.05, 0.6, n)
        density = float(rng.choice([math.sqrt(2.0), 1.0, 3.0]))
        # chords the mesh already has: no swap may create them
        forbidden = {frozenset((i, i + 2)) for i in range(1, n - 2, 2)}
        p1: list[tuple[int, int, int]] = []
        p2: list[tuple[int, int, int]] = []
        rounds = int(rng.integers(1, 6))
        new1, f1 = refine.refine_patch(
            v, patch, loop, scales, density, rounds, forbidden=forbidden, parents=p1
        )
        new2, f2 = refine.reference_refine_patch(
            v, patch, loop, scales, density, rounds, forbidden=forbidden, parents=p2
        )
        assert new1.tobytes() == new2.tobytes() and np.array_equal(f1, f2) and p1 == p2
        assert f1.dtype == np.int64 and new1.shape == (len(p1), 3)
        free = refine.reference_refine_patch(v, patch, loop, scales, density, rounds)[1]
        blocked += not np.array_equal(free, f2)
    assert blocked > 0  # the forbidden chords did change some patch


@pytest.mark.parametrize("seed", range(4))
def test_compiled_crossings_equal_the_numpy_reference(seed):
    rng = np.random.default_rng(100 + seed)
    found = 0
    for trial in range(25):
        n = int(rng.integers(3, 200))
        v = rng.uniform(0, 1, (n, 3))
        if trial % 3 == 0:
            v = np.round(v * 4) / 4  # coplanar and touching cases
        f = rng.integers(0, n, (int(rng.integers(1, 200)), 3))
        f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
        p = np.concatenate([f[:10], rng.integers(0, n, (10, 3))])
        a = intersect.intersecting_pairs(v, f, p)
        b = intersect.reference_intersecting_pairs(v, f, p)
        assert a.dtype == np.int64 and a.shape[1:] == (2,) and np.array_equal(a, b)
        found += len(a)
    assert found > 100  # the soups do cross: the comparison is not of empty lists


def test_compiled_crossings_see_a_long_sliver_and_keep_the_callers_numbers():
    # many small faces and one face far longer than them (tested outside the grid), which
    # a patch face pierces
    rng = np.random.default_rng(7)
    corners = rng.uniform(0, 10, (100, 1, 3)) + rng.uniform(0, 0.1, (100, 3, 3))
    small = corners.reshape(-1, 3)
    sliver = [[-5.0, 5, 5], [15, 5, 5.1], [5, 5.2, 5]]
    v = np.concatenate([small, sliver, [[4, 0, 0], [6, 10, 0], [5, 5, 15]]])
    s = len(small)
    f = np.concatenate([np.arange(s).reshape(-1, 3)[:40], [[s, s + 1, s + 2]]])
    p = np.array([[s + 3, s + 4, s + 5]])
    a = intersect.intersecting_pairs(v, f, p)
    assert [0, 40] in a.tolist()
    assert np.array_equal(a, intersect.reference_intersecting_pairs(v, f, p))


def test_fill_holes_refined_and_faired_is_unchanged_by_the_compiled_kernels(monkeypatch):
    # a bumpy open cap: the fill path through the core against the references
    rng = np.random.default_rng(3)
    n = 24
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(th), np.sin(th), 0.2 * np.sin(3 * th)])
    outer = np.column_stack([1.6 * np.cos(th), 1.6 * np.sin(th), 0.1 * rng.normal(size=n)])
    v = np.concatenate([ring, outer])
    faces = []
    for i in range(n):
        j = (i + 1) % n
        faces += [[j, i, n + i], [j, n + i, n + j]]
    surface = (v, np.array(faces))
    for fair in (None, 1, 2):
        (v1, f1), r1 = optri.fill_holes(surface, refine=True, fair=fair)
        with monkeypatch.context() as m:
            m.setattr(mesh, "refine_patch", refine.reference_refine_patch)
            m.setattr(mesh, "intersecting_pairs", intersect.reference_intersecting_pairs)
            (v2, f2), r2 = optri.fill_holes(surface, refine=True, fair=fair)
        assert r1[0].vertices_added > 10
        assert v1.tobytes() == v2.tobytes() and np.array_equal(f1, f2)
        assert [(r.faired, r.self_intersections) for r in r1] == [
            (r.faired, r.self_intersections) for r in r2
        ]


def test_compiled_kernels_refuse_indices_out_of_range():
    v = np.zeros((3, 3))
    with pytest.raises(ValueError, match="vertex index"):
        refine.refine_patch(v, np.array([[0, 1, 5]]), np.arange(3), np.ones(3))
    with pytest.raises(ValueError, match="vertex index"):
        intersect.intersecting_pairs(v, np.array([[0, 1, 2]]), np.array([[0, 1, -1]]))
    with pytest.raises(InvalidPolygonError, match="density"):
        refine.refine_patch(v, np.array([[0, 1, 2]]), np.arange(3), np.ones(3), -1.0)
