"""Top-down memoized DP: the paper's Algorithm 3.1, with an explicit stack.

A cell ``(i, j)`` starts unset (the paper's infinity); asking for it either
returns the stored value (a *look-up*) or computes it once, recursing into the
cells it needs. The recursion runs on an explicit stack of frames, so Python's
recursion limit never applies, whatever n.
"""

from __future__ import annotations

from ..objective import Cost
from .problem import Problem, Solution, triangles_from_splits
from .tables import export_table, new_tables

__all__ = ["solve"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True

_UNSET = None  # the paper's "infinity": not computed yet


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` by memoized recursion; O(n^3) time, O(n^2) space.

    ``Solution.stats`` holds ``weight_evaluations`` (triangle weights computed),
    ``lookups`` (requests answered from the table), ``cells`` (sub-polygons
    computed) and ``requests`` (all sub-polygon requests).
    """
    n = problem.n
    w = problem.evaluator()
    combine, less = problem.objective.combine, problem.objective.less
    worst = problem.objective.worst
    ok = problem.allowed_rows()
    cost, split = new_tables(problem, _UNSET)
    report = _progress_reporter(problem, n)

    evaluations = requests = misses = cells = 0
    # frame: [i, j, next k, best cost so far, best k so far]
    stack: list[list] = [[0, n - 1, 1, worst, -1]]
    while stack:
        frame = stack[-1]
        i, j, k, best, arg = frame
        row_i = cost[i]
        descended = False
        while k < j:
            if ok is not None and not (ok[i][k] and ok[k][j]):
                k += 1
                continue
            a = row_i[k]
            if a is _UNSET:
                frame[2:] = k, best, arg
                stack.append([i, k, i + 1, worst, -1])
                misses += 1
                descended = True
                break
            b = cost[k][j]
            if b is _UNSET:
                frame[2:] = k, best, arg
                stack.append([k, j, k + 1, worst, -1])
                misses += 1
                descended = True
                break
            requests += 2
            evaluations += 1
            c = combine(a, b, w(i, k, j))
            if less(c, best):
                best, arg = c, k
            k += 1
        if descended:
            continue
        row_i[j] = best
        split[i][j] = arg
        stack.pop()
        cells += 1
        if report is not None:
            report(cells)

    total: Cost = cost[0][n - 1]
    table = export_table(cost, split, problem.objective, _UNSET) if problem.keep_table else None
    tris = triangles_from_splits(lambda i, j: split[i][j], n)
    stats = {
        "weight_evaluations": evaluations,
        "lookups": requests - misses,
        "requests": requests,
        "cells": cells,
    }
    return Solution(total, tris, table, stats)


def _progress_reporter(problem: Problem, n: int):  # type: ignore[no-untyped-def]
    """Throttled ``progress(cells_done, cells_total)``, or None."""
    if problem.progress is None:
        return None
    total = (n - 1) * (n - 2) // 2
    step = max(1, total // 200)
    cb = problem.progress

    def report(done: int) -> None:
        if done % step == 0 or done >= total:
            cb(min(done, total), total)

    return report
