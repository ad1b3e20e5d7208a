"""The Hurtado–Noy tree of triangulations of a convex polygon, walked lazily.

Hurtado and Noy arrange all triangulations of the convex polygons P_3, P_4, ...
in one tree: level m holds the C(m-2) triangulations of P_m (vertices 0..m-1)
and each triangulation at level m+1 has exactly one *father* at level m.

The child rule used here (the one of Hurtado and Noy, in 0-based labels): in a
triangulation T of P_m let the last vertex m-1 have neighbours
0 = b_0 < b_1 < ... < b_r = m-2 (sides included), so its fan is the triangles
(b_t, b_{t+1}, m-1). Child ``s`` (s = 0..r, in that fixed order) inserts the new
vertex m between m-1 and 0: the first ``s`` fan triangles move from m-1 to m,
and the triangle (b_s, m-1, m) is added. Contracting the side (m-1, m) of a
child gives back its father, so every triangulation of P_{m+1} appears once,
and a father of degree r+1 at m-1 has r+1 >= 2 children ("two or more sons").

The walk is a depth-first traversal with O(m) state per level (the fan of the
last vertex and the child number), so n = 16 (2,674,440 triangulations) streams
in constant memory. Moving from child s to s+1 changes two triangles, so the
whole walk costs O(1) amortized per tree node.

References
----------
.. [1] F. Hurtado, M. Noy, "Graph of triangulations of a convex polygon and tree
   of triangulations", Computational Geometry 13 (1999) 179–188.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from ..errors import InvalidPolygonError

__all__ = ["HNCounts", "hn_index_triangulations", "hn_operation_counts"]

Tri = list[int]


def hn_index_triangulations(n: int) -> Iterator[list[Tri]]:
    """Yield every triangulation of the index polygon 0..n-1 in Hurtado–Noy order.

    Each item is the *same* list of ``n - 2`` triangles ``[i, k, j]``
    (``i < k < j``), updated in place between items: copy it to keep it.

    Examples
    --------
    >>> [[tuple(t) for t in tris] for tris in hn_index_triangulations(4)]
    [[(0, 1, 2), (0, 2, 3)], [(0, 1, 3), (1, 2, 3)]]
    >>> sum(1 for _ in hn_index_triangulations(8))
    132
    """
    if n < 3:
        raise InvalidPolygonError(f"a polygon needs at least 3 vertices, got {n}")
    tris: list[Tri] = [[0, 1, 2]] + [[0, 0, 0] for _ in range(n - 3)]
    if n == 3:
        yield tris
        return
    # Per level m (the parent has m vertices): neighbours of m-1, its fan, child number.
    nbrs: list[list[int]] = [[0, 1]]
    fans: list[list[int]] = [[0]]
    child: list[int] = [-1]
    m = 3
    while True:
        b, f = nbrs[-1], fans[-1]
        s = child[-1] + 1
        if s == len(b):
            # All children done: the last child moved every fan triangle to m; undo.
            for t in f:
                tris[t][2] = m - 1
            nbrs.pop()
            fans.pop()
            child.pop()
            m -= 1
            if m < 3:
                return
            continue
        child[-1] = s
        if s:
            tris[f[s - 1]][2] = m
        new = tris[m - 2]
        new[0], new[1], new[2] = b[s], m - 1, m
        if m + 1 == n:
            yield tris
            continue
        nbrs.append([*b[: s + 1], m - 1])
        fans.append([*f[:s], m - 2])
        child.append(-1)
        m += 1


@dataclass
class HNCounts:
    """Operations of one Hurtado–Noy generation step P_{n-1} -> P_n, as measured.

    Attributes
    ----------
    n : int
    parents, children : int
        Triangulations of P_{n-1} read and of P_n produced (C(n-3), C(n-2)).
    edge_checks : int
        Edges of each father scanned for incidence with vertex n-2 (2n-5 each).
    edges_written : int
        Edges (vertex pairs) written to describe each child (2n-3 each).
    weight_evaluations : int
        Triangle weights evaluated to weigh every child from its father's
        weight (only the moved and the new triangles are re-weighed).
    scratch_evaluations : int
        Triangle weights a from-scratch weighing of every child needs: (n-2) C(n-2).
    """

    n: int
    parents: int = 0
    children: int = 0
    edge_checks: int = 0
    edges_written: int = 0
    weight_evaluations: int = 0
    scratch_evaluations: int = 0

    @property
    def operations(self) -> int:
        """Edge checks plus edges written: what the paper's Eq. 5 counts."""
        return self.edge_checks + self.edges_written


def hn_operation_counts(n: int) -> HNCounts:
    """Generate all triangulations of P_n from those of P_{n-1}, counting operations.

    Runs the generation step the way the paper describes it (Section 4): each
    father is an edge list; its 2n-5 edges are checked for incidence with the
    last vertex, and each child is written out as its 2n-3 vertex pairs and
    weighed incrementally from its father.

    Examples
    --------
    >>> c = hn_operation_counts(7)
    >>> c.children, c.operations, c.edge_checks, c.edges_written
    (42, 588, 126, 462)
    """
    if n < 4:
        raise InvalidPolygonError(f"a generation step needs n >= 4, got {n}")
    counts = HNCounts(n)
    last = n - 2  # last vertex of the father P_{n-1}
    for tris in hn_index_triangulations(n - 1):
        counts.parents += 1
        edges = {(a, b) for t in tris for a, b in ((t[0], t[1]), (t[1], t[2]), (t[0], t[2]))}
        fan = []
        for a, b in edges:  # the paper's 2n-5 checks
            counts.edge_checks += 1
            if b == last:
                fan.append(a)
        fan.sort()
        for s in range(len(fan)):
            moved = set(fan[:s])
            child = [(a, n - 1 if (b == last and a in moved) else b) for a, b in edges]
            child += [(fan[s], n - 1), (last, n - 1)]
            counts.edges_written += len(child)
            counts.children += 1
            # re-weighed: the s fan triangles now on vertex n-1, and the new one
            counts.weight_evaluations += s + 1
    counts.scratch_evaluations = (n - 2) * counts.children
    return counts
