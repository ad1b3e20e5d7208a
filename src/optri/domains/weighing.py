"""Triangle weights on a domain: the built-in formulas and custom callables, by vertex index.

Every weight of :mod:`optri.weights` that reads coordinates works: the shape
weights depend on the triangle alone; ``"diagonal"`` counts half the length of
each side that is not a boundary edge of the domain (exterior or hole), so a
triangulation's total is the length of its diagonals. A custom weight is
called with the triangle's domain indices in increasing order, as
``w(i, k, j)`` or ``w(vertices, i, k, j)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import WeightError
from ..polygon import Polygon
from ..weights import Weight, WeightCode, side_length
from .domain import Domain

__all__ = ["DomainWeight", "domain_weights", "shape_only"]

TriangleFn = Callable[[int, int, int], float]

#: Built-in weights whose value depends on the triangle's corners alone.
_SHAPE_CODES = (
    WeightCode.PERIMETER,
    WeightCode.AREA,
    WeightCode.MAX_ANGLE,
    WeightCode.MIN_ANGLE,
    WeightCode.ASPECT_RATIO,
)


def shape_only(weight: Weight) -> bool:
    """True for a built-in weight that a triangle's corners alone decide."""
    return weight.code in _SHAPE_CODES


class DomainWeight:
    """One weight bound to a domain: ``w(a, b, c)`` over domain vertex indices.

    Examples
    --------
    >>> from optri.domains import as_domain
    >>> from optri.weights import get_weight
    >>> d = as_domain([[0, 0], [4, 0], [4, 4], [0, 4]], [[[1, 1], [2, 1], [1, 2]]])
    >>> w = DomainWeight(d, get_weight("diagonal"))
    >>> round(w(0, 1, 4), 6)    # half of diagonals 0-4 and 1-4; side 0-1 counts 0
    2.288246
    >>> round(w(0, 4, 6), 6)    # half of diagonals 0-4 and 0-6; hole edge 4-6 counts 0
    1.825141
    """

    def __init__(self, domain: Domain, weight: Weight) -> None:
        if weight.needs == "values":
            raise WeightError(
                f"weight {weight.name!r} needs vertex values; a polygon with holes has coordinates"
            )
        self.domain = domain
        self.weight = weight
        rows = [tuple(r) for r in domain.vertices.tolist()]
        if weight.code == WeightCode.DIAGONAL:
            self._fn = _diagonal_fn(domain, rows)
        else:
            # identity order: the evaluator's internal indices are the domain's indices
            n = domain.n
            proxy = Polygon(domain.vertices, domain.vertices, np.arange(n), "ccw", False)
            self._fn = weight.evaluator(proxy)

    def __call__(self, a: int, b: int, c: int) -> float:
        """Weight of triangle ``(a, b, c)`` (any order); WeightError on NaN."""
        i, k, j = sorted((a, b, c))
        v = float(self._fn(i, k, j))
        if v != v:
            raise WeightError(f"weight {self.weight.name!r} returned NaN for triangle {(i, k, j)}")
        return v

    def many(self, triangles: NDArray[np.int64]) -> NDArray[np.float64]:
        """Weights of ``(T, 3)`` triangles as a float64 array."""
        t = np.sort(triangles, axis=1).tolist()
        fn = self._fn
        out = np.fromiter((fn(i, k, j) for i, k, j in t), dtype=np.float64, count=len(t))
        bad = np.flatnonzero(np.isnan(out))
        if len(bad):
            tri = tuple(t[int(bad[0])])
            raise WeightError(f"weight {self.weight.name!r} returned NaN for triangle {tri}")
        return out


def domain_weights(domain: Domain, weights: Sequence[Weight]) -> tuple[DomainWeight, ...]:
    """One :class:`DomainWeight` per objective component."""
    return tuple(DomainWeight(domain, w) for w in weights)


def _diagonal_fn(domain: Domain, rows: list[tuple[float, ...]]) -> TriangleFn:
    nxt = domain.nxt.tolist()
    cache: dict[tuple[int, int], float] = {}

    def e(a: int, b: int) -> float:
        key = (a, b)
        v = cache.get(key)
        if v is None:
            v = 0.0 if nxt[a] == b or nxt[b] == a else 0.5 * side_length(rows, a, b)
            cache[key] = v
        return v

    return lambda i, k, j: e(i, k) + e(k, j) + e(i, j)


def total(values: Sequence[float], component: str) -> float:
    """Sum or maximum of triangle weights (``-inf`` for no triangles under max)."""
    if component == "sum":
        return float(math.fsum(values))
    return float(max(values)) if len(values) else -math.inf
