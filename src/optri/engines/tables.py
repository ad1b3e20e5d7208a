"""Shared bookkeeping of the pure-Python engines: cost/split tables and export."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..objective import Objective
from .memory import require_memory
from .problem import Problem

__all__ = ["PY_BYTES_PER_CELL", "export_table", "new_tables"]

#: Two nested-list tables of Python objects plus the exported float64 array.
PY_BYTES_PER_CELL = 2 * (8 + 24) + 8


def new_tables(problem: Problem, unset: Any) -> tuple[list[list[Any]], list[list[int]]]:
    """Allocate cost and split tables; sides (i, i+1) hold the neutral cost."""
    n = problem.n
    require_memory(
        PY_BYTES_PER_CELL * n * n,
        f"the pure-Python DP tables for n = {n}",
        "use method='fast' (compiled, one float64 table)",
    )
    cost: list[list[Any]] = [[unset] * n for _ in range(n)]
    split = [[-1] * n for _ in range(n)]
    neutral = problem.objective.neutral
    for i in range(n - 1):
        cost[i][i + 1] = neutral
    return cost, split


def export_table(
    cost: list[list[Any]], split: list[list[int]], objective: Objective, unset: Any
) -> NDArray[np.float64]:
    """The paper's n x n table: costs above the diagonal, splits below, 0 on it.

    Cells of sides and unreached chords hold 0 above the diagonal (no triangle)
    resp. -1 below (no split); unreachable chords hold inf above.
    """
    n = len(cost)
    out = np.zeros((n, n), dtype=np.float64)
    for i in range(n):
        row = cost[i]
        for j in range(i + 1, n):
            c = row[j]
            if c is unset:
                continue
            v = c[0] if objective.is_lex else c
            out[i, j] = 0.0 if v == -math.inf else v
            out[j, i] = split[i][j]
    return out
