"""Top-down memoized DP: the paper's Algorithm 3.1.

A cell ``(i, j)`` starts unset (the paper's infinity); asking for it either
returns the stored value (a *look-up*) or computes it once, recursing into the
cells it needs. Each cell is the generator :meth:`Recurrence.cell`; a
trampoline drives them on an explicit stack, so Python's recursion limit never
applies, whatever n. The problem's observer (:attr:`Problem.observer`) is told
of every call, hit and store, in the order the recursion makes them.
"""

from __future__ import annotations

from ..objective import Cost
from .problem import Problem, Solution
from .progress import table_work, work_reporter
from .recurrence import Recurrence, export_table, new_tables, triangles_from_splits

__all__ = ["solve"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True
#: Integer weights stay Python ints: exact costs at any size.
EXACT_INTS = True

_UNSET = None  # the paper's "infinity": not computed yet


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` by memoized recursion; O(n^3) time, O(n^2) space.

    ``Solution.stats`` holds ``weight_evaluations`` (triangle weights computed),
    ``lookups`` (requests answered from the table), ``cells`` (sub-polygons
    computed) and ``requests`` (all sub-polygon requests).
    """
    n = problem.n
    rec = Recurrence(problem)
    cost, split = new_tables(problem, _UNSET)
    report = work_reporter(problem)

    cells = work = 0

    def store(i: int, j: int, best: Cost, arg: int) -> None:
        nonlocal cells, work
        cost[i][j], split[i][j] = best, arg
        cells += 1
        work += j - i - 1
        if report is not None:
            report(work)

    # a look-up answers a cell computed before (sides are set before the recursion)
    requests = rec.top_down(lambda p, q: cost[p][q], store, hits=True)
    misses = cells - 1  # every computed cell but the root was a request that missed
    if report is not None:
        report(table_work(n))

    total: Cost = cost[0][n - 1]
    table = export_table(cost, split, problem.objective, _UNSET) if problem.keep_table else None
    tris = triangles_from_splits(lambda i, j: split[i][j], n)
    stats = {
        "weight_evaluations": rec.evaluations,
        "lookups": requests - misses,
        "requests": requests,
        "cells": cells,
    }
    return Solution(total, tris, table, stats)
