"""Candidate triangles for ``method="delaunay"``, widened step by step.

Zou et al. (2013) and CGAL's ``triangulate_hole_polyline`` restrict the
hole-filling search to faces of the 3-D Delaunay tetrahedralization of the
hole's vertices: O(n) candidates in practice instead of O(n^3). A loop side
that is not a Delaunay edge would make every patch impossible, so, as CGAL
does, every triangle on such a side is added. When even that set holds no
patch, :func:`candidate_sets` widens it before the cubic search over all
triangles is left as the last resort:

1. ``"delaunay"``: Delaunay faces + all triangles on missing sides (CGAL's set);
2. ``"delaunay-edges"``: every triangle whose three sides are Delaunay edges or
   loop sides;
3. ``"knn-8"``, ``"knn-16"``, ``"knn-32"``: the same with each vertex also joined
   to its 8, 16, 32 nearest vertices.

Planar (or nearly planar) holes have no proper tetrahedralization; their
Delaunay faces are the 2-D Delaunay triangles in the best-fit plane.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional

__all__ = ["KNN_STEPS", "candidate_sets", "delaunay_faces", "triangles_of_edges"]

#: Neighbour counts of the widening steps after the Delaunay edges.
KNN_STEPS = (8, 16, 32)

Tris = NDArray[np.int64]


def delaunay_faces(points: NDArray[np.float64]) -> Tris:
    """Unique sorted vertex triples that are Delaunay faces of ``points`` (n, 3).

    Rows ``(a, b, c)``, ``a < b < c``, ordered by ``(a, c)`` and then ``b``.

    Examples
    --------
    >>> tet = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> delaunay_faces(tet).tolist()
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
    """
    spatial = import_optional("scipy.spatial")
    centred = points - points.mean(axis=0)
    try:
        simplices = spatial.Delaunay(centred).simplices
        combos = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
    except (spatial.QhullError, ValueError):
        # flat input: triangulate in the best-fit plane instead
        basis = np.linalg.svd(centred, full_matrices=False)[2][:2]
        try:
            simplices = spatial.Delaunay(centred @ basis.T).simplices
        except (spatial.QhullError, ValueError):
            return np.zeros((0, 3), dtype=np.int64)
        combos = ((0, 1, 2),)  # type: ignore[assignment]  # a planar hole: triangles only
    faces = np.sort(np.concatenate([simplices[:, list(c)] for c in combos]), axis=1)
    return _unique_rows(faces.astype(np.int64), len(points))


def _unique_rows(tris: Tris, n: int) -> Tris:
    # one int64 key per sorted triple, ordered (first, last, middle): chord then apex
    keys = np.unique((tris[:, 0] * n + tris[:, 2]) * n + tris[:, 1])
    chord, mid = np.divmod(keys, n)
    first, last = np.divmod(chord, n)
    return np.column_stack((first, mid, last)).astype(np.int64)


def _side_keys(n: int) -> NDArray[np.int64]:
    i = np.arange(n - 1)
    return np.append(i * n + i + 1, n - 1)  # (i, i + 1), then (0, n - 1)


def _edge_keys(tris: Tris, n: int) -> NDArray[np.int64]:
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]])
    return np.unique(e[:, 0] * n + e[:, 1])


def _on_sides(sides: NDArray[np.int64], n: int) -> Tris:
    """Every triangle on the loop sides ``sides`` (keys a * n + b)."""
    a, b = np.divmod(sides, n)
    k = np.arange(n)
    rows = [
        np.sort(np.column_stack((np.full(n, x), np.full(n, y), k)), axis=1) for x, y in zip(a, b)
    ]
    out = np.concatenate(rows) if rows else np.zeros((0, 3), dtype=np.int64)
    ok = (out[:, 0] != out[:, 1]) & (out[:, 1] != out[:, 2])
    return out[ok]


def triangles_of_edges(keys: NDArray[np.int64], n: int) -> Tris:
    """Every triangle (a, c, b), a < c < b, whose three sides are in the edge set.

    ``keys``: sorted unique ``a * n + b`` (a < b). Wedges (a, c), (c, b) are
    enumerated per middle vertex and kept when (a, b) is an edge too.

    >>> triangles_of_edges(np.array([1, 2, 6, 7]), 4).tolist()   # 0-1, 0-2, 1-2, 1-3
    [[0, 1, 2]]
    """
    a, b = np.divmod(keys, n)
    lo = np.bincount(b, minlength=n)  # edges (a, c) ending at c, a < c
    order = np.argsort(b, kind="stable")
    a_in = a[order]  # grouped by c
    start_in = np.concatenate(([0], np.cumsum(lo)))
    hi = np.bincount(a, minlength=n)
    start_out = np.concatenate(([0], np.cumsum(hi)))  # keys are sorted by a: grouped
    reps = lo * hi  # wedges through each middle vertex
    if reps.sum() == 0:
        return np.zeros((0, 3), dtype=np.int64)
    c = np.repeat(np.arange(n), reps)
    local = np.arange(reps.sum()) - np.repeat(np.cumsum(reps) - reps, reps)
    first = a_in[start_in[c] + local // np.maximum(hi[c], 1)]
    last = b[start_out[c] + local % np.maximum(hi[c], 1)]
    want = first * n + last
    pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
    ok = keys[pos] == want
    return np.column_stack((first[ok], c[ok], last[ok])).astype(np.int64)


def _knn_keys(points: NDArray[np.float64], k: int) -> NDArray[np.int64]:
    spatial = import_optional("scipy.spatial")
    n = len(points)
    k = min(k, n - 1)
    _, idx = spatial.cKDTree(points).query(points, k + 1)
    a = np.repeat(np.arange(n), k)
    b = idx[:, 1:].ravel()
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    return np.unique(lo * n + hi)


def candidate_sets(
    points: NDArray[np.float64], faces: Tris | None = None
) -> Iterator[tuple[str, Tris]]:
    """Candidate triangle sets ``(name, triangles)``, each wider than the last.

    Triangles are rows ``(i, k, j)``, ``i < k < j``. The steps are listed in
    the module docstring; the caller stops at the first set holding a patch.
    ``faces`` replaces the Delaunay faces of ``points`` (rows ``a < b < c``):
    a polygon whose points repeat (a hole's islands cut open along bridges)
    passes the Delaunay faces of its distinct points, mapped to its copies.

    >>> sq = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    >>> [(name, len(t)) for name, t in candidate_sets(sq)][:2]
    [('delaunay', 2), ('delaunay-edges', 2)]
    """
    n = len(points)
    faces = delaunay_faces(points) if faces is None else faces
    edges = _edge_keys(faces, n)
    sides = _side_keys(n)
    missing = sides[~np.isin(sides, edges)]
    yield "delaunay", _unique_rows(np.concatenate([faces, _on_sides(missing, n)]), n)
    graph = np.union1d(edges, sides)
    yield "delaunay-edges", triangles_of_edges(graph, n)
    for k in KNN_STEPS:
        if k >= n - 1:
            return
        yield f"knn-{k}", triangles_of_edges(np.union1d(graph, _knn_keys(points, k)), n)
