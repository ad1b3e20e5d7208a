"""Cheap lower bounds on a block's optimum, valid whatever the solver managed.

For ``"max"``: every fixed edge side is covered by some triangle, so the
optimum is at least the largest, over the fixed sides, of the lightest
triangle covering it. For ``"sum"``: every triangulation of a block has the
same number of triangles, ``F + 2 (c - 1) - 2`` for F fixed sides in c
boundary components; with the weights shifted by their minimum ``m`` to be
non-negative, each fixed side takes its share of the triangle covering it,
at least the least ``(w - m) / k`` over the triangles covering it (``k`` fixed
sides each).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .candidates import Candidates
from .reduce import Block, DisjointSets

__all__ = ["max_floor", "sum_floor"]


def _per_side_min(
    cand: Candidates, block: Block, fixed: NDArray[np.bool_], score: NDArray[np.float64]
) -> NDArray[np.float64]:
    """For each fixed side the block covers, the least ``score`` of a triangle covering it."""
    t = block.triangles
    s, g = cand.sides[t], cand.signs[t]
    on = fixed[s]
    key = (2 * s + (g > 0))[on]
    w = np.broadcast_to(score[:, None], s.shape)[on]
    order = np.lexsort((w, key))
    first = np.ones(len(key), dtype=bool)
    first[1:] = key[order][1:] != key[order][:-1]
    return w[order][first]  # type: ignore[no-any-return]


def max_floor(
    cand: Candidates, block: Block, fixed: NDArray[np.bool_], values: NDArray[np.float64]
) -> float:
    """Lower bound on the block's largest triangle weight (``values``: per candidate)."""
    return float(_per_side_min(cand, block, fixed, values[block.triangles]).max())


def sum_floor(
    cand: Candidates, block: Block, fixed: NDArray[np.bool_], values: NDArray[np.float64]
) -> float:
    """Lower bound on the block's total weight (``values``: per candidate triangle)."""
    w = values[block.triangles]
    m = float(w.min())
    k = fixed[cand.sides[block.triangles]].sum(axis=1)
    share = np.where(k > 0, (w - m) / np.maximum(k, 1), np.inf)
    count = len(block.fixed) + 2 * (_components(block.fixed) - 1) - 2
    return count * m + float(_per_side_min(cand, block, fixed, share).sum())


def _components(edges: NDArray[np.int64]) -> int:
    return DisjointSets(edges.tolist()).count()
