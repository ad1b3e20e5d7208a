"""Triangle weight functions: named built-ins and user callables.

A weight gives each candidate triangle ``(i, k, j)`` (vertex indices,
``i < k < j`` in the engines' internal order) a number; the objective then sums
or maximizes those numbers over the triangles of a triangulation. Built-ins:

``"perimeter"``
    |v_i v_k| + |v_k v_j| + |v_j v_i|, the paper's Eq. (1).
``"diagonal"``
    half the length of each triangle side that is a diagonal, so a
    triangulation's total is the length of its diagonals: the classic minimum
    weight triangulation (MWT). Same optimum as ``"perimeter"`` under ``"sum"``.
``"area"``
    triangle area (constant sum on a convex polygon; use with ``"max"``).
``"product"``
    p_i * p_k * p_j on 1-D vertex values: the matrix-chain weight (CLRS 15.2).
``"max_angle"``
    the triangle's largest angle in radians (with ``"max"``: MinMax angle).
``"min_angle"``
    minus the triangle's smallest angle in radians (minimizing it maximizes
    the smallest angle; with ``"max"``: MaxMin angle).
``"aspect_ratio"``
    circumradius / (2 * inradius): 1 for an equilateral triangle, larger for
    worse shapes, infinite for a degenerate one.

A custom weight is any callable ``w(i, k, j) -> float`` over *input* vertex
indices, or ``w(vertices, i, k, j) -> float`` to receive the vertex array.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Union

import numpy as np

from .errors import WeightError
from .geometry import Polygon

__all__ = [
    "WEIGHTS",
    "Weight",
    "WeightLike",
    "custom_weight",
    "get_weight",
    "register_weight",
]

TriangleFn = Callable[[int, int, int], float]
EdgeFn = Callable[[int, int], float]

# Integer ids by which compiled engines select a built-in weight.
CODE_CUSTOM = -1
CODE_PERIMETER = 0
CODE_DIAGONAL = 1
CODE_AREA = 2
CODE_PRODUCT = 3
CODE_MAX_ANGLE = 4
CODE_MIN_ANGLE = 5
CODE_ASPECT_RATIO = 6


@dataclass(frozen=True)
class Weight:
    """A triangle weight.

    Attributes
    ----------
    name : str
        Registry name (``"custom"`` for user callables).
    needs : {"points", "values"}
        What vertex data the weight reads.
    bind : callable
        ``bind(polygon) -> w(i, k, j)`` over internal indices.
    edge : callable or None
        For edge-decomposable weights, ``edge(polygon) -> e(a, b)`` with
        ``w(i, k, j) == e(i, k) + e(k, j) + e(i, j)``; compiled engines then use
        the pure min-plus form.
    code : int
        Id of the compiled implementation (``CODE_CUSTOM`` if none).
    func : callable or None
        The user's function, for custom weights.
    compiled : callable or None
        The user's function when it is numba-compiled (``numba.njit``), so the
        compiled engine can call it: ``w(vertices, i, k, j)`` over input indices.
    """

    name: str
    needs: str
    bind: Callable[[Polygon], TriangleFn]
    edge: Callable[[Polygon], EdgeFn] | None = None
    code: int = CODE_CUSTOM
    func: Callable[..., float] | None = field(default=None, compare=False)
    description: str = ""
    compiled: Callable[..., float] | None = field(default=None, compare=False)

    def evaluator(self, polygon: Polygon) -> TriangleFn:
        """Return ``w(i, k, j)`` over ``polygon``'s internal indices."""
        self.check(polygon)
        return self.bind(polygon)

    def check(self, polygon: Polygon) -> None:
        """Raise :class:`WeightError` if the weight cannot read ``polygon``'s data."""
        if self.needs == "points" and polygon.is_values:
            raise WeightError(f"weight {self.name!r} needs vertex coordinates, got 1-D values")
        if self.needs == "values" and not polygon.is_values:
            raise WeightError(
                f"weight {self.name!r} needs a 1-D sequence of vertex values "
                f"(matrix dimensions), got coordinates"
            )


WeightLike = Union[str, Weight, Callable[..., float]]

WEIGHTS: dict[str, Weight] = {}


def register_weight(weight: Weight) -> Weight:
    """Add ``weight`` to the registry under ``weight.name`` and return it."""
    WEIGHTS[weight.name] = weight
    return weight


def get_weight(spec: WeightLike) -> Weight:
    """Resolve a weight name, :class:`Weight` or callable to a :class:`Weight`.

    Raises
    ------
    WeightError
        Unknown name or a non-callable object.

    Examples
    --------
    >>> get_weight("perimeter").name
    'perimeter'
    """
    if isinstance(spec, Weight):
        return spec
    if isinstance(spec, str):
        try:
            return WEIGHTS[spec]
        except KeyError:
            known = ", ".join(sorted(WEIGHTS))
            raise WeightError(f"unknown weight {spec!r}; choose one of: {known}") from None
    if callable(spec):
        return custom_weight(spec)
    raise WeightError(f"a weight must be a name or a callable, got {type(spec).__name__}")


def custom_weight(func: Callable[..., float], name: str = "custom") -> Weight:
    """Wrap a user callable ``w(i, k, j)`` or ``w(vertices, i, k, j)``.

    Indices passed to ``func`` are *input* vertex indices (before any
    re-orientation), so ``func`` may index the caller's own arrays. A
    numba-compiled ``func`` (``@numba.njit``) taking ``(vertices, i, k, j)``
    runs inside the compiled engine (``method="fast"``); any other callable
    makes ``method="auto"`` use a Python engine.
    """
    wants_vertices = _positional_arity(getattr(func, "py_func", func)) >= 4

    def bind(polygon: Polygon) -> TriangleFn:
        orig = polygon.order.tolist()
        verts = polygon.vertices

        if wants_vertices:

            def w(i: int, k: int, j: int) -> float:
                return float(func(verts, orig[i], orig[k], orig[j]))
        else:

            def w(i: int, k: int, j: int) -> float:
                return float(func(orig[i], orig[k], orig[j]))

        return w

    compiled = func if wants_vertices and _is_numba_function(func) else None
    kind = "numba-compiled user callable" if compiled is not None else "user callable"
    return Weight(name, "any", bind, func=func, description=kind, compiled=compiled)


def _is_numba_function(func: object) -> bool:
    """True for a numba ``@njit`` dispatcher (checked without importing numba)."""
    return type(func).__module__.startswith("numba.") and hasattr(func, "py_func")


def _positional_arity(func: Callable[..., float]) -> int:
    try:
        params = inspect.signature(func).parameters.values()
    except (TypeError, ValueError):
        return 3
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    return sum(p.kind in kinds for p in params)


# --- built-ins ---------------------------------------------------------------

_DENSE_MAX_N = 1500  # below this, Python evaluators use a precomputed distance table


def _distance_fn(polygon: Polygon) -> EdgeFn:
    pts = polygon.data
    if polygon.n <= _DENSE_MAX_N:
        diff = pts[:, None, :] - pts[None, :, :]
        table = np.sqrt((diff * diff).sum(axis=-1)).tolist()
        return lambda a, b: table[a][b]
    rows = [tuple(p) for p in pts.tolist()]
    return lambda a, b: math.dist(rows[a], rows[b])


def _perimeter_edge(polygon: Polygon) -> EdgeFn:
    return _distance_fn(polygon)


def _diagonal_edge(polygon: Polygon) -> EdgeFn:
    d = _distance_fn(polygon)
    last = polygon.n - 1

    def e(a: int, b: int) -> float:
        lo, hi = (a, b) if a < b else (b, a)
        if hi - lo == 1 or (lo == 0 and hi == last):
            return 0.0  # polygon side, not a diagonal
        return 0.5 * d(a, b)

    return e


def _from_edge(edge: Callable[[Polygon], EdgeFn]) -> Callable[[Polygon], TriangleFn]:
    def bind(polygon: Polygon) -> TriangleFn:
        e = edge(polygon)
        return lambda i, k, j: e(i, k) + e(k, j) + e(i, j)

    return bind


def _side_lengths(
    pts: list[tuple[float, ...]], i: int, k: int, j: int
) -> tuple[float, float, float]:
    return math.dist(pts[k], pts[j]), math.dist(pts[i], pts[j]), math.dist(pts[i], pts[k])


def _area_bind(polygon: Polygon) -> TriangleFn:
    pts = polygon.data
    if pts.shape[1] == 2:
        xs, ys = pts[:, 0].tolist(), pts[:, 1].tolist()

        def area2(i: int, k: int, j: int) -> float:
            return 0.5 * abs((xs[k] - xs[i]) * (ys[j] - ys[i]) - (ys[k] - ys[i]) * (xs[j] - xs[i]))

        return area2
    rows = pts.tolist()

    def area3(i: int, k: int, j: int) -> float:
        a, b, c = rows[i], rows[k], rows[j]
        u = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
        v = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
        cx = u[1] * v[2] - u[2] * v[1]
        cy = u[2] * v[0] - u[0] * v[2]
        cz = u[0] * v[1] - u[1] * v[0]
        return 0.5 * math.sqrt(cx * cx + cy * cy + cz * cz)

    return area3


def _product_bind(polygon: Polygon) -> TriangleFn:
    p = polygon.data.tolist()
    return lambda i, k, j: p[i] * p[k] * p[j]


def _angles(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Angles opposite sides a, b, c (law of cosines, clamped)."""

    def ang(x: float, y: float, z: float) -> float:
        den = 2.0 * y * z
        if den == 0.0:
            return math.pi
        return math.acos(max(-1.0, min(1.0, (y * y + z * z - x * x) / den)))

    return ang(a, b, c), ang(b, c, a), ang(c, a, b)


def _angle_bind(
    pick: Callable[[tuple[float, float, float]], float],
) -> Callable[[Polygon], TriangleFn]:
    def bind(polygon: Polygon) -> TriangleFn:
        pts = [tuple(p) for p in polygon.data.tolist()]
        return lambda i, k, j: pick(_angles(*_side_lengths(pts, i, k, j)))

    return bind


def _aspect_bind(polygon: Polygon) -> TriangleFn:
    pts = [tuple(p) for p in polygon.data.tolist()]

    def w(i: int, k: int, j: int) -> float:
        a, b, c = _side_lengths(pts, i, k, j)
        s = 0.5 * (a + b + c)
        q = (s - a) * (s - b) * (s - c)
        if q <= 0.0:
            return math.inf
        # R / (2 r) = a b c / (8 (s-a)(s-b)(s-c))
        return a * b * c / (8.0 * q)

    return w


register_weight(
    Weight(
        "perimeter",
        "points",
        _from_edge(_perimeter_edge),
        _perimeter_edge,
        CODE_PERIMETER,
        description="triangle perimeter (paper Eq. 1)",
    )
)
register_weight(
    Weight(
        "diagonal",
        "points",
        _from_edge(_diagonal_edge),
        _diagonal_edge,
        CODE_DIAGONAL,
        description="total diagonal length (classic MWT)",
    )
)
register_weight(Weight("area", "points", _area_bind, None, CODE_AREA, description="triangle area"))
register_weight(
    Weight(
        "product",
        "values",
        _product_bind,
        None,
        CODE_PRODUCT,
        description="p_i*p_k*p_j on vertex values (matrix chain)",
    )
)
register_weight(
    Weight(
        "max_angle",
        "points",
        _angle_bind(max),
        None,
        CODE_MAX_ANGLE,
        description="largest angle (radians)",
    )
)
register_weight(
    Weight(
        "min_angle",
        "points",
        _angle_bind(lambda t: -min(t)),
        None,
        CODE_MIN_ANGLE,
        description="minus the smallest angle (radians)",
    )
)
register_weight(
    Weight(
        "aspect_ratio",
        "points",
        _aspect_bind,
        None,
        CODE_ASPECT_RATIO,
        description="circumradius / (2 inradius), 1 = equilateral",
    )
)
