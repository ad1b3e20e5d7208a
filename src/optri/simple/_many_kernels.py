"""Many small polygons in one compiled call: checks, chord mask and DP, parallel over polygons.

Imported lazily by :mod:`optri.batch.compiled` (``import optri`` never loads
numba). Polygons arrive as ragged arrays: all vertices concatenated in ``xy``
(``(m, 2)`` float64, as given: a closing vertex may still be there) and, per
polygon, its first row and row count. Each polygon goes through, in one
compiled function:

1. the checks of :func:`optri.polygon.normalize_vertices` and
   :func:`optri.polygon.as_polygon` (finite, closing vertices dropped, at
   least 3 vertices, all distinct, orientation from the exact turn at the
   lowest vertex, strict convexity) and, unless convex, the exact simplicity
   test of :func:`optri.polygon.find_self_intersection`, all with the exact
   predicates of :mod:`optri.predicates`;
2. the valid-diagonal mask of :mod:`optri.simple._kernels` (ear clipping and
   the visibility walk), in internal (counter-clockwise) order;
3. the recurrence of :mod:`optri.engines._jit_kernels`: ``best_split`` cell
   by cell and ``trace`` for the triangles, so the split rule, the tie rule
   (smallest k) and the arithmetic are the compiled engine's. Two modes give
   the bits of the engine ``optri.triangulate`` would run: ``MODE_PYTHON``
   (the Python engines' ``cost(i, k) + cost(k, j) + w(i, k, j)``) and
   ``MODE_FAST`` (the compiled engine: the min-plus E-table for a sum of an
   edge-decomposable weight, else the same cells as ``MODE_PYTHON``). A sum of
   an edge-decomposable weight in ``MODE_PYTHON`` takes its edge weights from
   a table and records its splits as it goes (``best_split``'s arithmetic and
   rule, unrolled), then walks them as ``trace`` does.

A polygon that fails any check, or whose DP ends in NaN, an infinite cost or
an inconsistent walk, gets a non-zero status and no result: the caller solves
it with :func:`optri.triangulate`, which raises the exact error (or warning).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from ..engines._jit_kernels import NO_GATE, best_split, trace
from ..engines._jit_weights import edge_weight
from ..engines._minplus import FASTMATH as MINPLUS_FASTMATH
from ..engines.compiled import kernel
from ..predicates import orient_sign, strictly_between
from ._kernels import ear_clip, valid_mask, visibility_mask

__all__ = [
    "MINPLUS_FASTMATH",
    "MODE_FAST",
    "MODE_NONE",
    "MODE_PYTHON",
    "STATUS",
    "solve_chunk",
]

#: ``modes[n]``: how a polygon of n vertices is solved (``MODE_NONE``: not here).
MODE_NONE, MODE_PYTHON, MODE_FAST = 0, 1, 2
#: Status codes of :func:`solve_chunk`, by name: 0 is solved, any other falls back.
STATUS = {
    "ok": 0,
    "non-finite": 1,
    "too few vertices": 2,
    "repeated vertex": 3,
    "no turn at the lowest vertex": 4,
    "not simple": 5,
    "size not taken": 6,
    "mask walk failed": 7,
    "no finite optimum": 8,
    "zero-area triangle": 9,
}
_OK, _NONFINITE, _FEW, _REPEAT, _FLAT, _NOT_SIMPLE, _SIZE, _MASK, _DP, _ZERO = range(10)

_orient = kernel(inline="always")(orient_sign)
_between = kernel(inline="always")(strictly_between)


@kernel()
def _lowest(x, y, n):  # type: ignore[no-untyped-def]
    """Index of the lowest vertex, the leftmost among equals (as ``np.lexsort``)."""
    low = 0
    for v in range(1, n):
        if y[v] < y[low] or (y[v] == y[low] and x[v] < x[low]):
            low = v
    return low


@kernel()
def _normalized(xy, s, count):  # type: ignore[no-untyped-def]
    """``(status, n)``: normalize_vertices' checks on rows ``s .. s + count - 1``."""
    for v in range(s, s + count):
        if not (math.isfinite(xy[v, 0]) and math.isfinite(xy[v, 1])):
            return _NONFINITE, count
    n = count
    while n > 3 and xy[s, 0] == xy[s + n - 1, 0] and xy[s, 1] == xy[s + n - 1, 1]:
        n -= 1  # closing vertices
    if n < 3:
        return _FEW, n
    for a in range(s, s + n):
        for b in range(a + 1, s + n):
            if xy[a, 0] == xy[b, 0] and xy[a, 1] == xy[b, 1]:
                return _REPEAT, n
    return _OK, n


@kernel()
def _strictly_convex(x, y):  # type: ignore[no-untyped-def]
    """as_polygon's convexity of CCW ``x, y``: every turn strictly left, winding once."""
    n = x.shape[0]
    winds = 0
    for v in range(n):
        p, q = (v - 1) % n, (v + 1) % n
        if _orient(x[p], y[p], x[v], y[v], x[q], y[q]) <= 0:
            return False
        w = (q + 1) % n
        up_v = y[q] > y[v] or (y[q] == y[v] and x[q] > x[v])
        up_q = y[w] > y[q] or (y[w] == y[q] and x[w] > x[q])
        if not up_v and up_q:
            winds += 1
    return winds == 1


@kernel(inline="always")
def _on_open_segment(ax, ay, bx, by, cx, cy):  # type: ignore[no-untyped-def]
    """predicates.on_open_segment for one point: in the closed box, not an endpoint."""
    inside = min(ax, bx) <= cx <= max(ax, bx) and min(ay, by) <= cy <= max(ay, by)
    return inside and not (cx == ax and cy == ay) and not (cx == bx and cy == by)


@kernel()
def _pair_fault(x, y, e, f):  # type: ignore[no-untyped-def]
    """predicates.segment_pair_fault for edges e -> e+1 and f -> f+1: they cross or touch."""
    n = x.shape[0]
    e1, f1 = (e + 1) % n, (f + 1) % n
    ax, ay, bx, by = x[e], y[e], x[e1], y[e1]
    cx, cy, dx, dy = x[f], y[f], x[f1], y[f1]
    if min(ax, bx) > max(cx, dx) or min(cx, dx) > max(ax, bx):
        return False  # bounding boxes apart
    if min(ay, by) > max(cy, dy) or min(cy, dy) > max(ay, by):
        return False
    o1 = _orient(ax, ay, bx, by, cx, cy)
    o2 = _orient(ax, ay, bx, by, dx, dy)
    o3 = _orient(cx, cy, dx, dy, ax, ay)
    o4 = _orient(cx, cy, dx, dy, bx, by)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return (
        (o1 == 0 and _on_open_segment(ax, ay, bx, by, cx, cy))
        or (o2 == 0 and _on_open_segment(ax, ay, bx, by, dx, dy))
        or (o3 == 0 and _on_open_segment(cx, cy, dx, dy, ax, ay))
        or (o4 == 0 and _on_open_segment(cx, cy, dx, dy, bx, by))
    )


@kernel()
def _is_simple(x, y):  # type: ignore[no-untyped-def]
    """No two edges cross, touch or fold back (find_self_intersection finds nothing)."""
    n = x.shape[0]
    for e in range(n):
        for f in range(e + 1, n):
            if _pair_fault(x, y, e, f):
                return False
    return True


@kernel()
def _chord_mask(x, y):  # type: ignore[no-untyped-def]
    """``(mask, ok)``: simple.valid_diagonals_compiled of CCW ``x, y``, sides set."""
    n = x.shape[0]
    tris, ok = ear_clip(x, y)
    if ok:
        mask, ok = visibility_mask(x, y, tris)
    else:
        mask, ok = valid_mask(x, y), True
    for v in range(n):
        w = (v + 1) % n
        mask[v, w] = True
        mask[w, v] = True
        mask[v, v] = False
    return mask, ok


@kernel()
def _fill_cells(T, weigh, rule, mask, use_mask, neutral):  # type: ignore[no-untyped-def]
    """Every chord's cost by ``best_split``, shortest chords first (Python engines' values)."""
    n = T.shape[0]
    for i in range(n - 1):
        T[i, i + 1] = neutral
        T[i + 1, i] = neutral
    tables = (T, T)
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            c = np.inf
            if not use_mask or mask[i, j]:
                c = best_split(tables, weigh, rule, i, j)[0]
            T[i, j] = c
            T[j, i] = c


@kernel()
def _fill_edge_sums(T, S, pts, code, mask, use_mask):  # type: ignore[no-untyped-def]
    """The Python engines' table for a sum of an edge-decomposable weight, and its splits.

    ``cost(i, j) = min_k cost(i, k) + cost(k, j) + w(i, k, j)`` with
    ``w = (e(i, k) + e(k, j)) + e(i, j)``, added in that order as
    ``best_split`` and the Python engines do, from edge weights computed once;
    ``S[i, j]`` is the smallest optimal k (``best_split``'s rule), -1 if none.
    """
    n = T.shape[0]
    e = np.zeros((n, n))  # 0 where not a chord: its cost is +inf, so never chosen
    for i in range(n):
        for j in range(i + 1, n):
            if not use_mask or mask[i, j]:
                e[i, j] = edge_weight(code, pts, i, j)
                e[j, i] = e[i, j]
    for i in range(n - 1):
        T[i, i + 1] = 0.0
        T[i + 1, i] = 0.0
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            best, arg = np.inf, -1
            if not use_mask or mask[i, j]:
                ri, rj, ei, ej, eij = T[i], T[j], e[i], e[j], e[i, j]
                for k in range(i + 1, j):
                    c = ri[k] + rj[k] + ((ei[k] + ej[k]) + eij)
                    if c < best:
                        best, arg = c, k
            T[i, j] = best
            T[j, i] = best
            S[i, j] = arg


@kernel()
def _walk(S, tris):  # type: ignore[no-untyped-def]
    """``trace``'s bounded walk from chord (0, n-1) over recorded splits; True if whole."""
    n = S.shape[0]
    stack = np.empty((n, 2), dtype=np.int64)
    top, m = 1, 0
    stack[0, 0], stack[0, 1] = 0, n - 1
    while top > 0:
        top -= 1
        i, j = stack[top, 0], stack[top, 1]
        if j - i < 2:
            continue
        k = S[i, j]
        if k <= i or k >= j or m >= n - 2:
            return False
        tris[m, 0], tris[m, 1], tris[m, 2] = i, k, j
        m += 1
        stack[top, 0], stack[top, 1] = k, j
        stack[top + 1, 0], stack[top + 1, 1] = i, k
        top += 2
    return m == n - 2


# The min-plus E-table below compiles with the compiled engine's own flags, which let
# LLVM fuse the side lengths' squares (FMA): the table is the engine's bit for bit only
# with the same flags. Costs stay non-negative sums and minima, never NaN.
@kernel(fastmath=MINPLUS_FASTMATH)
def _fill_minplus(E, pts, code, mask, use_mask):  # type: ignore[no-untyped-def]
    """The compiled engine's E-table: ``E(i, j) = min_k E(i, k) + E(k, j) + 2 e(i, j)``.

    Sides hold ``e``; chords that are not diagonals +inf. The minimum is exact in
    any order, so the values are the min-plus kernel's, bit for bit.
    """
    n = E.shape[0]
    for i in range(n - 1):
        v = edge_weight(code, pts, i, i + 1)
        E[i, i + 1] = v
        E[i + 1, i] = v
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            v = np.inf
            if not use_mask or mask[i, j]:
                best = np.inf
                for k in range(i + 1, j):
                    best = min(best, E[i, k] + E[j, k])
                v = best + 2.0 * edge_weight(code, pts, i, j)
            E[i, j] = v
            E[j, i] = v


@kernel()
def _optimum(pts, code, is_max, edge, minplus, mask, use_mask):  # type: ignore[no-untyped-def]
    """``(cost, triangles, ok)`` of the CCW polygon ``pts`` by the recurrence."""
    n = pts.shape[0]
    T = np.empty((n, n), dtype=np.float64)
    order = np.arange(n)
    codes = np.array([code, code, NO_GATE], dtype=np.int64)
    gate = np.array([np.inf])
    weigh = (pts, codes, gate, pts, order, None, None, None)
    nan = np.zeros(1, dtype=np.int64)
    rule = (np.array([is_max, is_max]), False, nan)
    if edge and not minplus:  # splits recorded: the walk needs no second scan
        S = np.empty((n, n), dtype=np.int64)
        _fill_edge_sums(T, S, pts, code, mask, use_mask)
        tris = np.empty((n - 2, 3), dtype=np.int64)
        ok = _walk(S, tris)
        cost = T[0, n - 1]
    else:
        if minplus:
            _fill_minplus(T, pts, code, mask, use_mask)
            cost = T[0, n - 1] - edge_weight(code, pts, 0, n - 1)
            tris, bad = trace((T, T), None, None)
        else:
            _fill_cells(T, weigh, rule, mask, use_mask, -np.inf if is_max else 0.0)
            cost = T[0, n - 1]
            tris, bad = trace((T, T), weigh, rule)
        ok = bad[0] < 0 and nan[0] == 0 and tris.shape[0] == n - 2
    ok = ok and (cost == -np.inf or math.isfinite(cost))
    return cost, tris, ok


@kernel()
def _solve_one(xy, s, count, modes, code, is_max, edge, tris_out, t0):  # type: ignore[no-untyped-def]
    """``(status, n, cw, cost)`` of one polygon; its triangles (input indices) from row t0."""
    status, n = _normalized(xy, s, count)
    if status != _OK:
        return status, n, False, np.nan
    if n >= modes.shape[0] or modes[n] == MODE_NONE:
        return _SIZE, n, False, np.nan
    x = np.empty(n)
    y = np.empty(n)
    low = _lowest(xy[s : s + n, 0], xy[s : s + n, 1], n)
    p, q = s + (low - 1) % n, s + (low + 1) % n
    turn = _orient(xy[p, 0], xy[p, 1], xy[s + low, 0], xy[s + low, 1], xy[q, 0], xy[q, 1])
    if turn == 0:
        return _FLAT, n, False, np.nan
    cw = turn < 0
    order = np.empty(n, dtype=np.int64)
    for v in range(n):
        order[v] = (n - v) % n if cw else v  # internal (CCW) -> input index
        x[v] = xy[s + order[v], 0]
        y[v] = xy[s + order[v], 1]
    use_mask = not _strictly_convex(x, y)
    mask = np.ones((1, 1), dtype=np.bool_)
    if use_mask:
        if not _is_simple(x, y):
            return _NOT_SIMPLE, n, cw, np.nan
        mask, ok = _chord_mask(x, y)
        if not ok:
            return _MASK, n, cw, np.nan
    pts = np.empty((n, 2))
    pts[:, 0] = x
    pts[:, 1] = y
    minplus = modes[n] == MODE_FAST and edge
    cost, tris, ok = _optimum(pts, code, is_max, edge, minplus, mask, use_mask)
    if not ok:
        return _DP, n, cw, np.nan
    for t in range(n - 2):
        a, b, c = tris[t, 0], tris[t, 1], tris[t, 2]
        if _orient(x[a], y[a], x[b], y[b], x[c], y[c]) == 0:
            return _ZERO, n, cw, np.nan
        for m in range(3):
            tris_out[t0 + t, m] = order[tris[t, m]]
    return _OK, n, cw, cost


@kernel(parallel=True)
def solve_chunk(xy, starts, counts, perm, modes, code, is_max, edge, threads, out):  # type: ignore[no-untyped-def]
    """Solve polygon ``p`` from rows ``starts[p] .. starts[p] + counts[p] - 1`` of ``xy``.

    ``out = (status, sizes, cw, costs, tris)``: per polygon its status
    (:data:`STATUS`), vertex count after closing vertices are dropped,
    orientation and optimal cost, and its ``n - 2`` triangles (input indices)
    in ``tris`` from row ``starts[p] - 2 p``. Polygons are taken in the order
    ``perm`` (largest first), dealt round-robin to ``threads`` workers so each
    gets an even share of the work.
    """
    status, sizes, cw, costs, tris = out
    m = starts.shape[0]
    for t in prange(threads):
        for r in range(t, m, threads):
            p = perm[r]
            st, n, c, cost = _solve_one(
                xy, starts[p], counts[p], modes, code, is_max, edge, tris, starts[p] - 2 * p
            )
            status[p] = st
            sizes[p] = n
            cw[p] = c
            costs[p] = cost
