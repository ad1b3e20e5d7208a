"""Uniform sampling of triangulations: each split drawn in proportion to its count."""

from __future__ import annotations

import random
from typing import Any

from ..engines.recurrence import split_points, triangles_from_splits
from ..errors import InvalidPolygonError, check_seed
from ..objective import ObjectiveLike
from ..result import Triangulation
from .builder import PolygonOrN, TriangulationBuilder, as_enumerable, usable_chords
from .counting import catalan, count_table, require_count_memory

__all__ = ["random_triangulation"]


def random_triangulation(
    vertices_or_n: PolygonOrN,
    seed: int | random.Random | None = None,
    weight: Any = None,
    objective: ObjectiveLike = "sum",
) -> Triangulation:
    """One triangulation drawn uniformly at random among all of them.

    Chord (i, j) splits at k with probability count(i, k) count(k, j) / count(i, j),
    so every triangulation has probability 1 / count(0, n-1).

    Parameters
    ----------
    vertices_or_n : int or array_like
    seed : int or random.Random, optional
    weight, objective :
        As in :func:`enumerate_triangulations`.

    Notes
    -----
    Exact big-int arithmetic: O(n^2) for a convex polygon, O(n^3) for a mask.

    Examples
    --------
    >>> t = random_triangulation(10, seed=1)
    >>> t.check(); len(t.diagonals)
    7
    """
    rng = check_seed(seed)
    polygon = as_enumerable(vertices_or_n)
    n = polygon.n
    if not (polygon.convex or polygon.is_values):
        require_count_memory(n, "uniform sampling")
    ok = usable_chords(polygon)
    if ok is None:
        cat = [catalan(m) for m in range(n)]

        def cnt(i: int, j: int) -> int:
            return cat[j - i - 1]
    else:
        table = count_table(ok)
        if table[0][n - 1] == 0:
            raise InvalidPolygonError("the polygon has no triangulation with its allowed chords")

        def cnt(i: int, j: int) -> int:
            return table[i][j]

    def pick(i: int, j: int) -> int:
        r = rng.randrange(cnt(i, j))
        for k in split_points(i, j, ok):
            r -= cnt(i, k) * cnt(k, j)
            if r < 0:
                return k
        raise AssertionError("unreachable: the split weights add up to count(i, j)")

    tris = triangles_from_splits(pick, n).tolist()
    return TriangulationBuilder(polygon, weight, objective, "random")(tris)
