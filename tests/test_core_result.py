"""Triangulation.check() raises on each kind of broken triangulation, and names it."""

from dataclasses import replace

import numpy as np
import pytest

import optri
from optri.result import chords_cross_free

PENTAGON = [[0, 0], [4, 0], [5, 3], [2, 5], [-1, 3]]  # convex, counter-clockwise


@pytest.fixture
def good():
    t = optri.triangulate(PENTAGON, method="memo")
    t.check()  # the unbroken result passes
    return t


def _broken(t, triangles, **changes):
    return replace(t, triangles=np.array(triangles, dtype=np.int64).reshape(-1, 3), **changes)


@pytest.mark.parametrize(
    "triangles, message",
    [
        # diagonals (0, 2) and (1, 3) cross
        ([[0, 1, 2], [1, 2, 3], [0, 3, 4]], "two diagonals cross"),
        # a triangle twice (and one missing): side (0, 1) in two triangles
        ([[0, 1, 2], [0, 1, 2], [0, 3, 4]], r"edge \(0, 1\) used 2 times"),
        # a valid triangulation with one triangle wound clockwise
        ([[0, 2, 1], [0, 2, 3], [0, 3, 4]], "a triangle is clockwise"),
        ([[0, 1, 2], [0, 2, 3]], "expected 3 triangles"),
        ([[0, 1, 2], [0, 2, 3], [0, 3, 5]], "out of range"),
        ([[0, 1, 2], [0, 2, 2], [0, 3, 4]], "degenerate"),
    ],
)
def test_check_names_the_fault(good, triangles, message):
    with pytest.raises(AssertionError, match=message):
        _broken(good, triangles).check()


def test_check_recomputes_the_cost(good):
    with pytest.raises(AssertionError, match="recomputed"):
        replace(good, weight=good.weight * (1 + 1e-6)).check()
    replace(good, weight=good.weight * (1 + 1e-12)).check()  # within rtol


def test_crossing_found_without_geometry():
    # vertex values have no areas to check: only the index test can see the crossing
    t = optri.triangulate([1, 2, 3, 4, 5], "product", method="memo")
    t.check()
    with pytest.raises(AssertionError, match="two diagonals cross"):
        _broken(t, [[0, 1, 2], [1, 2, 3], [0, 3, 4]]).check()


@pytest.mark.parametrize(
    "chords, expected",
    [
        ([[0, 2], [1, 3]], False),  # interleaved ends: a crossing
        ([[0, 3], [1, 2]], True),  # nested
        ([[0, 2], [2, 4]], True),  # sharing an end
        ([[0, 2], [0, 3], [0, 4]], True),  # a fan
        ([[1, 4], [0, 2]], False),
        ([[0, 5], [1, 3], [2, 4]], False),  # the crossing pair inside an outer chord
    ],
)
def test_chords_cross_free(chords, expected):
    assert chords_cross_free(np.array(chords, dtype=np.int64)) is expected
