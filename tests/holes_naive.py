"""Slow, obviously correct versions of the 3-D hole searches (tests only).

``exact_liepa`` is the textbook two-pass search over states (i, j, m), every
state and every apex visited, no bound and no pruning: what the compiled core's
exact search (``src/core/holes_exact.cpp``) computes faster. Its triangle
normals and keys are plain Python written in the evaluator's arithmetic order
(``src/core/holes.hpp``): Python floats are IEEE doubles and ``math.sqrt`` is
correctly rounded, so its optimum is comparable bit for bit.
"""

from __future__ import annotations

import functools
import math

import numpy as np

DEGENERATE_KEY = 3.0
FOLD_KEY = 2.0
DEGENERATE_SINE2 = 1e-24


def unit_normal(Q, a, b, c):
    """Unit normal of triangle a->b->c, a degenerate flag and the area."""
    ux, uy, uz = (float(Q[b, t] - Q[a, t]) for t in range(3))
    vx, vy, vz = (float(Q[c, t] - Q[a, t]) for t in range(3))
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    uu = ux * ux + uy * uy + uz * uz
    vv = vx * vx + vy * vy + vz * vz
    n2 = nx * nx + ny * ny + nz * nz
    nn = math.sqrt(n2)
    if n2 <= DEGENERATE_SINE2 * (uu * vv):
        return 0.0, 0.0, 0.0, True, 0.5 * nn
    inv = 1.0 / nn
    return nx * inv, ny * inv, nz * inv, False, 0.5 * nn


def sorted_normal(Q, a, b, c):
    """:func:`unit_normal` of the triangle's vertices sorted."""
    a, b, c = sorted((a, b, c))
    return unit_normal(Q, a, b, c)


def key_of(x1, y1, z1, d1, x2, y2, z2, d2):
    """Key ``1 - cos`` of two patch triangles (unit normals, degenerate flags)."""
    if d1 or d2:
        return DEGENERATE_KEY
    return min(max(1.0 - (x1 * x2 + y1 * y2 + z1 * z2), 0.0), FOLD_KEY)


def mesh_key(Q, n, s, x, y, z, d):
    """Key of patch triangle (x, y, z, d) against the mesh triangle on side ``s``."""
    if d:
        return DEGENERATE_KEY
    mx, my, mz, md, _ = unit_normal(Q, (s + 1) % n, s, n + s)
    if md:
        return 0.0  # a zero-area mesh triangle has no normal to fold against
    return min(max(1.0 - (x * mx + y * my + z * mz), 0.0), FOLD_KEY)


def _key(Q, n, has_third, apex, outer):
    """Key between patch triangle ``apex`` and the triangle across its top chord."""
    x, y, z, d, _ = sorted_normal(Q, *apex)
    if outer is None:  # the root without third points: nothing across
        return 0.0
    if outer == "mesh":
        return mesh_key(Q, n, n - 1, x, y, z, d)
    ox, oy, oz, od, _ = sorted_normal(Q, *outer)
    return key_of(x, y, z, d, ox, oy, oz, od)


def _leaf(Q, n, has_third, s, m):
    """Key of side (s, s + 1) between patch triangle (s, s + 1, m) and the mesh."""
    if not has_third:
        return 0.0
    x, y, z, d, _ = sorted_normal(Q, s, s + 1, m)
    return mesh_key(Q, n, s, x, y, z, d)


def exact_liepa(Q, n, has_third, allowed=None):
    """(M, area, triangles) of the exact optimum; None if ``allowed`` admits no patch.

    Ties: the least area, then the smallest apex (as optri's search breaks them).
    """
    ok = np.ones((n, n), dtype=bool) if allowed is None else allowed
    root_outer = "mesh" if has_third else None

    def outer_of(i, j, m):
        return root_outer if m == n else tuple(sorted((i, j, m)))

    def half(a, b, c, value):
        # sub-polygon a..b seen from c: a side is the mesh's (leaf) key
        return _leaf(Q, n, has_third, a, c) if b - a == 1 else value(a, b, c)

    @functools.cache
    def bottleneck(i, j, m):
        if j - i >= 2 and not ok[i, j] and not (i == 0 and j == n - 1):
            return math.inf
        best = math.inf
        for k in range(i + 1, j):
            v = max(
                half(i, k, j, bottleneck),
                half(k, j, i, bottleneck),
                _key(Q, n, has_third, (i, k, j), outer_of(i, j, m)),
            )
            best = min(best, v)
        return best

    M = bottleneck(0, n - 1, n)
    if M == math.inf:
        return None

    def leaf_area(a, b, c):
        return 0.0 if _leaf(Q, n, has_third, a, c) <= M else math.inf

    @functools.cache
    def area(i, j, m):
        if j - i >= 2 and not ok[i, j] and not (i == 0 and j == n - 1):
            return math.inf, -1
        best, arg = math.inf, -1
        for k in range(i + 1, j):
            if _key(Q, n, has_third, (i, k, j), outer_of(i, j, m)) > M:
                continue
            left = leaf_area(i, k, j) if k - i == 1 else area(i, k, j)[0]
            right = leaf_area(k, j, i) if j - k == 1 else area(k, j, i)[0]
            value = left + right + unit_normal(Q, i, k, j)[4]
            if value < best:
                best, arg = value, k
        return best, arg

    tris, stack = [], [(0, n - 1, n)]
    while stack:
        i, j, m = stack.pop()
        k = area(i, j, m)[1]
        tris.append((i, k, j))
        stack += [(a, b, c) for a, b, c in ((i, k, j), (k, j, i)) if b - a > 1]
    return M, area(0, n - 1, n)[0], np.array(sorted(tris), dtype=np.int64)
