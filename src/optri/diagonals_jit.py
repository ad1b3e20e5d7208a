"""Compiled valid-diagonal kernel for simple polygons (numba, parallel over rows).

Imported lazily by :func:`optri.simple.valid_diagonals`, so ``import optri``
never loads numba. Under ``NUMBA_DISABLE_JIT=1`` the same code runs as Python.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

__all__ = ["valid_mask"]


@njit(cache=True, inline="always")
def _orient(ax, ay, bx, by, cx, cy, tol):  # type: ignore[no-untyped-def]
    """Sign of the turn a -> b -> c, 0 within a tolerance relative to both arms."""
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


@njit(cache=True)
def _in_cone(x, y, i, j, tol):  # type: ignore[no-untyped-def]
    """Does the chord from vertex i towards j start inside the polygon (CCW order)?"""
    n = x.shape[0]
    p = (i - 1) % n
    q = (i + 1) % n
    left_of_next = _orient(x[i], y[i], x[q], y[q], x[j], y[j], tol) > 0
    left_of_prev = _orient(x[p], y[p], x[i], y[i], x[j], y[j], tol) > 0
    if _orient(x[p], y[p], x[i], y[i], x[q], y[q], tol) > 0:  # convex corner
        return left_of_next and left_of_prev
    return left_of_next or left_of_prev  # reflex or straight: the union of half-planes


@njit(cache=True)
def _clear(x, y, i, j, tol):  # type: ignore[no-untyped-def]
    """No vertex on the open chord (i, j) and no edge crossing it properly.

    Vertices are visited outward from i in both directions: the edges that block
    a chord of a simple polygon are most often near its endpoint, so most
    invalid chords stop after a few steps.
    """
    n = x.shape[0]
    dx = x[j] - x[i]
    dy = y[j] - y[i]
    for s in range(n - 1):
        off = s // 2 + 1
        a = (i + off) % n if s % 2 == 0 else (i - off) % n
        if a == j:
            continue
        sa = _orient(x[i], y[i], x[j], y[j], x[a], y[a], tol)
        if sa == 0:
            t = (x[a] - x[i]) * dx + (y[a] - y[i]) * dy
            if 0.0 < t < dx * dx + dy * dy:
                return False  # the chord runs through vertex a
        b = (a + 1) % n
        if b == i or b == j:
            continue
        sb = _orient(x[i], y[i], x[j], y[j], x[b], y[b], tol)
        if sa * sb < 0:
            s1 = _orient(x[a], y[a], x[b], y[b], x[i], y[i], tol)
            s2 = _orient(x[a], y[a], x[b], y[b], x[j], y[j], tol)
            if s1 * s2 < 0:
                return False  # edge (a, a+1) crosses the chord
    return True


@njit(cache=True)
def _row(x, y, i, tol, out):  # type: ignore[no-untyped-def]
    n = x.shape[0]
    for j in range(i + 2, n):
        if i == 0 and j == n - 1:
            continue  # a polygon side
        if _in_cone(x, y, i, j, tol) and _in_cone(x, y, j, i, tol) and _clear(x, y, i, j, tol):
            out[i, j] = True
            out[j, i] = True


@njit(cache=True, parallel=True)
def valid_mask(x, y, tol):  # type: ignore[no-untyped-def]
    """(n, n) bool: ``out[i, j]`` iff chord (i, j) is an internal diagonal.

    Rows t and n-1-t go to the same task so every task checks about n chords.
    Polygon sides and the main diagonal are left False.
    """
    n = x.shape[0]
    out = np.zeros((n, n), dtype=np.bool_)
    for t in prange((n + 1) // 2):
        _row(x, y, t, tol, out)
        if n - 1 - t != t:
            _row(x, y, n - 1 - t, tol, out)
    return out
