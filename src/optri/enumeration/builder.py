"""Inputs and results of the enumeration: polygons or n in, :class:`Triangulation` out.

Shared by the enumeration, the uniform sampler and the k-best search: one
weight evaluator per polygon, triangle weights cached (an enumeration asks for
the same few C(n, 3) triangles millions of times).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..engines.problem import Problem, chord_rows
from ..errors import InvalidPolygonError
from ..objective import Cost, ObjectiveLike, as_objective
from ..polygon import Polygon, as_polygon
from ..result import Triangulation, recompute_cost
from ..simple import allowed_chords
from ..solve import PolygonLike, load_polygon
from ..weights import resolve_weights

__all__ = [
    "PolygonOrN",
    "TriangulationBuilder",
    "as_enumerable",
    "regular_polygon",
    "usable_chords",
]

PolygonOrN = PolygonLike | int


def usable_chords(polygon: Polygon) -> list[list[bool]] | None:
    """``ok[i][j]``: may chord (i, j) be used (sides always)? None: all (convex).

    Reads :func:`optri.simple.allowed_chords`, the one place that decides.
    """
    mask = allowed_chords(polygon)
    return None if mask is None else chord_rows(mask)


class TriangulationBuilder:
    """``builder(triangles) -> Triangulation`` for one polygon, weight and objective.

    Parameters
    ----------
    polygon : Polygon
    weight : str, callable or None
        None: results carry ``weight = nan`` and no cost check.
    objective : {"sum", "max"} or pair
    method : str
        Recorded as ``Triangulation.method``.
    """

    def __init__(self, polygon: Polygon, weight: Any, objective: ObjectiveLike, method: str):
        self.polygon = polygon
        self.method = method
        self.objective = as_objective(objective)
        self.order = polygon.order
        self._cache: dict[tuple[int, int, int], Cost] = {}
        if weight is None:
            self._w: Callable[[int, int, int], Cost] | None = None
            self._recompute = None
            self.weight_name: str | tuple[str, ...] = "none"
            return
        weights = resolve_weights(weight, len(self.objective.components))
        problem = Problem(polygon, weights, self.objective)
        self._w = problem.evaluator()
        names = tuple(w.name for w in problem.weights)
        self.weight_name = names if self.objective.is_lex else names[0]
        self._recompute = recompute_cost(self._w, self.objective, polygon.order)

    def triangle_weight(self, i: int, k: int, j: int) -> Cost:
        """w(i, k, j) over internal indices, computed once per triangle."""
        key = (i, k, j)
        v = self._cache.get(key)
        if v is None:
            assert self._w is not None
            v = self._cache[key] = self._w(i, k, j)
        return v

    def cost(self, tris: Sequence[Sequence[int]]) -> Cost:
        """Objective value of internal-index triangles (sorted ``i < k < j``)."""
        if self._w is None:
            return math.nan
        tw = self.triangle_weight
        vals = [tw(t[0], t[1], t[2]) for t in tris]
        return self.objective.finalize(self.objective.aggregate(vals))

    def __call__(self, tris: Sequence[Sequence[int]], cost: Cost | None = None) -> Triangulation:
        """A :class:`Triangulation` of ``tris`` (internal indices); cost computed if None."""
        arr = np.array(tris, dtype=np.int64).reshape(-1, 3)
        arr = arr[np.lexsort((arr[:, 2], arr[:, 1], arr[:, 0]))]
        if cost is None:
            cost = self.cost(arr.tolist())
        return Triangulation(
            vertices=self.polygon.vertices,
            triangles=self.order[arr],
            weight=cost,
            method=self.method,
            weight_name=self.weight_name,
            objective=self.objective.name,
            orientation=self.polygon.orientation,
            order=self.order,
            _recompute=self._recompute,
        )


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
    """A :class:`Polygon` from any input ``triangulate`` takes, or the regular n-gon for n."""
    if isinstance(vertices_or_n, (int, np.integer)):
        return as_polygon(regular_polygon(int(vertices_or_n)))
    return load_polygon(vertices_or_n)
