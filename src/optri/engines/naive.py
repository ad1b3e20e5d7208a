"""The un-memoized recursion: why the paper stores anything at all.

The same top-down recursion as :mod:`optri.engines.memo` (the paper's
Algorithm 3.1) without its look-up: every request for a sub-polygon computes
it again from scratch, down to the polygon sides. A chord spanning ``d`` sides
makes ``T(d) = 1 + 2 (T(1) + ... + T(d - 1)) = 3^(d - 1)`` calls, so the whole
n-gon makes ``3^(n - 2)``: the exponential cost memoization removes. The cell
is the same :meth:`Recurrence.cell` memo drives; its split table is written on
every computation (the same value each time) only so the triangles can be read
back, never read during the recursion. The engine refuses polygons above
:data:`optri.config.NAIVE_MAX_N`.
"""

from __future__ import annotations

from .. import config
from ..objective import Cost
from .problem import Problem, Solution
from .recurrence import Recurrence, export_table, new_tables, triangles_from_splits

__all__ = ["naive_calls", "solve", "unsupported"]

#: Honours Problem.gates (through Problem.evaluator).
SUPPORTS_GATES = True
#: Integer weights stay Python ints: exact costs at any size.
EXACT_INTS = True

_UNSET = None


def naive_calls(n: int) -> int:
    """Calls the un-memoized recursion makes on a convex n-gon: ``3^(n - 2)``.

    >>> [naive_calls(n) for n in (3, 4, 5)]
    [3, 9, 27]
    """
    return 3 ** (n - 2) if n >= 3 else 1


def unsupported(problem: Problem) -> str | None:
    """Why the naive recursion refuses ``problem`` (too many calls), or None."""
    if problem.n > config.NAIVE_MAX_N:
        return (
            f"the un-memoized recursion makes 3^(n-2) = {naive_calls(problem.n):,} calls at "
            f"n = {problem.n}; it takes n <= {config.NAIVE_MAX_N} (optri.config.NAIVE_MAX_N); "
            f"use method='memo' to see what memoization saves"
        )
    return None


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` by plain recursion; O(3^n) time, O(n^2) space.

    ``Solution.stats``: ``weight_evaluations``, ``requests`` (sub-polygon
    requests, sides included), ``cells`` (sub-polygons computed, repeats
    counted) and ``lookups`` (always 0: nothing is looked up).

    Examples
    --------
    >>> from optri.polygon import as_polygon
    >>> from optri.solve import build_problem
    >>> sol = solve(build_problem(as_polygon([5, 1, 5, 1, 5]), "product", "sum"))
    >>> sol.cost, sol.stats["requests"] + 1       # 3^(5-2) calls, root included
    (35, 27)
    """
    n = problem.n
    rec = Recurrence(problem)
    cost, split = new_tables(problem, _UNSET)
    neutral = problem.objective.neutral_for(problem.integer_costs)
    cells = 0

    def store(i: int, j: int, best: Cost, arg: int) -> None:
        nonlocal cells
        cost[i][j], split[i][j] = best, arg  # written, never read back
        cells += 1

    # nothing is looked up: only a polygon side (the base case, no triangle) is known
    requests = rec.top_down(lambda p, q: neutral if q - p == 1 else None, store, hits=False)

    table = export_table(cost, split, problem.objective, _UNSET) if problem.keep_table else None
    tris = triangles_from_splits(lambda i, j: split[i][j], n)
    stats = {
        "weight_evaluations": rec.evaluations,
        "requests": requests,
        "cells": cells,
        "lookups": 0,
    }
    return Solution(cost[0][n - 1], tris, table, stats)
