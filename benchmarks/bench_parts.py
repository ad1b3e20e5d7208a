"""Where the min-plus fill's time goes: one thread, part by part, against the in-cache rate.

The compiled engine's fill (``optri.engines._minplus``, perimeter sum) is timed whole
and then one part at a time over every tile, each part on its own pass: the edge
weights, the far products (unpaired: every tile copies its own ``B``) and the near
splits. The yardstick is the rate of the same register
block on a product whose operands sit in cache, in the far products' packed layout,
measured in the same run; each part's candidates are counted exactly. A part's
pass runs on a table already filled (its operands final), so the parts add up to
roughly the whole; the near splits read a tile that the whole fill would still hold in
cache, so their pass runs a little slower than inside it.

    python benchmarks/bench_parts.py [N ...] [--rounds 3]

Reaches into the engine's private kernels on purpose: this is the profile behind the
"where the time goes" paragraphs of docs/fast-engine.md.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import numpy as np
from numba import njit

from optri.bench.compare import convex_polygon
from optri.engines import _minplus as K
from optri.engines._llvm import outer_4x16, outer_8x16
from optri.engines.jit import minplus_tile
from optri.engines.memory import new_table


@njit(fastmath=K.FASTMATH)
def _parts(T, pts, W, P, mask, tile, done, part):  # type: ignore[no-untyped-def]
    """One pass over every tile: ``part`` 0 whole, 1 edges, 2 far, 3 near."""
    n = T.shape[0]
    nt = (n + tile - 1) // tile
    for d in range(nt):
        for t in range(nt - d):
            ti, tj = t, t + d
            if part == 0:
                K._tile(T, pts, 0, W, P, mask, tile, ti, tj, done, nt)
                continue
            i0, i1 = ti * tile, min(n, ti * tile + tile)
            j0, j1 = tj * tile, min(n, tj * tile + tile)
            ew = (W, i0, j0)
            if part == 1:
                K.tile_edges(W, pts, 0, i0, i1, j0, j1)
            elif part == 2 and d > 0:
                K._far(T, P, K._ROWS, i0, i1, j0, j1, i1, j0)
            elif part == 3:
                if d == 0:
                    K._triangle(T, ew, mask, P, i0, i1)
                else:
                    K._square(T, ew, mask, P, i0, i1, j0, j1)


@njit(fastmath=K.FASTMATH)
def _in_cache(C, A, B, reps):  # type: ignore[no-untyped-def]
    """``reps`` products ``C = min(C, A (+) B)`` in the far products' own layout.

    ``A`` holds 64 rows of ``kn`` splits, ``B`` four 16-column strips of ``kn`` rows
    one after another, as ``_far`` packs them: the same register block
    (8 x 16 where vectors are 64 bytes wide, else 4 x 16), operands in L1/L2.
    """
    kn = A.shape[1]
    for _ in range(reps):
        for i in range(0, C.shape[0], K._ROWS):
            for s in range(C.shape[1] // 16):
                if K._ROWS == 8:
                    outer_8x16(C, i, 16 * s, A, i, 0, B, s * kn, 0, kn)
                else:
                    outer_4x16(C, i, 16 * s, A, i, 0, B, s * kn, 0, kn)


def _best(fn: Callable[[], object], rounds: int) -> float:
    best = float("inf")
    for _ in range(rounds):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def peak_rate(rounds: int) -> float:
    """Candidates per second of the fill's register block on products in cache.

    64 rows x 64 columns x 256 splits, as ``_far`` runs it (its ``B`` packed, 256
    splits a pass): the shape of the C peak microbenchmark's kernels, which it matches
    on the Xeon of ``docs/fast-engine.md`` (2.7-3.0e10 against 2.7-2.9e10). A
    yardstick reading ``B`` from rows of a larger table would understate it.
    """
    rng = np.random.default_rng(0)
    kn, reps = K._KBLOCK, 400
    C, A, B = _block_of(64, 64), _block_of(64, kn), _block_of(4 * kn, 16)
    for x in (C, A, B):
        x[:] = rng.random(x.shape) + 1.0
    _in_cache(C, A, B, 1)
    return reps * 64 * 64 * kn / _best(lambda: _in_cache(C, A, B, reps), rounds)


def _block_of(rows: int, cols: int) -> np.ndarray:
    """An uninitialized ``rows x cols`` array starting a cache line, as the engine's table."""
    side = math.isqrt(rows * cols - 1) + 1
    return new_table(side, np.dtype(np.float64)).reshape(-1)[: rows * cols].reshape(rows, cols)


def near_candidates(n: int, tile: int) -> int:
    """Candidates of the near splits (inside each tile's rows and columns); the rest are far."""
    total = 0
    for i0 in range(0, n, tile):
        i1 = min(n, i0 + tile)
        i = np.arange(i0, i1)
        for j0 in range(i0, n, tile):
            j1 = min(n, j0 + tile)
            j = np.arange(j0, j1)
            if j0 == i0:  # a triangle: every split is near
                total += int(np.maximum(j[None, :] - i[:, None] - 1, 0).sum())
            else:  # k in (i, i1) or in [j0, j)
                total += len(j) * int((i1 - i - 1).sum()) + len(i) * int((j - j0).sum())
    return total


def profile(n: int, rounds: int) -> dict[str, float]:
    """Seconds of the whole one-thread fill and of each part, best of ``rounds``."""
    tile = minplus_tile(n)
    pts = np.asfortranarray(convex_polygon(n))
    mask = None  # every chord allowed: the fill's maskless version
    T = new_table(n, np.dtype(np.float64))  # as the engine allocates it
    nt = (n + tile - 1) // tile
    done = np.ones(nt * nt, dtype=np.int64)
    W = np.empty((tile, tile))
    P = np.empty((K._STRIP * (tile // 16), 16))
    _parts(T, pts, W, P, mask, tile, done, 0)  # compile, and fill the table once
    names = ("whole", "edge weights", "far products", "near splits")
    return {
        name: _best(lambda k=k: _parts(T, pts, W, P, mask, tile, done, k), rounds)
        for k, name in enumerate(names)
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sizes", nargs="*", type=int, default=[1000, 4000])
    ap.add_argument("--rounds", type=int, default=3, help="best of this many passes")
    args = ap.parse_args()
    rate = peak_rate(args.rounds)
    block = f"{K._ROWS} x 16"
    print(f"in-cache rate of the {block} register block, one thread: {rate:.2e} candidates/s")
    for n in args.sizes:
        parts = profile(n, args.rounds)
        total = n * (n - 1) * (n - 2) // 6
        tile = minplus_tile(n)
        near = near_candidates(n, tile)
        work = {"whole": total, "far products": total - near, "near splits": near}
        print(f"n = {n}, tile {tile}: at that rate the fill would take {total / rate * 1e3:.1f} ms")
        for name, sec in parts.items():
            line = f"  {name:13s} {sec * 1e3:8.1f} ms"
            if name in work:
                r = work[name] / sec
                line += f"  {work[name]:.3e} candidates, {r:.2e}/s, {r / rate:4.0%} of that rate"
            print(line)


if __name__ == "__main__":
    main()
