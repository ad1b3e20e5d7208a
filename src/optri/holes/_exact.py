"""Exact Liepa search over all triangulations of a 3-D polyline (numba).

Liepa's objective (largest dihedral angle, then total area) is not a sum of
triangle weights: a dihedral needs both triangles of an edge. The state
(i, j, m) -- sub-polygon i..j with the triangle (i, j, m) across its chord --
makes every dihedral known when its two triangles meet (Barequet, Dickerson,
Eppstein 1996): O(n^3) states, O(n) apexes each. Two passes make the pair
exact: :func:`bottleneck_lengths` finds the least largest key M (monotone),
:func:`area_lengths` the least area among patches whose keys are all <= M.

Speed and memory (the driver is :mod:`optri.holes.search`):

* States are stored compactly, one float64 per (chord, outer vertex) pair:
  slot ``off[i, j] + m`` for ``m < i`` and ``off[i, j] + m - (j - i + 1)``
  for ``m > j`` (the root (0, n - 1) has one slot, its mesh side): about
  n^3 / 3 slots, and the second pass reuses the first pass's array.
* Pass 1 is bounded by ``U``, the value of a known patch (Liepa's): a state
  worth more than U can never be part of the optimum, so it is stored as +inf
  and apexes over it are dropped. The remaining apexes of a chord are sorted
  by their sub-patch value, and a state's scan stops at the first apex whose
  sub-patch is already no better than the best found: its value is still the
  exact minimum.
* Pass 2 only visits states whose pass-1 value is <= M (marked -1), with the
  apexes sorted by (area, apex): the first apex whose key is <= M is the
  answer, the smallest apex among equal areas as before.

Every key uses the same arithmetic as the evaluator, so the result is the
exact optimum under :func:`optri.holes.liepa_objective`'s numbers.
"""

from __future__ import annotations

import math

import numpy as np

from ..engines.compiled import kernel
from ._kernels import DEGENERATE_KEY, DEGENERATE_SINE2, FOLD_KEY, mesh_key, sorted_normal

__all__ = [
    "PENDING",
    "area_lengths",
    "bottleneck_lengths",
    "leaf_table",
    "mark_pending",
    "state_count",
    "state_offsets",
    "trace",
]

#: Pass-2 mark of a state whose area is still to be computed (areas are >= 0).
PENDING = -1.0


def state_count(n: int) -> int:
    """Slots of the compact state array: (n-1)(n-2)(n-3)/3 + 1 (the root's)."""
    return (n - 1) * (n - 2) * (n - 3) // 3 + 1


@kernel()
def state_offsets(n):
    """First slot of each chord's states (-1 for sides); the root's slot is last."""
    off = np.full((n, n), -1, dtype=np.int64)
    s = 0
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            off[i, j] = s
            s += n - (j - i + 1)
    off[0, n - 1] = s
    return off


@kernel()
def _slot(off, a, b, m):
    if m < a:
        return off[a, b] + m
    return off[a, b] + m - (b - a + 1)


@kernel()
def leaf_table(Q, n, MN, has_third):
    """``leaf[s, m]``: key of side (s, s+1) between patch triangle (s, s+1, m) and the mesh."""
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
def _normals(X, Y, Z, a, b, cs, out, col):
    # unit normals of triangles {a, b, c} (a < b) for c in cs, vertices sorted as
    # sorted_normal takes them, into out[0:4, col + t]: unit_normal's arithmetic
    # in a loop the compiler vectorizes
    for t in range(cs.shape[0]):
        c = cs[t]
        if c < a:
            p, q, r = c, a, b
        elif c < b:
            p, q, r = a, c, b
        else:
            p, q, r = a, b, c
        ux = X[q] - X[p]
        uy = Y[q] - Y[p]
        uz = Z[q] - Z[p]
        vx = X[r] - X[p]
        vy = Y[r] - Y[p]
        vz = Z[r] - Z[p]
        nx = uy * vz - uz * vy
        ny = uz * vx - ux * vz
        nz = ux * vy - uy * vx
        n2 = nx * nx + ny * ny + nz * nz
        deg = n2 <= DEGENERATE_SINE2 * (
            (ux * ux + uy * uy + uz * uz) * (vx * vx + vy * vy + vz * vz)
        )
        inv = 0.0 if deg else 1.0 / math.sqrt(n2)
        out[0, col + t] = nx * inv
        out[1, col + t] = ny * inv
        out[2, col + t] = nz * inv
        out[3, col + t] = 1.0 if deg else 0.0


@kernel()
def _outer_normals(X, Y, Z, n, i, j, MN, has_third, out):
    # normals of the triangles across chord (i, j), in slot order; returns the
    # kind: 0 patch triangles, 1 the root's mesh triangle, 2 nothing (root only)
    if i == 0 and j == n - 1:
        if not has_third:
            return 2
        out[:4, 0] = MN[n - 1, :4]
        return 1
    _normals(X, Y, Z, i, j, np.arange(i), out, 0)
    _normals(X, Y, Z, i, j, np.arange(j + 1, n), out, i)
    return 0


@kernel()
def _key(ax, ay, az, ad, ox, oy, oz, od, kind):
    # key of apex triangle (ax, ay, az, ad) against the outer one: key_of / mesh_key
    if kind == 2:
        return 0.0
    if ad:
        return DEGENERATE_KEY
    if od:
        return DEGENERATE_KEY if kind == 0 else 0.0
    k = 1.0 - (ax * ox + ay * oy + az * oz)
    return min(max(k, 0.0), FOLD_KEY)


@kernel()
def _state_count(n, i, j):
    return 1 if i == 0 and j == n - 1 else n - (j - i + 1)


@kernel()
def bottleneck_lengths(Q, n, has_third, MN, leaf, allowed, off, B, U, L0, L1, buf):
    """Pass 1 for chord lengths ``L0 <= j - i < L1``: ``B[slot]`` = least max key.

    Values above ``U`` are stored as +inf. ``buf``: (10, n) scratch.
    """
    cap = np.nextafter(U, np.inf)  # a value <= U replaces it
    X, Y, Z = Q[:n, 0].copy(), Q[:n, 1].copy(), Q[:n, 2].copy()
    idx = np.empty(n, dtype=np.int64)
    for L in range(L0, L1):
        for i in range(n - L):
            j = i + L
            first, count = off[i, j], _state_count(n, i, j)
            cnt = 0
            if L == n - 1 or allowed[i, j]:
                cnt = _apexes_by_base(X, Y, Z, i, j, leaf, off, B, U, buf, idx)
            if cnt == 0:
                B[first : first + count] = np.inf
                continue
            kind = _outer_normals(X, Y, Z, n, i, j, MN, has_third, buf[6:])
            low = buf[4, 0]  # the least worth (first after sorting; kept there before)
            ranked = False
            for s in range(count):
                ox, oy, oz, od = buf[6, s], buf[7, s], buf[8, s], buf[9, s] != 0.0
                key = _key(buf[0, 0], buf[1, 0], buf[2, 0], buf[3, 0] != 0.0, ox, oy, oz, od, kind)
                if key <= low:  # no apex can beat the least worth
                    B[first + s] = low
                    continue
                if not ranked:
                    _rank(buf, cnt, 5, 4)
                    ranked = True
                best = min(cap, max(low, key))
                for t in range(1, cnt):
                    if buf[4, t] >= best:
                        break  # sorted: no later apex can do better
                    key = _key(
                        buf[0, t], buf[1, t], buf[2, t], buf[3, t] != 0.0, ox, oy, oz, od, kind
                    )
                    v = max(buf[4, t], key)
                    if v < best:
                        best = v
                B[first + s] = best if best <= U else np.inf


@kernel()
def _rank(buf, cnt, rows, by):
    # sort columns 0..cnt-1 of buf[:rows] by row ``by`` (stable: ties keep their order)
    order = np.argsort(buf[by, :cnt], kind="mergesort")
    buf[:rows, :cnt] = buf[:rows, :cnt][:, order]


@kernel()
def _apexes_by_base(X, Y, Z, i, j, leaf, off, B, U, buf, idx):
    # apexes k of chord (i, j) whose halves are worth <= U, as columns (x, y, z,
    # degenerate, worth) of buf in k order, but with one of least worth first;
    # returns their count
    cnt = 0
    low, at = np.inf, 0
    for k in range(i + 1, j):
        left = leaf[i, j] if k - i == 1 else B[_slot(off, i, k, j)]
        right = leaf[k, i] if j - k == 1 else B[_slot(off, k, j, i)]
        base = max(left, right)
        if base <= U:
            idx[cnt] = k
            buf[4, cnt] = base
            if base < low:
                low, at = base, cnt
            cnt += 1
    if cnt == 0:
        return 0
    buf[4, 0], buf[4, at] = buf[4, at], buf[4, 0]
    idx[0], idx[at] = idx[at], idx[0]
    _normals(X, Y, Z, i, j, idx[:cnt], buf, 0)
    return cnt


@kernel()
def _apexes_by_area(X, Y, Z, i, j, leaf, off, A, M, buf, idx):
    # apexes k of chord (i, j) whose halves have patches with keys <= M, as
    # columns (x, y, z, degenerate, area of the sub-patch, k) of buf in k order;
    # returns their count and the column of the least (area, k)
    cnt = 0
    low, at = np.inf, 0
    for k in range(i + 1, j):
        left = (0.0 if leaf[i, j] <= M else np.inf) if k - i == 1 else A[_slot(off, i, k, j)]
        right = (0.0 if leaf[k, i] <= M else np.inf) if j - k == 1 else A[_slot(off, k, j, i)]
        if left == np.inf or right == np.inf:
            continue
        idx[cnt] = k
        sub = (left + right) + unit_normal_area(X, Y, Z, i, k, j)  # as unit_normal computes it
        buf[4, cnt] = sub
        buf[5, cnt] = k
        if sub < low:
            low, at = sub, cnt
        cnt += 1
    _normals(X, Y, Z, i, j, idx[:cnt], buf, 0)
    return cnt, at


@kernel()
def unit_normal_area(X, Y, Z, a, b, c):
    """Area of triangle (a, b, c), a < b < c, with unit_normal's arithmetic."""
    ux = X[b] - X[a]
    uy = Y[b] - Y[a]
    uz = Z[b] - Z[a]
    vx = X[c] - X[a]
    vy = Y[c] - Y[a]
    vz = Z[c] - Z[a]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    return 0.5 * math.sqrt(nx * nx + ny * ny + nz * nz)


@kernel()
def area_lengths(Q, n, has_third, MN, leaf, off, A, M, L0, L1, buf):
    """Pass 2 for chord lengths ``L0 <= j - i < L1``: pending slots get their least area.

    ``A`` is pass 1's array with every value <= M replaced by :data:`PENDING`
    and every other by +inf. ``buf``: (10, n) scratch.
    """
    X, Y, Z = Q[:n, 0].copy(), Q[:n, 1].copy(), Q[:n, 2].copy()
    idx = np.empty(n, dtype=np.int64)
    for L in range(L0, L1):
        for i in range(n - L):
            j = i + L
            first, count = off[i, j], _state_count(n, i, j)
            pending = False
            for s in range(count):
                pending = pending or A[first + s] == PENDING
            if not pending:
                continue
            cnt, at = _apexes_by_area(X, Y, Z, i, j, leaf, off, A, M, buf, idx)
            kind = _outer_normals(X, Y, Z, n, i, j, MN, has_third, buf[6:])
            ranked = False
            for s in range(count):
                if A[first + s] != PENDING:
                    continue
                if cnt and _fits(buf, at, s, kind, M):  # the least area fits: done
                    A[first + s] = buf[4, at]
                    continue
                if not ranked:
                    _rank(buf, cnt, 6, 4)  # stable: the smaller apex first on ties
                    ranked, at = True, 0
                A[first + s] = _least_area(buf, cnt, s, kind, M)


@kernel()
def _fits(buf, t, s, kind, M):
    # is the key of apex column t against outer column s <= M?
    key = _key(
        buf[0, t],
        buf[1, t],
        buf[2, t],
        buf[3, t] != 0.0,
        buf[6, s],
        buf[7, s],
        buf[8, s],
        buf[9, s] != 0.0,
        kind,
    )
    return key <= M


@kernel()
def _least_area(buf, cnt, s, kind, M):
    # the first apex in (area, k) order whose key against outer s is <= M
    for t in range(cnt):
        if _fits(buf, t, s, kind, M):
            return buf[4, t]
    return np.inf


@kernel()
def mark_pending(states, M):
    """Before pass 2: :data:`PENDING` where pass 1 found <= M (a patch can use it), else +inf."""
    for s in range(states.shape[0]):
        states[s] = PENDING if states[s] <= M else np.inf


@kernel()
def trace(Q, n, has_third, MN, leaf, off, A, M, out):
    """Triangles of the optimum into ``out`` (n - 2, 3); False if a state has no apex."""
    X, Y, Z = Q[:n, 0].copy(), Q[:n, 1].copy(), Q[:n, 2].copy()
    buf = np.empty((10, n))
    idx = np.empty(n, dtype=np.int64)
    stack = np.empty((n, 3), dtype=np.int64)
    stack[0, 0] = 0
    stack[0, 1] = n - 1
    stack[0, 2] = n
    top = 1
    t = 0
    while top > 0:
        top -= 1
        i, j, m = stack[top, 0], stack[top, 1], stack[top, 2]
        cnt, _ = _apexes_by_area(X, Y, Z, i, j, leaf, off, A, M, buf, idx)
        kind = _outer_normals(X, Y, Z, n, i, j, MN, has_third, buf[6:])
        _rank(buf, cnt, 6, 4)
        s = 0 if m == n else (m if m < i else m - (j - i + 1))
        k = -1
        for r in range(cnt):
            if _fits(buf, r, s, kind, M):
                k = int(buf[5, r])
                break
        if k < 0 or t >= n - 2:
            return False
        out[t, 0] = i
        out[t, 1] = k
        out[t, 2] = j
        t += 1
        for a, b, c in ((i, k, j), (k, j, i)):
            if b - a > 1:
                stack[top, 0] = a
                stack[top, 1] = b
                stack[top, 2] = c
                top += 1
    return t == n - 2
