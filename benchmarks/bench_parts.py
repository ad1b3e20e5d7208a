"""Where the min-plus fill's time goes: one thread, part by part, against the in-cache rate.

The compiled engine's fill (``optri.engines._minplus``, perimeter sum) is timed whole
and then one part at a time over every tile, each part on its own pass: the edge
weights, the far products (unpaired: every tile copies its own ``B``), the near splits
and the tile copies to the lower half. The yardstick is the rate of the same register
block on a product whose operands sit in cache, measured in the same run. A part's
pass runs on a table already filled (its operands final), so the parts add up to
roughly the whole; the near splits read a tile that the whole fill would still hold in
cache, so their pass runs a little slower than inside it.

    python benchmarks/bench_parts.py [N ...] [--rounds 3]

Reaches into the engine's private kernels on purpose: this is the profile behind the
"where the time goes" paragraphs of docs/fast-engine.md.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
from numba import njit

from optri.bench.compare import convex_polygon
from optri.engines import _minplus as K
from optri.engines._jit_weights import edge_weight_row
from optri.engines._llvm import outer_4x16, outer_8x16
from optri.engines.jit import _aligned_table, minplus_tile


@njit(fastmath=K.FASTMATH)
def _parts(T, pts, W, P, mask, tile, done, part):  # type: ignore[no-untyped-def]
    """One pass over every tile: ``part`` 0 whole, 1 edges, 2 far, 3 near, 4 copies."""
    n = T.shape[0]
    nt = (n + tile - 1) // tile
    for d in range(nt):
        for t in range(nt - d):
            ti, tj = t, t + d
            if part == 0:
                K._tile(T, pts, 0, W, P, mask, False, tile, ti, tj, done, nt)
                continue
            i0, i1 = ti * tile, min(n, ti * tile + tile)
            j0, j1 = tj * tile, min(n, tj * tile + tile)
            ew = (W, i0, j0)
            if part == 1:
                for i in range(i0, i1):
                    edge_weight_row(0, pts, i, j0, W[i - i0, : j1 - j0])
            elif part == 2 and d > 0:
                K._far(T, P, mask, K._ROWS, i0, i1, j0, j1, i1, j0)
            elif part == 3:
                if d == 0:
                    K._triangle(T, ew, mask, False, i0, i1)
                else:
                    K._square(T, ew, mask, False, i0, i1, j0, j1)
            elif part == 4:
                K._mirror(T, i0, i1, j0, j1)


@njit(fastmath=K.FASTMATH)
def _in_cache(T, reps, s):  # type: ignore[no-untyped-def]
    """``reps`` products of ``s`` rows x ``s`` columns x ``s`` splits, operands in cache.

    In the fill's register block: 8 x 16 where vectors are 64 bytes wide, else 4 x 16.
    """
    for _ in range(reps):
        for i in range(0, s, K._ROWS):
            for j in range(2 * s, 3 * s, 16):
                if K._ROWS == 8:
                    outer_8x16(T, i, j, T, i, s, T, s, j, s)
                else:
                    outer_4x16(T, i, j, T, i, s, T, s, j, s)


def _best(fn: Callable[[], object], rounds: int) -> float:
    best = float("inf")
    for _ in range(rounds):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def peak_rate(rounds: int) -> float:
    """Candidates per second of the fill's register block on 128-cubed products in cache."""
    s, reps = 128, 200
    T = np.random.default_rng(0).random((3 * s, 3 * s)) + 1.0
    _in_cache(T, 1, s)
    return reps * s**3 / _best(lambda: _in_cache(T, reps, s), rounds)


def profile(n: int, rounds: int) -> dict[str, float]:
    """Seconds of the whole one-thread fill and of each part, best of ``rounds``."""
    tile = minplus_tile(n)
    pts = np.asfortranarray(convex_polygon(n))
    mask = np.zeros((1, 1), dtype=np.bool_)
    T = _aligned_table(n, np.dtype(np.float64))  # as the engine allocates it
    nt = (n + tile - 1) // tile
    done = np.ones(nt * nt, dtype=np.int64)
    W = np.empty((tile, tile))
    P = np.empty((K._KBLOCK * (tile // 16), 16))
    _parts(T, pts, W, P, mask, tile, done, 0)  # compile, and fill the table once
    names = ("whole", "edge weights", "far products", "near splits", "tile copies")
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
        ideal = n * (n - 1) * (n - 2) / 6 / rate
        tile = minplus_tile(n)
        print(f"n = {n}, tile {tile}: at that rate the fill would take {ideal * 1e3:.1f} ms")
        for name, sec in parts.items():
            print(f"  {name:13s} {sec * 1e3:8.1f} ms")


if __name__ == "__main__":
    main()
