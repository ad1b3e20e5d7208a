"""Geometric predicates: the one place where optri decides the sign of a turn.

Every yes/no question geometry asks (does the boundary turn left here, do two
segments cross, does a chord start into the polygon, does it pass a vertex)
is answered here, vectorized with numpy over leading axes. The compiled
valid-diagonal kernels (:mod:`optri.simple._kernels`) evaluate the same
scalar formula, :func:`orient_sign`.

A turn counts as straight when its cross product is within ``ORIENT_RTOL``
times the product of the two arms' L1 lengths.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from . import config

__all__ = [
    "ORIENT_RTOL",
    "chord_clear",
    "in_cone",
    "on_open_segment",
    "orient",
    "orient_sign",
    "segment_pair_fault",
    "turn_signs",
]

#: Relative tolerance of the orientation tests.
ORIENT_RTOL = 16 * config.GEOMETRY_RTOL

Array = NDArray[np.float64]


def orient_sign(ax, ay, bx, by, cx, cy, tol):  # type: ignore[no-untyped-def]
    """Sign of the turn a -> b -> c (+1 left, -1 right, 0 straight), scalar form.

    Plain Python that numba also compiles (:mod:`optri.simple._kernels`).

    >>> orient_sign(0.0, 0.0, 1.0, 0.0, 1.0, 1.0, ORIENT_RTOL)
    1
    """
    ux = bx - ax
    uy = by - ay
    vx = cx - ax
    vy = cy - ay
    c = ux * vy - uy * vx
    eps = tol * (abs(ux) + abs(uy)) * (abs(vx) + abs(vy))
    if c > eps:
        return 1
    if c < -eps:
        return -1
    return 0


def orient(a: Array, b: Array, c: Array) -> NDArray[np.int64]:
    """Sign of the turn a -> b -> c, broadcasting over leading axes; 0 within tolerance.

    >>> orient(np.array([0., 0.]), np.array([1., 0.]), np.array([[1., 1.], [2., 0.]])).tolist()
    [1, 0]
    """
    u, v = b - a, c - a
    cr = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    eps = ORIENT_RTOL * np.abs(u).sum(axis=-1) * np.abs(v).sum(axis=-1)
    return np.where(cr > eps, 1, np.where(cr < -eps, -1, 0)).astype(np.int64)


def turn_signs(points: Array) -> NDArray[np.int64]:
    """Sign of the turn at each vertex of a closed 2-D polygon (+1 left, -1 right, 0 straight).

    >>> turn_signs(np.array([[0., 0.], [1., 0.], [2., 0.], [1., 1.]])).tolist()
    [1, 0, 1, 1]
    """
    return orient(np.roll(points, 1, axis=0), points, np.roll(points, -1, axis=0))


def on_open_segment(a: Array, b: Array, c: Array) -> NDArray[np.bool_]:
    """For points c collinear with segment ab: c on the segment, other than at a or b."""
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    on = np.all((c >= lo) & (c <= hi), axis=-1)
    return on & ~np.all(c == a, axis=-1) & ~np.all(c == b, axis=-1)


def segment_pair_fault(
    a: Array, b: Array, c: Array, d: Array, adjacent: NDArray[np.bool_]
) -> tuple[int, str] | None:
    """First bad pair among segments ab, cd (rows): ``(row, how)`` or None.

    ``how`` is ``"cross"`` (proper crossing), ``"touch"`` (an endpoint on the
    other segment) or ``"overlap"`` (``adjacent`` segments folding back on each
    other). Segment endpoints are assumed distinct points.
    """
    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    touch = (
        ((o1 == 0) & on_open_segment(a, b, c))
        | ((o2 == 0) & on_open_segment(a, b, d))
        | ((o3 == 0) & on_open_segment(c, d, a))
        | ((o4 == 0) & on_open_segment(c, d, b))
    )
    bad = np.flatnonzero(cross | touch)
    if bad.size == 0:
        return None
    m = int(bad[0])
    return m, "overlap" if adjacent[m] else "cross" if cross[m] else "touch"


def in_cone(p: Array, i: NDArray[np.int64], j: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Whether the chord from vertex i towards vertex j starts into the CCW polygon ``p``."""
    n = p.shape[0]
    prev, nxt = p[(i - 1) % n], p[(i + 1) % n]
    left_of_next = orient(p[i], nxt, p[j]) > 0
    left_of_prev = orient(prev, p[i], p[j]) > 0
    convex = orient(prev, p[i], nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def chord_clear(p: Array, i: NDArray[np.int64], j: NDArray[np.int64]) -> NDArray[np.bool_]:
    """No vertex on the open chord and no proper edge crossing, for chords (i, j) of ``p``."""
    n = p.shape[0]
    a, b = p[i][:, None], p[j][:, None]  # (C, 1, 2)
    v, w = p[None, :], np.roll(p, -1, axis=0)[None, :]  # (1, n, 2)
    sv = orient(a, b, v)
    sw = np.roll(sv, -1, axis=1)
    d = b - a
    t = ((v - a) * d).sum(axis=-1)
    through = (sv == 0) & (t > 0) & (t < (d * d).sum(axis=-1))
    cross = (sv * sw < 0) & (orient(v, w, a) * orient(v, w, b) < 0)
    ends = np.arange(n)[None, :]
    at_end = (ends == i[:, None]) | (ends == j[:, None])
    at_end_next = np.roll(at_end, -1, axis=1)
    blocked = (through & ~at_end) | (cross & ~at_end & ~at_end_next)
    return ~blocked.any(axis=1)
