"""Shrinking the search: unusable triangles, forced diagonals, independent blocks, walks.

* A triangle with a diagonal side that no remaining triangle covers from the
  other side can be in no triangulation: :func:`prune` drops it, repeatedly.
* A remaining diagonal that no other remaining diagonal crosses is in every
  remaining triangulation (a triangulation is a maximal set of non-crossing
  diagonals): :func:`forced_diagonals` finds them.
* Boundary edges and forced diagonals are *fixed*; triangles linked through
  shared free diagonals or fixed edge sides form :func:`blocks`, whose
  constraints share nothing, so each block is solved on its own.
* A block whose fixed edges are connected covers a simply connected region:
  :func:`trace_walk` walks its boundary (a weakly simple polygon) for the DP.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from functools import cmp_to_key

import numpy as np
from numpy.typing import NDArray

from ..predicates import orient
from .candidates import Candidates, side_signs

__all__ = [
    "Block",
    "DisjointSets",
    "blocks",
    "crossing_any",
    "forced_diagonals",
    "prune",
    "trace_walk",
]

#: Segment pairs per block of the crossing tests.
_PAIRS = 1 << 21


class DisjointSets:
    """Union-find over vertex ids (path halving), built from an edge list.

    >>> sets = DisjointSets([(0, 1), (2, 3), (1, 0)])
    >>> sets.count(), sets.union(1, 2), sets.union(0, 3), sets.count()
    (2, True, False, 1)
    """

    def __init__(self, edges: Iterable[tuple[int, int]] = ()) -> None:
        self.parent: dict[int, int] = {}
        for x, y in edges:
            self.union(x, y)

    def find(self, x: int) -> int:
        """The representative of ``x``'s set (``x`` joins as a singleton if new)."""
        parent = self.parent
        parent.setdefault(x, x)
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def union(self, x: int, y: int) -> bool:
        """Join the sets of ``x`` and ``y``; False if they were one set already."""
        rx, ry = self.find(x), self.find(y)
        if rx == ry:
            return False
        self.parent[rx] = ry
        return True

    def count(self) -> int:
        """How many sets the ids seen so far form."""
        return len({self.find(x) for x in list(self.parent)})


def prune(cand: Candidates, keep: NDArray[np.bool_]) -> NDArray[np.bool_] | None:
    """``keep`` less every triangle that a diagonal side leaves uncovered, repeatedly.

    Returns None when some boundary edge is left with no triangle at all (no
    triangulation uses only the kept triangles).
    """
    keep = keep.copy()
    n_edges = len(cand.edges)
    diag = cand.is_diagonal
    while True:
        t = np.flatnonzero(keep)
        s, g = cand.sides[t].ravel(), cand.signs[t].ravel()
        left = np.bincount(s[g > 0], minlength=n_edges)
        right = np.bincount(s[g < 0], minlength=n_edges)
        if ((left + right)[: cand.n_boundary] == 0).any():
            return None
        other = np.where(cand.signs[t] > 0, right[cand.sides[t]], left[cand.sides[t]])
        bad = (diag[cand.sides[t]] & (other == 0)).any(axis=1)
        if not bad.any():
            return keep
        keep[t[bad]] = False


def alive_diagonals(cand: Candidates, keep: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Per edge: a diagonal that kept triangles use (on both sides, after :func:`prune`)."""
    used = np.zeros(len(cand.edges), dtype=bool)
    used[cand.sides[keep].ravel()] = True
    return used & cand.is_diagonal


def crossing_any(
    points: NDArray[np.float64], seg: NDArray[np.int64], others: NDArray[np.int64]
) -> NDArray[np.bool_]:
    """Per segment of ``seg`` (vertex pairs), whether it crosses one of ``others`` properly.

    Segments sharing an endpoint never cross properly (a zero sign). The
    O(S N + O N) orientation tests are made once, against every vertex; the
    S x O pairs are then sign products.
    """
    out = np.zeros(len(seg), dtype=bool)
    if len(seg) == 0 or len(others) == 0:
        return out
    s_seg = side_signs(points, seg)
    s_oth = side_signs(points, others)
    ox, oy = others[:, 0], others[:, 1]
    step = max(1, _PAIRS // len(others))
    for lo in range(0, len(seg), step):
        rows = seg[lo : lo + step]
        ours = s_seg[lo : lo + step]
        apart = (ours[:, ox] * ours[:, oy]) < 0  # the other's ends on both sides of ours
        theirs = (s_oth[:, rows[:, 0]] * s_oth[:, rows[:, 1]]).T < 0
        out[lo : lo + step] = (apart & theirs).any(axis=1)
    return out


def forced_diagonals(cand: Candidates, keep: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Per edge: a diagonal in every triangulation made of kept triangles.

    Such a diagonal is used by kept triangles and crossed by no other
    diagonal they use. Any maximal set of non-crossing such diagonals holds
    every one of them, so a greedy one (taken in edge order) is built first,
    and only its members are tested against all D: O(D G + G D) look-ups in
    :attr:`Candidates.turns` for a greedy set of G, in the compiled core.
    """
    from .._core import domains as core

    alive = np.flatnonzero(alive_diagonals(cand, keep))
    forced = np.zeros(len(cand.edges), dtype=bool)
    if len(alive) == 0:
        return forced
    nb = cand.n_boundary
    rows = core.forced(cand.turns, cand.edges[nb:], (alive - nb).astype(np.int64))
    forced[rows + nb] = True
    return forced


@dataclass(frozen=True)
class Block:
    """Kept triangles linked through free diagonals, and the fixed edges they cover.

    Attributes
    ----------
    triangles : ndarray of int64
        Candidate triangle ids.
    fixed : ndarray of int64, shape (F, 2)
        Directed fixed edges ``(x, y)`` (the block lies on their left).
    """

    triangles: NDArray[np.int64]
    fixed: NDArray[np.int64]


def blocks(cand: Candidates, keep: NDArray[np.bool_], fixed: NDArray[np.bool_]) -> list[Block]:
    """Split the kept triangles into independent blocks (``fixed``: per edge).

    Triangles sharing a free diagonal, or covering the same side of a fixed
    edge, are in one block: every constraint of the program then involves
    the triangles of one block only.
    """
    from .._core import domains as core

    tris = np.flatnonzero(keep)
    if len(tris) == 0:
        return []
    # linked: sharing a free diagonal (either side) or covering the same side of a fixed edge
    sides, signs = cand.sides[tris], cand.signs[tris]
    key = (2 * sides + (fixed[sides] & (signs > 0))).ravel()
    roots = core.link(np.ascontiguousarray(key, dtype=np.int64), 3)
    order = np.argsort(roots, kind="stable")
    cuts = np.flatnonzero(np.diff(roots[order])) + 1
    return [Block(m, _fixed_sides(cand, m, fixed)) for m in np.split(tris[order], cuts)]


def _fixed_sides(
    cand: Candidates, members: NDArray[np.int64], fixed: NDArray[np.bool_]
) -> NDArray[np.int64]:
    """The directed fixed sides of the block's triangles, distinct, in increasing order."""
    t = cand.triangles[members]
    pairs = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    ids = np.concatenate([cand.sides[members, m] for m in range(3)])
    n = np.int64(cand.n_boundary)  # the vertex count: (x, y) -> x n + y keeps their order
    keys = np.unique(pairs[fixed[ids]] @ np.array([n, 1], dtype=np.int64))
    return np.column_stack((keys // n, keys % n)).astype(np.int64)


def trace_walk(points: NDArray[np.float64], edges: NDArray[np.int64]) -> list[int] | None:
    """The closed boundary walk of a region with the directed ``edges`` (region on the left).

    From ``u -> v`` the walk leaves ``v`` along the first edge clockwise from
    ``v -> u``. Returns the vertex sequence when one walk uses every edge
    (the region is simply connected, possibly touching itself at vertices),
    else None (the region has holes: its edges form several walks).
    """
    out: dict[int, list[int]] = {}
    for x, y in edges.tolist():
        out.setdefault(x, []).append(y)
    u, v = (int(x) for x in edges[0])
    seq = [u]
    start = (u, v)
    for _ in range(len(edges)):
        seq.append(v)
        options = out.get(v, [])
        if not options:
            return None
        w = options[0] if len(options) == 1 else _first_clockwise(points, v, u, options)
        u, v = v, w
        if (u, v) == start:
            break
    else:
        return None
    seq.pop()  # the start vertex, reached again
    return seq if len(seq) == len(edges) else None


def _first_clockwise(points: NDArray[np.float64], v: int, u: int, options: list[int]) -> int:
    """Of the neighbours ``options`` of ``v``, the first clockwise from the direction to ``u``."""
    p = points

    def turn(a: int, b: int, c: int) -> int:
        return int(orient(p[a], p[b], p[c]))

    def half(w: int) -> int:
        # 0: clockwise angle from u in (0, pi]; 1: in (pi, 2 pi]
        s = turn(v, u, w)
        if s < 0:
            return 0
        if s > 0:
            return 1
        same = np.dot(p[w] - p[v], p[u] - p[v]) > 0
        return 1 if same else 0

    def before(a: int, b: int) -> int:
        ha, hb = half(a), half(b)
        if ha != hb:
            return ha - hb
        return turn(v, a, b)  # a first (negative) when b is clockwise of a

    return sorted(options, key=cmp_to_key(before))[0]
