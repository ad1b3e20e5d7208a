"""Every triangulation of a polygon, lazily: the Hurtado–Noy tree, or the recurrence over a mask.

Convex polygons are enumerated along the Hurtado–Noy tree
(:mod:`optri.enumeration.hurtado_noy`). A polygon with a restricted set of
usable chords (a simple, non-convex polygon) is enumerated by the recursion
over its splits instead (:func:`optri.engines.brute.all_index_triangulations`).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from ..engines.recurrence import split_points
from ..objective import ObjectiveLike
from ..polygon import Polygon
from ..result import Triangulation
from .builder import PolygonOrN, TriangulationBuilder, as_enumerable, usable_chords
from .hurtado_noy import hn_index_triangulations

__all__ = ["enumerate_triangulations", "index_triangulations"]


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
    for tris in chord_triangulations(polygon.n, ok):
        yield [list(t) for t in tris]


def chord_triangulations(n: int, ok: list[list[bool]]) -> Iterator[list[tuple[int, int, int]]]:
    """Every triangulation of polygon ``0..n-1`` whose chords ``ok`` allows, without recursion.

    The order of the recursive enumeration (the root's split slowest, then the
    left part's choices, then the right's), by backtracking over an explicit
    stack: a polygon of any size, a 6,000-vertex star included, lists its first
    triangulations at once. Triangles in preorder, ``(i, k, j)`` with ``i < k < j``.

    >>> import itertools
    >>> list(itertools.islice(chord_triangulations(5, [[True] * 5] * 5), 2))
    [[(0, 1, 4), (1, 2, 4), (2, 3, 4)], [(0, 1, 4), (1, 3, 4), (1, 2, 3)]]
    """
    todo = [(0, n - 1)] if n >= 3 else []  # intervals still to split (width >= 2 only)
    tris: list[tuple[int, int, int]] = []
    frames: list[list[Any]] = []  # [i, j, split points, choice, intervals pushed]
    while True:
        if todo:
            i, j = todo.pop()
            frames.append([i, j, list(split_points(i, j, ok)), -1, 0])
        else:
            yield list(tris)
        while frames:  # the top frame takes its next split, or gives its interval back
            frame = frames[-1]
            i, j, splits, choice, pushed = frame
            if choice >= 0:
                tris.pop()
                del todo[len(todo) - pushed :]
            frame[3] = choice = choice + 1
            if choice < len(splits):
                k = splits[choice]
                tris.append((i, k, j))
                parts = [p for p in ((k, j), (i, k)) if p[1] - p[0] >= 2]
                todo.extend(parts)  # the left part on top: done first
                frame[4] = len(parts)
                break
            frames.pop()
            todo.append((i, j))
        else:
            return


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
    (5, [35, 35, 75, 75, 175])
    """
    polygon = as_enumerable(vertices_or_n)
    build = TriangulationBuilder(polygon, weight, objective, "enumerate")
    for tris in index_triangulations(polygon):
        yield build(tris)
