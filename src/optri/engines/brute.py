"""Exhaustive search over every triangulation: the test oracle (small n only).

Generates all Catalan(n-2) triangulations of the index polygon that use only
allowed chords, evaluates each one's cost from scratch, keeps the first best.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from .. import config
from ..errors import InvalidPolygonError, NoTriangulationError
from .problem import Problem, Solution
from .recurrence import split_points

__all__ = ["all_index_triangulations", "solve"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True
#: Integer weights stay Python ints: exact costs at any size.
EXACT_INTS = True

Tri = tuple[int, int, int]


def all_index_triangulations(n: int, ok: list[list[bool]] | None = None) -> Iterator[list[Tri]]:
    """Yield every triangulation of polygon 0..n-1 as a list of (i, k, j).

    ``ok[a][b]`` restricts the chords that may be used (None: all).

    >>> sum(1 for _ in all_index_triangulations(6))
    14
    """

    def rec(i: int, j: int) -> Iterator[list[Tri]]:
        if j - i < 2:
            yield []
            return
        for k in split_points(i, j, ok):
            for left in rec(i, k):
                for right in rec(k, j):
                    yield [(i, k, j), *left, *right]

    yield from rec(0, n - 1)


def solve(problem: Problem) -> Solution:
    """Evaluate every triangulation; exponential, n <= ``config.BRUTE_MAX_N``."""
    n = problem.n
    if n > config.BRUTE_MAX_N:
        raise InvalidPolygonError(
            f"method='brute' enumerates Catalan(n-2) triangulations; n = {n} is above "
            f"the limit {config.BRUTE_MAX_N} (config.BRUTE_MAX_N)"
        )
    w = problem.evaluator()
    objective = problem.objective
    best_cost, best_tris, count = objective.worst, None, 0
    for tris in all_index_triangulations(n, problem.allowed_rows()):
        count += 1
        c = objective.aggregate([w(*t) for t in tris])
        if best_tris is None or objective.less(c, best_cost):
            best_cost, best_tris = c, tris
    if best_tris is None:
        raise NoTriangulationError("the polygon has no triangulation with the allowed diagonals")
    tris_arr = np.array(sorted(best_tris), dtype=np.int64).reshape(-1, 3)
    stats = {"triangulations": count, "weight_evaluations": count * (n - 2)}
    return Solution(best_cost, tris_arr, None, stats)
