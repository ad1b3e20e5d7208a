"""Validate and normalize polygon input; orientation and convexity predicates.

A polygon enters optri as an ``(n, 2)`` or ``(n, 3)`` array of vertices in order,
or as a 1-D sequence of vertex values (matrix-chain style weights need no
geometry). :func:`as_polygon` checks it and returns a :class:`Polygon` whose
*internal* vertex order is counter-clockwise; engines work on internal indices
and results are mapped back through :attr:`Polygon.order`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import config
from .errors import InvalidPolygonError

__all__ = [
    "Polygon",
    "as_polygon",
    "newell_normal",
    "require_convex",
    "signed_area",
    "turn_signs",
]


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
    try:
        arr = np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"vertices must be numbers: {exc}") from exc
    if arr.ndim == 2 and arr.shape[1] not in (2, 3) or arr.ndim not in (1, 2):
        raise InvalidPolygonError(
            f"expected an (n, 2) or (n, 3) array of vertices or a 1-D sequence of "
            f"values, got shape {arr.shape}"
        )
    _require_finite(arr)
    if arr.ndim == 2 and arr.shape[0] > 3 and np.array_equal(arr[0], arr[-1]):
        arr = arr[:-1]
    n = arr.shape[0]
    if n < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
    if arr.ndim == 1:
        return Polygon(arr, arr, np.arange(n, dtype=np.int64), None, True)
    _require_distinct(arr)
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


def require_convex(polygon: Polygon) -> None:
    """Raise :class:`InvalidPolygonError` unless ``polygon`` is strictly convex.

    The message names the first reflex or collinear vertex (input index).
    """
    if polygon.convex:
        return
    pts = polygon.planar_points
    assert pts is not None
    signs = turn_signs(pts)
    bad = np.flatnonzero(signs <= 0)
    if bad.size:
        v = int(polygon.order[bad[0]])
        kind = "collinear with its neighbours" if signs[bad[0]] == 0 else "reflex"
        raise InvalidPolygonError(
            f"polygon is not convex: vertex {v} is {kind}; the convex solvers need a "
            f"strictly convex polygon (simple polygons: see optri.triangulate docs)"
        )
    raise InvalidPolygonError("polygon is not convex: its boundary winds around more than once")


def signed_area(points: NDArray[np.float64]) -> float:
    """Shoelace signed area of a 2-D polygon: positive when counter-clockwise.

    >>> signed_area(np.array([[0., 0.], [1., 0.], [1., 1.], [0., 1.]]))
    1.0
    """
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def turn_signs(points: NDArray[np.float64]) -> NDArray[np.int64]:
    """Sign of the turn at each vertex (+1 left, -1 right, 0 collinear).

    Collinearity uses a tolerance relative to the two adjacent edge lengths.
    """
    prev = points - np.roll(points, 1, axis=0)
    nxt = np.roll(points, -1, axis=0) - points
    cross = prev[:, 0] * nxt[:, 1] - prev[:, 1] * nxt[:, 0]
    tol = config.GEOMETRY_RTOL * np.hypot(*prev.T) * np.hypot(*nxt.T) * 16
    return np.where(cross > tol, 1, np.where(cross < -tol, -1, 0)).astype(np.int64)


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
    from .simple import find_self_intersection, not_simple_error  # simple builds on geometry

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
