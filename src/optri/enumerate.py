"""All triangulations of a polygon: enumerate, count, draw uniformly at random.

Convex polygons are enumerated along the Hurtado–Noy tree
(:mod:`optri.hurtado_noy`). A polygon with a restricted set of usable chords
(``optri.solve.allowed_chords`` returns a mask for a simple, non-convex
polygon) is handled by the DP structure over that mask instead:

    count(i, j) = sum_k ok(i, k) ok(k, j) count(i, k) count(k, j),  count(i, i+1) = 1,

which for a convex polygon is the Catalan number C(j - i - 1).
"""

from __future__ import annotations

import math
import random
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .engines.brute import all_index_triangulations
from .engines.problem import triangles_from_splits
from .errors import InvalidPolygonError
from .geometry import Polygon, as_polygon
from .hurtado_noy import hn_index_triangulations
from .objective import ObjectiveLike
from .result import Triangulation
from .simple import count_table
from .triangulations import TriangulationBuilder, usable_chords

__all__ = [
    "catalan",
    "count_triangulations",
    "enumerate_triangulations",
    "index_triangulations",
    "random_triangulation",
    "regular_polygon",
]

PolygonOrN = ArrayLike | Polygon | int


def catalan(m: int) -> int:
    """The Catalan number C(m) = binom(2m, m) / (m + 1), exactly.

    >>> [catalan(m) for m in range(8)]
    [1, 1, 2, 5, 14, 42, 132, 429]
    """
    if m < 0:
        raise ValueError(f"catalan({m}) is undefined for negative m")
    return math.comb(2 * m, m) // (m + 1)


def regular_polygon(n: int) -> NDArray[np.float64]:
    """Vertices of the regular n-gon on the unit circle, counter-clockwise.

    >>> regular_polygon(4).round(6).tolist()
    [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [-0.0, -1.0]]
    """
    if n < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
    ang = 2 * np.pi * np.arange(n) / n
    return np.column_stack((np.cos(ang), np.sin(ang)))


def as_enumerable(vertices_or_n: PolygonOrN) -> Polygon:
    """A :class:`Polygon` from vertices, or the regular n-gon for an int n."""
    if isinstance(vertices_or_n, (int, np.integer)):
        return as_polygon(regular_polygon(int(vertices_or_n)))
    if isinstance(vertices_or_n, str):
        from .io import read_polygon

        return as_polygon(read_polygon(vertices_or_n))
    return as_polygon(vertices_or_n)


def count_triangulations(vertices_or_n: PolygonOrN) -> int:
    """Number of triangulations, as an exact (big) int.

    Parameters
    ----------
    vertices_or_n : int or array_like
        n for the convex n-gon, or the polygon itself.

    Returns
    -------
    int
        C(n - 2) for a convex polygon; for a polygon with restricted chords
        the DP count over the allowed-chord mask (O(n^3) big-int steps).

    Examples
    --------
    >>> count_triangulations(16)
    2674440
    >>> count_triangulations(40) == math.comb(76, 38) // 39
    True
    >>> count_triangulations([[0, 0], [1, 0], [1, 1], [0, 1]])
    2
    """
    if isinstance(vertices_or_n, (int, np.integer)):
        n = int(vertices_or_n)
        if n < 3:
            raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
        return catalan(n - 2)
    polygon = as_enumerable(vertices_or_n)
    ok = usable_chords(polygon)
    if ok is None:
        return catalan(polygon.n - 2)
    return count_table(ok)[0][polygon.n - 1]


def index_triangulations(polygon: Polygon) -> Iterator[list[list[int]]]:
    """Every triangulation as internal-index triangles ``[i, k, j]``, ``i < k < j``.

    The cheap generator under :func:`enumerate_triangulations`: Hurtado–Noy
    order for a convex polygon (the yielded list is reused; copy to keep it),
    the DP recursion over the allowed chords otherwise.
    """
    ok = usable_chords(polygon)
    if ok is None:
        yield from hn_index_triangulations(polygon.n)
        return
    for tris in all_index_triangulations(polygon.n, ok):
        yield [list(t) for t in tris]


def enumerate_triangulations(
    vertices_or_n: PolygonOrN,
    weight: Any = None,
    objective: ObjectiveLike = "sum",
) -> Iterator[Triangulation]:
    """Lazily yield every triangulation of a polygon (Hurtado–Noy order).

    Parameters
    ----------
    vertices_or_n : int or array_like
        The polygon (vertices, values, or a file path), or n for the regular
        n-gon on the unit circle.
    weight : str, callable or None
        When given, each item's ``weight`` is its cost under ``objective``;
        otherwise ``weight`` is NaN.
    objective : {"sum", "max"} or pair

    Yields
    ------
    Triangulation
        ``method == "enumerate"``; triangles in input indices.

    Notes
    -----
    O(n) state per tree level: n = 16 (2,674,440 triangulations) streams
    without holding them. Each item costs O(n) to build plus n - 2 (cached)
    triangle-weight look-ups when a weight is given.

    Examples
    --------
    >>> ts = list(enumerate_triangulations([5, 1, 5, 1, 5], weight="product"))
    >>> len(ts), sorted(t.weight for t in ts)
    (5, [35.0, 35.0, 75.0, 75.0, 175.0])
    """
    polygon = as_enumerable(vertices_or_n)
    build = TriangulationBuilder(polygon, weight, objective, "enumerate")
    for tris in index_triangulations(polygon):
        yield build(tris)


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
    polygon = as_enumerable(vertices_or_n)
    rng = seed if isinstance(seed, random.Random) else random.Random(seed)
    n = polygon.n
    ok = usable_chords(polygon)
    if ok is None:
        cat = [catalan(m) for m in range(n)]

        def cnt(i: int, j: int) -> int:
            return cat[j - i - 1]

        def usable(i: int, k: int, j: int) -> bool:
            return True
    else:
        table = count_table(ok)
        if table[0][n - 1] == 0:
            raise InvalidPolygonError("the polygon has no triangulation with its allowed chords")

        def cnt(i: int, j: int) -> int:
            return table[i][j]

        def usable(i: int, k: int, j: int) -> bool:
            return ok[i][k] and ok[k][j]

    def pick(i: int, j: int) -> int:
        r = rng.randrange(cnt(i, j))
        for k in range(i + 1, j):
            if usable(i, k, j):
                r -= cnt(i, k) * cnt(k, j)
                if r < 0:
                    return k
        raise AssertionError("unreachable: the split weights add up to count(i, j)")

    tris = triangles_from_splits(pick, n).tolist()
    return TriangulationBuilder(polygon, weight, objective, "random")(tris)
