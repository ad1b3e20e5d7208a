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
from .progress import cell_reporter
from .recurrence import Cell, Recurrence, export_table, new_tables, triangles_from_splits

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
    report = cell_reporter(problem)

    watch = problem.observer
    requests = misses = cells = 0
    stack: list[tuple[int, int, Cell]] = [(0, n - 1, rec.cell(0, n - 1))]
    if watch is not None:
        watch("call", 0, n - 1, None, None)
    value: Cost | None = None  # what the top frame asked for, or None when it starts
    while stack:
        i, j, frame = stack[-1]
        try:
            p, q = frame.send(value)  # type: ignore[arg-type]
        except StopIteration as done:
            best, arg = done.value
            cost[i][j], split[i][j] = best, arg
            stack.pop()
            value = best
            cells += 1
            if watch is not None:
                watch("store", i, j, arg if arg >= 0 else None, best)
            if report is not None:
                report(cells)
            continue
        requests += 1
        value = cost[p][q]
        if watch is not None:
            watch("call", p, q, None, None)
        if value is _UNSET:  # not computed yet: recurse into it
            misses += 1
            stack.append((p, q, rec.cell(p, q)))
        elif watch is not None:  # sides are set before the recursion starts
            watch("hit", p, q, None, value)

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
