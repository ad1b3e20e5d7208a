"""Triangle weights: each built-in written once, for Python and compiled engines alike.

A weight gives each candidate triangle ``(i, k, j)`` (vertex indices,
``i < k < j`` in the engines' internal order) a number; the objective then sums
or maximizes those numbers over the triangles of a triangulation. Built-ins:

``"perimeter"``
    ``|v_i v_k| + |v_k v_j| + |v_j v_i|``, the paper's Eq. (1).
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

One source
----------
The formulas below are plain Python over ``p[v][c]`` (coordinate ``c`` of
vertex ``v``): the Python engines call them on rows of tuples. Their compiled
twin is ``src/core/weights.hpp`` in the compiled core (what ``method="fast"``
calls): the same operations in the same order, so both compute the same
numbers bit for bit. The numba kernels (:mod:`optri.engines._jit_weights`)
compile these very functions; the CUDA device functions
(:mod:`optri.engines._gpu_device`) are a third text.

To add a weight: write its formula here, give it a :class:`WeightCode`, add
its branch to :func:`triangle_weight` (a sum over sides also to
:func:`edge_weight` and :attr:`Weight.edge_decomposable`) and register it at
the end of this module; then its branch in ``src/core/weights.hpp`` and its
CUDA twin in the device functions ``weight`` (and ``edge``) of
:mod:`optri.engines._gpu_device`. ``tests/test_weights.py`` needs no edit: for
every ``WeightCode`` it evaluates the Python formula, the C++ twin and the CUDA
twin (under numba's CUDA simulator) on the same random and degenerate
triangles, and fails until all three agree (the first two bit for bit, CUDA
within a few ulps).
"""

from __future__ import annotations

import inspect
import math
import numbers
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, Union

from .errors import WeightError, accepts_positional
from .polygon import Polygon

__all__ = [
    "WEIGHTS",
    "Weight",
    "WeightCode",
    "WeightLike",
    "compiled_weight_error",
    "custom_weight",
    "edge_weight",
    "edge_weight_row",
    "get_weight",
    "register_weight",
    "resolve_weights",
    "triangle_weight",
    "weight_number",
]

TriangleFn = Callable[[int, int, int], float]


class WeightCode(IntEnum):
    """Id by which compiled engines select a built-in weight (``CUSTOM``: a callable).

    The compiled core's ``enum class WeightCode`` (``src/core/weights.hpp``) has
    the same values.
    """

    CUSTOM = -1
    PERIMETER = 0
    DIAGONAL = 1
    AREA = 2
    PRODUCT = 3
    MAX_ANGLE = 4
    MIN_ANGLE = 5
    ASPECT_RATIO = 6


# --- formulas: plain Python that numba compiles too (no globals but math and WeightCode) ---


# Lengths and areas stay finite over the whole float range: the plain formula is used
# where its squares and products neither overflow nor underflow (every value of real
# data, bit for bit as before), and otherwise the same formula on values scaled by a
# power of two (exact), the result scaled back.
_SQ_LO = 2.0**-960  # a sum of squares above this lost nothing to underflow
_SQRT_LO = 2.0**-480  # its square root: a length above this is exact
_SHAPE_LO = 2.0**-250  # side lengths in [2**-250, 2**250]: cubes stay in range
_SHAPE_HI = 2.0**250


def _ldexp(x, e):  # type: ignore[no-untyped-def]
    """``x * 2**e``, infinite on overflow (Python's math.ldexp would raise instead)."""
    if x != 0.0 and math.frexp(x)[1] + e > 1024:
        return math.copysign(math.inf, x)
    return math.ldexp(x, e)


def _scaled_norm(dx, dy, dz):  # type: ignore[no-untyped-def]
    """sqrt(dx^2 + dy^2 + dz^2) without overflow or underflow in the squares."""
    m = max(abs(dx), max(abs(dy), abs(dz)))
    if m == 0.0 or m == math.inf:
        return m
    e = math.frexp(m)[1]
    x, y, z = math.ldexp(dx, -e), math.ldexp(dy, -e), math.ldexp(dz, -e)
    return _ldexp(math.sqrt(x * x + y * y + z * z), e)


def side_length(p, a, b):  # type: ignore[no-untyped-def]
    """Euclidean distance of vertices a and b (1, 2 or 3 coordinates), for any finite input."""
    pa, pb = p[a], p[b]
    dx = float(pa[0]) - float(pb[0])  # Python floats: overflow is inf, never a warning
    dy = float(pa[1]) - float(pb[1]) if len(pa) > 1 else 0.0
    dz = float(pa[2]) - float(pb[2]) if len(pa) > 2 else 0.0
    sq = dx * dx + dy * dy + dz * dz
    if _SQ_LO < sq < math.inf:
        return math.sqrt(sq)
    return _scaled_norm(dx, dy, dz)


def edge_weight(code, p, a, b):  # type: ignore[no-untyped-def]
    """``e(a, b)``, ``a < b``, of an edge-decomposable weight.

    Such a weight is w(i, k, j) = e(i, k) + e(k, j) + e(i, j). Perimeter: the
    side length. Diagonal: half of it for a diagonal, 0 for a polygon side
    (each diagonal is in two triangles, so a triangulation's total is its
    diagonals' length).
    """
    return _edge_of_length(code, p, a, b, side_length(p, a, b))


def _edge_of_length(code, p, a, b, d):  # type: ignore[no-untyped-def]
    """``e(a, b)`` from the length ``d`` of the segment (a, b)."""
    if code == WeightCode.DIAGONAL:
        if b - a == 1 or (a == 0 and b == len(p) - 1):
            return 0.0  # a polygon side is not a diagonal
        return 0.5 * d
    return d


def edge_weight_row(code, p, a, b0, out):  # type: ignore[no-untyped-def]
    """``out[q] = edge_weight(code, p, a, b0 + q)`` for every ``q``: a row at a time.

    The same values bit for bit, faster compiled: a first loop without
    branches (which vectorizes, fastest with each coordinate contiguous: a
    Fortran-ordered ``p``) takes the square roots of the same sums of squares
    as :func:`side_length` (2-D and 3-D vertices); lengths outside the range
    where that formula is exact, if any, are then taken from
    :func:`side_length` itself.

    >>> import numpy as np
    >>> out = np.empty(2)
    >>> p = np.array([[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]])
    >>> edge_weight_row(WeightCode.PERIMETER, p, 0, 1, out)
    >>> out.tolist()
    [5.0, 10.0]
    """
    dims = p.shape[1]
    if dims == 2:  # one loop per dimension: no branch inside
        for q in range(len(out)):
            dx = float(p[a, 0]) - float(p[b0 + q, 0])
            dy = float(p[a, 1]) - float(p[b0 + q, 1])
            out[q] = math.sqrt(dx * dx + dy * dy + 0.0 * 0.0)
    elif dims == 3:
        for q in range(len(out)):
            dx = float(p[a, 0]) - float(p[b0 + q, 0])
            dy = float(p[a, 1]) - float(p[b0 + q, 1])
            dz = float(p[a, 2]) - float(p[b0 + q, 2])
            out[q] = math.sqrt(dx * dx + dy * dy + dz * dz)
    else:  # 1-D vertex values
        for q in range(len(out)):
            out[q] = side_length(p, a, b0 + q)
    inexact = 0  # counted in a loop of its own, which vectorizes too
    for q in range(len(out)):
        inexact += 0 if _SQRT_LO < out[q] < math.inf else 1
    if inexact:
        for q in range(len(out)):
            if not _SQRT_LO < out[q] < math.inf:
                out[q] = side_length(p, a, b0 + q)
    if code != WeightCode.PERIMETER:
        for q in range(len(out)):
            out[q] = _edge_of_length(code, p, a, b0 + q, out[q])


def _cosine(x, y, z):  # type: ignore[no-untyped-def]
    """Clamped cosine of the angle opposite side ``x`` (law of cosines); -1 if degenerate."""
    den = 2.0 * y * z
    if den == 0.0:
        return -1.0  # angle pi
    return max(-1.0, min(1.0, (y * y + z * z - x * x) / den))


def triangle_area(p, i, k, j):  # type: ignore[no-untyped-def]
    """Area of triangle (i, k, j) in 2-D or 3-D, for any finite input."""
    dim = len(p[i])
    u0, u1 = p[k][0] - p[i][0], p[k][1] - p[i][1]
    v0, v1 = p[j][0] - p[i][0], p[j][1] - p[i][1]
    u2 = p[k][2] - p[i][2] if dim > 2 else 0.0
    v2 = p[j][2] - p[i][2] if dim > 2 else 0.0
    m = max(max(max(abs(u0), abs(u1)), max(abs(v0), abs(v1))), max(abs(u2), abs(v2)))
    e = 0
    if m > _SHAPE_HI or 0.0 < m < _SHAPE_LO:  # products would overflow or underflow
        e = math.frexp(m)[1]
        u0, u1, u2 = math.ldexp(u0, -e), math.ldexp(u1, -e), math.ldexp(u2, -e)
        v0, v1, v2 = math.ldexp(v0, -e), math.ldexp(v1, -e), math.ldexp(v2, -e)
    if dim == 2:
        return _ldexp(0.5 * abs(u0 * v1 - u1 * v0), 2 * e)
    cx = u1 * v2 - u2 * v1
    cy = u2 * v0 - u0 * v2
    cz = u0 * v1 - u1 * v0
    return _ldexp(0.5 * math.sqrt(cx * cx + cy * cy + cz * cz), 2 * e)


def _scaled_sides(p, i, k, j):  # type: ignore[no-untyped-def]
    """Side lengths |kj|, |ij|, |ik|, all scaled by one power of two to near 1.

    Scaling the coordinate differences (exact) before squaring keeps full precision
    for sides too short for float64's normal range and finite for sides near 1e308.
    """
    three = len(p[i]) > 2
    ax, ay = p[j][0] - p[k][0], p[j][1] - p[k][1]
    bx, by = p[j][0] - p[i][0], p[j][1] - p[i][1]
    cx, cy = p[k][0] - p[i][0], p[k][1] - p[i][1]
    az = p[j][2] - p[k][2] if three else 0.0
    bz = p[j][2] - p[i][2] if three else 0.0
    cz = p[k][2] - p[i][2] if three else 0.0
    m = max(max(abs(ax), abs(ay), abs(az)), max(abs(bx), abs(by), abs(bz)))
    e = math.frexp(max(m, max(abs(cx), abs(cy), abs(cz))))[1]
    return _norm_at(ax, ay, az, e), _norm_at(bx, by, bz, e), _norm_at(cx, cy, cz, e)


def _norm_at(x, y, z, e):  # type: ignore[no-untyped-def]
    """|(x, y, z)| * 2**-e, the components scaled first (exact)."""
    x, y, z = math.ldexp(x, -e), math.ldexp(y, -e), math.ldexp(z, -e)
    return math.sqrt(x * x + y * y + z * z)


def _shape(code, p, i, k, j):  # type: ignore[no-untyped-def]
    """The side-length weights: largest angle, minus smallest angle, aspect ratio.

    All three are scale-invariant, so very large or very small sides are first
    scaled by a power of two (exact) into a range where their cubes are finite.
    """
    a, b, c = side_length(p, k, j), side_length(p, i, j), side_length(p, i, k)
    m = max(a, max(b, c))
    if m > _SHAPE_HI or 0.0 < m < _SHAPE_LO:
        a, b, c = _scaled_sides(p, i, k, j)
    # acos is decreasing: the largest angle has the smallest cosine (one acos, not three)
    if code == WeightCode.MAX_ANGLE:
        return math.acos(min(_cosine(a, b, c), _cosine(b, c, a), _cosine(c, a, b)))
    if code == WeightCode.MIN_ANGLE:
        return -math.acos(max(_cosine(a, b, c), _cosine(b, c, a), _cosine(c, a, b)))
    s = 0.5 * (a + b + c)
    q = (s - a) * (s - b) * (s - c)
    if q <= 0.0:
        return math.inf  # degenerate
    return a * b * c / (8.0 * q)  # R / (2 r) = abc / (8 (s-a)(s-b)(s-c))


def triangle_weight(code, p, i, k, j):  # type: ignore[no-untyped-def]
    """Built-in weight ``code`` of triangle ``(i, k, j)``; NaN for an unknown code.

    >>> triangle_weight(WeightCode.PERIMETER, [(0.0, 0.0), (3.0, 0.0), (0.0, 4.0)], 0, 1, 2)
    12.0
    """
    if code == WeightCode.PERIMETER or code == WeightCode.DIAGONAL:
        return edge_weight(code, p, i, k) + edge_weight(code, p, k, j) + edge_weight(code, p, i, j)
    if code == WeightCode.AREA:
        return triangle_area(p, i, k, j)
    if code == WeightCode.PRODUCT:
        return p[i][0] * p[k][0] * p[j][0]
    if (
        code == WeightCode.MAX_ANGLE
        or code == WeightCode.MIN_ANGLE
        or code == WeightCode.ASPECT_RATIO
    ):
        return _shape(code, p, i, k, j)
    return math.nan


#: The rare paths (values beyond float64's comfortable range), compiled as calls rather
#: than inlined, so the common path stays small.
OUT_OF_LINE = (_ldexp, _scaled_norm, _norm_at, _scaled_sides, edge_weight_row)

#: The formulas, registered with numba by the compiled engine (optri.engines._jit_weights).
FORMULAS = (
    _ldexp,
    _scaled_norm,
    _norm_at,
    _scaled_sides,
    side_length,
    _edge_of_length,
    edge_weight,
    edge_weight_row,
    _cosine,
    triangle_area,
    _shape,
    triangle_weight,
)


# --- the Weight type and the registry -------------------------------------------


@dataclass(frozen=True)
class Weight:
    """A triangle weight.

    Attributes
    ----------
    name : str
        Registry name (``"custom"`` for user callables).
    needs : {"points", "values", "any"}
        What vertex data the weight reads.
    code : WeightCode
        Which built-in formula computes it (``CUSTOM`` for a user callable).
    description : str
    func : callable or None
        The user's function, for custom weights.
    compiled : callable or None
        The user's function when it is numba-compiled (``numba.njit``), so the
        compiled engine can call it: ``w(vertices, i, k, j)`` over input indices.

    Examples
    --------
    >>> w = WEIGHTS["perimeter"]
    >>> w.name, w.needs
    ('perimeter', 'points')
    """

    name: str
    needs: str
    code: WeightCode = WeightCode.CUSTOM
    description: str = ""
    func: Callable[..., float] | None = field(default=None, compare=False)
    compiled: Callable[..., float] | None = field(default=None, compare=False)

    @property
    def edge_decomposable(self) -> bool:
        """True when w(i, k, j) = e(i, k) + e(k, j) + e(i, j) (:func:`edge_weight`)."""
        return self.code in (WeightCode.PERIMETER, WeightCode.DIAGONAL)

    def evaluator(self, polygon: Polygon) -> TriangleFn:
        """Return ``w(i, k, j)`` over ``polygon``'s internal indices."""
        self.check(polygon)
        if self.code == WeightCode.CUSTOM:
            return _bind_custom(self, polygon)
        if self.code == WeightCode.PRODUCT and polygon.ints is not None:
            v = polygon.ints  # integer input: exact products (Python ints), exact sums
            return lambda i, k, j: v[i] * v[k] * v[j]
        rows = _rows(polygon)
        code = int(self.code)
        if self.edge_decomposable:
            return _edge_sum(code, rows)
        return lambda i, k, j: triangle_weight(code, rows, i, k, j)

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

#: The built-in weights by name, and any added with :func:`register_weight`.
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


def resolve_weights(spec: Any, components: int) -> tuple[Weight, ...]:
    """One :class:`Weight` per objective component from a weight or a sequence of them.

    >>> [w.name for w in resolve_weights(("max_angle", "perimeter"), 2)]
    ['max_angle', 'perimeter']

    Raises
    ------
    WeightError
        An unknown weight, or a count that does not match ``components``.
    """
    pair = isinstance(spec, Sequence) and not isinstance(spec, str)
    weights = tuple(get_weight(w) for w in spec) if pair else (get_weight(spec),)
    if len(weights) != components:
        raise WeightError(
            f"the objective has {components} component(s) but {len(weights)} weight(s) "
            f"were given; give one weight per component"
        )
    return weights


def custom_weight(func: Callable[..., float], name: str = "custom") -> Weight:
    """Wrap a user callable ``w(i, k, j)`` or ``w(vertices, i, k, j)``.

    Indices passed to ``func`` are *input* vertex indices (before any
    re-orientation), so ``func`` may index the caller's own arrays. A
    numba-compiled ``func`` (``@numba.njit``) taking ``(vertices, i, k, j)``
    runs inside the compiled engine (``method="fast"``); any other callable
    makes ``method="auto"`` use a Python engine.

    Examples
    --------
    >>> import optri
    >>> spread = custom_weight(lambda i, k, j: (j - i) ** 2)   # prefers short index spans
    >>> optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1], [-1, 0.5]], weight=spread).weight
    24.0
    """
    if not callable(func):
        raise WeightError(f"a weight must be a name or a callable, got {type(func).__name__}")
    target = getattr(func, "py_func", func)
    if not (accepts_positional(target, 3) or accepts_positional(target, 4)):
        raise WeightError(
            f"a custom weight is called as w(i, k, j) or w(vertices, i, k, j); "
            f"{getattr(target, '__name__', type(target).__name__)}{_signature(target)} "
            f"cannot take 3 or 4 positional arguments"
        )
    wants_vertices = positional_arity(target) >= 4
    compiled = func if wants_vertices and _is_numba_function(func) else None
    kind = "numba-compiled user callable" if compiled is not None else "user callable"
    return Weight(name, "any", WeightCode.CUSTOM, kind, func=func, compiled=compiled)


# --- Python evaluators -------------------------------------------------------------


def _rows(polygon: Polygon) -> list[tuple[float, ...]]:
    """Internal-order vertex rows as tuples (values as 1-tuples): fast to index in Python."""
    data = polygon.data
    return [tuple(r) for r in data.reshape(len(data), -1).tolist()]


def _edge_sum(code: int, rows: list[tuple[float, ...]]) -> TriangleFn:
    """``e(i, k) + e(k, j) + e(i, j)`` with each edge computed once (dense problems ask often)."""
    n = len(rows)
    cache: dict[int, float] = {}

    def e(a: int, b: int) -> float:
        key = a * n + b
        v = cache.get(key)
        if v is None:
            v = cache[key] = edge_weight(code, rows, a, b)
        return v

    return lambda i, k, j: e(i, k) + e(k, j) + e(i, j)


def _bind_custom(weight: Weight, polygon: Polygon) -> TriangleFn:
    """``w(i, k, j)`` over internal indices calling the user's function on input indices.

    Whatever the function raises, or a value that is not a real number, becomes a
    :class:`WeightError` naming the triangle, the original exception chained.
    """
    func = weight.func
    assert func is not None
    orig = polygon.order.tolist()
    lead = (polygon.vertices,) if positional_arity(getattr(func, "py_func", func)) >= 4 else ()

    def w(i: int, k: int, j: int) -> float:
        tri = (orig[i], orig[k], orig[j])
        try:
            value = func(*lead, *tri)
        except Exception as exc:
            raise WeightError(
                f"weight {weight.name!r} raised {type(exc).__name__} on triangle {tri}: {exc}"
            ) from exc
        if type(value) is float:
            return value
        return weight_number(value, weight.name, tri)

    return w


def weight_number(value: Any, name: str, tri: tuple[int, int, int]) -> float:
    """A user weight's ``value`` as a float, or :class:`WeightError` naming triangle ``tri``.

    Real numbers (Python, numpy, ``Fraction``) are taken; ``None``, strings, arrays
    (even of one element), complex numbers and ints past float range are not.

    >>> weight_number(None, "custom", (0, 1, 2))
    Traceback (most recent call last):
    ...
    optri.errors.WeightError: weight 'custom' returned NoneType None for triangle (0, 1, 2), ...
    """
    if isinstance(value, numbers.Real):
        try:
            return float(value)
        except (OverflowError, ValueError, TypeError) as exc:
            raise WeightError(
                f"weight {name!r} returned {_short(value)} for triangle {tri}, which is "
                f"not representable as a float ({exc})"
            ) from exc
    raise WeightError(
        f"weight {name!r} returned {type(value).__name__} {_short(value)} for triangle {tri}, "
        f"not a real number; a weight must return one int or float"
    )


def compiled_weight_error(
    weight: Weight,
    polygon: Polygon,
    allowed: Any,
    exc: BaseException | None = None,
    budget: int = 1_000_000,
) -> WeightError:
    """The :class:`WeightError` for an exception ``weight`` raised inside compiled code.

    The compiled code does not say which triangle failed, nor (``exc`` None) what it
    raised, so the user's function is called again from Python over the triangles
    the kernel evaluates (chords of ``allowed``, shortest first), at most ``budget``
    of them, to name the first that raises or returns a non-number. The error's
    ``__cause__`` is ``exc``, else the exception that call raised.
    """
    func = weight.func
    assert func is not None
    found, raised = _first_failing(func, polygon, allowed, budget)
    cause = exc if exc is not None else raised
    where = f"triangle {found}" if found is not None else "a triangle"
    what = type(cause).__name__ if cause is not None else "an exception"
    first = (str(cause).strip().splitlines() or [""])[0] if cause is not None else ""
    error = WeightError(
        f"weight {weight.name!r} raised {what} inside the compiled engine on {where}: {first}"
    )
    error.__cause__ = cause
    return error


def _first_failing(
    func: Callable[..., Any], polygon: Polygon, allowed: Any, budget: int
) -> tuple[tuple[int, int, int] | None, BaseException | None]:
    """The first triangle on which ``func`` raises (and what) or returns a non-number."""
    orig, verts, n = polygon.order.tolist(), polygon.vertices, polygon.n
    ok = (lambda a, b: True) if allowed is None else (lambda a, b: bool(allowed[a, b]))
    calls = 0
    for length in range(2, n):
        for i in range(n - length):
            j = i + length
            if not ok(i, j) and length < n - 1:
                continue
            for k in range(i + 1, j):
                if not ((k - i == 1 or ok(i, k)) and (j - k == 1 or ok(k, j))):
                    continue
                tri = (orig[i], orig[k], orig[j])
                calls += 1
                if calls > budget:
                    return None, None
                try:
                    value = func(verts, *tri)
                except Exception as exc:
                    return tri, exc
                if not isinstance(value, numbers.Real):
                    return tri, None
    return None, None


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _signature(func: Any) -> str:
    try:
        return str(inspect.signature(func))
    except (TypeError, ValueError):
        return "(...)"


def _is_numba_function(func: object) -> bool:
    """True for a numba ``@njit`` dispatcher (checked without importing numba)."""
    return type(func).__module__.startswith("numba.") and hasattr(func, "py_func")


def positional_arity(func: Callable[..., float]) -> int:
    """How many positional arguments ``func`` takes (3: ``w(i, k, j)``; 4: with vertices)."""
    try:
        params = inspect.signature(func).parameters.values()
    except (TypeError, ValueError):
        return 3
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    return sum(p.kind in kinds for p in params)


# --- the built-ins ---------------------------------------------------------------------

for _name, _needs, _code, _text in (
    ("perimeter", "points", WeightCode.PERIMETER, "triangle perimeter (paper Eq. 1)"),
    ("diagonal", "points", WeightCode.DIAGONAL, "total diagonal length (classic MWT)"),
    ("area", "points", WeightCode.AREA, "triangle area"),
    ("product", "values", WeightCode.PRODUCT, "p_i*p_k*p_j on vertex values (matrix chain)"),
    ("max_angle", "points", WeightCode.MAX_ANGLE, "largest angle (radians)"),
    ("min_angle", "points", WeightCode.MIN_ANGLE, "minus the smallest angle (radians)"),
    ("aspect_ratio", "points", WeightCode.ASPECT_RATIO, "circumradius / (2 inradius)"),
):
    register_weight(Weight(_name, _needs, _code, _text))
