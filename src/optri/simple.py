"""Simple (possibly concave) polygons: simplicity check and the valid-diagonal mask.

A triangulation of a simple polygon uses only *internal diagonals*: chords that
leave each endpoint into the polygon, cross no edge and pass through no other
vertex. Restricting the DP's chords to them (Klincsek 1980) gives the exact
optimum over the polygon's triangulations with every engine. Chords that run
along the boundary through a straight (180 degree) vertex are not diagonals, so
no zero-area triangle can be produced.
"""

from __future__ import annotations

import sys

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import config
from .errors import InvalidPolygonError
from .geometry import Polygon, as_polygon

__all__ = [
    "count_table",
    "count_triangulations_mask",
    "find_self_intersection",
    "not_simple_error",
    "require_simple",
    "valid_diagonals",
    "valid_diagonals_compiled",
    "valid_diagonals_numpy",
    "zero_area_triangles",
]

#: Relative tolerance of the orientation tests (same scale as geometry.turn_signs).
ORIENT_RTOL = 16 * config.GEOMETRY_RTOL
#: Up to this n the numpy O(n^3) mask is used: it is instant there and needs no numba.
NUMPY_MAX_N = 48
#: Edges per block in the O(n^2) simplicity check (memory ~ 100 * block * n bytes).
_BLOCK = 256


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
        hit = _edge_pair_faults(p[e], q[e], p[f], q[f], (f == e + 1) | ((e == 0) & (f == n - 1)))
        if hit is not None:
            m, how = hit
            return int(e[m]), int(f[m]), how
    return None


def _edge_pair_faults(
    a: NDArray, b: NDArray, c: NDArray, d: NDArray, adjacent: NDArray[np.bool_]
) -> tuple[int, str] | None:
    """First bad pair among segments ab, cd (rows): crossing, touching or folding."""
    o1, o2 = _orient(a, b, c), _orient(a, b, d)
    o3, o4 = _orient(c, d, a), _orient(c, d, b)
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    # an endpoint on the other segment, other than a shared vertex (vertices are distinct)
    touch = (
        ((o1 == 0) & _inside(a, b, c))
        | ((o2 == 0) & _inside(a, b, d))
        | ((o3 == 0) & _inside(c, d, a))
        | ((o4 == 0) & _inside(c, d, b))
    )
    # adjacent edges share a vertex and never cross properly: only folding back is bad
    bad = np.flatnonzero(cross | touch)
    if bad.size == 0:
        return None
    m = int(bad[0])
    return m, "overlap" if adjacent[m] else "cross" if cross[m] else "touch"


def valid_diagonals(polygon: ArrayLike | Polygon) -> NDArray[np.bool_]:
    """Which chords of a simple polygon are internal diagonals; ``(n, n)`` bool.

    Indices are the polygon's internal (counter-clockwise) order, as the engines
    use. ``mask[i, j]`` (symmetric) is True for a polygon side or for a chord
    that starts into the polygon at both ends (in-cone test), crosses no edge
    properly and passes through no other vertex. The polygon is assumed simple
    (see :func:`require_simple`).

    Notes
    -----
    Compiled with numba: the polygon is ear-clipped (O(n^2)) and each vertex
    sees through that triangulation, narrowing an angular window from triangle to
    triangle (O(n) per vertex, O(n^2) in all). Should ear clipping fail on
    inconsistent rounding, a direct check is used instead: each chord against
    the edges outward from its first endpoint, stopping at the first blocker
    (O(n^3) in the worst case).
    Up to ``NUMPY_MAX_N`` vertices while numba is not loaded yet, and without
    numba, :func:`valid_diagonals_numpy` is used (same result).

    Examples
    --------
    >>> m = valid_diagonals([[0, 0], [4, 0], [1, 1], [0, 4]])   # reflex vertex 2
    >>> m.astype(int)
    array([[0, 1, 1, 1],
           [1, 0, 1, 0],
           [1, 1, 0, 1],
           [1, 0, 1, 0]])
    """
    poly = as_polygon(polygon)
    pts = poly.planar_points
    if pts is None:
        raise InvalidPolygonError("valid diagonals need planar vertex coordinates")
    if poly.n <= NUMPY_MAX_N and "numba" not in sys.modules:
        return valid_diagonals_numpy(pts)  # small: not worth starting numba for
    try:
        return valid_diagonals_compiled(pts)
    except ImportError:  # pragma: no cover - numba is a core dependency
        return valid_diagonals_numpy(pts)


def valid_diagonals_compiled(points: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Compiled :func:`valid_diagonals` of CCW ``points``: ear clipping + visibility walk."""
    from .diagonals_jit import ear_clip, valid_mask, visibility_mask

    x = np.ascontiguousarray(points[:, 0], dtype=np.float64)
    y = np.ascontiguousarray(points[:, 1], dtype=np.float64)
    tris, ok = ear_clip(x, y, ORIENT_RTOL)
    mask = visibility_mask(x, y, tris, ORIENT_RTOL) if ok else valid_mask(x, y, ORIENT_RTOL)
    _set_sides(mask)
    return mask


def valid_diagonals_numpy(points: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Pure-numpy :func:`valid_diagonals` of CCW ``points``; O(n^3), for small n.

    The same predicates evaluated for every chord against every vertex and
    edge at once; used without numba and as a second implementation in tests.
    """
    p = np.asarray(points, dtype=np.float64)
    n = p.shape[0]
    i, j = np.triu_indices(n, 2)
    keep = ~((i == 0) & (j == n - 1))
    i, j = i[keep], j[keep]
    ok = _in_cone(p, i, j) & _in_cone(p, j, i)
    for lo in range(0, len(i), _BLOCK):
        ci, cj = i[lo : lo + _BLOCK], j[lo : lo + _BLOCK]
        ok[lo : lo + _BLOCK] &= _clear(p, ci, cj)
    mask = np.zeros((n, n), dtype=bool)
    mask[i[ok], j[ok]] = True
    mask |= mask.T
    _set_sides(mask)
    return mask


def count_triangulations_mask(ok: NDArray[np.bool_]) -> int:
    """Number of triangulations of the index polygon using chords allowed by ``ok``.

    Exact (Python ints), O(n^3); sides are always allowed.

    >>> count_triangulations_mask(np.ones((6, 6), dtype=bool))   # Catalan(4)
    14
    """
    n = ok.shape[0]
    allow = np.array(ok, dtype=bool)
    _set_sides(allow)
    return count_table(allow.tolist())[0][n - 1]


def count_table(ok: list[list[bool]]) -> list[list[int]]:
    """``count[i][j]``: triangulations of sub-polygon i..j over the allowed chords.

    ``count[i][j]`` is 0 when chord (i, j) is not allowed; sides count 1. The
    recurrence is count(i, j) = sum_k count(i, k) count(k, j) (Klincsek 1980).
    """
    n = len(ok)
    cnt = [[0] * n for _ in range(n)]
    for i in range(n - 1):
        cnt[i][i + 1] = 1
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            if not ok[i][j]:
                continue
            row_i = cnt[i]
            cnt[i][j] = sum(row_i[k] * cnt[k][j] for k in range(i + 1, j) if ok[i][k] and ok[k][j])
    return cnt


def zero_area_triangles(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> int:
    """How many ``triangles`` (vertex index rows) of 2-D ``points`` have zero area."""
    if len(triangles) == 0:
        return 0
    a, b, c = (points[triangles[:, m]] for m in range(3))
    return int(np.count_nonzero(_orient(a, b, c) == 0))


def _edge_start(poly: Polygon, e: int) -> int:
    """Input index u of internal edge ``e`` (e -> e+1) named as input edge u -> u+1."""
    n = poly.n
    u, v = int(poly.order[e]), int(poly.order[(e + 1) % n])
    return u if (u + 1) % n == v else v


def _set_sides(mask: NDArray[np.bool_]) -> None:
    n = mask.shape[0]
    k = np.arange(n)
    mask[k, (k + 1) % n] = True
    mask[(k + 1) % n, k] = True
    mask[k, k] = False


def _orient(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray:
    """Sign of the turn a -> b -> c (broadcasting over leading axes), 0 within tolerance."""
    u, v = b - a, c - a
    cr = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    eps = ORIENT_RTOL * np.abs(u).sum(axis=-1) * np.abs(v).sum(axis=-1)
    return np.where(cr > eps, 1, np.where(cr < -eps, -1, 0))


def _inside(a: NDArray, b: NDArray, c: NDArray) -> NDArray[np.bool_]:
    """For c collinear with segment ab: c on the segment, other than at a or b."""
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    on = np.all((c >= lo) & (c <= hi), axis=-1)
    return on & ~np.all(c == a, axis=-1) & ~np.all(c == b, axis=-1)


def _in_cone(p: NDArray[np.float64], i: NDArray, j: NDArray) -> NDArray[np.bool_]:
    n = p.shape[0]
    prev, nxt = p[(i - 1) % n], p[(i + 1) % n]
    left_of_next = _orient(p[i], nxt, p[j]) > 0
    left_of_prev = _orient(prev, p[i], p[j]) > 0
    convex = _orient(prev, p[i], nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def _clear(p: NDArray[np.float64], i: NDArray, j: NDArray) -> NDArray[np.bool_]:
    """No vertex on the open chord and no proper edge crossing, for chords (i, j)."""
    n = p.shape[0]
    a, b = p[i][:, None], p[j][:, None]  # (C, 1, 2)
    v, w = p[None, :], np.roll(p, -1, axis=0)[None, :]  # (1, n, 2)
    sv = _orient(a, b, v)
    sw = np.roll(sv, -1, axis=1)
    d = b - a
    t = ((v - a) * d).sum(axis=-1)
    through = (sv == 0) & (t > 0) & (t < (d * d).sum(axis=-1))
    cross = (sv * sw < 0) & (_orient(v, w, a) * _orient(v, w, b) < 0)
    ends = np.arange(n)[None, :]
    at_end = (ends == i[:, None]) | (ends == j[:, None])
    at_end_next = np.roll(at_end, -1, axis=1)
    blocked = (through & ~at_end) | (cross & ~at_end & ~at_end_next)
    return ~blocked.any(axis=1)
