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
from ..weights import Weight, WeightCode, edge_weight, side_length
from .candidates import Candidates
from .domain import Domain

__all__ = ["DomainWeight", "domain_weights", "shape_only"]

TriangleFn = Callable[[int, int, int], float]
EdgeFn = Callable[[int, int], float]

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
        #: ``e(a, b)``, ``a < b``, of a weight that is ``e(i, k) + e(k, j) + e(i, j)``; else None
        self._edge: EdgeFn | None = None
        if weight.code == WeightCode.DIAGONAL:
            self._edge = _diagonal_edge(domain, rows)
            e = self._edge
            self._fn = lambda i, k, j: e(i, k) + e(k, j) + e(i, j)
        else:
            if weight.edge_decomposable:
                code = int(weight.code)
                self._edge = lambda a, b: edge_weight(code, rows, a, b)
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
        return self._no_nan(out, triangles)

    def on(self, cand: Candidates) -> NDArray[np.float64]:
        """Weights of every candidate triangle of ``cand``, in its order; as :meth:`many`.

        A weight that sums over sides is evaluated once per edge and summed
        per triangle in the order :meth:`many` sums, ``e(i, k) + e(k, j) +
        e(i, j)`` for ``i < k < j``: the same floats.
        """
        e = self._edge
        if e is None:
            return self.many(cand.triangles)
        edge = np.fromiter(
            (e(a, b) for a, b in cand.edges.tolist()), dtype=np.float64, count=len(cand.edges)
        )
        s = edge[cand.sides]  # sides (t0, t1), (t1, t2), (t2, t0); t0 is the smallest corner
        rising = cand.triangles[:, 1] < cand.triangles[:, 2]
        out = np.where(rising, s[:, 0] + s[:, 1] + s[:, 2], s[:, 2] + s[:, 1] + s[:, 0])
        return self._no_nan(out, cand.triangles)

    def _no_nan(
        self, out: NDArray[np.float64], triangles: NDArray[np.int64]
    ) -> NDArray[np.float64]:
        bad = np.flatnonzero(np.isnan(out))
        if len(bad):
            tri = tuple(sorted(triangles[int(bad[0])].tolist()))
            raise WeightError(f"weight {self.weight.name!r} returned NaN for triangle {tri}")
        return out


def domain_weights(domain: Domain, weights: Sequence[Weight]) -> tuple[DomainWeight, ...]:
    """One :class:`DomainWeight` per objective component."""
    return tuple(DomainWeight(domain, w) for w in weights)


def _diagonal_edge(domain: Domain, rows: list[tuple[float, ...]]) -> EdgeFn:
    """Half the length of a diagonal, 0 for a boundary edge (of any ring); cached."""
    nxt = domain.nxt.tolist()
    cache: dict[tuple[int, int], float] = {}

    def e(a: int, b: int) -> float:
        key = (a, b)
        v = cache.get(key)
        if v is None:
            v = 0.0 if nxt[a] == b or nxt[b] == a else 0.5 * side_length(rows, a, b)
            cache[key] = v
        return v

    return e


def total(values: Sequence[float], component: str) -> float:
    """Sum or maximum of triangle weights (``-inf`` for no triangles under max)."""
    if component == "sum":
        return float(math.fsum(values))
    return float(max(values)) if len(values) else -math.inf
