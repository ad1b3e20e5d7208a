"""The yardstick a user writes by hand: the memoized recursion in plain Python.

No numpy, no optri: the textbook recursion for the minimum total perimeter of a
convex polygon's triangulation, cached with :func:`functools.cache`. It is
what ``method="fast"`` is measured against in ``optri bench``, on small n only
(it takes about n³/6 interpreted steps).

``python -m optri.bench.naive POLYGON.csv`` prints ``n weight seconds`` (the
recursion alone), like the C reference ``yardsticks/ref_mwt.c``.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from functools import cache

__all__ = ["min_perimeter", "read_csv"]


def min_perimeter(points: Sequence[tuple[float, float]]) -> float:
    """Least total perimeter over the triangulations of a convex polygon.

    >>> min_perimeter([(0, 0), (1, 0), (1, 1), (0, 1)])  # two right triangles
    6.82842712474619
    """
    n = len(points)

    def dist(a: int, b: int) -> float:
        return math.dist(points[a], points[b])

    @cache
    def best(i: int, j: int) -> float:
        if j - i < 2:
            return 0.0
        return min(
            best(i, k) + best(k, j) + dist(i, k) + dist(k, j) + dist(i, j) for k in range(i + 1, j)
        )

    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, 4 * n + 100))
    try:
        return best(0, n - 1)
    finally:
        sys.setrecursionlimit(old)


def read_csv(path: str) -> list[tuple[float, float]]:
    """``x,y`` lines of a file; other lines (a header, blanks) are skipped."""
    points = []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            parts = line.split(",")
            try:
                points.append((float(parts[0]), float(parts[1])))
            except (ValueError, IndexError):
                continue
    return points


if __name__ == "__main__":
    pts = read_csv(sys.argv[1])
    start = time.perf_counter()
    weight = min_perimeter(pts)
    print(len(pts), repr(weight), f"{time.perf_counter() - start:.6f}")
