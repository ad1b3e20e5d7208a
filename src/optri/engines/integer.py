"""Exact integer DP (``method="integer"``): the product weight on integer vertex values.

The matrix-chain recurrence

    cost(i, j) = min over i < k < j of cost(i, k) + cost(k, j) + v_i v_k v_j

evaluated by diagonal, each diagonal at once with numpy (cells in rows, splits
in columns). Every partial cost is at most ``(n - 2) max|v|^3``: when that is
below ``2**63`` the table is ``int64`` (no sum or product can overflow, so
every value is exact), otherwise it holds Python ints (object arrays), exact at
any size. Ties go to the smallest k, as in every engine; the walk back is
:func:`optri.engines.recurrence.triangles_from_splits` (bounded).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .memory import require_memory
from .problem import Problem, Solution
from .recurrence import triangles_from_splits

__all__ = ["EXACT_INTS", "auto_accepts", "solve", "unsupported"]

#: Computes integer costs exactly (see :attr:`Problem.needs_big_ints`).
EXACT_INTS = True
#: Candidate cells (rows x splits) evaluated per numpy step: bounds the scratch memory.
_BLOCK = 1 << 18
_INT64_MAX = 2**63 - 1


def unsupported(problem: Problem) -> str | None:
    """Why this engine cannot take ``problem`` (it takes integer product problems only)."""
    if not problem.integer_costs:
        return "it computes the 'product' weight on integer vertex values only"
    if problem.objective.is_lex:
        return "it does not do lexicographic objectives"
    if problem.allowed is not None or problem.gates:
        return "it does not take chord masks or triangle gates"
    return None


def auto_accepts(problem: Problem) -> bool:
    """``method="auto"`` uses it for every integer product problem (exact, vectorized)."""
    return unsupported(problem) is None


def solve(problem: Problem) -> Solution:
    """Exact integer optimum; O(n^3) time (numpy), O(n^2) space.

    ``Solution.stats``: ``cells``, ``int64`` (1 when the int64 table sufficed).

    >>> from optri.polygon import as_polygon
    >>> from optri.solve import build_problem
    >>> solve(build_problem(as_polygon([30, 35, 15, 5, 10, 20, 25]), "product", "sum")).cost
    15125
    """
    ints = problem.polygon.ints
    assert ints is not None
    n = len(ints)
    bound = max(n - 2, 1) * max(abs(v) for v in ints) ** 3
    small = bound <= _INT64_MAX
    dtype: Any = np.int64 if small else object
    require_memory(
        n * n * (8 + 8) + 4 * _BLOCK * 8,
        f"the exact integer DP tables for n = {n}",
        "use method='fast' (float64) if an inexact optimum will do",
    )
    v = np.array(ints if small else list(ints), dtype=dtype)
    cost = np.zeros((n, n), dtype=dtype)
    split = np.full((n, n), -1, dtype=np.int64)
    use_max = problem.objective.components[0] == "max"
    if use_max:  # a side holds the neutral -inf of "max": no triangle yet
        side = -(2**63) if small else -(bound + 1)
        cost[np.arange(n - 1), np.arange(1, n)] = side
    for d in range(2, n):
        _diagonal(cost, split, v, d, use_max)
    total = cost[0, n - 1]
    tris = triangles_from_splits(lambda i, j: split[i, j], n)
    table = _table(cost, split, use_max) if problem.keep_table else None
    stats = {"cells": (n - 1) * (n - 2) // 2, "int64": int(small)}
    return Solution(int(total), tris, table, stats)


def _diagonal(cost: Any, split: NDArray[np.int64], v: Any, d: int, use_max: bool) -> None:
    """Cells (i, i + d) of one diagonal, rows in blocks of about ``_BLOCK`` candidates."""
    n = cost.shape[0]
    ks = np.arange(1, d)
    rows = max(1, _BLOCK // (d - 1))
    for start in range(0, n - d, rows):
        i = np.arange(start, min(start + rows, n - d))
        j = i + d
        k = i[:, None] + ks[None, :]
        w = (v[i] * v[j])[:, None] * v[k]
        left, right = cost[i[:, None], k], cost[k, j[:, None]]
        if use_max:
            cand = np.maximum(np.maximum(left, right), w)
        else:
            cand = left + right + w
        arg = np.argmin(cand, axis=1)  # the first minimum: ties to the smallest k
        pick = np.arange(len(i))
        cost[i, j] = cand[pick, arg]
        split[i, j] = k[pick, arg]


def _table(cost: Any, split: NDArray[np.int64], use_max: bool) -> NDArray[np.float64]:
    """The paper's n x n table (costs above the diagonal as floats, splits below)."""
    n = cost.shape[0]
    iu = np.triu_indices(n, 1)
    out = np.zeros((n, n), dtype=np.float64)
    vals = np.array([float(c) for c in cost[iu].tolist()])
    sides = iu[1] - iu[0] == 1
    out[iu] = np.where(sides, 0.0, vals)
    out[iu[1], iu[0]] = np.where(sides, -1, split[iu])
    return out
