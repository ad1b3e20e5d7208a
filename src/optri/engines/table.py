"""Bottom-up tabulation: the "square matrix" method.

Fills every chord ``(i, j)`` in order of increasing ``j - i`` so both halves of
each split are ready when its cell asks for them (Cormen et al., *Introduction
to Algorithms*, 3rd ed., 15.2; Saracevic et al. 2018 for the square-matrix
presentation). The cell is the same :meth:`Recurrence.cell` memo drives.
"""

from __future__ import annotations

from .problem import Problem, Solution
from .progress import table_work, work_reporter
from .recurrence import Recurrence, export_table, new_tables, triangles_from_splits

__all__ = ["solve"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True
#: Integer weights stay Python ints: exact costs at any size.
EXACT_INTS = True

_UNSET = None


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` bottom-up; O(n^3) time, O(n^2) space.

    ``Solution.stats``: ``weight_evaluations``, ``cells`` and ``lookups``
    (sub-polygon costs read from the table: two per weight evaluation).
    The problem's observer is told of every look-up (``"hit"``), candidate and
    store; there are no calls, since nothing recurses.
    """
    n = problem.n
    rec = Recurrence(problem)
    cost, split = new_tables(problem, _UNSET)
    report = work_reporter(problem)

    watch = problem.observer
    cells = lookups = work = 0
    for i, j in rec.chords():
        frame = rec.cell(i, j)
        try:
            p, q = next(frame)
            while True:  # every sub-chord is shorter, so already in the table
                lookups += 1
                if watch is not None:
                    watch("hit", p, q, None, cost[p][q])
                p, q = frame.send(cost[p][q])
        except StopIteration as done:
            cost[i][j], split[i][j] = done.value
        cells += 1
        if watch is not None:
            k = split[i][j]
            watch("store", i, j, k if k >= 0 else None, cost[i][j])
        work += j - i - 1
        if report is not None:
            report(work)
    if report is not None:
        report(table_work(n))

    table = export_table(cost, split, problem.objective, _UNSET) if problem.keep_table else None
    tris = triangles_from_splits(lambda i, j: split[i][j], n)
    stats = {"weight_evaluations": rec.evaluations, "cells": cells, "lookups": lookups}
    return Solution(cost[0][n - 1], tris, table, stats)
