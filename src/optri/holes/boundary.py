"""Boundary loops of a triangle mesh, pinched vertices split as CGAL's border cycles are.

A boundary edge is an edge used by one face. At an ordinary boundary vertex
one boundary edge arrives and one leaves. At a *pinched* (non-manifold)
vertex several boundary loops touch; there each arriving edge is paired with
the leaving edge of the same fan of faces around the vertex (found by turning
around it from face to face), which is how a halfedge mesh that duplicates
pinched vertices (CGAL's) sees its border cycles. A cycle that still visits a
vertex twice is cut there into simple loops, so every loop can be filled as a
polygon. Everything but the final walk along each cycle is vectorized numpy.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError

__all__ = ["Loop", "boundary_loops", "edge_keys", "edge_summary", "trace_loops"]

Ints = NDArray[np.int64]


class Loop(NamedTuple):
    """One boundary loop: vertex ids in patch order, third vertices, pinched vertices."""

    vertices: Ints
    third: Ints
    pinched: tuple[int, ...]


def edge_keys(faces: Ints, nv: int) -> Ints:
    """Undirected key ``min * nv + max`` of every face edge.

    Entry ``3 * face + corner`` is the edge from corner ``corner`` to the next one.
    """
    a = faces.ravel()
    b = faces[:, [1, 2, 0]].ravel()
    return np.minimum(a, b) * nv + np.maximum(a, b)  # type: ignore[no-any-return]


def boundary_loops(faces: NDArray[np.integer]) -> list[tuple[Ints, Ints]]:
    """Closed boundary loops of a triangle mesh, each as ``(loop, third)``.

    ``loop`` lists vertex ids in *patch* order: each consecutive pair
    ``(loop[i], loop[i+1])`` is a boundary edge that an existing face runs the
    other way. ``third[i]`` is that face's third vertex. Loops through a
    pinched vertex are split into simple loops (:func:`trace_loops` also says
    where). Loops are ordered by their smallest vertex id and start there.

    Raises
    ------
    InvalidPolygonError
        Boundary edges that do not close into loops (faces inconsistently wound).

    Examples
    --------
    >>> loop, third = boundary_loops(np.array([[0, 1, 2], [0, 2, 3]]))[0]
    >>> loop.tolist(), third.tolist()
    ([0, 3, 2, 1], [2, 0, 0, 2])
    >>> bowtie = np.array([[0, 1, 2], [0, 3, 4]])       # two triangles pinched at 0
    >>> [lp.tolist() for lp, _ in boundary_loops(bowtie)]
    [[0, 2, 1], [0, 4, 3]]
    """
    return [(lp.vertices, lp.third) for lp in trace_loops(faces)]


def trace_loops(faces: NDArray[np.integer]) -> list[Loop]:
    """The boundary loops with the pinched vertices each one passes (see :func:`boundary_loops`)."""
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    f = f[
        (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    ]  # no zero-length edges
    if len(f) == 0:
        return []
    from .._core import topology

    nv = int(f.max()) + 1
    f = np.ascontiguousarray(f)
    bnd = topology.single_edges(f, nv)  # boundary face edges, as rows 3 * face + corner
    if len(bnd) == 0:
        return []
    face, corner = bnd // 3, bnd % 3
    a = f[face, corner]  # face edge a -> b, third vertex c
    b = f[face, (corner + 1) % 3]
    c = f[face, (corner + 2) % 3]
    pinched = set(np.flatnonzero(np.bincount(np.append(a, b), minlength=nv) > 2).tolist())
    try:
        succ = _successors(f, nv, a, b)
        return _walk_cycles(a, b, c, succ, pinched)
    except _Unoriented:
        return _undirected_loops(a, b, c, pinched)


class _Unoriented(Exception):
    """The boundary edges' directions do not chain (faces inconsistently wound)."""


def _successors(f: Ints, nv: int, a: Ints, b: Ints) -> Ints:
    """``succ[e]``: the boundary edge that follows boundary edge ``e`` (a -> b) at ``b``."""
    outgoing = np.argsort(a, kind="stable")
    first = np.searchsorted(a[outgoing], b)
    count = np.bincount(a, minlength=nv)[b]
    if (count == 0).any():
        raise _Unoriented
    succ = outgoing[first]  # right wherever one boundary edge leaves b
    many = np.flatnonzero(count > 1)
    if len(many):
        succ[many] = _fan_pairs(f, nv, a, b, many, outgoing, first, count)
    return succ  # type: ignore[no-any-return]


def _fan_pairs(
    f: Ints, nv: int, a: Ints, b: Ints, which: Ints, outgoing: Ints, first: Ints, count: Ints
) -> Ints:
    """At pinched vertices: the leaving boundary edge of the same fan of faces.

    From the face of arriving edge (a -> v), turn around v: the face's edge
    (v -> x) is shared with the next face (which has x -> v), until a face's
    edge (v -> x) is a boundary edge. Falls back to the leaving edges in order
    where the fan cannot be followed (non-manifold or inconsistently wound).
    """
    directed = f.ravel() * nv + f[:, [1, 2, 0]].ravel()
    d_order = np.argsort(directed, kind="stable")
    d_sorted = directed[d_order]
    m = len(f)
    v = b[which]
    # the arriving edge's face: the row of directed edge (a -> v)
    row = d_order[np.searchsorted(d_sorted, a[which] * nv + v)]
    out = np.full(len(which), -1, dtype=np.int64)
    active = np.arange(len(which))
    bnd_out = {(int(x), int(y)): e for e, (x, y) in enumerate(zip(a.tolist(), b.tolist()))}
    for _ in range(4 * m + 4):  # each step turns one face further around its vertex
        if len(active) == 0:
            break
        face, corner = row[active] // 3, row[active] % 3
        x = f[face, (corner + 2) % 3]  # the face runs a -> v -> x: its edge v -> x
        vv = v[active]
        done = np.array([(int(p), int(q)) in bnd_out for p, q in zip(vv, x)], dtype=np.bool_)
        for t in np.flatnonzero(done):
            out[active[t]] = bnd_out[(int(vv[t]), int(x[t]))]
        want = x * nv + vv  # the next face has the reverse edge x -> v
        pos = np.minimum(np.searchsorted(d_sorted, want), len(d_sorted) - 1)
        found = d_sorted[pos] == want
        nxt = d_order[pos]
        keep = ~done & found
        row[active[keep]] = nxt[keep]
        active = active[keep]
    stuck = np.flatnonzero(out < 0)
    for t in stuck:  # fans that cannot be followed: leaving edges in order
        e = which[t]
        out[t] = outgoing[first[e] + (t % count[e])]
    return out


def _walk_cycles(a: Ints, b: Ints, c: Ints, succ: Ints, pinched: set[int]) -> list[Loop]:
    """Follow the successor permutation; cut cycles that revisit a vertex; patch order."""
    seen = np.zeros(len(a), dtype=np.bool_)
    loops: list[Loop] = []
    succ_l, a_l = succ.tolist(), a.tolist()
    for start in np.argsort(a, kind="stable").tolist():
        if seen[start]:
            continue
        cycle, e = [], start
        while not seen[e]:
            seen[e] = True
            cycle.append(e)
            e = succ_l[e]
        if e != start:
            raise _Unoriented
        for part in _simple_parts([a_l[x] for x in cycle]):
            edges = np.array([cycle[p] for p in part], dtype=np.int64)
            loops.append(_as_loop(edges, a, b, c, pinched))
    loops.sort(key=lambda lp: (int(lp.vertices[0]), len(lp.vertices)))
    return loops


def _undirected_loops(a: Ints, b: Ints, c: Ints, pinched: set[int]) -> list[Loop]:
    """Loops of boundary edges taken without direction (faces inconsistently wound).

    Each loop is walked edge to edge, cut where it revisits a vertex, and run
    in the direction most of its faces want (a face edge a -> b asks for b -> a).
    """
    ends = np.concatenate([a, b])
    edge = np.concatenate([np.arange(len(a)), np.arange(len(a))])
    order = np.argsort(ends, kind="stable")
    starts = np.searchsorted(ends[order], np.arange(int(ends.max()) + 2))
    incident = edge[order].tolist()
    used = np.zeros(len(a), dtype=np.bool_)
    a_l, b_l = a.tolist(), b.tolist()
    loops: list[Loop] = []
    for first in range(len(a)):
        if used[first]:
            continue
        path, at, e = [], a_l[first], first  # walk edges: at --e--> other end
        while not used[e]:
            used[e] = True
            path.append((at, e))
            at = b_l[e] if a_l[e] == at else a_l[e]
            nxt = [x for x in incident[starts[at] : starts[at + 1]] if not used[x]]
            if not nxt:
                break
            e = nxt[0]
        if at != path[0][0]:
            raise InvalidPolygonError(
                f"the boundary does not close into loops at vertex {at} (edges shared by "
                f"three or more faces?); fix the mesh before filling"
            )
        for part in _simple_parts([v for v, _ in path]):
            loops.append(_undirected_loop([path[p] for p in part], a, b, c, pinched))
    loops.sort(key=lambda lp: (int(lp.vertices[0]), len(lp.vertices)))
    return loops


def _undirected_loop(
    walk: list[tuple[int, int]], a: Ints, b: Ints, c: Ints, pinched: set[int]
) -> Loop:
    # walk: (vertex, edge leaving it) in order; orient by the majority of faces
    verts = np.array([v for v, _ in walk], dtype=np.int64)
    edges = np.array([e for _, e in walk], dtype=np.int64)
    agree = int((a[edges] != verts).sum())  # walking b -> a, as the patch should
    third = c[edges]
    if 2 * agree < len(edges):  # most faces want the other direction
        verts = np.roll(verts[::-1], 1)
        third = third[::-1]
    first = int(np.argmin(verts))
    verts, third = np.roll(verts, -first), np.roll(third, -first)
    touched = tuple(sorted(int(v) for v in set(verts.tolist()) & pinched))
    return Loop(verts, third.astype(np.int64), touched)


def _simple_parts(starts: list[int]) -> list[list[int]]:
    """Cut a closed walk into closed walks that visit each vertex once.

    ``starts[p]``: the vertex at which step ``p`` of the walk starts. Returns
    lists of step positions; a sub-walk is cut off whenever a vertex comes back.

    >>> _simple_parts([0, 1, 2, 0, 3, 4])       # a figure eight through vertex 0
    [[0, 1, 2], [3, 4, 5]]
    """
    parts: list[list[int]] = []
    stack: list[int] = []
    at: dict[int, int] = {}
    for p, v in enumerate(starts):
        if v in at:  # a sub-walk closes at v: the steps since v was first left
            cut = at[v]
            parts.append(stack[cut:])
            for gone in stack[cut:]:
                at.pop(starts[gone], None)
            del stack[cut:]
        at[v] = len(stack)
        stack.append(p)
    if stack:
        parts.append(stack)
    return parts


def _as_loop(edges: Ints, a: Ints, b: Ints, c: Ints, pinched: set[int]) -> Loop:
    # faces run a -> b; the patch must run b -> a: reverse, third of (b, a) stays c
    verts = a[edges][::-1]
    third = np.roll(c[edges][::-1], -1)
    first = int(np.argmin(verts))  # start at the smallest id: deterministic output
    verts, third = np.roll(verts, -first), np.roll(third, -first)
    touched = tuple(sorted(int(v) for v in set(verts.tolist()) & pinched))
    return Loop(verts.astype(np.int64), third.astype(np.int64), touched)


def edge_summary(faces: NDArray[np.integer]) -> dict[str, int]:
    """Counts that say whether a mesh is closed: boundary and non-manifold edges.

    ``boundary``: edges used by one face; ``nonmanifold``: edges used by three
    or more; ``degenerate_faces``: faces that repeat a vertex id.

    >>> edge_summary(np.array([[0, 1, 2], [0, 2, 3]]))
    {'boundary': 4, 'nonmanifold': 0, 'degenerate_faces': 0}
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    bad = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2])
    good = f[~bad]
    if len(good) == 0:
        return {"boundary": 0, "nonmanifold": 0, "degenerate_faces": int(bad.sum())}
    _, counts = np.unique(edge_keys(good, int(good.max()) + 1), return_counts=True)
    return {
        "boundary": int((counts == 1).sum()),
        "nonmanifold": int((counts > 2).sum()),
        "degenerate_faces": int(bad.sum()),
    }
