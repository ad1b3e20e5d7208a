"""The labelled heuristic: bridge the holes of a block, then the exact DP on the walk.

The fixed edges of a block that is not simply connected form several
components (its outer boundary and its holes). Short free diagonals of the
block that join different components and cross no bridge chosen before are
added, shortest first, until the components are joined (Kruskal). The region
cut along the bridges is weakly simple; the DP then finds the best
triangulation that contains the bridges, exactly. Not optimal in general:
every result it gives is labelled ``"heuristic"``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..errors import NoTriangulationError
from .candidates import Candidates
from .pieces import Gate, solve_walk
from .reduce import Block, DisjointSets, crossing_any, trace_walk
from .weighing import DomainWeight

__all__ = ["choose_bridges", "bridge_block"]


def choose_bridges(
    points: NDArray[np.float64], cand: Candidates, block: Block, fixed: NDArray[np.bool_]
) -> NDArray[np.int64] | None:
    """Vertex pairs joining the fixed-edge components of ``block``, shortest first; or None."""
    sets = DisjointSets(block.fixed.tolist())
    components = sets.count()
    ids = np.unique(cand.sides[block.triangles])
    ids = ids[~fixed[ids]]
    pairs = cand.edges[ids]
    length = np.hypot(*(points[pairs[:, 0]] - points[pairs[:, 1]]).T)
    chosen: list[tuple[int, int]] = []
    for a, b in pairs[np.argsort(length, kind="stable")].tolist():
        if len(chosen) == components - 1:
            break
        if sets.find(a) == sets.find(b):
            continue
        if chosen and crossing_any(points, np.array([[a, b]]), np.array(chosen))[0]:
            continue
        sets.union(a, b)
        chosen.append((a, b))
    if len(chosen) != components - 1:
        return None
    return np.array(chosen, dtype=np.int64).reshape(-1, 2)


def bridge_block(
    points: NDArray[np.float64],
    usable: NDArray[np.bool_],
    cand: Candidates,
    block: Block,
    fixed: NDArray[np.bool_],
    weight: DomainWeight,
    component: str,
    gates: tuple[Gate, ...] = (),
) -> NDArray[np.int64] | None:
    """Triangles (domain indices) of the bridged DP on ``block``, or None if it finds none."""
    bridges = choose_bridges(points, cand, block, fixed)
    if bridges is None:
        return None
    edges = np.concatenate((block.fixed, bridges, bridges[:, ::-1]))
    walk = trace_walk(points, edges)
    if walk is None:  # pragma: no cover - bridges join every component
        return None
    try:
        tris, _ = solve_walk(points, usable, walk, weight, component, gates, bridges)
    except NoTriangulationError:  # the gates forbid every triangulation with these bridges
        return None
    return tris
