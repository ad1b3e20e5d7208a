"""Bottom-up tabulation: the "square matrix" method.

Fills every chord ``(i, j)`` in order of increasing ``j - i`` so both halves of
each split are ready when needed (Cormen et al., *Introduction to Algorithms*,
3rd ed., 15.2; Saracevic et al. 2018 for the square-matrix presentation).
"""

from __future__ import annotations

from .memo import _progress_reporter
from .problem import Problem, Solution, triangles_from_splits
from .tables import export_table, new_tables

__all__ = ["solve"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True

_UNSET = None


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` bottom-up; O(n^3) time, O(n^2) space.

    ``Solution.stats``: ``weight_evaluations`` and ``cells``.
    """
    n = problem.n
    w = problem.evaluator()
    combine, less = problem.objective.combine, problem.objective.less
    worst = problem.objective.worst
    ok = problem.allowed_rows()
    cost, split = new_tables(problem, _UNSET)
    report = _progress_reporter(problem, n)

    evaluations = cells = 0
    for d in range(2, n):
        for i in range(0, n - d):
            j = i + d
            if ok is not None and not ok[i][j]:
                continue
            row_i = cost[i]
            best, arg = worst, -1
            for k in range(i + 1, j):
                if ok is not None and not (ok[i][k] and ok[k][j]):
                    continue
                evaluations += 1
                c = combine(row_i[k], cost[k][j], w(i, k, j))
                if less(c, best):
                    best, arg = c, k
            row_i[j] = best
            split[i][j] = arg
            cells += 1
            if report is not None:
                report(cells)

    table = export_table(cost, split, problem.objective, _UNSET) if problem.keep_table else None
    tris = triangles_from_splits(lambda i, j: split[i][j], n)
    stats = {"weight_evaluations": evaluations, "cells": cells}
    return Solution(cost[0][n - 1], tris, table, stats)
