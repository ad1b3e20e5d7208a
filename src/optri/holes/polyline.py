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

import math
import time
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import config
from ..engines.memory import require_memory
from ..engines.problem import Problem
from ..engines.recurrence import triangles_from_splits, walk
from ..errors import InvalidPolygonError, NoTriangulationError, WeightError
from ..objective import Cost, ObjectiveLike
from ..polygon import Polygon
from ..result import Triangulation, recompute_cost
from ..solve import build_problem, solve_problem
from .candidates import candidate_lists
from .liepa import angle_of_key, as_points3d, liepa_keys, with_third_points

__all__ = ["METHODS", "fill_polyline"]

#: Accepted ``method`` values.
METHODS = ("auto", "exact", "liepa", "delaunay")


def fill_polyline(
    points3d: ArrayLike,
    weight: str | Callable[..., float] = "liepa",
    method: str = "exact",
    third_points: ArrayLike | None = None,
    *,
    objective: ObjectiveLike = "sum",
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
        this is an O(n^4)-time, O(n^3)-memory search (states: a chord plus the
        apex across it); for triangle weights O(n^3). ``"liepa"``: Liepa's
        O(n^3) recurrence, which measures each dihedral against the optimal
        sub-patch's top triangle only, a heuristic for the max-dihedral
        objective (identical to ``"exact"`` for triangle weights).
        ``"delaunay"``: candidate triangles restricted to faces of the 3-D
        Delaunay tetrahedralization of the vertices (Zou et al. 2013), solved
        with Liepa's recurrence for ``"liepa"`` and exactly otherwise; if
        those faces hold no triangulation it falls back to ``"auto"`` over all
        triangles (``stats["fallback"] == 1``). ``"auto"``: ``"exact"`` up to
        ``config.HOLES_EXACT_MAX_N`` vertices (when its table fits in memory), else
        ``"liepa"``.
    third_points : array_like, shape (n, 3), optional
        ``third_points[i]`` is the third vertex of the mesh triangle on
        boundary edge ``(i, i + 1)`` (CGAL's convention). Only ``"liepa"``
        uses them: the dihedral across a boundary edge is then counted too.
    objective : {"sum", "max"} or pair
        How triangle weights combine (ignored by ``"liepa"``).

    Returns
    -------
    Triangulation
        ``triangles`` (input indices ``(i, k, j)``, ``i < k < j``, wound in the
        polyline's order), ``weight`` (for ``"liepa"``: the pair (largest
        dihedral angle in radians, total area)), ``method`` and ``stats``.

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 points, NaN/inf, repeated points, all points collinear,
        ``third_points`` of the wrong shape, unknown method.
    WeightError
        Unknown weight, or a weight returning NaN.
    TableTooLargeError
        ``method="exact"`` with ``"liepa"`` on a polyline whose O(n^3) table
        does not fit in memory (use ``method="liepa"``).

    Notes
    -----
    Liepa's dihedral angle of two triangles sharing an edge is the angle
    between their normals when both are wound the same way, i.e. pi minus the
    opening angle between them: 0 for a flat continuation, pi for a full fold.
    It does not depend on the direction in which the polyline is given. A
    zero-area triangle counts as a fold of pi against every neighbour, so the
    exact search avoids degenerate triangles whenever it can.

    Which mode is exact: ``"exact"`` always (for ``"liepa"``: O(n^4) time and
    about 10 n^3 bytes; about 0.6 s at n = 200). ``"liepa"`` and ``"delaunay"``
    with the ``"liepa"`` weight are Liepa's heuristic (the latter is the
    search CGAL's ``triangulate_hole_polyline`` runs); with a triangle weight,
    ``"liepa"`` is exact and ``"delaunay"`` is exact over the Delaunay faces.
    The lexicographic pair is made exact by two passes: the least possible
    largest dihedral M first, then the least area among patches whose
    dihedrals are all <= M (one pass comparing pairs would not be exact, since
    a sub-patch with a larger area but a smaller dihedral can lose its
    advantage once a larger dihedral above it dominates).

    References
    ----------
    .. [1] P. Liepa, "Filling holes in meshes", Eurographics SGP 2003.
    .. [2] G. Barequet, M. Sharir, "Filling gaps in the boundary of a
       polyhedron", CAGD 12(2), 1995.
    .. [3] G. Barequet, M. Dickerson, D. Eppstein, "On triangulating
       three-dimensional polygons", SoCG 1996.
    .. [4] W. Zou, J. Ye, H. Kuo, et al., "An algorithm for triangulating
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
    """
    P = as_points3d(points3d)
    n = P.shape[0]
    Q, has_third = with_third_points(P, third_points)
    if method not in METHODS:
        raise InvalidPolygonError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    liepa = isinstance(weight, str) and weight == "liepa"
    start = time.perf_counter()
    stats: dict[str, Any] = {}
    hole = _Hole(Q, n, has_third, weight, objective, liepa)
    if method == "delaunay":
        tris, used = _fill_delaunay(hole, stats)
    else:
        found, used = _fill_all(hole, method)
        assert found is not None  # the full search always admits a triangulation
        tris = found
    seconds = time.perf_counter() - start
    return _result(P, Q, has_third, tris, weight, objective, liepa, used, stats, seconds)


# --- search -------------------------------------------------------------------


class _Hole(NamedTuple):
    """One fill request: points (+ third points) and what to minimize."""

    Q: NDArray[np.float64]
    n: int
    has_third: bool
    weight: Any
    objective: ObjectiveLike
    liepa: bool


def _fill_all(
    hole: _Hole,
    method: str,
    ptr: NDArray[np.int64] | None = None,
    ks: NDArray[np.int64] | None = None,
) -> tuple[NDArray[np.int64] | None, str]:
    """Triangles of the best patch (None if the candidates admit none) and the mode.

    ``ptr``/``ks``: CSR candidate apexes per chord (:func:`candidate_lists`);
    None for every triangle.
    """
    Q, n, has_third, weight, objective, liepa = hole
    from . import _exact, _kernels  # numba: loaded on first use only

    if not liepa:  # a sum or max of triangle weights: the normal engines
        allowed = None if ptr is None else _candidate_chords(n, ptr)
        return _engine_dp(Q[:n], weight, objective, allowed), "exact"
    if ptr is None:
        fits = _exact.exact_table_bytes(n) <= config.available_memory_bytes()
        if method == "exact" or (method == "auto" and n <= config.HOLES_EXACT_MAX_N and fits):
            require_memory(
                _exact.exact_table_bytes(n),
                f"the exact Liepa search of a {n}-vertex hole (O(n^3) states)",
                "use method='liepa' (Liepa's O(n^3) recurrence) or 'auto'",
            )
            _, _, S = _exact.exact_liepa(Q, n, has_third)
            return _walk_exact(S, n), "exact"
    empty = np.zeros(0, dtype=np.int64)
    _, _, K = _kernels.liepa_recurrence(
        Q, n, has_third, empty if ptr is None else ptr, empty if ks is None else ks
    )
    return _walk(K, n), "liepa"


def _fill_delaunay(hole: _Hole, stats: dict[str, Any]) -> tuple[NDArray[np.int64], str]:
    ptr, ks, faces = candidate_lists(hole.Q[: hole.n])
    stats["delaunay_faces"] = faces
    tris, _ = _fill_all(hole, "liepa", ptr, ks)
    if tris is not None:
        stats["fallback"] = 0
        return tris, "delaunay"
    stats["fallback"] = 1
    tris, used = _fill_all(hole, "auto")
    assert tris is not None  # every index triangulation is a candidate now
    return tris, f"delaunay->{used}"


def _candidate_chords(n: int, ptr: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Chord mask of the candidate triangles: their sides, and the polyline's own edges."""
    allowed = np.zeros((n, n), dtype=np.bool_)
    chords = np.flatnonzero(np.diff(ptr))  # chord i * n + j with candidate apexes
    i, j = np.divmod(chords, n)
    allowed[i, j] = allowed[j, i] = True
    return allowed


def _walk(K: NDArray[np.int32], n: int) -> NDArray[np.int64] | None:
    if K[0, n - 1] < 0:
        return None
    return triangles_from_splits(lambda i, j: K[i, j], n)


def _walk_exact(S: NDArray[np.int16], n: int) -> NDArray[np.int64]:
    """Triangles of the exact search: state (i, j, m) = chord (i, j) seen from apex m."""

    def expand(state: tuple[int, int, int]) -> tuple[tuple[int, int, int], list[Any]]:
        i, j, m = state
        k = int(S[i, j, m])
        children = [c for c in ((i, k, j), (k, j, i)) if c[1] - c[0] >= 2]
        return (i, k, j), children

    return np.array(walk((0, n - 1, n), expand, n - 2), dtype=np.int64).reshape(-1, 3)


def _problem(P: NDArray[np.float64], weight: Any, objective: ObjectiveLike) -> Problem:
    # a 3-D polyline: every index triangulation is a surface, so every chord is allowed
    n = len(P)
    polygon = Polygon(P, P, np.arange(n, dtype=np.int64), None, True)
    return build_problem(polygon, weight, objective, keep_table=False)


def _engine_dp(
    P: NDArray[np.float64],
    weight: Any,
    objective: ObjectiveLike,
    allowed: NDArray[np.bool_] | None,
) -> NDArray[np.int64] | None:
    """The recurrence over the chords ``allowed`` (None: all) with the fastest engine."""
    problem = _problem(P, weight, objective)
    problem.allowed = allowed
    try:
        return solve_problem(problem, "auto")[1].triangles
    except NoTriangulationError:
        if allowed is None:
            raise
        return None  # the candidates hold no triangulation


# --- result -------------------------------------------------------------------


def _result(
    P: NDArray[np.float64],
    Q: NDArray[np.float64],
    has_third: bool,
    tris: NDArray[np.int64],
    weight: Any,
    objective: ObjectiveLike,
    liepa: bool,
    method: str,
    stats: dict[str, Any],
    seconds: float,
) -> Triangulation:
    n = len(P)
    tris = tris[np.lexsort((tris[:, 2], tris[:, 1], tris[:, 0]))]
    again: Callable[[NDArray[np.int64]], Cost]
    if liepa:

        def liepa_cost(t: NDArray[np.int64]) -> Cost:
            key, area = liepa_keys(Q, n, has_third, t)
            return (angle_of_key(key), area)

        again = liepa_cost
        name: Any = ("liepa_dihedral", "area")
        obj_name: Any = ("max", "sum")
    else:
        problem = _problem(P, weight, objective)
        again = recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)
        names = tuple(w.name for w in problem.weights)
        name = names[0] if len(names) == 1 else names
        obj_name = problem.objective.name
    value = again(tris)
    if isinstance(value, float) and math.isnan(value):
        raise WeightError("the weight returned NaN")
    return Triangulation(
        vertices=P,
        triangles=tris.astype(np.int64),
        weight=value,
        method=method,
        weight_name=name,
        objective=obj_name,
        orientation=None,
        order=np.arange(n, dtype=np.int64),
        stats=stats,
        seconds=seconds,
        _recompute=again,
    )
