"""Compiled kernels for filling 3-D polylines (numba, ``cache=True``).

Vertex array ``Q`` holds the ``n`` polyline points, followed (when the mesh
around the hole is known) by the ``n`` third points: ``Q[n + s]`` is the third
vertex of the mesh triangle on boundary edge ``(s, s + 1)``. Every triangle
normal is computed by :func:`unit_normal` from its *sorted* vertex indices, so
the kernels and the evaluator (:func:`triangle_normals`) see bit-identical
values and their max-dihedral comparisons agree exactly.

The dihedral "key" of two adjacent, consistently oriented triangles is
``1 - cos(angle between their normals)`` in [0, 2]: monotone in the angle, so
comparing keys compares angles without an ``acos`` in the inner loops. A
degenerate (zero-area) triangle gets the worst key, 2 (a fold of pi).
"""

from __future__ import annotations

import math

import numpy as np

from ..engines.compiled import kernel

__all__ = [
    "DEGENERATE_KEY",
    "mesh_key",
    "sorted_normal",
    "liepa_recurrence",
    "mesh_normals",
    "pair_keys",
    "triangle_normals",
    "unit_normal",
]

#: Key given to any pair involving a zero-area triangle (angle pi).
DEGENERATE_KEY = 2.0
#: A triangle whose squared sine of the angle at its first vertex is at most this
#: is degenerate (sine <= 1e-12).
_DEGENERATE_SINE2 = 1e-24



@kernel()
def _cross(Q, a, b, c):
    # (b - a) x (c - a) and the squared lengths of both edge vectors
    ux = Q[b, 0] - Q[a, 0]
    uy = Q[b, 1] - Q[a, 1]
    uz = Q[b, 2] - Q[a, 2]
    vx = Q[c, 0] - Q[a, 0]
    vy = Q[c, 1] - Q[a, 1]
    vz = Q[c, 2] - Q[a, 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    return nx, ny, nz, ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz


@kernel()
def unit_normal(Q, a, b, c):
    """Unit normal of triangle a->b->c, a degenerate flag and the area."""
    nx, ny, nz, uu, vv = _cross(Q, a, b, c)
    n2 = nx * nx + ny * ny + nz * nz
    nn = math.sqrt(n2)
    if n2 <= _DEGENERATE_SINE2 * (uu * vv):
        return 0.0, 0.0, 0.0, True, 0.5 * nn
    inv = 1.0 / nn
    return nx * inv, ny * inv, nz * inv, False, 0.5 * nn


@kernel()
def sorted_normal(Q, a, b, c):
    # the same triangle always gets the same rounding: compute from sorted indices
    if a > b:
        a, b = b, a
    if b > c:
        b, c = c, b
    if a > b:
        a, b = b, a
    return unit_normal(Q, a, b, c)


@kernel()
def _key(x1, y1, z1, d1, x2, y2, z2, d2):
    if d1 or d2:
        return DEGENERATE_KEY
    k = 1.0 - (x1 * x2 + y1 * y2 + z1 * z2)
    if k < 0.0:
        return 0.0
    if k > 2.0:
        return 2.0
    return k


@kernel()
def mesh_normals(Q, n):
    """(n, 4) rows (x, y, z, degenerate) of the mesh triangles (p[s+1], p[s], t[s])."""
    out = np.zeros((n, 4))
    for s in range(n):
        x, y, z, d, _ = unit_normal(Q, (s + 1) % n, s, n + s)
        out[s, 0] = x
        out[s, 1] = y
        out[s, 2] = z
        out[s, 3] = 1.0 if d else 0.0
    return out


@kernel()
def triangle_normals(Q, tris):
    """(m, 5) rows (x, y, z, degenerate, area) of index triangles (sorted first)."""
    m = tris.shape[0]
    out = np.zeros((m, 5))
    for t in range(m):
        x, y, z, d, area = sorted_normal(Q, tris[t, 0], tris[t, 1], tris[t, 2])
        out[t, 0] = x
        out[t, 1] = y
        out[t, 2] = z
        out[t, 3] = 1.0 if d else 0.0
        out[t, 4] = area
    return out


@kernel()
def pair_keys(U, V):
    """Keys of row pairs (x, y, z, degenerate, ...) of two normal tables."""
    out = np.empty(U.shape[0])
    for r in range(U.shape[0]):
        out[r] = _key(
            U[r, 0], U[r, 1], U[r, 2], U[r, 3] != 0.0, V[r, 0], V[r, 1], V[r, 2], V[r, 3] != 0.0
        )
    return out


@kernel()
def mesh_key(MN, s, x, y, z, d, has_third):
    if not has_third:
        return 0.0
    return _key(x, y, z, d, MN[s, 0], MN[s, 1], MN[s, 2], MN[s, 3] != 0.0)


@kernel()
def _span(ptr, i, j, n):
    # candidate apexes of chord (i, j): ks[lo:hi] from the CSR lists, or every
    # k in (i, j) when unrestricted (lo = -1; the apex is then i + 1 + t)
    if ptr.shape[0] == 0:
        return -1, j - i - 1
    c = i * n + j
    return ptr[c], ptr[c + 1] - ptr[c]


@kernel()
def _apex(ks, lo, i, t):
    return i + 1 + t if lo < 0 else ks[lo + t]


@kernel()
def liepa_recurrence(Q, n, has_third, ptr, ks):
    """Liepa's O(n^3) recurrence: (max dihedral key, area), lexicographic.

    The dihedral across chord (i, k) is measured against the *optimal* top
    triangle of sub-polygon (i, k) (its apex from the split table), so this is
    a heuristic for the max-dihedral objective. ``ptr``/``ks``: CSR candidate
    apexes per chord (empty ``ptr``: all). Returns (key, area, split table);
    split[0, n-1] < 0 when the candidates admit no triangulation.
    """
    if ptr.shape[0] == 0:
        return _liepa_dense(Q, n, has_third)
    return _liepa_sparse(Q, n, has_third, ptr, ks)


@kernel()
def _liepa_sparse(Q, n, has_third, ptr, ks):
    """Liepa's O(n^3) recurrence: (max dihedral key, area), lexicographic.

    The dihedral across chord (i, k) is measured against the *optimal* top
    triangle of sub-polygon (i, k) (its apex from the split table), so this is
    a heuristic for the max-dihedral objective (exact for the area part only
    given the chosen shape). Returns (key, area, split table); split[0, n-1] < 0
    when the candidate set admits no triangulation.
    """
    MN = mesh_normals(Q, n) if has_third else np.zeros((1, 4))
    # per chord (i, j): best (key, area) and the unit normal of its top triangle,
    # stored at [i, j] and transposed at [j, i] so both halves of a split read
    # rows; a key of infinity marks a sub-polygon with no candidate triangulation
    O1 = np.full((n, n), np.inf)
    O2 = np.empty((n, n))  # read only where O1 is finite
    TN = np.empty((n, n, 4))
    K = np.full((n, n), -1, dtype=np.int32)
    for i in range(n - 1):
        O1[i, i + 1] = O1[i + 1, i] = 0.0
        O2[i, i + 1] = O2[i + 1, i] = 0.0
        K[i, i + 1] = i
    for i in range(n - 3, -1, -1):  # (i, k) earlier in this row, (k, j) in done rows
        for j in range(i + 2, n):
            lo, cnt = _span(ptr, i, j, n)
            if cnt == 0:
                continue
            root = i == 0 and j == n - 1
            best1 = np.inf
            best2 = np.inf
            bestk = -1
            bx = by = bz = 0.0
            bd = False
            for t in range(cnt):
                k = _apex(ks, lo, i, t)
                if O1[i, k] == np.inf or O1[j, k] == np.inf:
                    continue
                x, y, z, d, area = unit_normal(Q, i, k, j)
                if k - i == 1:
                    c1 = mesh_key(MN, i, x, y, z, d, has_third)
                else:
                    tn = TN[i, k]
                    c1 = max(O1[i, k], _key(x, y, z, d, tn[0], tn[1], tn[2], tn[3] != 0.0))
                if j - k == 1:
                    c1 = max(c1, mesh_key(MN, k, x, y, z, d, has_third))
                else:
                    tn = TN[j, k]
                    c1 = max(c1, O1[j, k], _key(x, y, z, d, tn[0], tn[1], tn[2], tn[3] != 0.0))
                if root:
                    c1 = max(c1, mesh_key(MN, n - 1, x, y, z, d, has_third))
                if c1 > best1:
                    continue
                c2 = O2[i, k] + O2[j, k] + area
                if c1 < best1 or c2 < best2:
                    best1, best2, bestk = c1, c2, k
                    bx, by, bz, bd = x, y, z, d
            K[i, j] = bestk
            O1[i, j] = O1[j, i] = best1
            O2[i, j] = O2[j, i] = best2
            for r, c in ((i, j), (j, i)):
                TN[r, c, 0] = bx
                TN[r, c, 1] = by
                TN[r, c, 2] = bz
                TN[r, c, 3] = 1.0 if bd else 0.0
    return O1[0, n - 1], O2[0, n - 1], K


@kernel(error_model="numpy")
def _liepa_dense(Q, n, has_third):
    # every apex is a candidate. Per chord, two simple loops over contiguous,
    # interleaved buffers (few pointers, no branches) that the compiler
    # vectorizes: W[t] = (unit normal, area, degenerate) of triangle (i, i+1+t, j);
    # C[t] = its (key, area) candidate. T[a, b] = (key, area, top normal) of
    # chord (a, b), stored at [i, j] and at [j, i] so both
    # halves of a split read rows. Sides and the root are fixed up in scalar code.
    MN = mesh_normals(Q, n) if has_third else np.zeros((1, 4))
    X = Q[:n, 0].copy()
    Y = Q[:n, 1].copy()
    Z = Q[:n, 2].copy()
    T = np.zeros((n, 5, n))
    K = np.full((n, n), -1, dtype=np.int32)
    C = np.empty((2, n))
    for i in range(n - 1):
        K[i, i + 1] = i
    # row i of T stays in cache while j grows: i descending, j ascending
    # (both halves of (i, j) are ready: (i, k) earlier in this row, (k, j) in
    # rows already done)
    for i in range(n - 3, -1, -1):
        for j in range(i + 2, n):
            m = j - i - 1
            vx = X[j] - X[i]
            vy = Y[j] - Y[i]
            vz = Z[j] - Z[i]
            vv = vx * vx + vy * vy + vz * vz
            xi, yi, zi = X[i], Y[i], Z[i]
            Xs, Ys, Zs = X[i + 1 : j], Y[i + 1 : j], Z[i + 1 : j]
            Ti = T[i, :, i + 1 : j]
            Tj = T[j, :, i + 1 : j]
            for t in range(m):
                ux = Xs[t] - xi
                uy = Ys[t] - yi
                uz = Zs[t] - zi
                nx = uy * vz - uz * vy
                ny = uz * vx - ux * vz
                nz = ux * vy - uy * vx
                n2 = nx * nx + ny * ny + nz * nz
                nn = math.sqrt(n2)
                uu = ux * ux + uy * uy + uz * uz
                deg = n2 <= _DEGENERATE_SINE2 * (uu * vv)
                inv = 0.0 if deg else 1.0 / nn  # a zero normal, never NaN
                ax = nx * inv
                ay = ny * inv
                az = nz * inv
                kl = 1.0 - (ax * Ti[2, t] + ay * Ti[3, t] + az * Ti[4, t])
                kr = 1.0 - (ax * Tj[2, t] + ay * Tj[3, t] + az * Tj[4, t])
                kl = min(max(kl, 0.0), 2.0)
                kr = min(max(kr, 0.0), 2.0)
                kl = DEGENERATE_KEY if deg else kl
                kr = DEGENERATE_KEY if deg else kr
                C[0, t] = max(max(Ti[0, t], Tj[0, t]), max(kl, kr))
                C[1, t] = Ti[1, t] + Tj[1, t] + 0.5 * nn
            _fix_ends(Q, n, i, j, has_third, MN, T, C)
            best1 = np.inf
            best2 = np.inf
            bt = 0
            for t in range(m):
                c1 = C[0, t]
                if c1 < best1 or (c1 == best1 and C[1, t] < best2):
                    best1 = c1
                    best2 = C[1, t]
                    bt = t
            K[i, j] = i + 1 + bt
            x, y, z, d, _ = unit_normal(Q, i, i + 1 + bt, j)
            for r, c in ((i, j), (j, i)):
                # a degenerate top folds against anything above it: its parents'
                # key is then the worst, DEGENERATE_KEY, whatever their normal
                T[r, 0, c] = DEGENERATE_KEY if d else best1
                T[r, 1, c] = best2
                T[r, 2, c] = x
                T[r, 3, c] = y
                T[r, 4, c] = z
    return best1, T[0, 1, n - 1], K


@kernel()
def _fix_ends(Q, n, i, j, has_third, MN, T, C):
    # apex k = i + 1 or j - 1 puts a polygon side in the triangle: its key is
    # against the mesh (or nothing), not a sub-polygon's top; the root also
    # meets the mesh across side (n - 1, 0). C is indexed by t = k - i - 1.
    ends = (i + 1, j - 1)
    for e in range(2 if j - i > 2 else 1):
        k = ends[e]
        x, y, z, d, _ = unit_normal(Q, i, k, j)
        if k - i == 1:
            c1 = mesh_key(MN, i, x, y, z, d, has_third)
        else:
            c1 = max(T[i, 0, k], _key(x, y, z, d, T[i, 2, k], T[i, 3, k], T[i, 4, k], False))
        if j - k == 1:
            c1 = max(c1, mesh_key(MN, k, x, y, z, d, has_third))
        else:
            c1 = max(c1, T[j, 0, k], _key(x, y, z, d, T[j, 2, k], T[j, 3, k], T[j, 4, k], False))
        C[0, k - i - 1] = c1
    if i == 0 and j == n - 1 and has_third:
        for k in range(i + 1, j):
            x, y, z, d, _ = unit_normal(Q, i, k, j)
            C[0, k - 1] = max(C[0, k - 1], mesh_key(MN, n - 1, x, y, z, d, has_third))
