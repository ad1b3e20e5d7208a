"""Compiled valid-diagonal kernels for simple polygons (numba).

Imported lazily by :func:`optri.simple.valid_diagonals`, so ``import optri``
never loads numba. Under ``NUMBA_DISABLE_JIT=1`` the same code runs as Python.
Serial kernels compile fast (the batch's per-polygon path uses them); a large
polygon's mask runs ``ear_clip_until`` and ``visibility_rows``, which release
the GIL, stop when asked, and walk the rows on every thread.
"""

from __future__ import annotations

import numpy as np
from numba import prange
from numba.extending import register_jitable

from ..engines.compiled import kernel
from ..predicates import COMPILED_HELPERS, orient_sign, strictly_between

__all__ = ["ear_clip", "ear_clip_until", "valid_mask", "visibility_mask", "visibility_rows"]


# the exact predicates of optri.predicates, compiled from the same source: the float
# filter inlined, its exact fallback (expansions, then integers) a call taken rarely
for _helper in COMPILED_HELPERS:
    register_jitable(_helper)
_orient = kernel(inline="always")(orient_sign)
_ROW_STRIDE = 64  # visibility_rows: thread s walks from vertices s, s + 64, s + 128, ...


@kernel()
def _in_cone(x, y, i, j):  # type: ignore[no-untyped-def]
    """Whether the chord from vertex i towards j starts inside the (CCW) polygon."""
    n = x.shape[0]
    p = (i - 1) % n
    q = (i + 1) % n
    left_of_next = _orient(x[i], y[i], x[q], y[q], x[j], y[j]) > 0
    left_of_prev = _orient(x[p], y[p], x[i], y[i], x[j], y[j]) > 0
    if _orient(x[p], y[p], x[i], y[i], x[q], y[q]) > 0:  # convex corner
        return left_of_next and left_of_prev
    return left_of_next or left_of_prev  # reflex or straight: the union of half-planes


@kernel()
def _clear(x, y, i, j):  # type: ignore[no-untyped-def]
    """No vertex on the open chord (i, j) and no edge crossing it properly.

    Vertices are visited outward from i in both directions: the edges that block
    a chord of a simple polygon are most often near its endpoint, so most
    invalid chords stop after a few steps.
    """
    n = x.shape[0]
    for s in range(n - 1):
        off = s // 2 + 1
        a = (i + off) % n if s % 2 == 0 else (i - off) % n
        if a == j:
            continue
        sa = _orient(x[i], y[i], x[j], y[j], x[a], y[a])
        if sa == 0 and strictly_between(x[i], y[i], x[j], y[j], x[a], y[a]):
            return False  # the chord runs through vertex a
        b = (a + 1) % n
        if b == i or b == j:
            continue
        sb = _orient(x[i], y[i], x[j], y[j], x[b], y[b])
        if sa * sb < 0:
            s1 = _orient(x[a], y[a], x[b], y[b], x[i], y[i])
            s2 = _orient(x[a], y[a], x[b], y[b], x[j], y[j])
            if s1 * s2 < 0:
                return False  # edge (a, a+1) crosses the chord
    return True


@kernel()
def _row(x, y, i, out):  # type: ignore[no-untyped-def]
    n = x.shape[0]
    for j in range(i + 2, n):
        if i == 0 and j == n - 1:
            continue  # a polygon side
        if _in_cone(x, y, i, j) and _in_cone(x, y, j, i) and _clear(x, y, i, j):
            out[i, j] = True
            out[j, i] = True


@kernel()
def valid_mask(x, y):  # type: ignore[no-untyped-def]
    """(n, n) bool: ``out[i, j]`` iff chord (i, j) is an internal diagonal.

    The fallback when :func:`ear_clip` fails: O(n^2) to O(n^3). Polygon sides and
    the main diagonal are left False.
    """
    n = x.shape[0]
    out = np.zeros((n, n), dtype=np.bool_)
    for i in range(n):
        _row(x, y, i, out)
    return out


@kernel()
def _blocks_ear(x, y, p, v, q, w):  # type: ignore[no-untyped-def]
    """Whether w lies in the closed counter-clockwise triangle (p, v, q)."""
    return (
        _orient(x[p], y[p], x[v], y[v], x[w], y[w]) >= 0
        and _orient(x[v], y[v], x[q], y[q], x[w], y[w]) >= 0
        and _orient(x[q], y[q], x[p], y[p], x[w], y[w]) >= 0
    )


@kernel()
def _is_ear(x, y, prv, nxt, v):  # type: ignore[no-untyped-def]
    p = prv[v]
    q = nxt[v]
    if _orient(x[p], y[p], x[v], y[v], x[q], y[q]) <= 0:
        return False  # not strictly convex: the triangle would be flat or outside
    w = nxt[q]
    while w != p:
        if _blocks_ear(x, y, p, v, q, w):
            return False
        w = nxt[w]
    return True


@kernel(nogil=True)
def ear_clip(x, y):  # type: ignore[no-untyped-def]
    """Some triangulation of a simple CCW polygon with no zero-area triangle.

    Returns ``(triangles (n-2, 3) int64 CCW, ok)``; ``ok`` is False if no ear
    was found, then the caller falls back to a method that needs no
    triangulation. With exact predicates every simple polygon has an ear (an
    ear triangle whose closed interior holds no other vertex), so ``ok`` is
    False only for input that is not simple. O(n^2) for most polygons.
    """
    return _clip(x, y, np.zeros(1, dtype=np.int64))


@kernel(nogil=True)
def ear_clip_until(x, y, stop):  # type: ignore[no-untyped-def]
    """:func:`ear_clip` without the GIL, returning ``ok`` False once ``stop[0]`` is set."""
    return _clip(x, y, stop)


@kernel()
def _clip(x, y, stop):  # type: ignore[no-untyped-def]
    n = x.shape[0]
    prv = np.empty(n, dtype=np.int64)
    nxt = np.empty(n, dtype=np.int64)
    for k in range(n):
        prv[k] = (k - 1) % n
        nxt[k] = (k + 1) % n
    tris = np.empty((max(n - 2, 0), 3), dtype=np.int64)
    left = n
    v = 0
    misses = 0
    m = 0
    while left > 3:
        if stop[0] != 0:
            return tris, False
        if _is_ear(x, y, prv, nxt, v):
            p = prv[v]
            q = nxt[v]
            tris[m, 0] = p
            tris[m, 1] = v
            tris[m, 2] = q
            m += 1
            nxt[p] = q
            prv[q] = p
            left -= 1
            misses = 0
            v = p  # the new corner at p may have become an ear
        else:
            misses += 1
            if misses > left:
                return tris, False
            v = nxt[v]
    p = prv[v]
    q = nxt[v]
    tris[m, 0] = p
    tris[m, 1] = v
    tris[m, 2] = q
    return tris, True


@kernel()
def _left_triangle(tris, n):  # type: ignore[no-untyped-def]
    """``left[a, b]``: the triangle lying left of the directed edge a -> b, or -1."""
    left = np.full((n, n), -1, dtype=np.int32)
    for t in range(tris.shape[0]):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        left[a, b] = t
        left[b, c] = t
        left[c, a] = t
    return left


@kernel()
def _checked_left(tris, n):  # type: ignore[no-untyped-def]
    """``(left, ok)``: :func:`_left_triangle`; ok False if a triangle names no vertex."""
    for t in range(tris.shape[0]):
        for m in range(3):
            if tris[t, m] < 0 or tris[t, m] >= n:
                return np.full((0, 0), -1, dtype=np.int32), False
    return _left_triangle(tris, n), True


@kernel()
def _third(tris, t, a, b):  # type: ignore[no-untyped-def]
    for m in range(3):
        c = tris[t, m]
        if c != a and c != b:
            return c
    return -1


@kernel()
def _see_from(x, y, tris, left, i, row):  # type: ignore[no-untyped-def]
    """Mark in ``row`` every vertex visible from vertex i through the polygon.

    Walks the triangulation's dual tree from the fan of triangles around i,
    carrying the open angular window (rays i->lo and i->hi) that still reaches
    through the current edge; a vertex strictly inside the window is visible.
    A vertex exactly on a window ray is hidden behind the vertex defining it.
    Returns False, having stopped, if ``tris`` is not a triangulation (the walk
    would leave its bounds): every step is bounded.
    """
    n = x.shape[0]
    # stack rows: directed edge (a, b) with the unvisited triangle on the left of b -> a,
    # and the window rays' vertices (lo on a's side, hi on b's side); each triangulation
    # edge is pushed at most once, so 2n rows always suffice
    stack = np.empty((2 * n, 4), dtype=np.int64)
    top = 0
    a = (i + 1) % n
    t = left[i, a]
    while t >= 0:  # the fan around i, counter-clockwise from side (i, i+1)
        b = _third(tris, t, i, a)
        if b < 0 or top >= n:
            return False  # a fan of more than n - 2 triangles: not a triangulation
        row[a] = True
        row[b] = True
        top = _push(stack, top, a, b, a, b)
        a = b
        t = left[i, a]
    pushes = top
    while top > 0:
        top -= 1
        a, b, lo, hi = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3]
        t = left[b, a]
        if t < 0:
            continue  # a polygon side: the view stops here
        c = _third(tris, t, a, b)
        if c < 0 or pushes + 2 > 2 * n:
            return False  # an edge seen twice: not a triangulation
        past_lo = _orient(x[i], y[i], x[lo], y[lo], x[c], y[c]) > 0
        before_hi = _orient(x[i], y[i], x[hi], y[hi], x[c], y[c]) < 0
        if past_lo and before_hi:
            row[c] = True
            top = _push(stack, top, a, c, lo, c)
            top = _push(stack, top, c, b, c, hi)
            pushes += 2
        elif past_lo:  # c at or beyond the hi ray: the window leaves through edge (a, c)
            top = _push(stack, top, a, c, lo, hi)
            pushes += 1
        else:  # c at or before the lo ray: the window leaves through edge (c, b)
            top = _push(stack, top, c, b, lo, hi)
            pushes += 1
    return True


@kernel(inline="always")
def _push(stack, top, a, b, lo, hi):  # type: ignore[no-untyped-def]
    stack[top, 0] = a
    stack[top, 1] = b
    stack[top, 2] = lo
    stack[top, 3] = hi
    return top + 1


@kernel(nogil=True)
def visibility_mask(x, y, tris):  # type: ignore[no-untyped-def]
    """(n, n) bool vertex visibility from a triangulation ``tris``; O(n^2) in all.

    ``out[i, j]`` iff the open segment (i, j) lies in the polygon's interior
    (sides included, as they are seen too). Returns ``(out, ok)``; ``ok`` is
    False when ``tris`` turned out not to be a triangulation of the polygon
    (every walk is bounded, so a corrupt input stops instead of running away).
    """
    n = x.shape[0]
    out = np.zeros((n, n), dtype=np.bool_)
    left, ok = _checked_left(tris, n)
    if not ok:
        return out, False
    for i in range(n):
        if not _see_from(x, y, tris, left, i, out[i]):
            return out, False
    for i in range(n):
        _both_ways(out, i)
    return out, True


@kernel(inline="always")
def _both_ways(out, i):  # type: ignore[no-untyped-def]
    """Chord (i, j), j > i, is visible iff seen from both ends; writes row i and column i."""
    for j in range(i + 1, out.shape[0]):
        both = out[i, j] and out[j, i]
        out[i, j] = both
        out[j, i] = both


@kernel(parallel=True, nogil=True)
def visibility_rows(x, y, tris, stop):  # type: ignore[no-untyped-def]
    """:func:`visibility_mask` on every numba thread, without the GIL.

    Each vertex's walk writes only its own row, so the rows are independent;
    threads take every ``_ROW_STRIDE``-th row, which spreads rows of unequal
    cost evenly. Returns ``ok`` False once ``stop[0]`` is set (checked before
    each row). The mask is the serial kernel's, bit for bit.
    """
    n = x.shape[0]
    out = np.zeros((n, n), dtype=np.bool_)
    left, ok = _checked_left(tris, n)
    if not ok:
        return out, False
    bad = np.zeros(_ROW_STRIDE, dtype=np.int64)  # one flag per stride: no shared write
    for s in prange(_ROW_STRIDE):
        for i in range(s, n, _ROW_STRIDE):
            if stop[0] != 0 or not _see_from(x, y, tris, left, i, out[i]):
                bad[s] = 1
                break
    if bad.any():
        return out, False
    for i in prange(n):  # row i's thread alone writes row i right of the diagonal, column i below
        _both_ways(out, i)
    return out, True
