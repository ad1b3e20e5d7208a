"""The tiling search in plain Python: the compiled kernel's reference.

The same algorithm as ``optri._core.contours.tile`` (``src/core/contours.cpp``),
operation for operation, so that both return identical bits: each cell takes
one addition (or one max) per candidate, ties go to the first of the
candidates in the order g below, e below, g left, f left, and equal costs to
the smaller start. Kept for the tests, which compare the two on
random tables, and as the readable statement of the search.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["tile_reference"]

_INF = math.inf


def _solve(
    wp: list[list[float]],
    wq: list[list[float]],
    is_max: bool,
    j0: int,
    lo: list[int],
    hi: list[int],
) -> tuple[float, list[int], list[int], list[int]]:
    """Best tiling path from (0, j0) to (m, j0 + n) inside columns ``[lo[i], hi[i]]``.

    Besides the general layer ``g``, two forced families are followed so that
    no path runs a whole row or column (a fan that would give a span four
    triangles): ``e`` goes up column j0 then along one row, ``f`` along row 0
    then up one column; leaving a family enters ``g``.
    """
    m, n = len(wp), len(wp[0])
    cl = [max(lo[i], j0) for i in range(m + 1)]
    ch = [min(hi[i], j0 + n) for i in range(m + 1)]
    g: dict[tuple[int, int], float] = {}
    e: dict[tuple[int, int], float] = {}
    f: dict[tuple[int, int], float] = {}
    came: dict[tuple[int, int], int] = {}

    def combine(v: float, w: float) -> float:
        return (w if w > v else v) if is_max else v + w

    for i in range(m + 1):
        for j in range(cl[i], ch[i] + 1):
            below = i > 0 and cl[i - 1] <= j <= ch[i - 1]
            left = j > cl[i]
            ev = fv = gv = _INF
            step = 0
            if i == 0 and j == j0:
                ev = fv = -_INF if is_max else 0.0
            else:
                up = wp[(i - 1) % m][j % n] if below else 0.0
                side = wq[i % m][(j - 1) % n] if left else 0.0
                if j == j0 and i < m and below:
                    ev = combine(e[i - 1, j], up)
                if j0 < j < j0 + n and i < m and left:
                    ev = combine(e[i, j - 1], side)
                if i == 0 and j < j0 + n and left:
                    fv = combine(f[i, j - 1], side)
                if 0 < i < m and j > j0 and below:
                    fv = combine(f[i - 1, j], up)
                if i > 0 and j > j0:
                    cand = [_INF] * 4
                    if below:
                        cand[0] = combine(g[i - 1, j], up)
                        if i - 1 > 0:
                            cand[1] = combine(e[i - 1, j], up)
                    if left:
                        cand[2] = combine(g[i, j - 1], side)
                        if j - 1 > j0:
                            cand[3] = combine(f[i, j - 1], side)
                    gv = cand[0]
                    for k in range(1, 4):
                        if cand[k] < gv:
                            gv, step = cand[k], k
            g[i, j], e[i, j], f[i, j], came[i, j] = gv, ev, fv, step
    if not g[m, j0 + n] < _INF:  # no tiling (n or m is 1, or infinite weights)
        return g[m, j0 + n], [0] * (m + 1), [2 * n] * (m + 1), []
    i, j, layer = m, j0 + n, "g"
    plo, phi = [0] * (m + 1), [0] * (m + 1)
    plo[i] = phi[i] = j
    steps = [0] * (m + n)
    for s in range(m + n - 1, -1, -1):
        if layer == "g":
            k = came[i, j]
            steps[s] = 0 if k < 2 else 1
            layer = "e" if k == 1 else "f" if k == 3 else "g"
        elif layer == "e":
            steps[s] = 1 if j > j0 else 0
        else:
            steps[s] = 0 if i > 0 else 1
        if steps[s] == 0:
            i -= 1
            plo[i] = phi[i] = j
        else:
            j -= 1
            plo[i] = j
    return g[m, j0 + n], plo, phi, steps


def tile_reference(
    wp: NDArray[np.float64], wq: NDArray[np.float64], is_max: bool, start: int = -1
) -> tuple[float, int, bytes]:
    r"""``(cost, start j0, steps)`` of the best tiling, as the compiled kernel returns them.

    ``wp[i, j]`` weighs triangle (a_i, a_i+1, b_j) and ``wq[i, j]`` triangle
    (a_i, b_j, b_j+1); ``start >= 0`` fixes the first span at (a_0, b_start).
    ``(inf, -1, b"")`` when no tiling has a finite cost.

    >>> w = np.ones((3, 3))
    >>> tile_reference(w, w, False)
    (6.0, 0, b'\x01\x00\x01\x01\x00\x00')
    """
    m, n = wp.shape
    p, q = wp.tolist(), wq.tolist()
    lo, hi = [0] * (m + 1), [2 * n] * (m + 1)
    best: list[tuple[float, int, list[int]]] = []

    def offer(j0: int, cost: float, steps: list[int]) -> None:
        if not cost < _INF:
            return
        if not best or cost < best[0][0] or (cost == best[0][0] and j0 < best[0][1]):
            best[:] = [(cost, j0, steps)]

    if start >= 0 or is_max:
        for j0 in [start] if start >= 0 else range(n):
            cost, _, _, steps = _solve(p, q, is_max, j0, lo, hi)
            offer(j0, cost, steps)
    else:
        cost, plo, phi, steps = _solve(p, q, is_max, 0, lo, hi)
        offer(0, cost, steps)

        def divide(jl: int, left: list[int], jh: int, right: list[int]) -> None:
            if jh - jl < 2:
                return
            mid = jl + (jh - jl) // 2
            cost, mlo, mhi, steps = _solve(p, q, is_max, mid, left, right)
            offer(mid, cost, steps)
            divide(jl, left, mid, mhi)
            divide(mid, mlo, jh, right)

        divide(0, plo, n, [v + n for v in phi])
    if not best:
        return _INF, -1, b""
    cost, j0, steps = best[0]
    return cost, j0, bytes(steps)
