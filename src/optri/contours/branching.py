"""Branching between slices: several contours merged into one by bridges.

Where one contour of a slice overlaps several of the next (or several overlap
several), the branches are merged into one composite contour at an
intermediate level, as Meyers, Skinner and Sloan (1992) and Bajaj, Coyle and
Lin (1996) do: a copy of each branch is lifted to that level (a band of
vertical quads joins it to its branch), the copies are spliced into one simple
loop by pairs of bridge edges between closest vertices, and each bridge closes
with a quadrilateral face at that level (the crotch between the branches). The
composite is then tiled optimally to the single contour on the other side.
Every vertex stays distinct, so the surface stays manifold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError
from ..predicates import orient

__all__ = ["Loop", "bridge_faces", "merge_loops"]

#: Closest vertex pairs tried per branch before merging gives up.
BRIDGE_TRIES = 2000


@dataclass
class Loop:
    """A closed contour in the mesh being built: vertex ids and their 3-D points."""

    ids: NDArray[np.int64]
    points: NDArray[np.float64]


def merge_loops(loops: list[Loop]) -> tuple[Loop, list[tuple[int, int, int, int]]]:
    """Splice same-oriented, disjoint planar loops into one simple loop.

    Returns the composite and, per bridge, ``(u, u1, vp, v)``: the composite's
    cut side ``u -> u1`` and the branch's cut side ``vp -> v``; the bridges are
    ``u -> v`` and ``vp -> u1``. Loops join in order of their closest vertex
    pair; a pair is used only when neither bridge meets a side of any loop
    (except at its own ends) or the other bridge.

    >>> sq = np.array([[0., 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
    >>> comp, bridges = merge_loops([Loop(np.arange(4), sq), Loop(np.arange(4, 8), sq + [2, 0, 0])])
    >>> comp.ids.tolist(), bridges
    ([0, 1, 4, 5, 6, 7, 2, 3], [(1, 2, 7, 4)])
    """
    comp = loops[0]
    original = {(int(a), int(b)) for a, b in zip(comp.ids, np.roll(comp.ids, -1))}
    rest = list(loops[1:])
    bridges = []
    while rest:
        comp, k, bridge = _join_closest(comp, original, rest)
        loop = rest.pop(k)
        original |= {(int(a), int(b)) for a, b in zip(loop.ids, np.roll(loop.ids, -1))}
        bridges.append(bridge)
    return comp, bridges


def _join_closest(
    comp: Loop, original: set[tuple[int, int]], rest: list[Loop]
) -> tuple[Loop, int, tuple[int, int, int, int]]:
    nxt = np.roll(comp.ids, -1)
    usable = np.array([(int(a), int(b)) in original for a, b in zip(comp.ids, nxt)])
    cands = []
    for k, loop in enumerate(rest):
        d = ((comp.points[:, None, :2] - loop.points[None, :, :2]) ** 2).sum(axis=2)
        d[~usable] = np.inf
        flat = np.argsort(d, axis=None, kind="stable")[:BRIDGE_TRIES]
        cands += [(float(d.flat[f]), k, *divmod(int(f), d.shape[1])) for f in flat]
    cands.sort(key=lambda c: c[0])
    sides = _sides([comp, *rest])
    for dist, k, ci, vj in cands[:BRIDGE_TRIES]:
        if not np.isfinite(dist):
            break
        loop = rest[k]
        n = len(loop.ids)
        order = (np.arange(n) + vj) % n
        u, u1 = int(comp.ids[ci]), int(nxt[ci])
        v, vp = int(loop.ids[order[0]]), int(loop.ids[order[-1]])
        pu, pu1 = comp.points[ci, :2], comp.points[(ci + 1) % len(comp.ids), :2]
        pv, pvp = loop.points[order[0], :2], loop.points[order[-1], :2]
        if not (_clear(pu, pv, u, v, sides) and _clear(pvp, pu1, vp, u1, sides)):
            continue
        if _meet(pu, pv, pvp, pu1):
            continue
        ids = np.concatenate([comp.ids[: ci + 1], loop.ids[order], comp.ids[ci + 1 :]])
        pts = np.vstack([comp.points[: ci + 1], loop.points[order], comp.points[ci + 1 :]])
        return Loop(ids, pts), k, (u, u1, vp, v)
    raise InvalidPolygonError(
        "could not bridge the branches of a contour: no pair of close vertices joins them "
        "without crossing another contour of the slice"
    )


def _sides(loops: list[Loop]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Every side of the loops: vertex ids ``(k, 2)`` and 2-D ends ``(k, 2, 2)``."""
    ids = np.concatenate([np.column_stack([lp.ids, np.roll(lp.ids, -1)]) for lp in loops])
    pts = np.concatenate(
        [
            np.stack([lp.points[:, :2], np.roll(lp.points[:, :2], -1, axis=0)], axis=1)
            for lp in loops
        ]
    )
    return ids, pts


def _clear(
    p: NDArray[np.float64],
    q: NDArray[np.float64],
    ip: int,
    iq: int,
    sides: tuple[NDArray[np.int64], NDArray[np.float64]],
) -> bool:
    """Segment pq meets no side, except sides at its own ends (exact)."""
    ids, pts = sides
    free = ~np.isin(ids, [ip, iq]).any(axis=1)
    c, d = pts[free, 0], pts[free, 1]
    pp, qq = np.broadcast_to(p, c.shape), np.broadcast_to(q, c.shape)
    o1, o2 = orient(pp, qq, c), orient(pp, qq, d)
    o3, o4 = orient(c, d, pp), orient(c, d, qq)
    lo1, hi1 = np.minimum(pp, qq), np.maximum(pp, qq)
    lo2, hi2 = np.minimum(c, d), np.maximum(c, d)
    boxes = np.all((lo1 <= hi2) & (lo2 <= hi1), axis=1)
    return not bool(np.any((o1 * o2 <= 0) & (o3 * o4 <= 0) & boxes))


def _meet(
    a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64], d: NDArray[np.float64]
) -> bool:
    o1, o2 = int(orient(a, b, c)), int(orient(a, b, d))
    o3, o4 = int(orient(c, d, a)), int(orient(c, d, b))
    return o1 * o2 <= 0 and o3 * o4 <= 0


def bridge_faces(
    points: dict[int, NDArray[np.float64]], quad: tuple[int, int, int, int]
) -> list[tuple[int, int, int]]:
    """Two triangles of a planar quadrilateral, both turning as the quadrilateral does.

    The first diagonal (q0-q2) when its two triangles do, else the other.
    """
    q0, q1, q2, q3 = quad
    p = [points[v][:2] for v in quad]
    whole = _turn(p[0], p[1], p[2]) + _turn(p[0], p[2], p[3])
    sign = 1 if whole > 0 else -1
    if _turn(p[0], p[1], p[2]) * sign > 0 and _turn(p[0], p[2], p[3]) * sign > 0:
        return [(q0, q1, q2), (q0, q2, q3)]
    return [(q0, q1, q3), (q1, q2, q3)]


def _turn(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]) -> float:
    return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
