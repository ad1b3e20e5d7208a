"""Numba kernels of the compiled engine: one n x n table, filled in place.

Table layout: ``T[i, j]`` (``i < j``) holds the cost of chord ``(i, j)`` and
``T[j, i]`` the same value, so for a cell ``(i, j)`` both operands of every
split, ``cost(i, k)`` = ``T[i, k]`` and ``cost(k, j)`` = ``T[j, k]``, are read
along contiguous rows ``T[i]`` and ``T[j]``.

Two evaluation orders of the one recurrence (``best_split``):

* ``minplus_tiles``: sum objective with an edge-decomposable weight
  ``w(i, k, j) = e(i, k) + e(k, j) + e(i, j)``. The table holds
  ``E = cost + e`` and ``E(i, j) = 2 e(i, j) + min_k E(i, k) + E(k, j)``, a
  pure min-plus product (as in ``ref_mwt.c``). It runs over square tiles of
  cells; tiles on one tile-diagonal are independent (``prange``). A tile first
  takes the "far" splits, whose halves lie in earlier tiles, with a 2 x 4
  register block (two streamed rows ``i`` shared by four columns ``j``), then
  the "near" splits in dependency order.
* ``generic_tiles``: any built-in or numba-compiled weight, ``sum`` or
  ``max``, one table per component of a lexicographic objective, over the
  same tiles, each cell scanning all its splits.
"""

from __future__ import annotations

import sys

import numpy as np
from llvmlite import ir
from numba import njit, prange, types
from numba.core import cgutils
from numba.extending import intrinsic, overload

from ..objective import lex_better
from ..weights import WeightCode
from ._jit_weights import edge_weight, triangle_weight
from .compiled import kernel

__all__ = [
    "NO_GATE",
    "best_split",
    "generic_tiles",
    "minplus_split",
    "minplus_tiles",
    "split_table",
    "subtract_edges",
    "trace",
    "uncached",
]

# Table values are never NaN (weights are checked) but may be +inf (unusable chord),
# so "ninf" must stay off.
_FASTMATH = {"nnan", "nsz", "arcp", "contract", "reassoc"}
NO_GATE = -2  # codes[2] when the problem has no gate
_KBLOCK = 512  # split vertices per pass over a tile: 2 x 64 rows x 512 x 8 B fit in L2


@intrinsic
def _fmin(typingctx, a, b):
    """``llvm.minnum`` (no NaN): unlike ``a if a < b else b`` LLVM vectorizes its reductions."""
    sig = a(a, a)

    def codegen(context, builder, signature, args):
        t = args[0].type
        fn = builder.module.declare_intrinsic("llvm.minnum", [t], ir.FunctionType(t, [t, t]))
        return builder.call(fn, args, fastmath=("nnan", "nsz"))

    return sig, codegen


def _item_pointer(context, builder, signature, args):
    ty = signature.args[0]
    ary = context.make_array(ty)(context, builder, value=args[0])
    return cgutils.get_item_pointer(context, builder, ty, ary, [args[1]], wraparound=False)


@intrinsic
def _fetch_add(typingctx, arr, idx):
    """``arr[idx] += 1`` atomically; the old value (1-D int64 ``arr``)."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        return builder.atomic_rmw("add", ptr, ir.Constant(ir.IntType(64), 1), "seq_cst")

    return types.int64(arr, idx), codegen


@intrinsic
def _load_acquire(typingctx, arr, idx):
    """``arr[idx]``, an atomic load: writes released before it was set are visible."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        return builder.load_atomic(ptr, "acquire", 8)

    return types.int64(arr, idx), codegen


@intrinsic
def _store_release(typingctx, arr, idx, val):
    """``arr[idx] = val`` after every earlier write of this thread (atomic store)."""

    def codegen(context, builder, signature, args):
        ptr = _item_pointer(context, builder, signature, args)
        builder.store_atomic(args[2], ptr, "release", 8)
        return context.get_dummy_value()

    return types.none(arr, idx, val), codegen


# sched_yield (POSIX) or SwitchToThread (Windows): both take nothing, return an int
_YIELD_SYMBOL = "SwitchToThread" if sys.platform == "win32" else "sched_yield"
_SPINS = 2000  # polls of a tile's flag before a waiting thread gives up its CPU


@intrinsic
def _yield_cpu(typingctx):
    """Let the OS run another thread now: a waiter must not starve the thread it waits on."""

    def codegen(context, builder, signature, args):
        fnty = ir.FunctionType(ir.IntType(32), [])
        builder.call(cgutils.get_or_insert_function(builder.module, fnty, _YIELD_SYMBOL), [])
        return context.get_dummy_value()

    return types.none(), codegen


@kernel(inline="always")
def _wait_done(done, idx):
    """Wait until ``done[idx]`` is set: spin briefly, then yield between polls.

    On a machine with more runnable threads than cores, the tile waited on may
    belong to a thread the OS has descheduled; spinning would burn the very CPU
    time it needs.
    """
    spins = 0
    while _load_acquire(done, idx) == 0:
        spins += 1
        if spins >= _SPINS:
            _yield_cpu()


# --- min-plus path (sum of an edge-decomposable weight) -----------------------------


# Inner loops run over slices from index 0: with a loop index LLVM cannot prove
# non-negative, numba's negative-index wraparound turns the vector loads into gathers.


@kernel(fastmath=_FASTMATH, inline="always")
def _rowmin(best, a, b):
    """``min(best, min_k a[k] + b[k])`` over two equal-length contiguous slices."""
    for k in range(a.shape[0]):
        best = _fmin(best, a[k] + b[k])
    return best


@kernel(fastmath=_FASTMATH, inline="always")
def _block24(T, i, j, k0, k1):
    """Cells (i..i+1, j..j+3): two streamed rows shared by four columns."""
    ra, rb = T[i, k0:k1], T[i + 1, k0:k1]
    r0, r1, r2, r3 = T[j, k0:k1], T[j + 1, k0:k1], T[j + 2, k0:k1], T[j + 3, k0:k1]
    a0, a1, a2, a3 = T[i, j], T[i, j + 1], T[i, j + 2], T[i, j + 3]
    b0, b1, b2, b3 = T[i + 1, j], T[i + 1, j + 1], T[i + 1, j + 2], T[i + 1, j + 3]
    for k in range(ra.shape[0]):
        x, y = ra[k], rb[k]
        c0, c1, c2, c3 = r0[k], r1[k], r2[k], r3[k]
        a0 = _fmin(a0, x + c0)
        a1 = _fmin(a1, x + c1)
        a2 = _fmin(a2, x + c2)
        a3 = _fmin(a3, x + c3)
        b0 = _fmin(b0, y + c0)
        b1 = _fmin(b1, y + c1)
        b2 = _fmin(b2, y + c2)
        b3 = _fmin(b3, y + c3)
    T[i, j], T[i, j + 1], T[i, j + 2], T[i, j + 3] = a0, a1, a2, a3
    T[i + 1, j], T[i + 1, j + 1], T[i + 1, j + 2], T[i + 1, j + 3] = b0, b1, b2, b3


@kernel(fastmath=_FASTMATH, inline="always")
def _block44(T, i, j, k0, k1):
    """Cells (i..i+3, j..j+3) over splits k0 <= k < k1: 16 sums per 8 loads.

    The loop runs along contiguous rows ``T[i..i+3]`` and ``T[j..j+3]``; LLVM
    vectorizes it over k, so the 16 minima live in vector registers until the end.
    """
    x0, x1, x2, x3 = T[i, k0:k1], T[i + 1, k0:k1], T[i + 2, k0:k1], T[i + 3, k0:k1]
    y0, y1, y2, y3 = T[j, k0:k1], T[j + 1, k0:k1], T[j + 2, k0:k1], T[j + 3, k0:k1]
    a0, a1, a2, a3 = T[i, j], T[i, j + 1], T[i, j + 2], T[i, j + 3]
    b0, b1, b2, b3 = T[i + 1, j], T[i + 1, j + 1], T[i + 1, j + 2], T[i + 1, j + 3]
    c0, c1, c2, c3 = T[i + 2, j], T[i + 2, j + 1], T[i + 2, j + 2], T[i + 2, j + 3]
    d0, d1, d2, d3 = T[i + 3, j], T[i + 3, j + 1], T[i + 3, j + 2], T[i + 3, j + 3]
    for k in range(x0.shape[0]):
        e0, e1, e2, e3 = y0[k], y1[k], y2[k], y3[k]
        x = x0[k]
        a0, a1, a2, a3 = _fmin(a0, x + e0), _fmin(a1, x + e1), _fmin(a2, x + e2), _fmin(a3, x + e3)
        x = x1[k]
        b0, b1, b2, b3 = _fmin(b0, x + e0), _fmin(b1, x + e1), _fmin(b2, x + e2), _fmin(b3, x + e3)
        x = x2[k]
        c0, c1, c2, c3 = _fmin(c0, x + e0), _fmin(c1, x + e1), _fmin(c2, x + e2), _fmin(c3, x + e3)
        x = x3[k]
        d0, d1, d2, d3 = _fmin(d0, x + e0), _fmin(d1, x + e1), _fmin(d2, x + e2), _fmin(d3, x + e3)
    T[i, j], T[i, j + 1], T[i, j + 2], T[i, j + 3] = a0, a1, a2, a3
    T[i + 1, j], T[i + 1, j + 1], T[i + 1, j + 2], T[i + 1, j + 3] = b0, b1, b2, b3
    T[i + 2, j], T[i + 2, j + 1], T[i + 2, j + 2], T[i + 2, j + 3] = c0, c1, c2, c3
    T[i + 3, j], T[i + 3, j + 1], T[i + 3, j + 2], T[i + 3, j + 3] = d0, d1, d2, d3


@kernel(fastmath=_FASTMATH, inline="always")
def _block11(T, i, j, k0, k1):
    T[i, j] = _rowmin(T[i, j], T[i, k0:k1], T[j, k0:k1])


@kernel(fastmath=_FASTMATH, inline="always")
def _any_allowed(mask, use_mask, i0, i1, j0, j1):
    """Whether any cell of rows i0..i1-1, columns j0..j1-1 is an allowed chord."""
    if not use_mask:
        return True
    for i in range(i0, i1):
        for j in range(j0, j1):
            if mask[i, j]:
                return True
    return False


@kernel(fastmath=_FASTMATH, _nrt=False)
def _far(T, mask, use_mask, i0, i1, j0, j1):
    """``T[i, j] = min(T[i, j], min over i1 <= k < j0 of T[i, k] + T[j, k])``.

    In blocks of 512 splits (4 + 64 rows of 512 doubles stay in L1/L2). With a
    chord mask, blocks of cells that are all disallowed are skipped: a simple
    polygon has few valid diagonals, so most of the product is never needed
    (disallowed cells end up +inf either way).
    """
    if not _any_allowed(mask, use_mask, i0, i1, j0, j1):
        return
    for k0 in range(i1, j0, _KBLOCK):
        k1 = min(j0, k0 + _KBLOCK)
        i = i0
        while i + 4 <= i1:
            j = j0
            while j + 4 <= j1:
                if _any_allowed(mask, use_mask, i, i + 4, j, j + 4):
                    _block44(T, i, j, k0, k1)
                j += 4
            for jj in range(j, j1):
                for ii in range(i, i + 4):
                    _block11(T, ii, jj, k0, k1)
            i += 4
        for ii in range(i, i1):
            for jj in range(j0, j1):
                _block11(T, ii, jj, k0, k1)


@kernel(fastmath=_FASTMATH, inline="always")
def _store(T, pts, code, mask, use_mask, i, j, best):
    """Final ``E(i, j) = best + 2 e(i, j)`` (+inf for a disallowed chord), both halves."""
    if use_mask and not mask[i, j]:
        v = np.inf  # not a diagonal: never used
    else:
        v = best + 2.0 * edge_weight(code, pts, i, j)
    T[i, j] = v
    T[j, i] = v


@kernel(fastmath=_FASTMATH, inline="always")
def _cell(T, pts, code, mask, use_mask, i, j, i1, j0):
    """Cell (i, j) alone: its near splits ``i < k < i1`` and ``j0 <= k < j``."""
    if j == i + 1:
        v = edge_weight(code, pts, i, j)  # a side: cost 0, so E = e
        T[i, j] = v
        T[j, i] = v
        return
    lo, hi = min(i1, j), max(j0, i1)
    best = _rowmin(T[i, j], T[i, i + 1 : lo], T[j, i + 1 : lo])
    best = _rowmin(best, T[i, hi:j], T[j, hi:j])
    _store(T, pts, code, mask, use_mask, i, j, best)


@kernel(fastmath=_FASTMATH, _nrt=False)
def _near24(T, pts, code, mask, use_mask, i, j, i1, j0):
    """Near splits of cells (i..i+1, j..j+3), ``j >= i + 3``, then their final values.

    Splits ``i + 2 <= k < j`` are common to all eight cells and run in the
    register block (below the tile's rows, then left of its columns); the few
    splits through the block's own cells (``k = i + 1`` and ``j <= k < j + 3``)
    follow, in dependency order: row i + 1 left to right, then row i.
    """
    lo, hi = min(i1, j), max(j0, i1)
    if lo > i + 2:
        _block24(T, i, j, i + 2, lo)
    if j > hi:
        _block24(T, i, j, hi, j)
    for r in range(i + 1, i - 1, -1):
        for c in range(j, j + 4):
            best = T[r, c]
            if r == i:
                best = _fmin(best, T[i, i + 1] + T[i + 1, c])
            for k in range(j, c):
                best = _fmin(best, T[r, k] + T[k, c])
            _store(T, pts, code, mask, use_mask, r, c, best)


@kernel(fastmath=_FASTMATH, inline="always")
def _near_block(T, pts, code, mask, use_mask, i, j, i1, j0):
    """Block (i..i+1, j..j+3) off the diagonal: register block, or +inf if all disallowed."""
    if _any_allowed(mask, use_mask, i, i + 2, j, j + 4):
        _near24(T, pts, code, mask, use_mask, i, j, i1, j0)
    else:
        for r in range(i, i + 2):
            for c in range(j, j + 4):
                T[r, c] = np.inf
                T[c, r] = np.inf


@kernel(fastmath=_FASTMATH, _nrt=False)
def _near_rows(T, pts, code, mask, use_mask, r, i1, j0, j1):
    """Rows r and r + 1 of a tile: cells alone where a block does not fit, else blocks."""
    first = max(j0, r + 1)
    jb = max(first, r + 3)  # from here every cell of a 2 x 4 block is a chord
    for c in range(first, min(jb, j1)):
        if c > r + 1:
            _cell(T, pts, code, mask, use_mask, r + 1, c, i1, j0)
        _cell(T, pts, code, mask, use_mask, r, c, i1, j0)
    j = jb
    while j + 4 <= j1:
        _near_block(T, pts, code, mask, use_mask, r, j, i1, j0)
        j += 4
    for c in range(j, j1):
        _cell(T, pts, code, mask, use_mask, r + 1, c, i1, j0)
        _cell(T, pts, code, mask, use_mask, r, c, i1, j0)


@kernel(fastmath=_FASTMATH, _nrt=False)
def _near_waves(T, pts, code, mask, use_mask, i0, i1, j0, j1):
    """Near splits of a tile off the diagonal cut into whole 2 x 4 blocks.

    Block (p, q) (row pair p from the bottom, column quad q from the left)
    needs the blocks below and left of it, so the blocks of one anti-diagonal
    p + q are independent: taken wave by wave, one block's short dependent
    chain (its own cells, one after another) overlaps the next one's loops.
    """
    pairs, quads = (i1 - i0) // 2, (j1 - j0) // 4
    for w in range(pairs + quads - 1):
        for p in range(max(0, w - quads + 1), min(pairs, w + 1)):
            i, j = i1 - 2 - 2 * p, j0 + 4 * (w - p)
            if j < i + 3:  # the block holding side (i1 - 1, j0): cell by cell
                for c in range(j, j + 4):
                    _cell(T, pts, code, mask, use_mask, i + 1, c, i1, j0)
                    _cell(T, pts, code, mask, use_mask, i, c, i1, j0)
            else:
                _near_block(T, pts, code, mask, use_mask, i, j, i1, j0)


@kernel(fastmath=_FASTMATH, _nrt=False)
def _tile(T, pts, code, mask, use_mask, tile, ti, tj):
    n = T.shape[0]
    i0, i1 = ti * tile, min(n, ti * tile + tile)
    j0, j1 = tj * tile, min(n, tj * tile + tile)
    for i in range(i0, i1):
        for j in range(max(j0, i + 2), j1):
            T[i, j] = np.inf
    if tj > ti + 1:
        _far(T, mask, use_mask, i0, i1, j0, j1)
    if tj > ti and (i1 - i0) % 2 == 0 and (j1 - j0) % 4 == 0:
        _near_waves(T, pts, code, mask, use_mask, i0, i1, j0, j1)
        return
    # near splits, in dependency order: rows upwards (in pairs), columns rightwards
    r = i1 - 1
    if (i1 - i0) % 2:
        for c in range(max(j0, r + 1), j1):
            _cell(T, pts, code, mask, use_mask, r, c, i1, j0)
        r -= 1
    while r > i0:
        _near_rows(T, pts, code, mask, use_mask, r - 1, i1, j0, j1)
        r -= 2


@kernel(parallel=True, fastmath=_FASTMATH)
def minplus_tiles(T, pts, code, chords, tile, d0, d1, workers):
    """Fill tile-diagonals ``d0 <= tj - ti < d1`` of the E-table (sum, edge weight).

    ``chords = (mask, use_mask)``, as for :func:`generic_tiles`. Each of
    ``workers`` threads takes the next tile (diagonal by diagonal) from a shared counter and starts
    it once the two tiles it reads last, left of it and below it, are done: no
    barrier between tile-diagonals, so no thread idles at the end of one.
    """
    mask, use_mask = chords
    nt = (T.shape[0] + tile - 1) // tile
    d1 = min(d1, nt)
    order = np.empty((max(0, (d1 - d0) * nt), 2), dtype=np.int64)
    m = 0
    for d in range(d0, d1):
        for t in range(nt - d):
            order[m, 0], order[m, 1] = t, d
            m += 1
    done = np.zeros(nt * nt, dtype=np.int64)  # tile (ti, tj) at ti * nt + tj
    for ti in range(nt):  # tiles of earlier calls
        for tj in range(ti, min(nt, ti + d0)):
            done[ti * nt + tj] = 1
    taken = np.zeros(1, dtype=np.int64)
    for _ in prange(workers):
        while True:
            k = _fetch_add(taken, 0)
            if k >= m:
                break
            t, d = order[k, 0], order[k, 1]
            if d > 0:
                _wait_done(done, t * nt + t + d - 1)
                _wait_done(done, (t + 1) * nt + t + d)
            _tile(T, pts, code, mask, use_mask, tile, t, t + d)
            _store_release(done, t * nt + t + d, 1)


@kernel()
def subtract_edges(out, pts, code):
    """``out[i, j] -= e(i, j)`` above the diagonal: costs from an exported E-table."""
    n = out.shape[0]
    for i in range(n - 1):
        for j in range(i + 1, n):
            out[i, j] -= edge_weight(code, pts, i, j)


@kernel(fastmath=_FASTMATH)
def minplus_split(T, i, j):
    """Smallest k minimizing ``E(i, k) + E(k, j)``; -1 if every split is infinite.

    A vectorized minimum first, then the first split that reaches it (the
    sums are the same additions both times, so equality is exact).
    """
    ri, rj = T[i, i + 1 : j], T[j, i + 1 : j]
    best = _rowmin(np.inf, ri, rj)
    if best == np.inf:
        return -1
    for kk in range(ri.shape[0]):
        if ri[kk] + rj[kk] == best:
            return i + 1 + kk
    return -1


# --- generic path (any compiled weight, sum / max / lexicographic) -------------------
#
# Arguments travel in three packed tuples, built by optri.engines.jit:
#   tables = (T1, T2)            cost tables of components 1 and 2 (T2 read only if lex)
#   weigh  = (pts, codes, gate, verts, order, wfn1, wfn2, wfng)
#            built-in weights by code (codes = [w1, w2, gate weight or NO_GATE]) on
#            pts; a user's numba weights wfn* on the input vertices ``verts``
#            (indices mapped back through ``order``); the gate's threshold gate[0]
#   rule   = (is_max, lex, nan)  combine of each component (max or sum), whether the
#            objective is a lexicographic pair, and the flag a NaN weight sets


def _user_weight(wfn, verts, a, b, c):  # type: ignore[no-untyped-def]
    """A user's numba weight ``wfn(verts, a, b, c)``; NaN where there is none."""


@overload(_user_weight, inline="always")
def _user_weight_impl(wfn, verts, a, b, c):  # type: ignore[no-untyped-def]
    # chosen while typing: a None ``wfn`` (every built-in weight) compiles to a constant
    if isinstance(wfn, types.NoneType):
        return lambda wfn, verts, a, b, c: np.nan
    return lambda wfn, verts, a, b, c: float(wfn(verts, a, b, c))


@kernel(inline="always")
def _weight(code, pts, i, k, j, wfn, verts, order):
    if code == WeightCode.CUSTOM:
        return _user_weight(wfn, verts, order[i], order[k], order[j])
    return triangle_weight(code, pts, i, k, j)


@kernel(inline="always")
def _combine(is_max, a, b, w):
    if is_max:
        return max(a, max(b, w))
    return a + b + w


@kernel(inline="always")
def _gated_first(weigh, i, k, j):
    """Weight of component 1; +inf when a gate is set and the gate weight exceeds it."""
    pts, codes, gate, verts, order = weigh[0], weigh[1], weigh[2], weigh[3], weigh[4]
    w1 = _weight(codes[0], pts, i, k, j, weigh[5], verts, order)
    if codes[2] != NO_GATE:  # a triangle above the gate's threshold is forbidden
        if _weight(codes[2], pts, i, k, j, weigh[7], verts, order) > gate[0]:
            w1 = np.inf
    return w1


# ties of a lexicographic objective: optri.objective's rule, compiled from its source
_lex_better = kernel(inline="always")(lex_better)


@kernel(inline="always")
def best_split(tables, weigh, rule, i, j):
    """The recurrence for one cell: ``(cost1, cost2, k)``, ties to the smallest k.

    ``cost(i, j) = best_k combine(cost(i, k), cost(k, j), w(i, k, j))``, compared
    on component 1, then (``lex``) component 2, component-1 values within
    ``optri.objective.LEX_TIE_RTOL`` counting as equal. A NaN weight sets ``nan[0]``.
    With ``codes[2] != NO_GATE``, a triangle whose weight ``codes[2]`` exceeds
    ``gate[0]`` gets weight +inf (second phase of a max-led lexicographic objective).
    """
    T1, T2 = tables
    is_max, lex, nan = rule
    pts, codes, verts, order = weigh[0], weigh[1], weigh[3], weigh[4]
    b1, b2, arg = np.inf, np.inf, -1
    r1i, r1j = T1[i, i + 1 : j], T1[j, i + 1 : j]
    if lex:
        r2i, r2j = T2[i, i + 1 : j], T2[j, i + 1 : j]
    else:
        r2i, r2j = r1i, r1j
    for kk in range(r1i.shape[0]):
        k = i + 1 + kk
        if r1i[kk] == np.inf or r1j[kk] == np.inf:
            continue  # a half with no triangulation (not a diagonal): skip its weight
        w1 = _gated_first(weigh, i, k, j)
        if w1 != w1:
            nan[0] = 1
            continue
        v1 = _combine(is_max[0], r1i[kk], r1j[kk], w1)
        if not lex:
            if v1 < b1:
                b1, arg = v1, k
            continue
        w2 = _weight(codes[1], pts, i, k, j, weigh[6], verts, order)
        if w2 != w2:
            nan[0] = 1
            continue
        v2 = _combine(is_max[1], r2i[kk], r2j[kk], w2)
        if _lex_better(v1, v2, b1, b2):
            b1, b2, arg = v1, v2, k
    return b1, b2, arg


@kernel(parallel=True)
def generic_tiles(tables, weigh, rule, chords, tile, d0, d1):
    """Fill tile-diagonals ``d0 <= tj - ti < d1`` of the cost table(s).

    ``chords = (mask, use_mask)``. Sides must hold the neutral cost already.
    Tiles on one tile-diagonal are independent; inside a tile, cells go rows
    upwards, columns rightwards, so both halves of every split are final when read.
    """
    T1, T2 = tables
    mask, use_mask = chords
    lex = rule[1]
    n = T1.shape[0]
    nt = (n + tile - 1) // tile
    for d in range(d0, d1):
        for t in prange(nt - d):
            i0, i1 = t * tile, min(n, t * tile + tile)
            j0, j1 = (t + d) * tile, min(n, (t + d) * tile + tile)
            for i in range(i1 - 1, i0 - 1, -1):
                for j in range(max(j0, i + 2), j1):
                    if use_mask and not mask[i, j]:
                        c1, c2 = np.inf, np.inf
                    else:
                        c1, c2, _ = best_split(tables, weigh, rule, i, j)
                    T1[i, j] = c1
                    T1[j, i] = c1
                    if lex:
                        T2[i, j] = c2
                        T2[j, i] = c2


# --- reconstruction and the exported table ---------------------------------------------


@kernel(inline="always")
def _split(tables, weigh, rule, minplus, i, j):
    if minplus:
        return minplus_split(tables[0], i, j)
    return best_split(tables, weigh, rule, i, j)[2]


@kernel()
def trace(tables, weigh, rule, minplus):
    """Optimal triangles from chord (0, n-1) down.

    Re-scans only the O(n) cells on the optimal path. Returns ``(triangles,
    bad)``; ``bad = (i, j)`` of a chord with no finite split, else ``(-1, -1)``.
    The walk is bounded: at most n - 2 triangles, each with i < k < j.
    """
    n = tables[0].shape[0]
    tris = np.empty((max(n - 2, 0), 3), dtype=np.int64)
    stack = np.empty((n, 2), dtype=np.int64)
    top, m = 1, 0
    stack[0, 0], stack[0, 1] = 0, n - 1
    while top > 0:
        top -= 1
        i, j = stack[top, 0], stack[top, 1]
        if j - i < 2:
            continue
        k = _split(tables, weigh, rule, minplus, i, j)
        if k <= i or k >= j or m >= n - 2:
            return tris[:m], (i, j)
        tris[m, 0], tris[m, 1], tris[m, 2] = i, k, j
        m += 1
        stack[top, 0], stack[top, 1] = k, j
        stack[top + 1, 0], stack[top + 1, 1] = i, k
        top += 2
    return tris[:m], (-1, -1)


@kernel(parallel=True)
def split_table(tables, weigh, rule, minplus):
    """Optimal split of every chord (O(n^3): only for an exported table)."""
    n = tables[0].shape[0]
    out = np.full((n, n), -1, dtype=np.int32)
    for i in prange(n):
        for j in range(i + 2, n):
            out[i, j] = _split(tables, weigh, rule, minplus, i, j)
    return out


_TWINS: dict[str, object] = {}


def uncached(name: str) -> object:
    """Kernel ``name`` compiled without the disk cache, for a user's numba weight.

    A user function's type differs in every process, so caching its
    specializations would only grow the cache; the callees above are inlined,
    so they add no cached entries either.
    """
    if name not in _TWINS:
        cached = globals()[name]
        options = {k: v for k, v in cached.targetoptions.items() if k != "nopython"}
        _TWINS[name] = njit(**options)(cached.py_func)
    return _TWINS[name]
