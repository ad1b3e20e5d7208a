"""Refinement of a hole's patch: Liepa's centroid splits with density control.

A patch straight from the triangulation has only the hole's boundary vertices, so
its triangles are as long as the hole is wide. Liepa (2003) gives it the density of
the mesh around it:

* every boundary vertex ``v`` gets a scale ``s(v)``: the mean length of its mesh
  edges; a new vertex gets the mean scale of the triangle it splits;
* a triangle ``(a, b, c)`` with centroid ``m`` is split in three at ``m`` when, for
  every corner ``x``, ``density * |m - x|`` exceeds both ``s(m)`` and ``s(x)``;
* edges are relaxed as Liepa and CGAL do: the three sides of each split triangle
  right after its split, and after each round of splits every interior edge once, in
  the order the faces name them. An edge is swapped when the vertex across it lies
  inside the diametral sphere (the sphere through three vertices centred in their
  plane) of the triangle on either side -- Delaunay in 3-D; boundary edges and swaps
  to an edge that already exists are never made, so the patch stays manifold; nor
  are swaps that fold the patch more sharply, or any swap across a crease sharper
  than ``CREASE`` degrees unless it leaves the two faces nearly flat: a swap replaces
  two faces by the other two faces of their tetrahedron, and across a crease that
  tetrahedron is wide enough to hold faces of the mesh or of the patch, which the new
  faces would then cross;
* rounds repeat until no triangle splits, or ``max_rounds``; a sweep tests each edge
  once, so no round can cycle. (CGAL also stops at a sweep that swaps nothing, which
  can leave a patch far coarser than its scales ask where the hole's sides are long.)

A larger ``density`` splits more (smaller triangles); ``sqrt(2)``, Liepa's value, the
default, gives triangles about as long as the mesh edges around the hole.

:func:`refine_patch` runs in the compiled core; :func:`reference_refine_patch` is the
same algorithm in Python, which the tests hold the core equal to, bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError

__all__ = ["boundary_scales", "reference_refine_patch", "refine_patch"]

Point = tuple[float, float, float]

#: Dihedral angle (degrees) under which an edge swap may sharpen the fold between its faces.
FOLD_FREE = 10.0
_FOLD_FREE_COS = math.cos(math.radians(FOLD_FREE))
#: Dihedral angle (degrees) between two faces above which their edge is swapped only
#: when the swap leaves them within ``FOLD_FREE`` of flat.
CREASE = 60.0
_CREASE_COS = math.cos(math.radians(CREASE))

#: Rounds of splitting and relaxation at most (each round at most triples the faces).
MAX_ROUNDS = 40


def boundary_scales(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], loop: NDArray[np.int64]
) -> NDArray[np.float64]:
    """``s(v)`` for each loop vertex: the mean length of the mesh edges at ``v``.

    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [2, 0, 0], [0, 1, 0]])
    >>> boundary_scales(v, np.array([[0, 1, 2]]), np.array([0, 1, 2])).round(3).tolist()
    [1.5, 2.118, 1.618]
    """
    loop = np.asarray(loop, dtype=np.int64)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    on_loop = np.zeros(len(vertices), dtype=bool)
    on_loop[loop] = True
    f = f[on_loop[f[:, 0]] | on_loop[f[:, 1]] | on_loop[f[:, 2]]]  # faces holding its edges
    a, b = f.ravel(), f[:, [1, 2, 0]].ravel()
    nv = len(vertices)  # distinct edges in (low, high) order, by one key each
    e = np.column_stack(np.divmod(np.unique(np.minimum(a, b) * nv + np.maximum(a, b)), nv))
    length = np.linalg.norm(vertices[e[:, 0]] - vertices[e[:, 1]], axis=1)
    ends = np.concatenate([e[:, 0], e[:, 1]])  # summed in this order, as np.add.at would
    # sums per edge end over the ends present: work in the loop's faces, not the mesh's
    at, slot = np.unique(ends, return_inverse=True)
    if len(at) == 0:
        return np.zeros(len(loop))
    total = np.bincount(slot, weights=np.concatenate([length, length]), minlength=len(at))
    count = np.bincount(slot, minlength=len(at))
    where = np.minimum(np.searchsorted(at, loop), len(at) - 1)
    mine = np.where(at[where] == loop, count[where], 0)
    out = np.where(mine > 0, total[where] / np.maximum(mine, 1), 0.0)
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

    Each round splits the triangles that are too large for the scales around them at
    their centroids, relaxing the three sides of each split triangle right after its
    split, then tests every edge of the patch once (the module's docstring has the
    tests); rounds go on until no triangle splits.

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
        Rounds of splits and relaxation at most.
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
    from .. import _core

    ends = np.array([tuple(p) for p in (forbidden or ()) if len(p) == 2], dtype=np.int64)
    ends = ends.reshape(-1, 2)  # each pair as (low, high), in the set's order
    pairs = np.column_stack([ends.min(axis=1), ends.max(axis=1)])
    new, faces, split = _core.refine.refine_patch(
        np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 3),
        np.ascontiguousarray(patch, dtype=np.int64).reshape(-1, 3),
        np.ascontiguousarray(loop, dtype=np.int64).reshape(-1),
        np.ascontiguousarray(scales, dtype=np.float64).reshape(-1),
        float(density),
        int(max_rounds),
        pairs,
        _FOLD_FREE_COS,
        _CREASE_COS,
    )
    if parents is not None:
        parents.extend(map(tuple, split.tolist()))
    return new, faces


def reference_refine_patch(
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
    """:func:`refine_patch` in plain Python: the reference the compiled core must equal.

    The same arguments and results, bit for bit (the tests compare the two); it states
    the algorithm in readable form and is never used on the fill path.

    >>> import numpy as np
    >>> v = np.array([[0., 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]])
    >>> args = (v, np.array([[0, 1, 2], [0, 2, 3]]), np.arange(4), np.full(4, 1.0))
    >>> all(np.array_equal(x, y) for x, y in zip(reference_refine_patch(*args),
    ...                                            refine_patch(*args)))
    True
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
    # plain floats: the per-triangle work below is scalar, where numpy's overhead dominates
    coords: dict[int, Point] = {
        int(i): (float(x), float(y), float(z)) for i, (x, y, z) in _rows(pts, faces)
    }
    added: list[Point] = []

    def point(i: int) -> Point:
        return coords[i] if i < base else added[i - base]

    where = _sides(faces)  # kept up to date by every split and swap
    for _ in range(max_rounds):
        split = False
        for t in range(len(faces)):  # faces its splits add wait for the next round
            a, b, c = faces[t]
            pa, pb, pc = point(a), point(b), point(c)
            m = (
                (pa[0] + pb[0] + pc[0]) / 3.0,
                (pa[1] + pb[1] + pc[1]) / 3.0,
                (pa[2] + pb[2] + pc[2]) / 3.0,
            )
            sm = (sigma.get(a, 0.0) + sigma.get(b, 0.0) + sigma.get(c, 0.0)) / 3.0
            if sm > 0 and all(
                density * math.dist(m, p) > max(sm, sigma.get(x, 0.0))
                for x, p in ((a, pa), (b, pb), (c, pc))
            ):
                k = base + len(added)
                added.append(m)
                sigma[k] = sm
                if parents is not None:
                    parents.append((a, b, c))
                t2, t3 = len(faces), len(faces) + 1
                faces[t] = (a, b, k)
                faces += [(b, c, k), (c, a, k)]
                where[(b, k)], where[(k, a)] = t, t
                where[(b, c)], where[(c, k)], where[(k, b)] = t2, t2, t2
                where[(c, a)], where[(a, k)], where[(k, c)] = t3, t3, t3
                for u, v in ((a, b), (b, c), (c, a)):  # its sides, relaxed at once
                    _swap(faces, where, u, v, point, loop_edges, blocked)
                split = True
        if not split:
            break
        _sweep(faces, where, point, loop_edges, blocked)
    new = np.asarray(added, dtype=np.float64).reshape(-1, 3)
    return new, np.asarray(faces, dtype=np.int64).reshape(-1, 3)


def _rows(pts: NDArray[np.float64], faces: list[tuple[int, int, int]]) -> Any:
    """``(index, row)`` of each vertex the faces use."""
    used = np.unique(np.asarray(faces, dtype=np.int64).reshape(-1))
    return zip(used.tolist(), pts[used].tolist())


def _sides(faces: list[tuple[int, int, int]]) -> dict[tuple[int, int], int]:
    """Each directed edge of the faces -> the index of the face it bounds."""
    where: dict[tuple[int, int], int] = {}
    for t, (a, b, c) in enumerate(faces):
        where[(a, b)], where[(b, c)], where[(c, a)] = t, t, t
    return where


def _swap(
    faces: list[tuple[int, int, int]],
    where: dict[tuple[int, int], int],
    u: int,
    v: int,
    point: Callable[[int], Any],
    fixed_edges: set[frozenset[int]],
    blocked: set[frozenset[int]],
) -> bool:
    """Swap the edge ``u-v`` (in place) if it fails the diametral-sphere test; whether it did.

    The edge is kept when it is in ``fixed_edges``, when it bounds one face only, when
    the swap would make an edge of ``blocked`` or one the faces already have, when
    neither opposite vertex lies inside the other triangle's diametral sphere, or when
    the swap folds the patch (:func:`_folds`). ``where`` follows the swap.
    """
    t1, t2 = where.get((u, v)), where.get((v, u))
    if t1 is None or t2 is None or frozenset((u, v)) in fixed_edges:
        return False
    x = _third(faces[t1], u, v)
    y = _third(faces[t2], v, u)
    if x == y or (x, y) in where or (y, x) in where or frozenset((x, y)) in blocked:
        return False
    pu, pv, px, py = point(u), point(v), point(x), point(y)
    if not (_inside_sphere(pu, pv, px, py) or _inside_sphere(pv, pu, py, px)):
        return False
    if _folds(pu, pv, px, py):
        return False
    # (u, v, x) and (v, u, y) become (u, y, x) and (v, x, y): same winding
    faces[t1], faces[t2] = (u, y, x), (v, x, y)
    del where[(u, v)], where[(v, u)]
    where[(u, y)], where[(y, x)], where[(x, u)] = t1, t1, t1
    where[(v, x)], where[(x, y)], where[(y, v)] = t2, t2, t2
    return True


def _sweep(
    faces: list[tuple[int, int, int]],
    where: dict[tuple[int, int], int],
    point: Callable[[int], Any],
    fixed_edges: set[frozenset[int]],
    blocked: set[frozenset[int]],
) -> int:
    """Test every interior edge once (:func:`_swap`), in place; the number of swaps.

    ``where`` is :func:`_sides` of the faces. Edges are taken in the order the faces
    first name them (the face on their other side comes later); an edge a swap makes
    is not tested in the same sweep.
    """
    edges = [
        (u, v)
        for t, (a, b, c) in enumerate(faces)
        for u, v in ((a, b), (b, c), (c, a))
        if where.get((v, u), -1) > t
    ]
    swaps = 0
    for u, v in edges:
        swaps += _swap(faces, where, u, v, point, fixed_edges, blocked)
    return swaps


def _third(face: tuple[int, int, int], u: int, v: int) -> int:
    """The vertex of ``face`` that follows the directed edge ``(u, v)``."""
    a, b, c = face
    if a == u:
        return c
    return a if b == u else b


def _inside_sphere(a: Point, b: Point, c: Point, d: Point) -> bool:
    """Whether ``d`` lies strictly inside the sphere through ``a, b, c`` centred in their plane."""
    ax, ay, az = a
    bx, by, bz = b[0] - ax, b[1] - ay, b[2] - az  # ab
    cx, cy, cz = c[0] - ax, c[1] - ay, c[2] - az  # ac
    nx, ny, nz = by * cz - bz * cy, bz * cx - bx * cz, bx * cy - by * cx  # n = ab x ac
    nn = nx * nx + ny * ny + nz * nz
    if nn == 0.0:
        return True  # a degenerate triangle: swapping its edge can only help
    s = (cx * cx + cy * cy + cz * cz) / (2 * nn)
    t = (bx * bx + by * by + bz * bz) / (2 * nn)
    # centre - a = (n x ab) s + (ac x n) t
    ox = (ny * bz - nz * by) * s + (cy * nz - cz * ny) * t
    oy = (nz * bx - nx * bz) * s + (cz * nx - cx * nz) * t
    oz = (nx * by - ny * bx) * s + (cx * ny - cy * nx) * t
    r2 = ox * ox + oy * oy + oz * oz
    dx, dy, dz = d[0] - ax - ox, d[1] - ay - oy, d[2] - az - oz
    return dx * dx + dy * dy + dz * dz < r2 * (1 - 1e-12)


def _folds(u: Point, v: Point, x: Point, y: Point) -> bool:
    """Whether swapping ``u-v`` for ``x-y`` in ``(u, v, x), (v, u, y)`` may fold the patch.

    The new pair ``(u, y, x), (v, x, y)`` may meet at a dihedral angle under
    ``FOLD_FREE`` degrees; otherwise no sharper than the old pair's, and the old pair
    must meet at under ``CREASE`` degrees. On a curved patch a swap that sharpens a
    fold, or one across a crease, would lay faces over their neighbours or through the
    mesh (a self-intersecting patch).
    """
    old = _cosine(_normal(u, v, x), _normal(v, u, y))
    new = _cosine(_normal(u, y, x), _normal(v, x, y))
    if new >= _FOLD_FREE_COS:
        return False
    return new < old or old < _CREASE_COS


def _cosine(a: Point, b: Point) -> float:
    na, nb = _dot(a, a), _dot(b, b)
    if na == 0.0 or nb == 0.0:
        return 1.0  # a degenerate face has no fold to speak of
    return _dot(a, b) / math.sqrt(na * nb)


def _normal(a: Point, b: Point, c: Point) -> Point:
    return _cross((b[0] - a[0], b[1] - a[1], b[2] - a[2]), (c[0] - a[0], c[1] - a[1], c[2] - a[2]))


def _dot(u: Point, v: Point) -> float:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _cross(u: Point, v: Point) -> Point:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
