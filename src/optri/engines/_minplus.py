"""The min-plus fill of the compiled engine: sum of an edge-decomposable weight.

With ``w(i, k, j) = e(i, k) + e(k, j) + e(i, j)`` the table holds
``E = cost + e`` and ``E(i, j) = 2 e(i, j) + min_k E(i, k) + E(k, j)``: a
pure min-plus product (as in ``ref_mwt.c``). ``T[i, j]`` (``i < j``) holds
``E(i, j)``; the fill reads and writes nothing on or below the diagonal.

Every split is evaluated by one register block, ``outer_4x16`` of
:mod:`optri.engines._llvm` (4 rows x 16 columns of cells held in vector
registers while the split ``k`` runs; operands ``T[i, k]`` and row
``T[k, j:j + 16]``), or ``outer_8x16`` where vectors are 64 bytes wide
(``_ROWS``), in an order that makes almost all of the work a dense product of
finished cells:

* tiles of ``tile x tile`` cells, taken from a queue by each thread; a tile
  starts when the tiles left of it and below it are done;
* in a tile, the "far" splits (between its rows and its columns) first: one
  dense product, whose ``B`` rows are first copied into a contiguous buffer
  along table rows (``_far``; 8 x 16 register blocks where vectors are 64
  bytes wide). A tile
  on an even tile-diagonal applies most of the far splits of the tile above
  it too, from the same copy (``_tile``);
* then the "near" splits, by recursive halving of the tile (bottom-left,
  bottom-right, top-left, top-right): before a quarter is solved, the splits
  through quarters already finished are applied to it as dense products (the
  large ones, ``_PACK`` cells of ``B`` or more, packed as the far ones, ``_near``);
  only blocks of at most ``_LEAF`` rows or columns go cell by cell.

The trace reads the splits of a chord ``(i, j)`` from row ``i`` and column
``j`` (``minplus_split``); for an exported table, whose every chord's split is
needed, the table is first copied to its lower half (``mirror_table``), where
column ``j`` is row ``j``.

A diagonal tile (a triangle) halves into two triangles and the square
between them. The minimum of a set of sums does not depend on the order they
are taken in, so every order gives the same table, bit for bit.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from ._jit_weights import edge_weight, edge_weight_row
from ._llvm import (
    block_rows,
    claim_at,
    copy_8,
    fetch_add,
    fmin,
    load_acquire,
    load_at,
    outer_4x4,
    outer_4x8,
    outer_4x16,
    outer_4x16_fresh,
    outer_8x16,
    outer_8x16_fresh,
    store_at,
    store_release,
    transpose_8x8,
    wait_done,
)
from .compiled import kernel

__all__ = [
    "FASTMATH",
    "minplus_split",
    "minplus_tiles",
    "mirror_table",
    "subtract_edges",
    "tile_edges",
    "tile_flags",
    "worker_bytes",
]

# Table values are never NaN (weights are checked) but may be +inf (unusable chord),
# so "ninf" must stay off.
FASTMATH = {"nnan", "nsz", "arcp", "contract", "reassoc"}
_KBLOCK = 256  # splits per pass of a register block over a far product
# rows of _far's packed buffer per strip: one more than a block of splits, so that the
# copy's stores of a table row (one per strip, 32 KB apart at tile 256 without the spare
# row) do not all fall in one L1 set; on the Xeon of docs/fast-engine.md, one thread's
# far products at n = 4000 took 346 ms with it, 357 ms without
_STRIP = _KBLOCK + 1
# cells of B from which a near product packs B as _far does: on the EPYC of
# docs/fast-engine.md, B read from the table's rows ran the 4 x 16 block at 2.0e10
# candidates/s on 64 x 64 x 64 products and 1.7-1.8e10 on 128^3, against 2.3-2.5e10
# packed, copy included; at 32^3 the copy cost more than it saved (2.1e10 against 2.4e10)
_PACK = 64 * 64
_LEAF = 4  # blocks this small (rows or columns) are solved cell by cell
_ROWS = block_rows()  # rows of the dense products' register block: 8 or 4


@kernel(fastmath=FASTMATH, inline="always")
def _rowmin(best, a, b):
    """``min(best, min_k a[k] + b[k])`` over two equal-length contiguous slices."""
    # Runs over slices from index 0: with a loop index LLVM cannot prove non-negative,
    # numba's negative-index wraparound turns the vector loads into gathers.
    for k in range(a.shape[0]):
        best = fmin(best, a[k] + b[k])
    return best


@kernel(fastmath=FASTMATH, inline="always")
def _colmin(best, T, i, j, k0, k1):
    """``min(best, min over k0 <= k < k1 of T[i, k] + T[k, j])``: row ``i``, column ``j``.

    For the few cells at the edges of blocks.
    """
    for k in range(k0, k1):
        best = fmin(best, T[i, k] + T[k, j])
    return best


@kernel(fastmath=FASTMATH, inline="always")
def _any_allowed(mask, i0, i1, j0, j1):
    """Whether any cell of rows i0..i1-1, columns j0..j1-1 is an allowed chord."""
    if mask is None:
        return True
    for i in range(i0, i1):
        for j in range(j0, j1):
            if mask[i, j]:
                return True
    return False


@kernel(fastmath=FASTMATH, inline="always")
def _block(T, mask, i, j, k0, kn, cols):
    """Register block rows ``i..i+3`` x ``cols`` (16, 8 or 4) columns from ``j``, ``kn`` splits.

    Skipped when no cell of it is an allowed chord.
    """
    if _any_allowed(mask, i, i + 4, j, j + cols):
        if cols == 16:
            outer_4x16(T, i, j, T, i, k0, T, k0, j, kn)
        elif cols == 8:
            outer_4x8(T, i, j, T, i, k0, T, k0, j, kn)
        else:
            outer_4x4(T, i, j, T, i, k0, T, k0, j, kn)


@kernel(fastmath=FASTMATH, _nrt=False)
def _product(T, mask, rows, ia, ib, ja, jb, k0, k1):
    """``T[i, j] = min(T[i, j], min over k0 <= k < k1 of T[i, k] + T[k, j])``.

    For rows ``ia <= i < ib``, columns ``ja <= j < jb``; every operand cell
    must be final. With ``rows`` = 8 (``_ROWS`` where vectors are 64 bytes
    wide), the whole 8 x 16 blocks first; the rest in 4 x 16 register blocks
    (4 x 8, then cell by cell, at the edges), ``_KBLOCK`` splits at a time so
    that a block's rows stay in L1. With a chord mask, blocks whose cells are all
    disallowed are skipped: a simple polygon has few valid diagonals, so most
    of the product is never needed (disallowed cells end up +inf either way).
    """
    if rows == 8:
        i8 = ia + (ib - ia) // 8 * 8
        jf = ja + (jb - ja) // 16 * 16
        for kb in range(k0, k1, _KBLOCK):
            kn = min(k1, kb + _KBLOCK) - kb
            for i in range(ia, i8, 8):
                for j in range(ja, jf, 16):
                    if _any_allowed(mask, i, i + 8, j, j + 16):
                        outer_8x16(T, i, j, T, i, kb, T, kb, j, kn)
        _product4(T, mask, ia, i8, jf, jb, k0, k1)
        _product4(T, mask, i8, ib, ja, jb, k0, k1)
    else:
        _product4(T, mask, ia, ib, ja, jb, k0, k1)


@kernel(fastmath=FASTMATH, _nrt=False)
def _product4(T, mask, ia, ib, ja, jb, k0, k1):
    """``_product`` in 4-row register blocks."""
    if k1 <= k0 or ib <= ia or jb <= ja:
        return
    for kb in range(k0, k1, _KBLOCK):
        ke = min(k1, kb + _KBLOCK)
        i = ia
        while i + 4 <= ib:
            j = ja
            while j + 16 <= jb:
                _block(T, mask, i, j, kb, ke - kb, 16)
                j += 16
            for cols in (8, 4):
                if j + cols <= jb:
                    _block(T, mask, i, j, kb, ke - kb, cols)
                    j += cols
            for r in range(i, i + 4):
                for c in range(j, jb):
                    T[r, c] = _colmin(T[r, c], T, r, c, kb, ke)
            i += 4
        for r in range(i, ib):
            for c in range(ja, jb):
                T[r, c] = _colmin(T[r, c], T, r, c, kb, ke)


@kernel(fastmath=FASTMATH, _nrt=False)
def _far(T, P, rows, ia, ib, ja, jb, k0, k1, fresh=False):
    """``_product`` of a tile's far splits, or of a large near product, from packed rows.

    No chord mask. For each block of ``_KBLOCK`` splits, the rows
    ``B[k, j:j + 16]`` of each 16-column strip are first copied into ``P``:
    strip ``s`` at rows ``s * _STRIP`` on, its splits one after another. The
    copy runs along table rows: row ``k``'s whole strips, one contiguous run of
    the table which the hardware prefetches, go to the ``k``-th row of every
    strip, 64 bytes at a time (``copy_8``). Copied strip by strip instead, one
    short piece per table row, the copy took a quarter of the far product's
    time on the Xeon of ``docs/fast-engine.md``. The register block, ``rows``
    x 16 (``_ROWS``), then reads its ``B`` operand as one contiguous run.
    Columns and rows beyond whole strips and blocks go through ``_product``.
    The candidates are the same sums, so the result is the same, bit for bit.
    ``P`` holds ``_STRIP`` rows for each of a tile's whole strips, enough for
    any near product of the tile, whose columns are at most the tile's.

    ``fresh`` (with ``k0 < k1``): the cells start from +inf, not from the table,
    whose values are not read: the first block of splits writes the whole
    strips without loading them (``outer_4x16_fresh``, ``outer_8x16_fresh``),
    and only the cells beyond them are set to +inf first. A tile's first far
    product so needs no pass of its own that sets the tile to +inf, whose
    stores, one cache line after another, each waited for the line to be taken
    from the other CPU.
    """
    jf = ja + (jb - ja) // 16 * 16
    i_f = ia + (ib - ia) // rows * rows
    if fresh:
        _fill_inf(T, ia, ib, jf, jb)
        _fill_inf(T, i_f, ib, ja, jf)
    for kb in range(k0, k1, _KBLOCK):
        kn = min(k1, kb + _KBLOCK) - kb
        for t in range(kn):  # row kb + t of B, whole strips, into each strip's run
            for s in range((jf - ja) // 16):
                copy_8(T, kb + t, ja + 16 * s, P, s * _STRIP + t, 0)
                copy_8(T, kb + t, ja + 16 * s + 8, P, s * _STRIP + t, 8)
        first = fresh and kb == k0
        for i in range(ia, i_f, rows):
            for s in range((jf - ja) // 16):
                if rows == 8 and first:
                    outer_8x16_fresh(T, i, ja + 16 * s, T, i, kb, P, s * _STRIP, 0, kn)
                elif rows == 8:
                    outer_8x16(T, i, ja + 16 * s, T, i, kb, P, s * _STRIP, 0, kn)
                elif first:
                    outer_4x16_fresh(T, i, ja + 16 * s, T, i, kb, P, s * _STRIP, 0, kn)
                else:
                    outer_4x16(T, i, ja + 16 * s, T, i, kb, P, s * _STRIP, 0, kn)
    _product(T, None, rows, ia, ib, jf, jb, k0, k1)
    _product(T, None, rows, i_f, ib, ja, jf, k0, k1)


@kernel(fastmath=FASTMATH, inline="always")
def _near(T, mask, P, ia, ib, ja, jb, k0, k1):
    """``_product`` between the quarters of a block of near splits.

    Without a chord mask, a product whose ``B`` holds ``_PACK`` cells or more is
    packed first, as the far products' are (``_far``).
    """
    if mask is None and (k1 - k0) * (jb - ja) >= _PACK:
        _far(T, P, _ROWS, ia, ib, ja, jb, k0, k1)
    else:
        _product(T, mask, _ROWS, ia, ib, ja, jb, k0, k1)


@kernel(fastmath=FASTMATH, inline="always")
def _edge(ew, i, j):
    """``e(i, j)`` from the tile's edge weights ``ew = (W, i0, j0)``: ``W[i - i0, j - j0]``."""
    W, wi, wj = ew
    return load_at(W, i - wi, j - wj)


@kernel(fastmath=FASTMATH, inline="always")
def _final(T, ew, mask, i, j, best):
    """Store and return ``E(i, j) = best + 2 e(i, j)`` (a side: ``e``; disallowed: +inf).

    ``ew = (W, i0, j0)``: ``e(i, j)`` is ``W[i - i0, j - j0]``. Only
    ``T[i, j]`` is written.
    """
    if j == i + 1:  # a side: cost 0
        v = T.dtype.type(_edge(ew, i, j))
        store_at(T, i, j, v)
        return v
    return _final_chord(T, ew, mask, i, j, best)


@kernel(fastmath=FASTMATH, inline="always")
def _final_chord(T, ew, mask, i, j, best):
    """``_final`` of a cell that is not a side (``j > i + 1``)."""
    v = best + 2.0 * _edge(ew, i, j)
    if mask is not None and not mask[i, j]:
        v = np.inf  # not a diagonal: never used
    v = T.dtype.type(v)
    store_at(T, i, j, v)
    return v  # as stored (float32 rounds it), not reloaded: no store-to-load wait


@kernel(fastmath=FASTMATH, inline="always")
def _cell(T, ew, mask, i, j, b, c):
    """Final value of cell (i, j): its splits ``i < k < b`` and ``c <= k < j``, then 2 e.

    Every other split must be applied already.
    """
    best = _colmin(T[i, j], T, i, j, i + 1, min(b, j))
    best = _colmin(best, T, i, j, c, j)
    _final(T, ew, mask, i, j, best)


@kernel(fastmath=FASTMATH, inline="always")
def _min3(x, y, z):
    return fmin(fmin(x, y), z)


@kernel(fastmath=FASTMATH, inline="always")
def _min4(w, x, y, z):
    return fmin(fmin(w, x), fmin(y, z))


@kernel(fastmath=FASTMATH, inline="always")
def _row4(T, i, c):
    """Cells (i, c) to (i, c + 3)."""
    return load_at(T, i, c), load_at(T, i, c + 1), load_at(T, i, c + 2), load_at(T, i, c + 3)


@kernel(fastmath=FASTMATH, inline="always")
def _upper4(T, a):
    """The six chords inside vertices a..a + 3: (a, a + 1), (a, a + 2), ..., (a + 2, a + 3)."""
    return (
        load_at(T, a, a + 1),
        load_at(T, a, a + 2),
        load_at(T, a, a + 3),
        load_at(T, a + 1, a + 2),
        load_at(T, a + 1, a + 3),
        load_at(T, a + 2, a + 3),
    )


@kernel(fastmath=FASTMATH, _nrt=False)
def _leaf4(T, ew, mask, a, c):
    """Block rows [a, a + 4) x columns [c, c + 4), ``a + 4 <= c``, in straight-line code.

    ``xrq`` is cell (a + r, c + q). Its splits run through the rows' triangle
    (``arr'``, final) and the cells below it (``xr'q``), and through the cells
    left of it (``xrq'``) and the columns' triangle (``bq'q``, final). The
    values stay in registers; each cell takes its left neighbour last, so the
    chain from cell to cell is one addition and one minimum. Only cell
    (a + 3, c) can be a polygon side (where ``c = a + 4``). The cells are read
    with ``load_at``: every index here is non-negative, and numba's
    wraparound of them took over a quarter of the leaf's instructions.
    """
    a01, a02, a03, a12, a13, a23 = _upper4(T, a)
    b01, b02, b03, b12, b13, b23 = _upper4(T, c)
    c1, c2, c3 = c + 1, c + 2, c + 3
    i = a + 3
    t0, t1, t2, t3 = _row4(T, i, c)
    x30 = _final(T, ew, mask, i, c, t0)
    x31 = _final_chord(T, ew, mask, i, c1, fmin(t1, x30 + b01))
    x32 = _final_chord(T, ew, mask, i, c2, _min3(t2, x30 + b02, x31 + b12))
    m = _min3(t3, x30 + b03, x31 + b13)
    x33 = _final_chord(T, ew, mask, i, c3, fmin(m, x32 + b23))
    i = a + 2
    t0, t1, t2, t3 = _row4(T, i, c)
    x20 = _final_chord(T, ew, mask, i, c, fmin(t0, a23 + x30))
    m = fmin(t1, a23 + x31)
    x21 = _final_chord(T, ew, mask, i, c1, fmin(m, x20 + b01))
    m = _min3(t2, a23 + x32, x20 + b02)
    x22 = _final_chord(T, ew, mask, i, c2, fmin(m, x21 + b12))
    m = _min4(t3, a23 + x33, x20 + b03, x21 + b13)
    x23 = _final_chord(T, ew, mask, i, c3, fmin(m, x22 + b23))
    i = a + 1
    t0, t1, t2, t3 = _row4(T, i, c)
    x10 = _final_chord(T, ew, mask, i, c, _min3(t0, a12 + x20, a13 + x30))
    m = _min3(t1, a12 + x21, a13 + x31)
    x11 = _final_chord(T, ew, mask, i, c1, fmin(m, x10 + b01))
    m = _min4(t2, a12 + x22, a13 + x32, x10 + b02)
    x12 = _final_chord(T, ew, mask, i, c2, fmin(m, x11 + b12))
    m = fmin(_min3(t3, a12 + x23, a13 + x33), _min3(x10 + b03, x11 + b13, x12 + b23))
    x13 = _final_chord(T, ew, mask, i, c3, m)
    i = a
    t0, t1, t2, t3 = _row4(T, i, c)
    m = _min4(t0, a01 + x10, a02 + x20, a03 + x30)
    x00 = _final_chord(T, ew, mask, i, c, m)
    m = _min4(t1, a01 + x11, a02 + x21, a03 + x31)
    x01 = _final_chord(T, ew, mask, i, c1, fmin(m, x00 + b01))
    m = fmin(_min4(t2, a01 + x12, a02 + x22, a03 + x32), x00 + b02)
    x02 = _final_chord(T, ew, mask, i, c2, fmin(m, x01 + b12))
    m = fmin(_min4(t3, a01 + x13, a02 + x23, a03 + x33), _min3(x00 + b03, x01 + b13, x02 + b23))
    _final_chord(T, ew, mask, i, c3, m)


@kernel(fastmath=FASTMATH, _nrt=False)
def _square8(T, ew, mask, a, c):
    """``_square`` of an 8 x 8 block: four leaves, the products between them inline."""
    _leaf4(T, ew, mask, a + 4, c)
    _block(T, mask, a + 4, c + 4, c, 4, 4)
    _leaf4(T, ew, mask, a + 4, c + 4)
    _block(T, mask, a, c, a + 4, 4, 4)
    _leaf4(T, ew, mask, a, c)
    _block(T, mask, a, c + 4, a + 4, 4, 4)
    _block(T, mask, a, c + 4, c, 4, 4)
    _leaf4(T, ew, mask, a, c + 4)


@kernel(fastmath=FASTMATH, _nrt=False)
def _square16(T, ew, mask, a, c):
    """``_square`` of a 16 x 16 block: four 8 x 8 blocks, the products between them."""
    _square8(T, ew, mask, a + 8, c)
    for r in range(a + 8, a + 16, 4):
        _block(T, mask, r, c + 8, c, 8, 8)
    _square8(T, ew, mask, a + 8, c + 8)
    for r in range(a, a + 8, 4):
        _block(T, mask, r, c, a + 8, 8, 8)
    _square8(T, ew, mask, a, c)
    for r in range(a, a + 8, 4):
        _block(T, mask, r, c + 8, a + 8, 8, 8)
        _block(T, mask, r, c + 8, c, 8, 8)
    _square8(T, ew, mask, a, c + 8)


@kernel(fastmath=FASTMATH, _nrt=False)
def _square(T, ew, mask, P, a, b, c, e):
    """Finish block rows [a, b) x columns [c, e), ``b <= c``: its near splits.

    On entry every split outside ``(a, b) + [c, e)`` is applied, and the
    cells left of the block (its rows) and below it (its columns) are final.
    Quarters in order bottom-left, bottom-right, top-left, top-right; before
    each, the splits through the quarters already finished, as products.
    """
    if b - a == 16 and e - c == 16:
        _square16(T, ew, mask, a, c)
        return
    if b - a == 8 and e - c == 8:
        _square8(T, ew, mask, a, c)
        return
    if b - a == 4 and e - c == 4:
        _leaf4(T, ew, mask, a, c)
        return
    if b - a <= _LEAF or e - c <= _LEAF:
        for i in range(b - 1, a - 1, -1):
            for j in range(c, e):
                _cell(T, ew, mask, i, j, b, c)
        return
    m = b - _half(b - a, 4)  # bottom rows [m, b), top rows [a, m)
    m2 = c + _half(e - c, 16)  # left columns [c, m2), right columns [m2, e)
    _square(T, ew, mask, P, m, b, c, m2)
    _near(T, mask, P, m, b, m2, e, c, m2)
    _square(T, ew, mask, P, m, b, m2, e)
    _near(T, mask, P, a, m, c, m2, m, b)
    _square(T, ew, mask, P, a, m, c, m2)
    _near(T, mask, P, a, m, m2, e, m, b)
    _near(T, mask, P, a, m, m2, e, c, m2)
    _square(T, ew, mask, P, a, m, m2, e)


@kernel(inline="always")
def _half(size, unit):
    """Where to halve ``size``: the largest ``unit`` times a power of two below it.

    A tile of 128 halves into 64 and 64; the last tile of n = 1000 (104
    vertices) into 64 and 40, then 32 and 8, so that the halving ends in
    16 x 16 and 8 x 8 blocks, which have straight-line code, and 4 x 4
    leaves. Cutting at the middle rounded to ``unit`` (104 into 48 and 56,
    56 into 16 and 40, 24 into 12 and 12, ...) ended in blocks of 12, 6 and 3
    cells solved cell by cell: at n = 1000 the fill took 4-5 % longer. Below
    ``2 unit``, about half.
    """
    h = size // 2
    if h >= unit:
        h = unit
        while 2 * h < size:
            h *= 2
    return h


@kernel(fastmath=FASTMATH, _nrt=False)
def _triangle(T, ew, mask, P, a, e):
    """Finish every chord inside vertices [a, e): two triangles, then the square between."""
    if e - a <= _LEAF:
        for i in range(e - 2, a - 1, -1):
            for j in range(i + 1, e):
                _cell(T, ew, mask, i, j, e, e)
        return
    m = a + _half(e - a, 16)
    _triangle(T, ew, mask, P, a, m)
    _triangle(T, ew, mask, P, m, e)
    _square(T, ew, mask, P, a, m, m, e)


@kernel(fastmath=FASTMATH, _nrt=False)
def _mirror(T, i0, i1, j0, j1):
    """``T[j, i] = T[i, j]`` for ``i < j`` in rows [i0, i1) x columns [j0, j1).

    By 8 x 8 transposes in vector registers, cell by cell where a block
    reaches the diagonal or the block's edge.
    """
    for j in range(j0, j1, 8):  # eight rows of the other half at a time, left to right
        for i in range(i0, i1, 8):
            if i + 8 <= i1 and j + 8 <= j1 and i + 8 <= j:
                transpose_8x8(T, i, j, T, j, i)
            else:
                for r in range(i, min(i + 8, i1)):
                    for c in range(max(j, r + 1), min(j + 8, j1)):
                        T[c, r] = T[r, c]


@kernel(fastmath=FASTMATH)
def mirror_table(T):
    """``T[j, i] = T[i, j]`` below the diagonal: the filled table, for ``minplus_split``.

    After the fill (which writes only above the diagonal), for an exported
    table, whose every chord's split is found: with the lower half, the
    splits of ``(i, j)`` read two rows instead of a row and a column. In
    blocks of 64 x 64 cells, so that both halves' lines stay in cache.
    """
    n = T.shape[0]
    for i0 in range(0, n, 64):
        for j0 in range(i0, n, 64):
            _mirror(T, i0, min(n, i0 + 64), j0, min(n, j0 + 64))


@kernel(fastmath=FASTMATH, _nrt=False)
def _fill_inf(T, ia, ib, ja, jb):
    for i in range(ia, ib):
        for j in range(ja, jb):
            T[i, j] = np.inf


@kernel(inline="always")
def _claim_row(T, i, a, b):
    """``claim_at`` every cache line of cells ``T[i, a:b]`` (``a < b``)."""
    step = max(1, 64 // T.itemsize)
    for j in range(a, b, step):
        claim_at(T, i, j)
    claim_at(T, i, b - 1)  # the last line, where a does not start one


@kernel(fastmath=FASTMATH, _nrt=False)
def tile_edges(W, pts, code, i0, i1, j0, j1, T=None, above=0):
    """``W[i - i0, j - j0] = e(i, j)`` for rows [i0, i1) x columns [j0, j1): a tile's edges.

    Only for ``j > i``, the cells the fill reads: a diagonal tile (a triangle)
    takes half the square roots of a square one. Computed over the whole square,
    the 128-tiles of the diagonal took 60 us each instead of 40 at n = 1000 on the
    Xeon of ``docs/fast-engine.md``, a sixth of their time spent on cells never read.

    With a table ``T``, each row first claims the cache lines of the tile's cells
    in ``T`` (and those of row ``i - above`` too, where ``above > 0``: the tile
    above, whose rows this one fills as well), so that taking them from the
    other CPU, which read them in the solve before, overlaps the square roots
    (``claim_at``). In the EPYC's spells that took a two-thread solve at
    n = 1000 from 6.13 to 5.92 ms, and from 4.87 to 4.81 ms outside them
    (medians of 291-1,931 turns in alternating processes).
    """
    for i in range(i0, i1):
        if T is not None and above > 0:
            _claim_row(T, i - above, j0, j1)
        b = max(j0, i + 1)
        if b < j1:
            if T is not None:
                _claim_row(T, i, b, j1)
            edge_weight_row(code, pts, i, b, W[i - i0, b - j0 : j1 - j0])


@kernel(inline="always")
def _below_shares(d):
    """Whether the tile below a tile on tile-diagonal ``d`` applies their shared far splits.

    The one definition of the pairs (see ``_tile``): a tile on an odd
    tile-diagonal ``d >= 5`` and the tile below it, on ``d - 1``, which applies
    the shared splits and then sets the flag the tile above waits for.
    """
    return d % 2 == 1 and d >= 5


@kernel(fastmath=FASTMATH, _nrt=False)
def _tile(T, pts, code, W, P, mask, tile, ti, tj, done, nt):
    """Solve tile (ti, tj); ``done[a * nt + b]`` says whether tile (a, b) is finished.

    The far splits of two tiles of one column, (ti, tj) with ``tj - ti``
    even and the tile above it, are mostly the same products with the same
    ``B`` rows: the lower tile applies both, ``k`` in ``[i1, j0 - tile)``,
    from one copy of ``B``: half the copying, which took 8 % of the fill at
    n = 4000 on the Xeon of ``docs/fast-engine.md``. The tile above then
    applies only what is left: ``k`` in the lower tile's rows (not finished
    before) and in the last column tile (its left neighbour, not finished
    before either). The shared splits read the upper tile's rows left of
    ``j0 - tile``, which are final once tile (ti - 1, tj - 2) is done.

    The lower tile sets ``done[tj * nt + ti - 1]`` (below the diagonal, where
    no tile is) once the shared splits are applied, and the tile above then
    starts with the splits through its left neighbour, before the tile below
    is finished: at the end of the fill, where the last tiles have no other
    work beside them, the tile above no longer waits for all of the one below
    (two threads, n = 1000: fills 0.97x the time).
    """
    n = T.shape[0]
    i0, i1 = ti * tile, min(n, ti * tile + tile)
    j0, j1 = tj * tile, min(n, tj * tile + tile)
    d = tj - ti
    # the lower tile of a pair applies the shared far splits to the tile above's rows too
    above = tile if mask is None and ti >= 1 and _below_shares(d + 1) else 0
    tile_edges(W, pts, code, i0, i1, j0, j1, T, above)
    ew = (W, i0, j0)
    if d == 0:
        for i in range(i0, i1):
            for j in range(i + 2, j1):
                T[i, j] = np.inf
        _triangle(T, ew, mask, P, i0, i1)
    elif mask is not None:
        _fill_inf(T, i0, i1, j0, j1)
        _product(T, mask, _ROWS, i0, i1, j0, j1, i1, j0)
    elif _below_shares(d):  # the tile below applied the shared far splits
        _far(T, P, _ROWS, i0, i1, j0, j1, j0 - tile, j0)
        wait_done(done, (ti + 1) * nt + tj)
        _far(T, P, _ROWS, i0, i1, j0, j1, i1, i1 + tile)
    elif above > 0:  # also the shared far splits of the tile above
        wait_done(done, (ti - 1) * nt + tj - 2)
        _far(T, P, _ROWS, i0 - tile, i1, j0, j1, i1, j0 - tile, True)
        store_release(done, tj * nt + ti - 1, 1)  # the tile above may start
        _far(T, P, _ROWS, i0, i1, j0, j1, j0 - tile, j0)
    elif d > 1:
        _far(T, P, _ROWS, i0, i1, j0, j1, i1, j0, True)
    else:  # next to the diagonal: near splits only
        _fill_inf(T, i0, i1, j0, j1)
    if d > 0:
        _square(T, ew, mask, P, i0, i1, j0, j1)


def worker_bytes(tile: int, itemsize: int) -> int:
    """Bytes of one thread's buffers in ``minplus_tiles``: edge weights, the copied operand.

    A ``tile x tile`` float64 tile of edge weights and ``_far``'s packed rows
    (``_KBLOCK`` splits x the tile's whole 16-column strips).
    """
    return tile * tile * 8 + _STRIP * (tile // 16) * 16 * itemsize


def tile_flags(n: int, tile: int) -> tuple[np.ndarray, np.ndarray]:
    """Fresh ``(done, stop)`` arrays for ``minplus_tiles`` on an ``n``-vertex table.

    ``done[ti * nt + tj]`` becomes 1 when tile (ti, tj) is finished (``nt`` tiles
    a side), which a watching thread may read for progress; setting ``stop[0]``
    to 1 makes the threads take no further tile. ``done[tj * nt + ti]``, below
    the diagonal, becomes 1 when the far splits that tile (ti, tj) shares with
    the tile below it are applied (``progress.tile_work`` gives those places
    no work).
    """
    nt = (n + tile - 1) // tile
    return np.zeros(nt * nt, dtype=np.int64), np.zeros(1, dtype=np.int64)


@kernel(parallel=True, fastmath=FASTMATH, nogil=True)
def minplus_tiles(T, pts, code, mask, tile, workers, done, stop):
    """Fill the E-table (sum, edge weight) above the diagonal, tile by tile.

    ``mask``: None (every chord allowed), or a boolean ``n x n`` array; cells
    where it is False get +inf. Each is its own compiled version, so that the
    fill without a mask tests none (the ``mask is None`` branches are pruned
    when numba compiles). Each of ``workers`` threads takes the next tile (diagonal
    by diagonal) from a shared counter and starts it once the two tiles it
    reads last, left of it and below it, are done (a tile that applies far
    splits of the tile above it also waits for the tile that finishes those
    rows; the tile above waits for its left neighbour and those shared
    splits, and for the tile below only later; see ``_tile``): no barrier
    between tile-diagonals, so no thread idles at the end of one. Every wait
    is for a tile taken earlier, so the earliest unfinished tile never waits.

    ``done, stop`` are fresh ``tile_flags(n, tile)``. Runs without the GIL:
    another thread may watch ``done`` and set ``stop[0]``, after which no
    thread takes a new tile; the tiles already taken are finished (each waits
    only for tiles taken before it), so the call returns within about one
    tile's time.
    """
    nt = (T.shape[0] + tile - 1) // tile
    order = np.empty((nt * (nt + 1) // 2, 2), dtype=np.int64)
    m = 0
    for d in range(nt):
        for t in range(nt - d):
            order[m, 0], order[m, 1] = t, d
            m += 1
    taken = np.zeros(1, dtype=np.int64)
    scratch = np.empty((workers, tile, tile))  # e(i, j) of the tile a worker is on
    # _far's rows (the chord-mask path multiplies from the table itself)
    packed = np.empty(
        (workers, 0 if mask is not None else _STRIP * (tile // 16), 16), dtype=T.dtype
    )
    columns = np.asfortranarray(pts)  # each coordinate contiguous: edge rows vectorize
    for w in prange(workers):
        while load_acquire(stop, 0) == 0:
            k = fetch_add(taken, 0)
            if k >= m:
                break
            t, d = order[k, 0], order[k, 1]
            if d > 0:
                wait_done(done, t * nt + t + d - 1)
                if mask is None and _below_shares(d):  # only the tile below's shared splits
                    wait_done(done, (t + d) * nt + t)
                else:
                    wait_done(done, (t + 1) * nt + t + d)
            _tile(T, columns, code, scratch[w], packed[w], mask, tile, t, t + d, done, nt)
            store_release(done, t * nt + t + d, 1)


@kernel(fastmath=FASTMATH)
def subtract_edges(out, pts, code):
    """``out[i, j] -= e(i, j)`` above the diagonal: costs from an exported E-table.

    Compiled with the fill's flags, so that ``e`` has the same bits as there
    (a side's cost comes out exactly 0).
    """
    n = out.shape[0]
    for i in range(n - 1):
        for j in range(i + 1, n):
            out[i, j] -= edge_weight(code, pts, i, j)


@kernel(fastmath=FASTMATH)
def minplus_split(T, i, j, mirrored):
    """Smallest k minimizing ``E(i, k) + E(k, j)``; -1 if every split is infinite.

    ``E(k, j)`` from column ``j``, or from row ``j`` of the lower half where
    ``mirrored`` (``mirror_table``): two rows, a vectorized minimum. The
    minimum first, then the first split that reaches it (the sums are the
    same additions both times, so equality is exact).
    """
    if mirrored:
        ri, rj = T[i, i + 1 : j], T[j, i + 1 : j]
        best = _rowmin(np.inf, ri, rj)
        if best == np.inf:
            return -1
        for kk in range(ri.shape[0]):
            if ri[kk] + rj[kk] == best:
                return i + 1 + kk
        return -1
    best = np.inf
    for k in range(i + 1, j):  # a column: one cache line per split, loads independent
        best = fmin(best, load_at(T, i, k) + load_at(T, k, j))
    if best == np.inf:
        return -1
    for k in range(i + 1, j):
        if load_at(T, i, k) + load_at(T, k, j) == best:
            return k
    return -1
