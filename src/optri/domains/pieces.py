"""The exact DP on a simply connected piece of a domain, given as its boundary walk.

A walk is the closed sequence of domain vertices around a region with no hole
inside, the region on its left: a simple polygon, or a weakly simple one where
a diagonal (forced, or a bridge to a hole) is walked along on both sides and
its ends appear twice. The usual recurrence over the walk's positions is then
exact once the chords it may use are exactly the diagonals inside the region:
pairs of positions whose vertices are joined by a valid diagonal of the domain
that starts into the region at both positions (in-cone against the walk's own
neighbours, which tells the copies of a repeated vertex apart) and crosses no
bridge. Forced diagonals need no test: no valid diagonal crosses them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..engines import select_engine
from ..engines.problem import Problem
from ..objective import Objective
from ..polygon import Polygon
from ..predicates import orient
from ..weights import Weight, WeightCode, custom_weight
from .reduce import crossing_any
from .weighing import DomainWeight, shape_only

__all__ = ["Gate", "walk_mask", "solve_walk"]


@dataclass(frozen=True)
class Gate:
    """Triangles whose ``weight`` exceeds ``threshold`` are forbidden."""

    weight: DomainWeight
    threshold: float


def walk_mask(
    points: NDArray[np.float64],
    usable: NDArray[np.bool_],
    seq: Sequence[int],
    bridges: NDArray[np.int64] | None = None,
) -> NDArray[np.bool_]:
    """Which chords between positions of the walk ``seq`` lie inside its region; (m, m).

    ``usable[a, b]``: vertices ``a`` and ``b`` are joined by a boundary edge or
    a valid diagonal of the domain. ``bridges``: vertex pairs walked along on
    both sides that other diagonals may cross (the heuristic's bridges).
    """
    s = np.asarray(seq, dtype=np.int64)
    m = len(s)
    pts = points[s]
    x, y = np.triu_indices(m, 2)
    keep = ~((x == 0) & (y == m - 1))
    x, y = x[keep], y[keep]
    ok = (s[x] != s[y]) & usable[s[x], s[y]]
    x, y = x[ok], y[ok]
    ok = _cone(pts, x, y) & _cone(pts, y, x)
    x, y = x[ok], y[ok]
    if bridges is not None and len(bridges):
        crossed = crossing_any(points, np.column_stack((s[x], s[y])), bridges)
        x, y = x[~crossed], y[~crossed]
    mask = np.zeros((m, m), dtype=bool)
    mask[x, y] = True
    k = np.arange(m)
    mask[k, (k + 1) % m] = True
    mask |= mask.T
    return mask


def _cone(
    pts: NDArray[np.float64], i: NDArray[np.int64], j: NDArray[np.int64]
) -> NDArray[np.bool_]:
    """Position ``i``'s chord towards position ``j`` starts into the walk's region."""
    m = len(pts)
    prev, apex, nxt, target = pts[(i - 1) % m], pts[i], pts[(i + 1) % m], pts[j]
    left_of_next = orient(apex, nxt, target) > 0
    left_of_prev = orient(prev, apex, target) > 0
    convex = orient(prev, apex, nxt) > 0
    return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)


def solve_walk(
    points: NDArray[np.float64],
    usable: NDArray[np.bool_],
    seq: Sequence[int],
    weight: DomainWeight,
    component: str,
    gates: Sequence[Gate] = (),
    bridges: NDArray[np.int64] | None = None,
) -> tuple[NDArray[np.int64], str]:
    """Optimal triangles (domain indices, counter-clockwise) of the walk ``seq``; and the engine.

    ``component`` is ``"sum"`` or ``"max"``. Raises
    :class:`~optri.errors.NoTriangulationError` when the gates leave no
    triangulation.
    """
    s = np.asarray(seq, dtype=np.int64)
    m = len(s)
    if m == 3:
        return s.reshape(1, 3), "dp"
    pts = points[s]
    polygon = Polygon(pts, pts, np.arange(m, dtype=np.int64), "ccw", False)
    piece_gates = tuple((_piece_weight(g.weight, s, "max"), g.threshold) for g in gates)
    problem = Problem(
        polygon,
        (_piece_weight(weight, s, component),),
        Objective((component,)),
        allowed=walk_mask(points, usable, seq, bridges),
        keep_table=False,
        gates=piece_gates,
    )
    custom = any(w.code == WeightCode.CUSTOM for w in problem.weights) or any(
        g.code == WeightCode.CUSTOM for g, _ in piece_gates
    )
    # the compiled engine takes one gate; Python weights run in the Python engines
    name, solve = select_engine("table" if custom or len(gates) > 1 else "auto", problem)
    solution = solve(problem)
    return s[solution.triangles], name


def _piece_weight(weight: DomainWeight, s: NDArray[np.int64], component: str) -> Weight:
    """The weight the engines evaluate on the walk's positions.

    A shape weight is evaluated on the walk's coordinates directly (compiled
    engine possible). So is ``"diagonal"`` under ``"sum"``: sides of the walk
    that are diagonals of the domain are in exactly one triangle of the
    piece, so the piece's total differs from the domain's by a constant and
    the optimum is the same. Anything else goes through the domain weight.
    """
    w = weight.weight
    if shape_only(w) or (w.code == WeightCode.DIAGONAL and component == "sum"):
        return w
    order = s.tolist()

    def lookup(i: int, k: int, j: int) -> Any:
        return weight(order[i], order[k], order[j])

    return custom_weight(lookup, name=w.name)
