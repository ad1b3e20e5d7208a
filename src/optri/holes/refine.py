"""Refinement of a hole's patch: Liepa's centroid splits with density control.

A patch straight from the triangulation has only the hole's boundary vertices, so
its triangles are as long as the hole is wide. Liepa (2003) gives it the density of
the mesh around it:

* every boundary vertex ``v`` gets a scale ``s(v)``: the mean length of its mesh
  edges; a new vertex gets the mean scale of the triangle it splits;
* a triangle ``(a, b, c)`` with centroid ``m`` is split in three at ``m`` when, for
  every corner ``x``, ``density * |m - x|`` exceeds both ``s(m)`` and ``s(x)``;
* after a round of splits, interior edges are relaxed: an edge is swapped when the
  vertex across it lies inside the diametral sphere of the triangle on its other
  side (the sphere through its three vertices centred in its plane) -- Delaunay in
  3-D, as Liepa does; boundary edges and swaps to an edge that already exists are
  never made, so the patch stays manifold;
* rounds repeat until no triangle splits, or ``max_rounds``.

A larger ``density`` splits more (smaller triangles); ``sqrt(2)``, Liepa's value, the
default, gives triangles about as long as the mesh edges around the hole.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError

__all__ = ["boundary_scales", "refine_patch"]

#: Rounds of splitting and relaxation at most (each round at most triples the faces).
MAX_ROUNDS = 40
#: Relaxation sweeps after a round at most.
MAX_SWEEPS = 50


def boundary_scales(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], loop: NDArray[np.int64]
) -> NDArray[np.float64]:
    """``s(v)`` for each loop vertex: the mean length of the mesh edges at ``v``.

    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [2, 0, 0], [0, 1, 0]])
    >>> boundary_scales(v, np.array([[0, 1, 2]]), np.array([0, 1, 2])).round(3).tolist()
    [1.5, 2.118, 1.618]
    """
    f = np.asarray(faces, dtype=np.int64)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    length = np.linalg.norm(vertices[e[:, 0]] - vertices[e[:, 1]], axis=1)
    total = np.zeros(len(vertices))
    count = np.zeros(len(vertices))
    for c in range(2):
        np.add.at(total, e[:, c], length)
        np.add.at(count, e[:, c], 1)
    loop = np.asarray(loop, dtype=np.int64)
    out = np.where(count[loop] > 0, total[loop] / np.maximum(count[loop], 1), 0.0)
    if not np.any(out > 0):
        return out
    # a loop vertex with no mesh edge (an isolated polyline) takes its loop neighbours'
    side = np.linalg.norm(vertices[loop] - vertices[np.roll(loop, -1)], axis=1)
    fallback = 0.5 * (side + np.roll(side, 1))
    return np.where(out > 0, out, fallback)


def refine_patch(
    vertices: NDArray[np.float64],
    patch: NDArray[np.int64],
    loop: NDArray[np.int64],
    scales: NDArray[np.float64],
    density: float = math.sqrt(2.0),
    max_rounds: int = MAX_ROUNDS,
    *,
    forbidden: set[frozenset[int]] | None = None,
    parents: list[tuple[int, int, int]] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Refine a hole's patch; returns ``(new_vertices, faces)``.

    Parameters
    ----------
    vertices : (n, 3) array
        The mesh's vertices (not modified).
    patch : (m, 3) int array
        The patch's triangles over mesh vertex indices, consistently wound.
    loop : int array
        The hole's boundary loop (mesh vertex indices), whose edges are never swapped.
    scales : array
        ``s(v)`` of each loop vertex (:func:`boundary_scales`), in loop order.
    density : float
        Liepa's alpha, > 0.
    max_rounds : int
        Split-and-relax rounds at most.
    forbidden : set of frozenset, optional
        Vertex pairs an edge swap must not join (edges the mesh already has between
        the loop's vertices: a swap to one would give that edge a third face).
    parents : list, optional
        Filled with the triangle ``(a, b, c)`` each new vertex is the centroid of, in
        the order of the new vertices (to interpolate texture coordinates, normals or
        colours the same way: the mean of the three corners').

    Returns
    -------
    (new_vertices, faces)
        The vertices added (to be appended after ``vertices``; new indices start at
        ``len(vertices)``) and the refined patch over old and new indices.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]])
    >>> new, faces = refine_patch(v, np.array([[0, 1, 2], [0, 2, 3]]), np.arange(4),
    ...                           np.full(4, 1.0))
    >>> len(new) > 0, len(faces) == 2 + 2 * len(new)
    (True, True)
    """
    if not (density > 0 and math.isfinite(density)):
        raise InvalidPolygonError(f"density must be a positive number, got {density!r}")
    pts = np.asarray(vertices, dtype=np.float64)
    base = len(pts)
    sigma: dict[int, float] = {int(x): float(s) for x, s in zip(loop, scales)}
    faces: list[tuple[int, int, int]] = [
        (int(a), int(b), int(c)) for a, b, c in np.asarray(patch, dtype=np.int64)
    ]
    loop_edges = {frozenset((int(a), int(b))) for a, b in zip(loop, np.roll(loop, -1))}
    blocked = set(forbidden or ())
    added: list[tuple[float, float, float]] = []

    def point(i: int) -> NDArray[np.float64]:
        return pts[i] if i < base else np.asarray(added[i - base])

    for _ in range(max_rounds):
        split = False
        next_faces: list[tuple[int, int, int]] = []
        for a, b, c in faces:
            pa, pb, pc = point(a), point(b), point(c)
            m = (pa + pb + pc) / 3.0
            sm = (sigma.get(a, 0.0) + sigma.get(b, 0.0) + sigma.get(c, 0.0)) / 3.0
            if sm > 0 and all(
                density * float(np.linalg.norm(m - p)) > max(sm, sigma.get(x, 0.0))
                for x, p in ((a, pa), (b, pb), (c, pc))
            ):
                k = base + len(added)
                added.append((float(m[0]), float(m[1]), float(m[2])))
                sigma[k] = sm
                if parents is not None:
                    parents.append((a, b, c))
                next_faces += [(a, b, k), (b, c, k), (c, a, k)]
                split = True
            else:
                next_faces.append((a, b, c))
        faces = next_faces
        if not split:
            break
        faces = _relax(faces, point, loop_edges, blocked)
    new = np.asarray(added, dtype=np.float64).reshape(-1, 3)
    return new, np.asarray(faces, dtype=np.int64).reshape(-1, 3)


def _relax(
    faces: list[tuple[int, int, int]],
    point: Callable[[int], NDArray[np.float64]],
    fixed_edges: set[frozenset[int]],
    blocked: set[frozenset[int]],
) -> list[tuple[int, int, int]]:
    """Swap interior edges whose opposite vertex is inside the diametral sphere.

    ``fixed_edges`` are never swapped away; no swap creates an edge of ``blocked``.
    """
    faces = list(faces)
    for _ in range(MAX_SWEEPS):
        where: dict[tuple[int, int], int] = {}  # directed edge -> face index
        for t, (a, b, c) in enumerate(faces):
            where[(a, b)], where[(b, c)], where[(c, a)] = t, t, t
        edges = {frozenset(e) for e in where}
        swapped = False
        done: set[int] = set()
        for (u, v), t1 in list(where.items()):
            t2 = where.get((v, u))
            if t2 is None or t1 in done or t2 in done or frozenset((u, v)) in fixed_edges:
                continue
            x = _third(faces[t1], u, v)
            y = _third(faces[t2], v, u)
            if x == y or frozenset((x, y)) in edges or frozenset((x, y)) in blocked:
                continue
            if not _inside_sphere(point(u), point(v), point(x), point(y)):
                continue
            # (u, v, x) and (v, u, y) become (u, y, x) and (v, x, y): same winding
            faces[t1], faces[t2] = (u, y, x), (v, x, y)
            edges.discard(frozenset((u, v)))
            edges.add(frozenset((x, y)))
            done |= {t1, t2}
            swapped = True
        if not swapped:
            break
    return faces


def _third(face: tuple[int, int, int], u: int, v: int) -> int:
    """The vertex of ``face`` that follows the directed edge ``(u, v)``."""
    a, b, c = face
    return {(a, b): c, (b, c): a, (c, a): b}[(u, v)]


def _inside_sphere(
    a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64], d: NDArray[np.float64]
) -> bool:
    """Whether ``d`` lies strictly inside the sphere through ``a, b, c`` centred in their plane."""
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    nn = float(n @ n)
    if nn == 0.0:
        return True  # a degenerate triangle: swapping its edge can only help
    center = a + (np.cross(n, ab) * float(ac @ ac) + np.cross(ac, n) * float(ab @ ab)) / (2 * nn)
    r2 = float((a - center) @ (a - center))
    return float((d - center) @ (d - center)) < r2 * (1 - 1e-12)
