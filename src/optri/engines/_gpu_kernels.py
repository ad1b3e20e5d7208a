"""CUDA kernels of the GPU engine: tiled min-plus wavefront over one n x n table.

The table ``tab`` (padded to a multiple of the tile side ``T``) holds the value of
chord (i, j) at ``tab[i, j]`` *and* ``tab[j, i]`` (i < j), so a row segment
``tab[i, k0:k1]`` is the costs (i, k) and ``tab[j, k0:k1]`` the costs (k, j):
both inner streams are contiguous (cf. the CPU yardstick ``ref_mwt.c``).

Tile (I, J) (I <= J) is finished once every tile on an earlier tile diagonal is.
One factory per kernel, each compiled with only the constants it reads:

* :func:`init_kernel`: polygon sides get their base cost, every other cell +inf.
* :func:`product_kernel` (J - I >= 2): min over the middle k-tiles I < K < J of
  ``A(I, K) (x) B(K, J)``, a min-plus tile product. ``T x KC`` slices of both
  operands are staged in shared memory and each serves all ``T * T`` cells of
  the tile; each thread keeps an ``RH x CW`` block of cells in registers. Long
  k-ranges are split over several blocks that meet through ``atomic.min``.
* :func:`finish_kernel`: the k inside tiles I and J depend on cells of the tile
  itself, so the tile is completed by a wavefront over its own local diagonals,
  in shared memory, one ``syncthreads`` per local diagonal.
* :func:`rebuild_kernel` walks the optimal splits back to triangles (one block);
  :func:`export_kernel` writes the paper's n x n table (``keep_table=True``).

:func:`build_kernels` assembles the set for one tile / slice / threads / dtype.
Kernels take the weight code and objective as arguments (one design for all
weights, computed in-kernel from coordinates, :mod:`optri.engines._gpu_device`);
tile, slice depth, threads and dtype are compile-time constants. Every kernel is
declared with launch bounds (its block size), so ptxas caps its registers at
what a block of that size can get on one SM: without them the generic
``product`` (138 registers a thread on sm_90) could not launch 512 threads.

``eform`` selects the min-plus form of edge-decomposable weights under "sum":
``E = C + e`` and ``E(i, j) = min_k E(i, k) + E(k, j) + 2 e(i, j)`` (no weight in
the inner loop): one source gives ``product_minplus`` (E form, accumulators in
registers) and ``product`` (weight computed per candidate).
"""

from __future__ import annotations

import functools
import math
from types import SimpleNamespace
from typing import Any

from ._gpu_device import OBJ_SUM, device_functions

__all__ = [
    "build_kernels",
    "export_kernel",
    "finish_kernel",
    "init_kernel",
    "product_kernel",
    "rebuild_kernel",
    "thread_layout",
]

#: numba.cuda, bound by the first kernel factory called. A module global, not a
#: closure variable, because the CUDA simulator swaps the module's globals.
cuda: Any = None


def thread_layout(tile: int, threads: int) -> tuple[int, int, int, int]:
    """``(TX, TY, RH, CW)``: a TY x TX grid of threads, each owning RH x CW cells.

    TX and TY divide the tile and TX * TY <= threads; threads beyond help load.

    >>> thread_layout(64, 256)
    (16, 16, 4, 4)
    >>> thread_layout(4, 3)
    (1, 2, 2, 4)
    """

    def largest_divisor(limit: int) -> int:
        return max(d for d in range(1, tile + 1) if tile % d == 0 and d <= max(1, limit))

    tx = largest_divisor(math.isqrt(threads))
    ty = largest_divisor(threads // tx)
    return tx, ty, tile // ty, tile // tx


@functools.cache
def build_kernels(tile: int, kchunk: int, threads: int, dtype: str) -> SimpleNamespace:
    """Compile-on-first-launch kernels for one tile / slice / threads / dtype setting.

    ``finish`` runs ``finish_threads`` threads a block (one per cell of a local
    diagonal, at most the tile side), the others ``threads``. A kernel is shared
    by every setting that gives it the same constants.
    """
    finish_threads = min(threads, tile)
    return SimpleNamespace(
        init=init_kernel(threads),
        product_minplus=product_kernel(tile, kchunk, threads, dtype, eform=True),
        product=product_kernel(tile, kchunk, threads, dtype, eform=False),
        finish=finish_kernel(tile, finish_threads, dtype),
        finish_threads=finish_threads,
        rebuild=rebuild_kernel(threads),
        export=export_kernel(threads),
    )


def _jit(max_threads: int) -> Any:
    """``cuda.jit`` with launch bounds (none in the simulator); binds the global ``cuda``."""
    global cuda
    import numba
    from numba import cuda as numba_cuda

    cuda = numba_cuda
    if numba.config.ENABLE_CUDASIM:  # type: ignore[attr-defined]  # set at import, from env
        return cuda.jit
    return cuda.jit(launch_bounds=max_threads)


def _numba_type(dtype: str) -> Any:
    """The numba scalar type of a table dtype name (``"float32"``, ``"float64"``)."""
    import numba
    import numpy as np

    return numba.from_dtype(np.dtype(dtype))


@functools.cache
def init_kernel(threads: int) -> Any:
    """``init(tab, pts, n, code, obj, eform)``: the table before any split is tried."""
    edge = device_functions().edge
    inf = math.inf

    @_jit(threads)
    def init(tab, pts, n, code, obj, eform):
        # sides get their base cost; every other cell starts at +inf (the
        # identity of atomic.min). Each thread writes only its own cells, in
        # row order, so the writes coalesce; edge() is symmetric bit for bit.
        size = tab.shape[0]
        neutral = 0.0 if obj == OBJ_SUM else -inf
        for e in range(cuda.grid(1), size * size, cuda.gridsize(1)):
            i = e // size
            j = e - i * size
            if j == i + 1 or i == j + 1:
                tab[i, j] = edge(code, n, pts, i, j) if eform else neutral
            else:
                tab[i, j] = inf

    return init


@functools.cache
def product_kernel(tile: int, kchunk: int, threads: int, dtype: str, eform: bool) -> Any:
    """``product(tab, pts, dim, n, code, obj, D, splits, total)``: tiles (I, I + D).

    Block ``blk`` takes tile ``blk // splits`` and share ``blk % splits`` of its
    middle k-tiles. ``eform`` is a compile-time constant, so each specialization
    keeps one inner loop: the min-plus one has no calls, its sums stay in registers.
    """
    dev = device_functions()
    weight, combine = dev.weight, dev.combine
    T, KC, EFORM = tile, kchunk, eform
    TX, TY, RH, CW = thread_layout(T, threads)
    NACT = TX * TY
    KCP = KC + 1  # padded row length: shapes must be plain constants
    RC = RH * CW
    ft = _numba_type(dtype)
    inf = math.inf

    @_jit(threads)
    def product(tab, pts, dim, n, code, obj, D, splits, total):
        As = cuda.shared.array((T, KCP), ft)  # +1: no bank conflicts across rows
        Bs = cuda.shared.array((T, KCP), ft)
        best = cuda.local.array(RC, ft)
        tid = cuda.threadIdx.x
        nth = cuda.blockDim.x
        tx = tid % TX
        ty = tid // TX
        for blk in range(cuda.blockIdx.x, total, cuda.gridDim.x):
            ti = blk // splits
            s = blk - ti * splits
            i0 = ti * T
            j0 = (ti + D) * T
            k_lo = (ti + 1 + (s * (D - 1)) // splits) * T
            k_hi = (ti + 1 + ((s + 1) * (D - 1)) // splits) * T
            for c in range(RH * CW):
                best[c] = inf
            for k0 in range(k_lo, k_hi, KC):
                for e in range(tid, T * KC, nth):
                    r = e // KC
                    c = e - r * KC
                    As[r, c] = tab[i0 + r, k0 + c]  # (i, k), row-contiguous
                    Bs[r, c] = tab[j0 + r, k0 + c]  # (k, j) from the transposed half
                cuda.syncthreads()
                # min(), not compare-and-branch, and constant-trip loops: the
                # RH x CW accumulators then live in registers (checked in the PTX)
                if tid >= NACT:
                    pass
                elif EFORM:
                    for c in range(KC):
                        for r in range(RH):
                            a = As[ty + r * TY, c]
                            for q in range(CW):
                                x = r * CW + q
                                best[x] = min(best[x], a + Bs[tx + q * TX, c])
                else:
                    for c in range(KC):
                        for r in range(RH):
                            a = As[ty + r * TY, c]
                            for q in range(CW):
                                x = r * CW + q
                                w = weight(
                                    code,
                                    dim,
                                    n,
                                    pts,
                                    i0 + ty + r * TY,
                                    k0 + c,
                                    j0 + tx + q * TX,
                                )
                                best[x] = min(best[x], combine(obj, a, Bs[tx + q * TX, c], w))
                cuda.syncthreads()
            if tid < NACT:
                for r in range(RH):
                    for q in range(CW):
                        cuda.atomic.min(tab, (i0 + ty + r * TY, j0 + tx + q * TX), best[r * CW + q])

    return product


@functools.cache
def finish_kernel(tile: int, threads: int, dtype: str) -> Any:
    """``finish(tab, pts, mask, has_mask, dim, n, code, obj, eform, D, count)``: tiles (I, I + D).

    One block a tile, ``threads`` (at most ``tile``) threads a block.
    """
    dev = device_functions()
    weight, combine, edge = dev.weight, dev.combine, dev.edge
    T = tile
    TP = T + 1  # padded row length: shapes must be plain constants
    ft = _numba_type(dtype)
    inf = math.inf

    @_jit(threads)
    def finish(tab, pts, mask, has_mask, dim, n, code, obj, eform, D, count):
        Cs = cuda.shared.array((T, TP), ft)
        tid = cuda.threadIdx.x
        nth = cuda.blockDim.x
        same = D == 0
        for ti in range(cuda.blockIdx.x, count, cuda.gridDim.x):
            i0 = ti * T
            j0 = (ti + D) * T
            for e in range(tid, T * T, nth):
                r = e // T
                c = e - r * T
                Cs[r, c] = tab[i0 + r, j0 + c]
            cuda.syncthreads()
            # local diagonal s = jl - il; cells of one s are independent, and each
            # needs only cells of smaller s in this tile (plus finished tiles)
            for s in range(2 if same else 1 - T, T):
                for il in range(tid, T, nth):
                    jl = il + s
                    if jl < 0 or jl >= T:
                        continue
                    i = i0 + il
                    j = j0 + jl
                    if j - i < 2:
                        continue  # polygon side: keeps its base cost
                    v = Cs[il, jl]
                    # k in tile I, after i: (i, k) in tile (I, I), (k, j) here
                    for kl in range(il + 1, jl if same else T):
                        a = Cs[il, kl] if same else tab[i, i0 + kl]
                        if eform:
                            c = a + Cs[kl, jl]
                        else:
                            w = weight(code, dim, n, pts, i, i0 + kl, j)
                            c = combine(obj, a, Cs[kl, jl], w)
                        if c < v:
                            v = c
                    # k in tile J, before j: (i, k) here, (k, j) in tile (J, J)
                    for kl in range(0, 0 if same else jl):
                        b = tab[j, j0 + kl]
                        if eform:
                            c = Cs[il, kl] + b
                        else:
                            w = weight(code, dim, n, pts, i, j0 + kl, j)
                            c = combine(obj, Cs[il, kl], b, w)
                        if c < v:
                            v = c
                    if eform:
                        v = v + 2.0 * edge(code, n, pts, i, j)
                    if has_mask and mask[i, j] == 0:
                        v = inf  # chord not usable: nothing may split on it
                    Cs[il, jl] = v
                cuda.syncthreads()
            for e in range(tid, T * T, nth):
                r = e // T
                c = e - r * T
                if not same or r < c:
                    tab[i0 + r, j0 + c] = Cs[r, c]
                    tab[j0 + c, i0 + r] = Cs[r, c]
            cuda.syncthreads()

    return finish


@functools.cache
def rebuild_kernel(threads: int) -> Any:
    """``rebuild(tab, pts, dim, n, code, obj, eform, stack, tris, out)``: one block."""
    import numba

    dev = device_functions()
    edge, scan = dev.edge, dev.scan
    f64, i64 = numba.float64, numba.int64

    @_jit(threads)
    def rebuild(tab, pts, dim, n, code, obj, eform, stack, tris, out):
        # one block walks the optimal splits from (0, n-1) down; the O(n)
        # re-scan of each chord is shared by the threads and reduced in shared memory
        sb = cuda.shared.array(threads, f64)
        sa = cuda.shared.array(threads, i64)
        st = cuda.shared.array(2, i64)  # stack top, triangles written
        tid = cuda.threadIdx.x
        nth = cuda.blockDim.x
        if tid == 0:
            stack[0, 0] = 0
            stack[0, 1] = n - 1
            st[0] = 1
            st[1] = 0
            out[0] = tab[0, n - 1] - (edge(code, n, pts, 0, n - 1) if eform else 0.0)
            out[1] = 0.0
        cuda.syncthreads()
        while st[0] > 0:
            top = st[0] - 1
            i = stack[top, 0]
            j = stack[top, 1]
            best, arg = scan(tab, pts, dim, n, code, obj, eform, i, j, i + 1 + tid, nth)
            sb[tid] = best
            sa[tid] = arg
            cuda.syncthreads()
            step = 1
            while step < nth:
                if tid % (2 * step) == 0 and tid + step < nth:
                    ob = sb[tid + step]
                    oa = sa[tid + step]
                    # smaller cost wins; on a tie the smaller valid k (memo's tie rule)
                    tie = ob == sb[tid] and oa >= 0 and (sa[tid] < 0 or oa < sa[tid])
                    if ob < sb[tid] or tie:
                        sb[tid] = ob
                        sa[tid] = oa
                cuda.syncthreads()
                step *= 2
            if tid == 0:
                k = sa[0]
                if k < 0:
                    out[1] = 1.0  # no finite split: no valid triangulation
                    out[2] = i
                    out[3] = j
                    st[0] = 0
                else:
                    m = st[1]
                    tris[m, 0] = i
                    tris[m, 1] = k
                    tris[m, 2] = j
                    st[1] = m + 1
                    top = st[0] - 1
                    if j - k >= 2:
                        stack[top, 0] = k
                        stack[top, 1] = j
                        top += 1
                    if k - i >= 2:
                        stack[top, 0] = i
                        stack[top, 1] = k
                        top += 1
                    st[0] = top
            cuda.syncthreads()

    return rebuild


@functools.cache
def export_kernel(threads: int) -> Any:
    """``export(tab, pts, mask, has_mask, dim, n, code, obj, eform, out)``: the n x n table."""
    dev = device_functions()
    edge, scan = dev.edge, dev.scan
    inf = math.inf

    @_jit(threads)
    def export(tab, pts, mask, has_mask, dim, n, code, obj, eform, out):
        # the paper's table: cost above the diagonal, optimal split below
        for e in range(cuda.grid(1), n * n, cuda.gridsize(1)):
            i = e // n
            j = e - i * n
            if j < i:
                continue
            if j == i:
                out[i, i] = 0.0
                continue
            if j - i < 2 or (has_mask and mask[i, j] == 0):
                out[i, j] = 0.0
                out[j, i] = -1.0 if j - i < 2 else 0.0
                continue
            best, arg = scan(tab, pts, dim, n, code, obj, eform, i, j, i + 1, 1)
            v = tab[i, j] - (edge(code, n, pts, i, j) if eform else 0.0)
            out[i, j] = 0.0 if v == -inf else v
            out[j, i] = arg

    return export
