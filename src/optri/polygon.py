"""The one input validator: a :class:`Polygon` from vertex input, or a clear error.

A polygon enters optri as an ``(n, 2)`` or ``(n, 3)`` array of vertices in order,
or as a 1-D sequence of vertex values (matrix-chain style weights need no
geometry). :func:`as_polygon` checks shape, finiteness, distinct vertices,
planarity and orientation and returns a :class:`Polygon` whose *internal*
vertex order is counter-clockwise; engines work on internal indices and results
are mapped back through :attr:`Polygon.order`. :func:`require_simple` checks
that the boundary does not touch itself. Every sign of a turn is decided
exactly in :mod:`optri.predicates` (collinear means exactly collinear,
convex means every turn strictly left); the one tolerance left is 3-D
planarity (``config.PLANARITY_RTOL``), as 3-D coordinates are rarely exactly
coplanar. Areas are computed on centred coordinates with a compensated sum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import config
from .errors import InvalidPolygonError
from .predicates import following, segment_pair_fault, turn_signs

__all__ = [
    "Polygon",
    "as_polygon",
    "drop_closing_vertices",
    "find_self_intersection",
    "is_ring_pair",
    "newell_normal",
    "normalize_vertices",
    "require_simple",
    "signed_area",
]

#: Edges per block in the O(n^2) simplicity check (memory ~ 100 * block * n bytes).
_BLOCK = 256


@dataclass(frozen=True)
class Polygon:
    """A validated polygon (or value sequence) ready for the engines.

    Attributes
    ----------
    vertices : ndarray
        The input as given (closing duplicate removed), ``(n, d)`` or ``(n,)``.
    data : ndarray
        Vertices in internal order: counter-clockwise for planar input.
    order : ndarray of int64
        ``order[internal_index] == input_index``.
    orientation : {"ccw", "cw", None}
        Orientation of the input; None for values and non-planar 3D input.
    convex : bool
        Strictly convex (no three consecutive collinear vertices).
    ints : tuple of int or None
        The exact values of integer vertex values (1-D input of integer type):
        weights such as ``"product"`` compute with them exactly.

    Examples
    --------
    >>> p = as_polygon([[0, 0], [0, 1], [1, 1], [1, 0]])    # clockwise
    >>> p.orientation, p.convex, p.order.tolist()
    ('cw', True, [0, 3, 2, 1])
    """

    vertices: NDArray[np.float64]
    data: NDArray[np.float64]
    order: NDArray[np.int64]
    orientation: str | None
    convex: bool
    ints: tuple[int, ...] | None = None

    @property
    def n(self) -> int:
        """Number of vertices."""
        return int(self.data.shape[0])

    @property
    def is_values(self) -> bool:
        """True for a 1-D sequence of vertex values (no geometry)."""
        return self.data.ndim == 1

    @property
    def planar_points(self) -> NDArray[np.float64] | None:
        """Internal-order 2-D coordinates (3-D input projected on its plane)."""
        if self.is_values:
            return None
        if self.data.shape[1] == 2:
            return self.data
        return _project_to_plane(self.data)


def normalize_vertices(data: ArrayLike, *, values: bool = True) -> NDArray[np.float64]:
    """Vertex input as a float64 array, checked: the normalization every entry point shares.

    Accepts ``(n, 2)`` or ``(n, 3)`` vertices in order or, with ``values``, a
    1-D sequence of vertex values. Closing vertices (last vertices equal to the
    first, repeated any number of times) are dropped (coordinates only: values
    may repeat). ``triangulate``, ``batch``, the file readers and the CLI all
    come through here.

    Raises
    ------
    InvalidPolygonError
        Not real numbers (strings, complex numbers, objects), a number too large
        for float64 (a Python int of 10**400), the wrong shape, NaN or infinite
        coordinates, fewer than 3 vertices, or a repeated vertex (the message
        names both indices).

    Examples
    --------
    >>> normalize_vertices([[0, 0], [1, 0], [0, 1], [0, 0], [0, 0]]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    arr = _checked_array(data, values)
    if arr.ndim == 2:
        _require_distinct(arr)
    return arr


def _checked_array(data: ArrayLike, values: bool) -> NDArray[np.float64]:
    """:func:`normalize_vertices` but for its check of repeated vertices."""
    arr = _as_float_array(data)
    shape_ok = (arr.ndim == 2 and arr.shape[1] in (2, 3)) or (arr.ndim == 1 and values)
    if not shape_ok:
        also = " or a 1-D sequence of values" if values else ""
        raise InvalidPolygonError(
            f"expected an (n, 2) or (n, 3) array of vertices{also}, got shape {arr.shape}"
        )
    _require_finite(arr)
    if arr.ndim == 2:
        arr = drop_closing_vertices(arr)
    n = arr.shape[0]
    if n < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
    return arr


def drop_closing_vertices(ring: NDArray[np.float64]) -> NDArray[np.float64]:
    """``ring`` without its closing vertices: trailing copies of the first, however many.

    At least 3 vertices are kept (what remains is then refused as repeated).

    >>> drop_closing_vertices(np.array([[0., 0.], [1., 0.], [0., 1.], [0., 0.], [0., 0.]])).shape
    (3, 2)
    """
    end = len(ring)
    while end > 3 and np.array_equal(ring[0], ring[end - 1]):
        end -= 1
    return ring[:end]


def _as_float_array(data: ArrayLike) -> NDArray[np.float64]:
    """``data`` as float64, refusing what is not a real number instead of coercing it."""
    try:
        raw = np.asarray(data)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"vertices must be numbers: {exc}") from exc
    kind = raw.dtype.kind
    if kind == "c":
        raise InvalidPolygonError(
            "vertices are complex numbers; give real coordinates (x, y) or (x, y, z)"
        )
    if kind == "b":
        raise InvalidPolygonError("vertices are booleans; give real coordinates")
    if kind == "O":
        return _object_to_float(raw)
    try:
        return raw.astype(np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"vertices must be numbers: {exc}") from exc


def _object_to_float(raw: NDArray[Any]) -> NDArray[np.float64]:
    """An object array of real numbers (big Python ints, say) as float64, checked one by one."""
    out = np.empty(raw.shape, dtype=np.float64)
    dest = out.reshape(-1)
    width = raw.shape[-1] if raw.ndim > 1 else 1
    for pos, v in enumerate(raw.reshape(-1).tolist()):
        if isinstance(v, bool) or not isinstance(v, Real):
            raise InvalidPolygonError(
                f"vertex {pos // width} has a coordinate that is not a real number: "
                f"{type(v).__name__} {str(v)[:40]}"
            )
        try:
            dest[pos] = float(v)
        except OverflowError:
            size = f"an integer of {len(str(abs(v)))} digits" if isinstance(v, int) else "a number"
            raise InvalidPolygonError(
                f"vertex {pos // width} has a coordinate too large for float64 ({size}); "
                f"scale the coordinates down"
            ) from None
    return out


def as_polygon(data: ArrayLike | Polygon) -> Polygon:
    """Check vertex input and return a :class:`Polygon` in counter-clockwise order.

    Parameters
    ----------
    data : array_like or Polygon
        ``(n, 2)`` or ``(n, 3)`` vertices in order, or a 1-D sequence of values.
        Closing vertices equal to the first are dropped (coordinates only:
        values may repeat).

    Returns
    -------
    Polygon

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 vertices, NaN or infinite coordinates, repeated vertices,
        all vertices (exactly) collinear, an array of the wrong shape, or a
        boundary that folds back on itself at its lowest vertex.

    Notes
    -----
    The orientation is the exact turn at the lowest (then leftmost) vertex,
    which is strictly convex in every simple polygon; convexity is exact too:
    every turn strictly left and the boundary winding once.

    Examples
    --------
    >>> p = as_polygon([[0, 0], [0, 1], [1, 1], [1, 0]])   # clockwise square
    >>> p.orientation, p.order.tolist()
    ('cw', [0, 3, 2, 1])
    """
    if isinstance(data, Polygon):
        return data
    arr = _checked_array(data, True)
    n = arr.shape[0]
    identity = np.arange(n, dtype=np.int64)
    if arr.ndim == 1:
        return Polygon(arr, arr, identity, None, True, _integer_values(data))
    if arr.shape[1] == 3:
        _require_distinct(arr)
        planar = _planar_or_none(arr)
        if planar is None:  # a skew 3-D polygon: every index triangulation is valid
            return Polygon(arr, arr, identity, None, True)
        signs = turn_signs(planar)  # planar 3-D: order kept, read in its own plane
        if not signs.any():
            raise InvalidPolygonError("all vertices are collinear: the polygon has no area")
        return Polygon(arr, arr, identity, None, _is_strictly_convex(planar, signs))
    signs = turn_signs(arr)
    convex = _is_strictly_convex(arr, signs)
    if not convex:  # a strictly convex ring's vertices are all distinct: no search needed
        _require_distinct(arr)
    if not signs.any():
        raise InvalidPolygonError("all vertices are collinear: the polygon has no area")
    turn = int(signs[0] if convex else signs[_lowest(arr)])
    if turn == 0:
        _refuse_folded(arr)
    order = identity
    if turn < 0:
        order = np.concatenate(([0], np.arange(n - 1, 0, -1))).astype(np.int64)
    return Polygon(arr, arr[order], order, "ccw" if turn > 0 else "cw", convex)


def _integer_values(data: ArrayLike) -> tuple[int, ...] | None:
    """The values as Python ints when the 1-D input is of integer type, else None.

    A list of Python ints is taken as it is: numpy would turn ``[2**63 + 5, 3]``
    (too large for int64, mixed with small ones) into rounded floats.
    """
    if isinstance(data, (list, tuple)) and data and all(_is_int(v) for v in data):
        return tuple(int(v) for v in data)
    raw = np.asarray(data)
    if raw.dtype.kind in "iu":
        return tuple(int(v) for v in raw.tolist())
    if raw.dtype.kind == "O":
        vals = raw.tolist()
        if all(isinstance(v, int) and not isinstance(v, bool) for v in vals):
            return tuple(vals)
    return None


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def is_ring_pair(obj: Any) -> bool:
    """Whether ``obj`` is ``(exterior, [holes])``: a pair whose first item is itself a ring.

    >>> is_ring_pair(([[0, 0], [3, 0], [0, 3]], [[[1, 1], [1, 2], [2, 1]]]))
    True
    >>> is_ring_pair([[0, 0], [1, 1]])       # two vertices, not a pair of rings
    False
    """
    if not isinstance(obj, (tuple, list)) or len(obj) != 2:
        return False
    holes = obj[1]
    if not isinstance(holes, (tuple, list)) and not (
        isinstance(holes, np.ndarray) and holes.ndim == 3
    ):
        return False
    try:
        return bool(np.ndim(obj[0]) == 2)
    except ValueError:  # ragged
        return False


def signed_area(points: NDArray[np.float64]) -> float:
    """Shoelace signed area of a 2-D polygon: positive when counter-clockwise.

    Computed on coordinates centred on the bounding box (no cancellation at
    offsets such as UTM's 500000, 4600000) and summed with ``math.fsum``; one
    power-of-two scaling keeps the products in range for any finite input.

    >>> signed_area(np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]]))
    1.0
    """
    p = np.asarray(points, dtype=np.float64)[:, :2]
    if len(p) == 0:
        return 0.0
    lo, hi = p.min(axis=0), p.max(axis=0)
    q = p - (lo + (hi - lo) / 2)
    big = float(np.abs(q).max())
    if big == 0.0 or not math.isfinite(big):
        return 0.0 if big == 0.0 else math.nan
    s = -math.frexp(big)[1]  # exact scaling: |q| < 1 while summing
    q = np.ldexp(q, s)
    x, y = q[:, 0], q[:, 1]
    cross = x * following(y) - following(x) * y
    return math.ldexp(0.5 * math.fsum(cross.tolist()), -2 * s)


def newell_normal(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Newell's area vector of a 3-D polygon (twice its vector area), on centred points."""
    centred = points - points.mean(axis=0)
    nxt = following(centred)
    return np.cross(centred, nxt).sum(axis=0)


def _lowest(points: NDArray[np.float64]) -> int:
    """Index of the lowest vertex, the leftmost among equals, the first among repeats.

    Exact comparisons, O(n) (a lexicographic sort took 15 us at n = 1000).

    >>> _lowest(np.array([[2., 0.], [1., 1.], [1., 0.], [1., 0.]]))
    2
    """
    y = points[:, 1]
    low = np.flatnonzero(y == y.min())
    return int(low[np.argmin(points[low, 0])])


def _is_strictly_convex(points: NDArray[np.float64], signs: NDArray[np.int64]) -> bool:
    """Every turn strictly one way and the boundary winding once (a pentagram winds twice).

    With every turn the same way, the edge direction turns monotonically, by less
    than pi a step, so it enters the half-plane of directions "up, or horizontal
    eastwards" once per winding, in either orientation: counted exactly.
    Such a ring bounds a convex polygon of which every vertex is a corner, so
    its vertices are distinct.

    >>> square = np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]])
    >>> _is_strictly_convex(square, turn_signs(square))
    True
    >>> twice = np.concatenate((square, square))      # around the square twice
    >>> _is_strictly_convex(twice, turn_signs(twice))
    False
    """
    if not (np.all(signs > 0) or np.all(signs < 0)):
        return False
    x, y = points[:, 0], points[:, 1]
    nx, ny = following(x), following(y)
    upper = (ny > y) | ((ny == y) & (nx > x))
    return int(np.count_nonzero(~upper & following(upper))) == 1


def _refuse_folded(points: NDArray[np.float64]) -> None:
    """The lowest vertex is straight: the boundary folds back there; name the edges."""
    hit = find_self_intersection(points)
    if hit is not None:
        raise not_simple_error(hit[0], hit[1], len(points), hit[2])  # input order kept here
    raise InvalidPolygonError(
        f"the boundary turns back on itself at vertex {_lowest(points)}: not a simple polygon"
    )


def _require_finite(arr: NDArray[np.float64]) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        row = int(np.argwhere(bad)[0][0])
        raise InvalidPolygonError(f"vertex {row} has a non-finite coordinate ({arr[row].tolist()})")


def _require_distinct(arr: NDArray[np.float64]) -> None:
    nxt = following(arr)
    same = np.all(arr == nxt, axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % arr.shape[0]
        raise InvalidPolygonError(f"vertex {j} repeats vertex {i}; remove duplicates")
    # any repeat at all? equal rows are neighbours once sorted (10x faster than np.unique)
    rows = arr[np.lexsort(arr.T[::-1])]
    if not np.all(rows[1:] == rows[:-1], axis=1).any():
        return
    _, first, counts = np.unique(arr, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        row = arr[first[np.flatnonzero(counts > 1)[0]]]
        idx = np.flatnonzero(np.all(arr == row, axis=1))
        raise InvalidPolygonError(
            f"vertex {int(idx[1])} repeats vertex {int(idx[0])}; remove duplicates"
        )


def _plane_basis(points: NDArray[np.float64]) -> tuple[Any, Any, Any, Any]:
    """``(centred, normal, u, v)``: centred points scaled below 1 and an orthonormal basis.

    The normal is Newell's (so a simple polygon projects counter-clockwise);
    where the polygon has no net area (a bow-tie) the best-fit plane's. None
    for the basis when all points coincide.
    """
    centred = points - points.mean(axis=0)
    big = float(np.abs(centred).max())
    if big == 0.0:
        return centred, None, None, None
    centred = np.ldexp(centred, -math.frexp(big)[1])  # exact: no overflow in products
    normal = np.cross(centred, following(centred)).sum(axis=0)
    norm = float(np.linalg.norm(normal))
    if norm <= 1e-12:
        normal = np.linalg.svd(centred)[2][-1]
    else:
        normal = normal / norm
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(normal, helper)
    u /= np.linalg.norm(u)
    return centred, normal, u, np.cross(normal, u)


def _planar_or_none(points: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """Coordinates in the polygon's own plane, or None when it is not planar.

    Planar: every vertex within ``config.PLANARITY_RTOL`` times the polygon's
    extent of the plane.
    """
    centred, normal, u, v = _plane_basis(points)
    if normal is None:
        return None
    if np.abs(centred @ normal).max() > config.PLANARITY_RTOL * float(np.abs(centred).max()):
        return None
    return _ccw_projection(centred, u, v)


def _project_to_plane(points: NDArray[np.float64]) -> NDArray[np.float64]:
    centred, normal, u, v = _plane_basis(points)
    if normal is None:
        return points[:, :2].copy()
    return _ccw_projection(centred, u, v)


def _ccw_projection(centred: Any, u: Any, v: Any) -> NDArray[np.float64]:
    """Projection on (u, v), mirrored if needed so the lowest vertex turns left."""
    flat = np.column_stack((centred @ u, centred @ v))
    low = _lowest(flat)
    n = len(flat)
    if turn_signs(flat[[(low - 1) % n, low, (low + 1) % n]])[1] < 0:
        flat[:, 1] = -flat[:, 1]
    return flat


def require_simple(polygon: ArrayLike | Polygon) -> None:
    """Raise :class:`InvalidPolygonError` unless the polygon's boundary is simple.

    The message names the offending edges by input vertex indices, for example
    ``"polygon is not simple: edges 0-1 and 2-3 cross"``.

    Examples
    --------
    >>> require_simple([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> require_simple([[0, 0], [1, 1], [1, 0], [0, 1]])   # a bow-tie
    Traceback (most recent call last):
    ...
    optri.errors.InvalidPolygonError: polygon is not simple: edges 0-1 and 2-3 cross; ...
    """
    poly = as_polygon(polygon)
    pts = poly.planar_points
    if pts is None:
        return
    hit = find_self_intersection(pts)
    if hit is None:
        return
    e, f, how = hit
    raise not_simple_error(_edge_start(poly, e), _edge_start(poly, f), poly.n, how)


def not_simple_error(e: int, f: int, n: int, how: str) -> InvalidPolygonError:
    """The error for input edges ``e -> e+1`` and ``f -> f+1`` meeting (``how``)."""
    e, f = sorted((e, f))
    return InvalidPolygonError(
        f"polygon is not simple: edges {e}-{(e + 1) % n} and {f}-{(f + 1) % n} {how}; "
        f"optri triangulates simple polygons only (untangle or split the boundary)"
    )


def find_self_intersection(points: NDArray[np.float64]) -> tuple[int, int, str] | None:
    """First pair of edges ``(e, f, how)`` that meet improperly, or None.

    Edge ``e`` joins vertex ``e`` to ``e + 1`` (mod n). ``how`` is ``"cross"``
    (proper crossing), ``"touch"`` (non-adjacent edges sharing a point) or
    ``"overlap"`` (adjacent edges folding back on each other). O(n^2) time in
    numpy blocks of ``_BLOCK`` edges, O(n * _BLOCK) memory.
    """
    p = np.asarray(points, dtype=np.float64)
    n = p.shape[0]
    q = following(p)
    lo, hi = np.minimum(p, q), np.maximum(p, q)
    lox, loy, hix, hiy = lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]
    for start in range(0, n, _BLOCK):
        rows = np.arange(start, min(start + _BLOCK, n))
        # bounding boxes first: only overlapping pairs (few, for most polygons) get tested
        near = lox[rows, None] <= hix
        near &= lox <= hix[rows, None]
        near &= loy[rows, None] <= hiy
        near &= loy <= hiy[rows, None]
        r, f = np.nonzero(near)
        e = rows[r]
        keep = f > e
        e, f = e[keep], f[keep]
        hit = segment_pair_fault(p[e], q[e], p[f], q[f], (f == e + 1) | ((e == 0) & (f == n - 1)))
        if hit is not None:
            m, how = hit
            return int(e[m]), int(f[m]), how
    return None


def _edge_start(poly: Polygon, e: int) -> int:
    """Input index u of internal edge ``e`` (e -> e+1) named as input edge u -> u+1."""
    n = poly.n
    u, v = int(poly.order[e]), int(poly.order[(e + 1) % n])
    return u if (u + 1) % n == v else v
