"""Simple (possibly concave) polygons: which chords a triangulation may use.

A triangulation of a simple polygon uses only *internal diagonals*: chords that
leave each endpoint into the polygon, cross no edge and pass through no other
vertex. Restricting the DP's chords to them (Klincsek 1980) gives the exact
optimum over the polygon's triangulations with every engine. Chords that run
along the boundary through a straight (180 degree) vertex are not diagonals, so
no zero-area triangle can be produced.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import config
from ..engines.interrupts import watched
from ..engines.memory import require_memory
from ..engines.threads import available
from ..errors import InvalidPolygonError, OptriError
from ..polygon import Polygon, as_polygon, find_self_intersection, require_simple
from ..predicates import chord_clear, in_cone, orient

__all__ = [
    "allowed_chords",
    "mask_bytes",
    "valid_diagonals",
    "valid_diagonals_compiled",
    "valid_diagonals_numpy",
    "zero_area_triangles",
]

#: Chords per block of the numpy mask (memory ~ 100 * block * n bytes).
_BLOCK = 256


def allowed_chords(polygon: Polygon) -> NDArray[np.bool_] | None:
    """Chords a triangulation may use, in internal (counter-clockwise) indices.

    None (every chord) for a strictly convex polygon, for vertex values and for
    a skew 3-D polygon; otherwise the polygon must be simple and the result is
    the ``(n, n)`` bool mask of its sides and internal diagonals
    (:func:`valid_diagonals`, planar 3-D input in its own plane). The one
    place that decides which chords exist, for the engines, counting,
    enumeration and sampling alike.

    Raises
    ------
    InvalidPolygonError
        The boundary crosses or touches itself (the message names the edges).

    Examples
    --------
    >>> from optri.polygon import as_polygon
    >>> allowed_chords(as_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])) is None
    True
    """
    if polygon.convex:
        return None
    require_simple(polygon)
    return _diagonals(polygon)


def valid_diagonals(polygon: ArrayLike | Polygon) -> NDArray[np.bool_]:
    """Which chords of a simple polygon are internal diagonals; ``(n, n)`` bool.

    Indices are the polygon's internal (counter-clockwise) order, as the engines
    use. ``mask[i, j]`` (symmetric) is True for a polygon side or for a chord
    that starts into the polygon at both ends (in-cone test), crosses no edge
    properly and passes through no other vertex.

    Raises
    ------
    InvalidPolygonError
        The boundary crosses or touches itself (:func:`require_simple`, which names
        the edges; "internal diagonal" means nothing there), or the vertices are
        not planar.

    Notes
    -----
    Every test is exact (:mod:`optri.predicates`): a chord is a diagonal exactly
    when it is one for the float64 coordinates taken as exact numbers.
    Compiled (``optri._core.simple``): the polygon is ear-clipped (O(n^2)) and
    each vertex sees through that triangulation, narrowing an angular window from
    triangle to triangle (O(n) per vertex, O(n^2) in all); the simplicity check
    before it takes about a quarter of that time.

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
    if poly.planar_points is None:
        raise InvalidPolygonError("valid diagonals need planar vertex coordinates")
    require_simple(poly)
    return _diagonals(poly)


def _diagonals(poly: Polygon) -> NDArray[np.bool_]:
    """:func:`valid_diagonals` of a planar polygon known to be simple."""
    pts = poly.planar_points
    assert pts is not None  # checked by the callers
    require_memory(
        mask_bytes(poly.n),
        f"the chord mask of a {poly.n}-vertex simple polygon",
        "split the polygon into smaller pieces",
    )
    return valid_diagonals_compiled(pts)


def mask_bytes(n: int) -> int:
    """Peak bytes of :func:`valid_diagonals` for ``n`` vertices (about 5 n^2).

    The ``(n, n)`` bool mask, the walk's ``(n, n)`` int32 table of triangles
    left of each edge and the ear-clipping arrays.

    >>> mask_bytes(1000)
    6000000
    """
    return 6 * n * n


def valid_diagonals_compiled(points: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Compiled :func:`valid_diagonals` of CCW ``points``: ear clipping + visibility walk.

    For a simple polygon. Should ear clipping or the walk fail on one that is not
    (this function does not check), a direct check is used instead: each chord
    against the edges outward from its first endpoint, stopping at the first
    blocker (O(n^3) in the worst case). From ``config.MASK_WATCH_MIN_N``
    vertices the kernels run in a helper thread, the walk's rows on every thread
    (:func:`optri.engines.threads.available`), and Ctrl-C stops them at
    the next ear or row.
    """
    from .._core import simple as core

    x = np.ascontiguousarray(points[:, 0], dtype=np.float64)
    y = np.ascontiguousarray(points[:, 1], dtype=np.float64)
    stop = np.zeros(1, dtype=np.int64)
    if len(x) >= config.MASK_WATCH_MIN_N:
        threads = available()
        found: list[tuple[NDArray[np.bool_], bool]] = []
        watched(lambda: found.append(core.diagonals(x, y, stop, threads)), threads, stop, _idle)
        mask, ok = found[0]
    else:
        mask, ok = core.diagonals(x, y, stop, 1)
    if not ok:  # input that is not simple (ear clipping may still succeed on it)
        if find_self_intersection(points) is None:
            raise OptriError(
                "internal error: the ear-clipping triangulation is inconsistent "
                "(a bounded walk stopped); please report this input"
            )
        mask = core.valid_mask(x, y)  # the scan needs no triangulation
    _set_sides(mask)
    return mask


def _idle() -> None:
    """Nothing to report while the mask is computed (the poll of :func:`watched`)."""


def valid_diagonals_numpy(points: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Pure-numpy :func:`valid_diagonals` of CCW ``points``; O(n^3), for small n.

    The same predicates evaluated for every chord against every vertex and
    edge at once: a second implementation, which the tests compare against.
    """
    p = np.asarray(points, dtype=np.float64)
    n = p.shape[0]
    i, j = np.triu_indices(n, 2)
    keep = ~((i == 0) & (j == n - 1))
    i, j = i[keep], j[keep]
    ok = in_cone(p, i, j) & in_cone(p, j, i)
    for lo in range(0, len(i), _BLOCK):
        ci, cj = i[lo : lo + _BLOCK], j[lo : lo + _BLOCK]
        ok[lo : lo + _BLOCK] &= chord_clear(p, ci, cj)
    mask = np.zeros((n, n), dtype=bool)
    mask[i[ok], j[ok]] = True
    mask |= mask.T
    _set_sides(mask)
    return mask


def zero_area_triangles(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> int:
    """How many ``triangles`` (vertex index rows) of 2-D ``points`` have zero area."""
    if len(triangles) == 0:
        return 0
    a, b, c = (points[triangles[:, m]] for m in range(3))
    return int(np.count_nonzero(orient(a, b, c) == 0))


def _set_sides(mask: NDArray[np.bool_]) -> None:
    n = mask.shape[0]
    k = np.arange(n)
    mask[k, (k + 1) % n] = True
    mask[(k + 1) % n, k] = True
    mask[k, k] = False
