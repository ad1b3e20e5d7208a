"""Optimal triangulation of a closed 3-D polyline: ``fill_polyline``.

A hole in a triangle mesh is bounded by a closed polyline; every index
triangulation of it is a candidate patch (Barequet-Sharir 1995). The weight
``"liepa"`` is Liepa's (2003): the largest dihedral angle between adjacent
patch triangles (and, given ``third_points``, between a patch triangle and the
mesh triangle across a boundary edge), ties broken by the total area. Other
weights (``"area"``, ``"perimeter"``, any optri weight, a callable) are sums of
triangle weights and go through the standard O(n^3) recurrence.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InvalidPolygonError, NoTriangulationError
from ..objective import ObjectiveLike
from ..result import Triangulation
from .liepa import as_points3d, power_of_two_scale, with_third_points
from .modes import METHODS, Hole, fill_all, fill_delaunay, result

__all__ = ["METHODS", "fill_polyline"]


def fill_polyline(
    points3d: ArrayLike,
    weight: str | Callable[..., float] = "liepa",
    method: str = "exact",
    third_points: ArrayLike | None = None,
    *,
    objective: ObjectiveLike = "sum",
    forbidden: ArrayLike | None = None,
) -> Triangulation:
    """Optimal triangulation (patch) of a closed 3-D polyline.

    Parameters
    ----------
    points3d : array_like, shape (n, 3) or (n, 2)
        Polyline vertices in order (2-D input is lifted to z = 0); a closing
        vertex equal to the first is dropped.
    weight : str or callable
        ``"liepa"`` (default): (largest dihedral angle, total area) compared
        lexicographically. ``"area"``, ``"perimeter"``, any name in
        :data:`optri.WEIGHTS`, or a callable ``w(i, k, j)`` /
        ``w(vertices, i, k, j)``: a sum of triangle weights.
    method : {"exact", "liepa", "delaunay", "auto"}
        ``"exact"``: the optimum over *all* triangulations. For ``"liepa"``
        this is a search over states (chord, apex across it): O(n^4) time at
        worst, pruned by the value of Liepa's patch, about 8 n^3 / 3 bytes;
        for triangle weights O(n^3). ``"liepa"``: Liepa's O(n^3) recurrence,
        which measures each dihedral against the optimal sub-patch's top
        triangle only, a heuristic for the max-dihedral objective (identical
        to ``"exact"`` for triangle weights). ``"delaunay"``: candidate
        triangles restricted to faces of the 3-D Delaunay tetrahedralization
        of the vertices plus every triangle on a loop side that is not a
        Delaunay edge (CGAL's set), widened step by step when that set holds
        no patch (:mod:`optri.holes.candidates`); ``stats["candidates"]``
        names the set used. Solved with Liepa's recurrence for ``"liepa"``
        and exactly otherwise; when no set holds a patch it falls back to
        ``"auto"`` over all triangles (``stats["fallback"] == 1``).
        ``"auto"``: ``"exact"`` up to ``config.HOLES_EXACT_MAX_N`` vertices
        (when its states fit in memory), else ``"liepa"``.
    third_points : array_like, shape (n, 3), optional
        ``third_points[i]`` is the third vertex of the mesh triangle on
        boundary edge ``(i, i + 1)`` (CGAL's convention). Only ``"liepa"``
        uses them: the dihedral across a boundary edge is then counted too.
    objective : {"sum", "max"} or pair
        How triangle weights combine (ignored by ``"liepa"``).
    forbidden : array_like of shape (m, 2), optional
        Index pairs ``(a, b)`` that no patch edge may join (edges a mesh
        already has: using one would give that edge four faces). Polyline
        sides cannot be forbidden.

    Returns
    -------
    Triangulation
        ``triangles`` (input indices ``(i, k, j)``, ``i < k < j``, wound in the
        polyline's order), ``weight`` (for ``"liepa"``: the pair (largest
        dihedral angle in radians, total area)), ``method`` and ``stats``
        (``degenerate``: zero-area -- exactly collinear -- triangles in the
        patch, 0 whenever a patch without one exists, else the fewest any
        patch has; ``degenerate_unavoidable``: whether ``degenerate > 0`` and
        no patch has fewer; ``forbidden``: chords excluded).

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 points, NaN/inf, repeated points, all points collinear,
        ``third_points`` or ``forbidden`` of the wrong shape, unknown method.
    NoTriangulationError
        Every patch uses a forbidden chord.
    WeightError
        Unknown weight, or a weight returning NaN.
    TableTooLargeError
        ``method="exact"`` with ``"liepa"`` on a polyline whose states do not
        fit in memory (use ``method="liepa"``); raised before allocating.

    Notes
    -----
    Liepa's dihedral angle of two triangles sharing an edge is the angle
    between their normals when both are wound the same way, i.e. pi minus the
    opening angle between them: 0 for a flat continuation, pi for a full fold.
    It does not depend on the direction in which the polyline is given.

    Degenerate triangles (three exactly collinear points, decided by exact
    orientation tests) come first in every mode and weight: the patch has none
    whenever some patch over the allowed chords has none, and otherwise the
    fewest any patch has, with the best objective among patches with that
    many. For ``"liepa"`` a degenerate triangle counts as worse than a full
    fold against every neighbour (its angle is reported as pi), so a patch with
    one is worth (pi, area) and the fewest are found with the least area.
    ``"delaunay"`` widens its candidate set rather than accept one that a
    patch over all triangles avoids.

    Which mode is exact: ``"exact"`` always. ``"liepa"`` and ``"delaunay"``
    with the ``"liepa"`` weight are Liepa's heuristic (the latter is the
    search CGAL's ``triangulate_hole_polyline`` runs); with a triangle weight,
    ``"liepa"`` is exact and ``"delaunay"`` is exact over the candidate set.
    The lexicographic pair is made exact by two passes: the least possible
    largest dihedral M first, then the least area among patches whose
    dihedrals are all <= M.

    References
    ----------
    .. [1] P. Liepa, "Filling holes in meshes", Eurographics SGP 2003.
    .. [2] G. Barequet, M. Sharir, "Filling gaps in the boundary of a
       polyhedron", CAGD 12(2), 1995.
    .. [3] G. Barequet, M. Dickerson, D. Eppstein, "On triangulating
       three-dimensional polygons", SoCG 1996.
    .. [4] M. Zou, T. Ju, N. Carr, "An algorithm for triangulating
       multiple 3D polygons", Eurographics SGP 2013.

    Examples
    --------
    >>> from optri import fill_polyline
    >>> square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    >>> t = fill_polyline(square, weight="area")
    >>> round(t.weight, 12), t.triangles.tolist()
    (1.0, [[0, 1, 3], [1, 2, 3]])
    >>> bent = [[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]]
    >>> fill_polyline(bent).triangles.tolist()      # folds along the short diagonal
    [[0, 1, 3], [1, 2, 3]]
    >>> fill_polyline(bent, forbidden=[[1, 3]]).triangles.tolist()   # that edge exists
    [[0, 1, 2], [0, 2, 3]]
    """
    P = as_points3d(points3d)
    n = P.shape[0]
    Q, has_third = with_third_points(P, third_points)
    if method not in METHODS:
        raise InvalidPolygonError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    allowed, nforbid = chord_mask(n, forbidden)
    liepa = isinstance(weight, str) and weight == "liepa"
    Qs, exponent = power_of_two_scale(Q)
    start = time.perf_counter()
    stats: dict[str, Any] = {"forbidden": nforbid}
    hole = Hole(P, Qs, exponent, n, has_third, weight, objective, liepa, allowed)
    if method == "delaunay":
        tris, used = fill_delaunay(hole, stats)
    else:
        tris, used = fill_all(hole, method, stats)
    if tris is None:
        raise NoTriangulationError(
            f"every patch of this {n}-vertex polyline uses a forbidden chord "
            f"({nforbid} forbidden): no patch keeps the mesh edge-manifold"
        )
    return result(hole, tris, used, stats, time.perf_counter() - start)


def chord_mask(n: int, forbidden: ArrayLike | None) -> tuple[NDArray[np.bool_], int]:
    """``(allowed, count)``: the n x n chord mask with the ``forbidden`` pairs cleared.

    >>> allowed, count = chord_mask(5, [[0, 2], [3, 1]])
    >>> bool(allowed[0, 2]), bool(allowed[1, 3]), bool(allowed[0, 3]), count
    (False, False, True, 2)
    """
    allowed = np.ones((n, n), dtype=np.bool_)
    if forbidden is None:
        return allowed, 0
    pairs = np.asarray(forbidden)
    if pairs.size == 0:
        return allowed, 0
    if pairs.ndim != 2 or pairs.shape[1] != 2 or not np.issubdtype(pairs.dtype, np.integer):
        raise InvalidPolygonError(
            f"forbidden must be an (m, 2) array of vertex index pairs, got shape {pairs.shape}"
        )
    a, b = pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)
    if a.min() < 0 or b.min() < 0 or max(a.max(), b.max()) >= n or (a == b).any():
        raise InvalidPolygonError(f"forbidden pairs must join two different vertices of 0..{n - 1}")
    gap = np.abs(a - b)
    if ((gap == 1) | (gap == n - 1)).any():
        raise InvalidPolygonError("a polyline side cannot be forbidden: every patch uses it")
    allowed[a, b] = allowed[b, a] = False
    return allowed, int(len(np.unique(np.minimum(a, b) * n + np.maximum(a, b))))
