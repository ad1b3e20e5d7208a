"""Exact Liepa search over all triangulations of a 3-D polyline (numba).

Liepa's objective (largest dihedral angle, then total area) is not a sum of
triangle weights: a dihedral needs both triangles of an edge. The state
(i, j, m) -- sub-polygon i..j with the triangle (i, j, m) across its chord --
makes every dihedral known when its two triangles meet (Barequet, Dickerson,
Eppstein 1996): O(n^3) states, O(n) splits each. See :func:`exact_liepa`.
"""

from __future__ import annotations

import numpy as np

from ..engines.compiled import kernel
from ._kernels import (
    DEGENERATE_KEY,
    mesh_key,
    mesh_normals,
    sorted_normal,
    unit_normal,
)

__all__ = ["exact_liepa", "exact_table_bytes"]


@kernel()
def _leaf_table(Q, n, MN, has_third):
    # LEAF[s, m]: key of side (s, s+1) between patch triangle (s, s+1, m) and the mesh
    leaf = np.zeros((n, n))
    if not has_third:
        return leaf
    for s in range(n - 1):
        for m in range(n):
            if m == s or m == s + 1:
                continue
            x, y, z, d, _ = sorted_normal(Q, s, s + 1, m)
            leaf[s, m] = mesh_key(MN, s, x, y, z, d, has_third)
    return leaf


@kernel()
def _apex_normals(Q, i, j):
    # component rows (x, y, z, degenerate) and areas of triangles (i, k, j),
    # k = i + 1 .. j - 1: contiguous per component for the vectorized loops
    nk = np.zeros((4, j - i - 1))
    area = np.zeros(j - i - 1)
    for t in range(j - i - 1):
        x, y, z, d, a = unit_normal(Q, i, i + 1 + t, j)
        nk[0, t] = x
        nk[1, t] = y
        nk[2, t] = z
        nk[3, t] = 1.0 if d else 0.0
        area[t] = a
    return nk, area


@kernel()
def _keys_against(nk, ox, oy, oz, od, has, out):
    # out[t] = _key(apex triangle t, outer triangle), the same arithmetic
    if not has:
        out[:] = 0.0
        return
    if od:
        out[:] = DEGENERATE_KEY
        return
    X, Y, Z, D = nk[0], nk[1], nk[2], nk[3]
    for t in range(out.shape[0]):
        k = 1.0 - (X[t] * ox + Y[t] * oy + Z[t] * oz)
        k = min(max(k, 0.0), 2.0)
        out[t] = DEGENERATE_KEY if D[t] != 0.0 else k


# keys and areas are never NaN and min/max are exact in any order, so fast-math
# (which lets the compiler reorder the two reductions below) changes no result:
# there is no other arithmetic in them
@kernel(fastmath=True)
def _min_of_max(a, b):
    best = np.inf
    for t in range(a.shape[0]):
        best = min(best, max(a[t], b[t]))
    return best


@kernel(fastmath=True)
def _min_where(sub, keys, M, buf):
    # least sub[t] among apexes whose key is <= M (inf if none) into buf first
    best = np.inf
    for t in range(sub.shape[0]):
        c = sub[t] if keys[t] <= M else np.inf
        buf[t] = c
        best = min(best, c)
    return best


@kernel()
def _chord_inputs(Q, i, j, B, LEAF):
    # per apex k of chord (i, j): normal of (i, k, j), its area, and the worse key
    # of its two halves (sub-polygon (i, k) seen from apex j, (k, j) from apex i)
    nk, area = _apex_normals(Q, i, j)
    base = np.zeros(j - i - 1)
    for t in range(j - i - 1):
        k = i + 1 + t
        left = LEAF[i, j] if k - i == 1 else B[i, k, j]
        right = LEAF[k, i] if j - k == 1 else B[k, j, i]
        base[t] = max(left, right)
    return nk, area, base


@kernel()
def _outer_normal(Q, n, i, j, m, MN, has_third):
    # the triangle across chord (i, j): (i, j, m), or the mesh triangle at the root
    if m == n:
        if has_third:
            return MN[n - 1, 0], MN[n - 1, 1], MN[n - 1, 2], MN[n - 1, 3] != 0.0, True
        return 0.0, 0.0, 0.0, False, False
    x, y, z, d, _ = sorted_normal(Q, i, j, m)
    return x, y, z, d, True


@kernel()
def _outside(n, i, j):
    if i == 0 and j == n - 1:
        out = np.empty(1, dtype=np.int64)
        out[0] = n
        return out
    out = np.empty(n - (j - i + 1), dtype=np.int64)
    t = 0
    for m in range(n):
        if m < i or m > j:
            out[t] = m
            t += 1
    return out


@kernel()
def _bottleneck_pass(Q, n, has_third, MN, LEAF, B):
    # B[i, j, m]: least possible max key inside sub-polygon (i..j) and across
    # chord (i, j) to the outer triangle (i, j, m); m == n is the root's mesh side
    keys = np.empty(n)
    for L in range(2, n):
        for i in range(n - L):
            j = i + L
            nk, _, base = _chord_inputs(Q, i, j, B, LEAF)
            kb = keys[: L - 1]
            for m in _outside(n, i, j):
                ox, oy, oz, od, has = _outer_normal(Q, n, i, j, m, MN, has_third)
                _keys_against(nk, ox, oy, oz, od, has, kb)
                B[i, j, m] = _min_of_max(base, kb)
    return B[0, n - 1, n]


@kernel()
def _area_pass(Q, n, has_third, MN, LEAF, M, A, S):
    # A[i, j, m]: least area of sub-polygon (i..j) using only pairs with key <= M;
    # S[i, j, m]: its apex (the smallest on ties)
    keys = np.empty(n)
    buf = np.empty(n)
    for L in range(2, n):
        for i in range(n - L):
            j = i + L
            nk, area = _apex_normals(Q, i, j)
            sub = np.full(L - 1, np.inf)
            for t in range(L - 1):
                k = i + 1 + t
                left = (0.0 if LEAF[i, j] <= M else np.inf) if k - i == 1 else A[i, k, j]
                right = (0.0 if LEAF[k, i] <= M else np.inf) if j - k == 1 else A[k, j, i]
                sub[t] = left + right + area[t]
            kb, bb = keys[: L - 1], buf[: L - 1]
            for m in _outside(n, i, j):
                ox, oy, oz, od, has = _outer_normal(Q, n, i, j, m, MN, has_third)
                _keys_against(nk, ox, oy, oz, od, has, kb)
                best = _min_where(sub, kb, M, bb)
                arg = -1
                if best < np.inf:
                    for t in range(L - 1):
                        if bb[t] == best:
                            arg = i + 1 + t
                            break
                A[i, j, m] = best
                S[i, j, m] = arg
    return A[0, n - 1, n]


def exact_liepa(Q: np.ndarray, n: int, has_third: bool) -> tuple[float, float, np.ndarray]:
    """Exact (max dihedral key, area) optimum over all triangulations; O(n^4).

    State (i, j, m): sub-polygon i..j with the triangle (i, j, m) across its
    chord, so every dihedral is known when its two triangles meet
    (Barequet-Dickerson-Eppstein 1996). Two passes make the lexicographic pair
    exact: the first finds the least max key M (bottleneck: monotone), the
    second minimizes area over triangulations whose keys are all <= M.
    Returns (M, area, S) with S[i, j, m] the optimal apex.
    """
    MN = mesh_normals(Q, n) if has_third else np.zeros((1, 4))
    LEAF = _leaf_table(Q, n, MN, has_third)
    B = np.full((n, n, n + 1), np.inf)
    M = _bottleneck_pass(Q, n, has_third, MN, LEAF, B)
    del B  # the second pass needs only M: free the table before the next two
    A = np.full((n, n, n + 1), np.inf)
    S = np.full((n, n, n + 1), -1, dtype=np.int16)
    area = _area_pass(Q, n, has_third, MN, LEAF, M, A, S)
    return float(M), float(area), S


def exact_table_bytes(n: int) -> int:
    """Peak bytes of :func:`exact_liepa`'s tables (float64 + int16 per state)."""
    return n * n * (n + 1) * 10
