"""Independent exact oracles for the exactness tests (not collected).

Every double is an integer times a power of two, so a polygon's coordinates
scaled by one common power of two are Python ints, and orientation becomes
integer arithmetic: exact, and written here without any of optri's code. On
top of it: the valid-diagonal mask (in-cone at both ends, no vertex on the
open chord, no proper crossing), the number of triangulations over that mask
and the minimum perimeter-sum DP (Klincsek 1980), all in plain Python.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np


def sign_q(ax, ay, bx, by, cx, cy) -> int:
    """Exact sign of the turn a -> b -> c with Fractions (the predicate oracle)."""
    d = (Fraction(bx) - Fraction(ax)) * (Fraction(cy) - Fraction(ay)) - (
        Fraction(by) - Fraction(ay)
    ) * (Fraction(cx) - Fraction(ax))
    return (d > 0) - (d < 0)


def between_q(ax, ay, bx, by, cx, cy) -> bool:
    """c strictly inside segment ab, for c collinear with it (Fractions)."""
    a, b, c = (tuple(map(Fraction, p)) for p in ((ax, ay), (bx, by), (cx, cy)))
    dot = (c[0] - a[0]) * (b[0] - a[0]) + (c[1] - a[1]) * (b[1] - a[1])
    return 0 < dot < (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2


def as_integers(points: np.ndarray) -> tuple[list[int], list[int]]:
    """The coordinates times one power of two: Python ints, exactly."""
    fr = [Fraction(float(v)) for v in np.asarray(points, dtype=float).ravel()]
    den = max(f.denominator for f in fr)  # powers of two: the largest divides by all
    ints = [f.numerator * (den // f.denominator) for f in fr]
    return ints[0::2], ints[1::2]


def ccw(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise order starting at vertex 0, decided by the exact area."""
    x, y = as_integers(points)
    n = len(x)
    twice = sum(x[i] * y[(i + 1) % n] - x[(i + 1) % n] * y[i] for i in range(n))
    return points if twice > 0 else np.concatenate([points[:1], points[:0:-1]])


def exact_mask(points: np.ndarray) -> np.ndarray:
    """(n, n) internal diagonals of a simple CCW polygon, sides True; exact ints."""
    x, y = as_integers(points)
    n = len(x)

    def o(a: int, b: int, c: int) -> int:
        d = (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a])
        return (d > 0) - (d < 0)

    def starts_inside(i: int, j: int) -> bool:
        p, q = (i - 1) % n, (i + 1) % n
        after, before = o(i, q, j) > 0, o(p, i, j) > 0
        return (after and before) if o(p, i, q) > 0 else (after or before)

    def on_chord(i: int, j: int, v: int) -> bool:
        dot = (x[v] - x[i]) * (x[j] - x[i]) + (y[v] - y[i]) * (y[j] - y[i])
        return o(i, j, v) == 0 and 0 < dot < (x[j] - x[i]) ** 2 + (y[j] - y[i]) ** 2

    def clear(i: int, j: int) -> bool:
        for v in range(n):
            if v not in (i, j) and on_chord(i, j, v):
                return False
            w = (v + 1) % n
            if len({i, j, v, w}) == 4:
                if o(i, j, v) * o(i, j, w) < 0 and o(v, w, i) * o(v, w, j) < 0:
                    return False
        return True

    ok = np.zeros((n, n), dtype=bool)
    for i in range(n):
        ok[i, (i + 1) % n] = ok[(i + 1) % n, i] = True
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            if starts_inside(i, j) and starts_inside(j, i) and clear(i, j):
                ok[i, j] = ok[j, i] = True
    return ok


def exact_count(ok: np.ndarray) -> int:
    """Triangulations over the chord mask ``ok`` (big ints)."""
    n = len(ok)
    cnt = [[0] * n for _ in range(n)]
    for i in range(n - 1):
        cnt[i][i + 1] = 1
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            if ok[i, j]:
                cnt[i][j] = sum(
                    cnt[i][k] * cnt[k][j] for k in range(i + 1, j) if ok[i, k] and ok[k, j]
                )
    return cnt[0][n - 1]


def perimeter_dp(points: np.ndarray, ok: np.ndarray) -> float:
    """Minimum total triangle perimeter over the mask (sides True); inf if none."""
    n = len(points)
    length = [[math.hypot(*(points[a] - points[b])) for b in range(n)] for a in range(n)]
    cost = [[math.inf] * n for _ in range(n)]
    for i in range(n - 1):
        cost[i][i + 1] = 0.0
    for d in range(2, n):
        for i in range(n - d):
            j = i + d
            if not ok[i, j]:
                continue
            li = length[i]
            cost[i][j] = min(
                (
                    cost[i][k] + cost[k][j] + li[k] + length[k][j] + li[j]
                    for k in range(i + 1, j)
                    if ok[i, k] and ok[k, j]
                ),
                default=math.inf,
            )
    return cost[0][n - 1]


def exact_strictly_convex(points: np.ndarray) -> bool:
    """Whether every other vertex lies strictly on one and the same side of every edge.

    Either orientation; a ring around twice, or one with a straight vertex, is not.
    Exact ints, O(n^2).
    """
    x, y = as_integers(points)
    n = len(x)
    sides = set()
    for a in range(n):
        b = (a + 1) % n
        for c in range(n):
            if c not in (a, b):
                d = (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a])
                sides.add((d > 0) - (d < 0))
    return sides in ({1}, {-1})


def exact_simple(points: np.ndarray) -> bool:
    """Whether the closed ring of distinct points is simple: no two edges meet improperly.

    Adjacent edges may only share their common vertex (no fold-back); other edges
    may not cross, touch or overlap. Exact ints, O(n^2).
    """
    x, y = as_integers(points)
    n = len(x)

    def o(a: int, b: int, c: int) -> int:
        d = (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a])
        return (d > 0) - (d < 0)

    def on_closed(a: int, b: int, c: int) -> bool:  # c on segment ab, given collinear
        return min(x[a], x[b]) <= x[c] <= max(x[a], x[b]) and min(y[a], y[b]) <= y[c] <= max(
            y[a], y[b]
        )

    for e in range(n):
        a, b = e, (e + 1) % n
        for f in range(e + 1, n):
            c, d = f, (f + 1) % n
            if b == c or d == a:  # adjacent: they share one vertex, must not fold back
                s, p, q = (b, a, d) if b == c else (a, b, c)
                if (
                    o(p, s, q) == 0
                    and (x[p] - x[s]) * (x[q] - x[s]) + (y[p] - y[s]) * (y[q] - y[s]) > 0
                ):
                    return False
                continue
            o1, o2, o3, o4 = o(a, b, c), o(a, b, d), o(c, d, a), o(c, d, b)
            if o1 * o2 < 0 and o3 * o4 < 0:
                return False
            if (
                (o1 == 0 and on_closed(a, b, c))
                or (o2 == 0 and on_closed(a, b, d))
                or (o3 == 0 and on_closed(c, d, a))
                or (o4 == 0 and on_closed(c, d, b))
            ):
                return False
    return True
