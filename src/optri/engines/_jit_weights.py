"""Compiled triangle weights, selected by :attr:`optri.weights.Weight.code`.

Each function mirrors the Python built-in in :mod:`optri.weights` formula for
formula (same side lengths, same clamping), so the compiled and Python engines
agree to rounding. Vertex data arrive as a 2-D float64 array in internal
order; 1-D vertex values are passed as an ``(n, 1)`` column.
"""

from __future__ import annotations

import math

from numba import njit

from ..weights import (
    CODE_AREA,
    CODE_ASPECT_RATIO,
    CODE_DIAGONAL,
    CODE_MAX_ANGLE,
    CODE_MIN_ANGLE,
    CODE_PERIMETER,
    CODE_PRODUCT,
)

__all__ = ["edge_weight", "triangle_weight"]


@njit(cache=True, inline="always")
def _dist(pts, a, b):
    s = 0.0
    for c in range(pts.shape[1]):
        d = pts[a, c] - pts[b, c]
        s += d * d
    return math.sqrt(s)


@njit(cache=True, inline="always")
def edge_weight(code, pts, a, b):
    """``e(a, b)`` of an edge-decomposable weight (perimeter or diagonal), ``a < b``."""
    d = _dist(pts, a, b)
    if code == CODE_DIAGONAL:
        if b - a == 1 or (a == 0 and b == pts.shape[0] - 1):
            return 0.0  # a polygon side is not a diagonal
        return 0.5 * d
    return d


@njit(cache=True, inline="always")
def _cos(x, y, z):
    """Clamped cosine of the angle opposite side ``x``; -1 (angle pi) if degenerate."""
    den = 2.0 * y * z
    if den == 0.0:
        return -1.0  # the Python version returns pi, whose cosine this is
    return max(-1.0, min(1.0, (y * y + z * z - x * x) / den))


@njit(cache=True)
def _area(pts, i, k, j):
    if pts.shape[1] == 2:
        ux, uy = pts[k, 0] - pts[i, 0], pts[k, 1] - pts[i, 1]
        vx, vy = pts[j, 0] - pts[i, 0], pts[j, 1] - pts[i, 1]
        return 0.5 * abs(ux * vy - uy * vx)
    u0, u1, u2 = pts[k, 0] - pts[i, 0], pts[k, 1] - pts[i, 1], pts[k, 2] - pts[i, 2]
    v0, v1, v2 = pts[j, 0] - pts[i, 0], pts[j, 1] - pts[i, 1], pts[j, 2] - pts[i, 2]
    cx = u1 * v2 - u2 * v1
    cy = u2 * v0 - u0 * v2
    cz = u0 * v1 - u1 * v0
    return 0.5 * math.sqrt(cx * cx + cy * cy + cz * cz)


@njit(cache=True)
def triangle_weight(code, pts, i, k, j):
    """Built-in weight ``code`` of triangle ``(i, k, j)``; NaN for an unknown code."""
    if code == CODE_PERIMETER or code == CODE_DIAGONAL:
        return (
            edge_weight(code, pts, i, k)
            + edge_weight(code, pts, k, j)
            + edge_weight(code, pts, i, j)
        )
    if code == CODE_AREA:
        return _area(pts, i, k, j)
    if code == CODE_PRODUCT:
        return pts[i, 0] * pts[k, 0] * pts[j, 0]
    a, b, c = _dist(pts, k, j), _dist(pts, i, j), _dist(pts, i, k)
    # acos is decreasing: the largest angle has the smallest cosine (one acos, not three)
    if code == CODE_MAX_ANGLE:
        return math.acos(min(_cos(a, b, c), _cos(b, c, a), _cos(c, a, b)))
    if code == CODE_MIN_ANGLE:
        return -math.acos(max(_cos(a, b, c), _cos(b, c, a), _cos(c, a, b)))
    if code == CODE_ASPECT_RATIO:
        s = 0.5 * (a + b + c)
        q = (s - a) * (s - b) * (s - c)
        if q <= 0.0:
            return math.inf
        return a * b * c / (8.0 * q)  # R / (2 r)
    return math.nan
