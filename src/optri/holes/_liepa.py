"""Liepa's O(n^3) recurrence, compiled: over all apexes (dense) or candidate lists (sparse).

Both minimize (max dihedral key, area) lexicographically per chord, measuring
the dihedral across chord (i, k) against the *optimal* top triangle of
sub-polygon (i, k) only: a heuristic for the max-dihedral objective (the
exact search is :mod:`optri.holes._exact`). A chord that ``allowed`` forbids
(an edge the mesh already has) is never used. The kernels fill arrays the
caller allocated and return nothing, so a Ctrl-C between calls surfaces as a
plain ``KeyboardInterrupt``; the dense kernel runs a range of rows per call.
"""

from __future__ import annotations

import math

import numpy as np

from ..engines.compiled import kernel
from ._kernels import DEGENERATE_KEY, DEGENERATE_SINE2, FOLD_KEY, key_of, mesh_key, unit_normal

__all__ = ["dense_rows", "sparse_chords", "sparse_trace"]


@kernel()
def _store_none(T, K, i, j):
    # chord (i, j) admits no patch (forbidden, or every split is): +inf for its parents
    K[i, j] = -1
    for r, c in ((i, j), (j, i)):
        T[r, 0, c] = np.inf
        T[r, 1, c] = np.inf
        T[r, 2, c] = 0.0
        T[r, 3, c] = 0.0
        T[r, 4, c] = 0.0


@kernel(error_model="numpy")
def dense_rows(Q, n, has_third, MN, allowed, T, K, C, i_hi, i_lo):
    """Rows ``i = i_hi .. i_lo`` (descending) of the dense recurrence, in place.

    ``T[a, :, b]`` = (key, area, top normal) of chord (a, b), stored at
    ``[i, :, j]`` and ``[j, :, i]`` so both halves of a split read rows (zeros
    on the polygon sides); ``K[i, j]`` its apex, -1 if it admits no patch;
    ``C`` a (2, n) scratch buffer. Per chord, two simple loops over contiguous
    buffers that the compiler vectorizes; sides and the root are fixed up in
    scalar code (:func:`_fix_ends`).
    """
    X = Q[:n, 0].copy()
    Y = Q[:n, 1].copy()
    Z = Q[:n, 2].copy()
    for i in range(i_hi, i_lo - 1, -1):
        for j in range(i + 2, n):
            if not allowed[i, j] and not (i == 0 and j == n - 1):
                _store_none(T, K, i, j)
                continue
            m = j - i - 1
            vx = X[j] - X[i]
            vy = Y[j] - Y[i]
            vz = Z[j] - Z[i]
            vv = vx * vx + vy * vy + vz * vz
            xi, yi, zi = X[i], Y[i], Z[i]
            Xs, Ys, Zs = X[i + 1 : j], Y[i + 1 : j], Z[i + 1 : j]
            o = i + 1  # T indexed directly: a slice of an argument has strides the
            # compiler cannot see, and the loop below would not vectorize
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
                deg = n2 <= DEGENERATE_SINE2 * (uu * vv)
                inv = 0.0 if deg else 1.0 / nn  # a zero normal, never NaN
                ax = nx * inv
                ay = ny * inv
                az = nz * inv
                kl = 1.0 - (ax * T[i, 2, o + t] + ay * T[i, 3, o + t] + az * T[i, 4, o + t])
                kr = 1.0 - (ax * T[j, 2, o + t] + ay * T[j, 3, o + t] + az * T[j, 4, o + t])
                kl = min(max(kl, 0.0), FOLD_KEY)
                kr = min(max(kr, 0.0), FOLD_KEY)
                kl = DEGENERATE_KEY if deg else kl
                kr = DEGENERATE_KEY if deg else kr
                C[0, t] = max(max(T[i, 0, o + t], T[j, 0, o + t]), max(kl, kr))
                C[1, t] = T[i, 1, o + t] + T[j, 1, o + t] + 0.5 * nn
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
            if best1 == np.inf:
                _store_none(T, K, i, j)
                continue
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
            c1 = max(T[i, 0, k], key_of(x, y, z, d, T[i, 2, k], T[i, 3, k], T[i, 4, k], False))
        if j - k == 1:
            c1 = max(c1, mesh_key(MN, k, x, y, z, d, has_third))
        else:
            c1 = max(c1, T[j, 0, k], key_of(x, y, z, d, T[j, 2, k], T[j, 3, k], T[j, 4, k], False))
        C[0, k - i - 1] = c1
    if i == 0 and j == n - 1 and has_third:
        for k in range(i + 1, j):
            x, y, z, d, _ = unit_normal(Q, i, k, j)
            C[0, k - 1] = max(C[0, k - 1], mesh_key(MN, n - 1, x, y, z, d, has_third))


@kernel()
def _chord_id(keys, key):
    # index of chord key (i * n + j) in the sorted ``keys``, -1 if absent
    p = np.searchsorted(keys, key)
    if p < keys.shape[0] and keys[p] == key:
        return p
    return -1


@kernel()
def sparse_chords(Q, n, has_third, MN, keys, order, ptr, apex, V, TN, K):
    """The recurrence over candidate triangles, chord by chord, in place.

    ``keys`` (sorted): chords ``i * n + j`` with candidate apexes
    ``apex[ptr[c]:ptr[c + 1]]`` (increasing); ``order``: chord ids by
    increasing ``j - i``. Fills ``V[c] = (key, area)`` (+inf: no patch),
    ``TN[c]`` = the top triangle's (x, y, z, degenerate) and ``K[c]`` its apex.
    """
    for p in range(order.shape[0]):
        c = order[p]
        i = keys[c] // n
        j = keys[c] % n
        root = i == 0 and j == n - 1
        best1 = np.inf
        best2 = np.inf
        bestk = -1
        bx = by = bz = 0.0
        bd = False
        for t in range(ptr[c], ptr[c + 1]):
            k = apex[t]
            cl = -1 if k - i == 1 else _chord_id(keys, i * n + k)
            cr = -1 if j - k == 1 else _chord_id(keys, k * n + j)
            if (k - i > 1 and (cl < 0 or V[cl, 0] == np.inf)) or (
                j - k > 1 and (cr < 0 or V[cr, 0] == np.inf)
            ):
                continue
            x, y, z, d, area = unit_normal(Q, i, k, j)
            if cl < 0:
                c1 = mesh_key(MN, i, x, y, z, d, has_third)
                c2 = area
            else:
                c1 = max(
                    V[cl, 0], key_of(x, y, z, d, TN[cl, 0], TN[cl, 1], TN[cl, 2], TN[cl, 3] != 0)
                )
                c2 = V[cl, 1] + area
            if cr < 0:
                c1 = max(c1, mesh_key(MN, k, x, y, z, d, has_third))
            else:
                c1 = max(
                    c1,
                    V[cr, 0],
                    key_of(x, y, z, d, TN[cr, 0], TN[cr, 1], TN[cr, 2], TN[cr, 3] != 0),
                )
                c2 = c2 + V[cr, 1]
            if root:
                c1 = max(c1, mesh_key(MN, n - 1, x, y, z, d, has_third))
            if c1 < best1 or (c1 == best1 and c2 < best2):
                best1, best2, bestk = c1, c2, k
                bx, by, bz, bd = x, y, z, d
        V[c, 0] = best1
        V[c, 1] = best2
        K[c] = bestk
        TN[c, 0] = bx
        TN[c, 1] = by
        TN[c, 2] = bz
        TN[c, 3] = 1.0 if bd else 0.0


@kernel()
def sparse_trace(n, keys, K, out):
    """Triangles of the sparse solution into ``out`` (n - 2, 3); False if it is incomplete."""
    stack = np.empty((n, 2), dtype=np.int64)
    stack[0, 0] = 0
    stack[0, 1] = n - 1
    top = 1
    t = 0
    while top > 0:
        top -= 1
        i = stack[top, 0]
        j = stack[top, 1]
        c = _chord_id(keys, i * n + j)
        if c < 0 or K[c] < 0 or t >= n - 2:
            return False
        k = K[c]
        out[t, 0] = i
        out[t, 1] = k
        out[t, 2] = j
        t += 1
        if k - i > 1:
            stack[top, 0] = i
            stack[top, 1] = k
            top += 1
        if j - k > 1:
            stack[top, 0] = k
            stack[top, 1] = j
            top += 1
    return t == n - 2
