"""The one input validator: a :class:`Polygon` from vertex input, or a clear error.

A polygon enters optri as an ``(n, 2)`` or ``(n, 3)`` array of vertices in order,
or as a 1-D sequence of vertex values (matrix-chain style weights need no
geometry). :func:`as_polygon` checks shape, finiteness, distinct vertices,
planarity and orientation and returns a :class:`Polygon` whose *internal*
vertex order is counter-clockwise; engines work on internal indices and results
are mapped back through :attr:`Polygon.order`. :func:`require_simple` checks
that the boundary does not touch itself. Signs of turns are decided in
:mod:`optri.predicates`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import config
from .errors import InvalidPolygonError
from .predicates import segment_pair_fault, turn_signs

__all__ = [
    "Polygon",
    "as_polygon",
    "find_self_intersection",
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
    1-D sequence of vertex values. A last vertex equal to the first is dropped
    (coordinates only: values may repeat).

    Raises
    ------
    InvalidPolygonError
        Not numbers, the wrong shape, NaN or infinite coordinates, fewer than 3
        vertices, or a repeated vertex (the message names both indices).

    Examples
    --------
    >>> normalize_vertices([[0, 0], [1, 0], [0, 1], [0, 0]]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    try:
        arr = np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"vertices must be numbers: {exc}") from exc
    shape_ok = (arr.ndim == 2 and arr.shape[1] in (2, 3)) or (arr.ndim == 1 and values)
    if not shape_ok:
        also = " or a 1-D sequence of values" if values else ""
        raise InvalidPolygonError(
            f"expected an (n, 2) or (n, 3) array of vertices{also}, got shape {arr.shape}"
        )
    _require_finite(arr)
    if arr.ndim == 2 and arr.shape[0] > 3 and np.array_equal(arr[0], arr[-1]):
        arr = arr[:-1]
    n = arr.shape[0]
    if n < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
    if arr.ndim == 2:
        _require_distinct(arr)
    return arr


def as_polygon(data: ArrayLike | Polygon) -> Polygon:
    """Check vertex input and return a :class:`Polygon` in counter-clockwise order.

    Parameters
    ----------
    data : array_like or Polygon
        ``(n, 2)`` or ``(n, 3)`` vertices in order, or a 1-D sequence of values.
        A last vertex equal to the first is dropped (coordinates only: values
        may repeat).

    Returns
    -------
    Polygon

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 vertices, NaN or infinite coordinates, repeated vertices,
        all vertices collinear, or an array of the wrong shape.

    Examples
    --------
    >>> p = as_polygon([[0, 0], [0, 1], [1, 1], [1, 0]])   # clockwise square
    >>> p.orientation, p.order.tolist()
    ('cw', [0, 3, 2, 1])
    """
    if isinstance(data, Polygon):
        return data
    arr = normalize_vertices(data)
    n = arr.shape[0]
    if arr.ndim == 1:
        return Polygon(arr, arr, np.arange(n, dtype=np.int64), None, True)
    planar = arr if arr.shape[1] == 2 else _planar_or_none(arr)
    if planar is None:  # a skew 3-D polygon: every index triangulation is valid
        return Polygon(arr, arr, np.arange(n, dtype=np.int64), None, True)
    if arr.shape[1] == 3:  # planar 3-D: order kept, convexity read in its plane
        convex3 = _is_strictly_convex(planar)
        return Polygon(arr, arr, np.arange(n, dtype=np.int64), None, convex3)
    area = signed_area(planar)
    scale = float(np.ptp(planar, axis=0).max()) ** 2
    if abs(area) <= config.GEOMETRY_RTOL * scale * n:
        _refuse_flat(planar)
    order = np.arange(n, dtype=np.int64)
    orientation = "ccw" if area > 0 else "cw"
    if orientation == "cw":
        order = np.concatenate(([0], np.arange(n - 1, 0, -1))).astype(np.int64)
    internal = arr[order]
    convex = _is_strictly_convex(planar[order])
    return Polygon(arr, internal, order, orientation, convex)


def signed_area(points: NDArray[np.float64]) -> float:
    """Shoelace signed area of a 2-D polygon: positive when counter-clockwise.

    >>> signed_area(np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]]))
    1.0
    """
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def newell_normal(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Newell's area vector of a 3-D polygon (twice its vector area)."""
    nxt = np.roll(points, -1, axis=0)
    return np.cross(points, nxt).sum(axis=0)


def _is_strictly_convex(ccw_points: NDArray[np.float64]) -> bool:
    if np.any(turn_signs(ccw_points) <= 0):
        return False
    # all left turns can still wind twice (a pentagram): total turning must be 2*pi
    edges = np.roll(ccw_points, -1, axis=0) - ccw_points
    ang = np.arctan2(edges[:, 1], edges[:, 0])
    turning = np.mod(np.diff(np.append(ang, ang[0])) + np.pi, 2 * np.pi) - np.pi
    return bool(abs(turning.sum() - 2 * np.pi) < 1e-6)


def _refuse_flat(points: NDArray[np.float64]) -> None:
    """Zero net area: name the crossing edges of a bow-tie, else report collinearity."""
    centred = points - points.mean(axis=0)
    if np.linalg.matrix_rank(centred, tol=config.GEOMETRY_RTOL * float(np.abs(centred).max())) < 2:
        raise InvalidPolygonError("all vertices are collinear: the polygon has no area")
    hit = find_self_intersection(points)
    if hit is not None:
        raise not_simple_error(hit[0], hit[1], len(points), hit[2])  # input order kept here
    raise InvalidPolygonError("all vertices are collinear: the polygon has no area")


def _require_finite(arr: NDArray[np.float64]) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        row = int(np.argwhere(bad)[0][0])
        raise InvalidPolygonError(f"vertex {row} has a non-finite coordinate ({arr[row].tolist()})")


def _require_distinct(arr: NDArray[np.float64]) -> None:
    nxt = np.roll(arr, -1, axis=0)
    same = np.all(arr == nxt, axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % arr.shape[0]
        raise InvalidPolygonError(f"vertex {j} repeats vertex {i}; remove duplicates")
    _, first, counts = np.unique(arr, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        row = arr[first[np.flatnonzero(counts > 1)[0]]]
        idx = np.flatnonzero(np.all(arr == row, axis=1))
        raise InvalidPolygonError(
            f"vertex {int(idx[1])} repeats vertex {int(idx[0])}; remove duplicates"
        )


def _plane_basis(points: NDArray[np.float64]) -> tuple[Any, Any, Any]:
    normal = newell_normal(points)
    norm = float(np.linalg.norm(normal))
    if norm == 0.0:
        return None, None, None
    normal = normal / norm
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(normal, helper)
    u /= np.linalg.norm(u)
    return normal, u, np.cross(normal, u)


def _planar_or_none(points: NDArray[np.float64]) -> NDArray[np.float64] | None:
    normal, u, v = _plane_basis(points)
    if normal is None:
        return None
    centred = points - points.mean(axis=0)
    scale = float(np.abs(centred).max())
    if np.abs(centred @ normal).max() > 1e-9 * scale:
        return None
    return np.column_stack((centred @ u, centred @ v))


def _project_to_plane(points: NDArray[np.float64]) -> NDArray[np.float64]:
    normal, u, v = _plane_basis(points)
    if normal is None:
        return points[:, :2].copy()
    centred = points - points.mean(axis=0)
    return np.column_stack((centred @ u, centred @ v))


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
    q = np.roll(p, -1, axis=0)
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
