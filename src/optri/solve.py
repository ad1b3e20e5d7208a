"""``triangulate``: validate -> weights -> engine -> :class:`Triangulation`."""

from __future__ import annotations

import math
import os
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .domains import Domain, triangulate_domain
from .engines import check_method, select_engine
from .engines.memory import require_memory
from .engines.problem import Problem, ProgressFn, Solution
from .errors import (
    InvalidPolygonError,
    NoTriangulationError,
    check_callback,
    check_flag,
    check_float_dtype,
    check_seconds,
)
from .io.files import read_rings
from .io.geo import geo_polygon_rings
from .objective import Objective, ObjectiveLike, as_objective, tie_ceiling
from .polygon import Polygon, as_polygon, is_ring_pair
from .result import Triangulation, recompute_cost
from .simple import allowed_chords, zero_area_triangles
from .weights import WeightLike, resolve_weights

__all__ = [
    "build_problem",
    "load_polygon",
    "require_table_floor",
    "solution_result",
    "solve_problem",
    "triangulate",
]

PolygonLike = ArrayLike | Polygon | Domain | str | os.PathLike[str]


def triangulate(
    vertices: PolygonLike,
    weight: WeightLike | Sequence[WeightLike] = "perimeter",
    objective: ObjectiveLike = "sum",
    method: str = "auto",
    *,
    progress: ProgressFn | None = None,
    keep_table: bool | None = None,
    dtype: Any = np.float64,
    time_limit: float | None = None,
) -> Triangulation:
    """Optimal triangulation of a polygon by dynamic programming.

    Minimizes, over all triangulations, the sum (or maximum, or a
    lexicographic pair) of a triangle weight, by the recurrence

        cost(i, j) = min_{i<k<j} cost(i, k) + cost(k, j) + w(i, k, j),
        cost(i, i+1) = 0,

    (the paper's Eq. 3 in 0-based vertex indices) and reconstructs the optimal
    triangles from the optimal splits.

    Parameters
    ----------
    vertices : array_like, Polygon, str or path
        ``(n, 2)`` or ``(n, 3)`` vertices in order (either orientation; a closing
        vertex equal to the first is dropped), a 1-D sequence of vertex values
        for value weights such as ``"product"``, a path to a CSV/JSON/GeoJSON/WKT
        file, or a geometry object (``__geo_interface__``, e.g. shapely).
        A polygon with holes, as a shapely Polygon with interiors, a GeoJSON or
        WKT polygon with holes, an ``(exterior, [hole, ...])`` pair of rings or
        a :class:`~optri.domains.Domain`, is solved by
        :func:`optri.domains.triangulate_domain` (vertices numbered exterior
        first, then each hole; ``n + 2h - 2`` triangles).
    weight : str, callable or pair
        A name from :data:`optri.weights.WEIGHTS` (default ``"perimeter"``, the
        paper's Eq. 1), a callable ``w(i, k, j)`` / ``w(vertices, i, k, j)``
        over input indices, or one weight per component of a lexicographic
        objective.
    objective : {"sum", "max"} or pair
        How triangle weights combine: total, bottleneck, or lexicographic.
    method : {"auto", "memo", "table", "naive", "brute", "fast", "gpu", "integer"}
        ``"memo"``: the paper's top-down memoization; ``"table"``: bottom-up
        square matrix; ``"naive"``: the recursion without its table (3^(n-2)
        calls, n <= 12, for teaching); ``"brute"``: all triangulations (n <= 13);
        ``"fast"``: compiled; ``"gpu"``: CUDA; ``"integer"``: exact integers for
        the ``"product"`` weight on integer values; ``"auto"``: the fastest that
        can take it. The product weight on integer values always gives an
        exact ``int`` (float tables are refused where they could round).
        A polygon with holes takes ``"auto"``, ``"ip"`` or ``"bridge"``
        (:data:`optri.domains.METHODS`).
    progress : callable, optional
        ``progress(done, total)`` called as the table fills: split evaluations
        done out of the table's ``n (n - 1) (n - 2) / 6`` (chord (i, j) takes
        ``j - i - 1``), so ``done / total`` grows with the time spent, in every
        engine. An exception it raises stops the solve and propagates
        unchanged (a way to cancel).
    keep_table : bool, optional
        Keep the n x n table (default: the Python engines keep it).
    dtype : numpy dtype
        Float type of compiled tables (float64, or float32 to halve memory).
    time_limit : float, optional
        Polygons with holes: seconds for the search, past which the best
        triangulation found is returned labelled ``optimality="heuristic"``
        with a proven bound. The DP of a simple polygon has no limit.

    Returns
    -------
    Triangulation
        ``weight``, ``triangles`` (input indices, counter-clockwise),
        ``diagonals``, ``table``, ``stats``...

    Raises
    ------
    InvalidParameterError
        A parameter it cannot take (``dtype``, ``time_limit``, ``keep_table``,
        ``progress``), checked before any work; :class:`ParameterTypeError`
        (also a ``TypeError``) for the wrong type.
    InvalidPolygonError
        Fewer than 3 vertices, NaN/inf, repeated vertices, a polygon the
        method cannot take.
    WeightError
        Unknown weight or objective, weight not fitting the input, a user weight
        that raises or returns a non-number or NaN (the triangle named, the
        original exception chained).
    NoTriangulationError
        The optimum is not a finite float64 (weights that overflow, such as
        lengths of a polygon with coordinates near 1e308): never returned as inf.
    EngineUnavailableError
        The method cannot run here.
    TableTooLargeError
        The table would not fit in memory (raised before allocating).

    See Also
    --------
    matrix_chain : the same DP on matrix dimensions.

    Notes
    -----
    O(n^3) time and O(n^2) space for every DP engine.

    References
    ----------
    .. [1] A. Selimi, S. Krrabaj, M. Saracevic, S. Pepic, "Memoization method for
       storing minimum-weight triangulation of convex polygon", Computer Science
       20(2), 2019, https://doi.org/10.7494/csci.2019.20.2.3193
    .. [2] G. T. Klincsek, "Minimal triangulations of polygonal domains", Annals
       of Discrete Mathematics 9, 1980.

    Examples
    --------
    >>> import optri
    >>> t = optri.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], method="memo")
    >>> round(t.weight, 6)              # two triangles of perimeter 2 + sqrt(2)
    6.828427
    >>> t.triangles.tolist(), t.diagonals.tolist()
    ([[0, 1, 3], [1, 2, 3]], [[1, 3]])
    >>> optri.triangulate([1, 3, 1, 4, 1, 5], weight="product").weight   # integers: exact
    13
    >>> square, hole = [[0, 0], [3, 0], [3, 3], [0, 3]], [[1, 1], [2, 1], [2, 2], [1, 2]]
    >>> t = optri.triangulate((square, [hole]))
    >>> len(t.triangles), t.optimality
    (8, 'proven')
    """
    dtype = check_float_dtype(dtype)
    check_flag(keep_table, "keep_table")
    check_callback(progress, "progress", 2)
    time_limit = check_seconds(time_limit, "time_limit")
    resolve_weights(weight, len(as_objective(objective).components))  # before any reading
    source = _source(vertices)
    if isinstance(source, _Holed):
        return triangulate_domain(
            source.exterior, source.holes, weight, objective, method, time_limit=time_limit
        )
    check_method(method)
    polygon = as_polygon(source)
    if not polygon.convex:  # a convex polygon has no mask: the engine's own check is first
        require_table_floor(polygon.n, method, dtype)
    problem = build_problem(
        polygon, weight, objective, progress=progress, keep_table=keep_table, dtype=dtype
    )
    start = time.perf_counter()
    try:
        name, solution = solve_problem(problem, method)
    except NoTriangulationError as exc:
        raise NoTriangulationError(f"{exc}; {_NOT_FINITE}", exc.chord) from exc
    seconds = time.perf_counter() - start
    _require_finite(solution.cost)
    if problem.allowed is not None:
        _report_degenerate(problem, solution.triangles, solution.stats)
    return _to_result(
        problem, solution.cost, solution.triangles, name, seconds, solution.table, solution.stats
    )


def require_table_floor(n: int, method: str, dtype: Any) -> None:
    """Refuse, before the chord mask is built, a polygon whose table cannot fit anyway.

    Every CPU engine keeps at least one ``n x n`` table of ``dtype`` (float32: 4 bytes a
    cell) beside the ``n x n`` bool chord mask of a non-convex polygon; the engines
    check their full needs later. ``method="gpu"`` keeps its table on the device. Only
    for a non-convex polygon: a convex one has no mask to build, so the engine's own
    check comes first (one reading of the memory counters less per call).

    >>> require_table_floor(10**6, "auto", "float64")
    Traceback (most recent call last):
    ...
    optri.errors.TableTooLargeError: the DP table for n = 1000000 and its chord mask needs ...
    """
    table = 0 if method == "gpu" else n * n * np.dtype(dtype).itemsize
    require_memory(
        n * n + table,
        f"the DP table for n = {n} and its chord mask",
        "use dtype=float32 (half the memory), method='gpu', or split the polygon",
    )


def solve_problem(problem: Problem, method: str = "auto") -> tuple[str, Solution]:
    """Run an engine on ``problem``; returns ``(engine name, Solution)``.

    A lexicographic objective led by ``"max"`` is solved in two phases
    (:attr:`optri.objective.Objective.two_phase`): the bottleneck first, then
    the rest gated by it. The brute-force oracle evaluates the objective
    directly instead.
    """
    objective = problem.objective
    if objective.two_phase and method != "brute":
        first = replace(
            problem, weights=problem.weights[:1], objective=Objective(("max",)), keep_table=False
        )
        _, bottleneck = solve_problem(first, method)
        first_cost = cast(float, bottleneck.cost)  # a scalar "max" objective
        rest = replace(
            problem,
            weights=problem.weights[1:],
            objective=Objective(objective.components[1:]),
            # near-ties with the bottleneck pass the gate too (objective.LEX_TIE_RTOL)
            gates=(*problem.gates, (problem.weights[0], tie_ceiling(first_cost))),
        )
        name, second = solve_problem(rest, method)
        tail = second.cost if isinstance(second.cost, tuple) else (second.cost,)
        stats = {
            k: bottleneck.stats.get(k, 0) + second.stats.get(k, 0)
            for k in {*bottleneck.stats, *second.stats}
        }
        return name, Solution((first_cost, *tail), second.triangles, second.table, stats)
    name, solve = select_engine(method, problem)
    if problem.keep_table is None:
        problem.keep_table = name in ("memo", "table")
    return name, solve(problem)


def build_problem(
    polygon: Polygon,
    weight: WeightLike | Sequence[WeightLike],
    objective: ObjectiveLike,
    *,
    allowed: NDArray[np.bool_] | None = None,
    progress: ProgressFn | None = None,
    keep_table: bool | None = None,
    dtype: Any = np.float64,
) -> Problem:
    """Resolve weights and objective and decide which chords are allowed."""
    obj = as_objective(objective)
    weights = resolve_weights(weight, len(obj.components))
    options: dict[str, Any] = {}
    if allowed is None:
        start = time.perf_counter()
        allowed = allowed_chords(polygon)
        if allowed is not None:
            options["mask_seconds"] = time.perf_counter() - start
    return Problem(
        polygon,
        weights,
        obj,
        allowed=allowed,
        progress=progress,
        keep_table=keep_table,  # type: ignore[arg-type]
        dtype=np.dtype(dtype),
        options=options,
    )


def load_polygon(vertices: PolygonLike) -> Polygon:
    """A :class:`Polygon` from any input ``triangulate`` takes: array, path, geometry object.

    A path is read by :func:`optri.io.read_rings`; an object with
    ``__geo_interface__`` (a shapely Polygon, a GeoJSON-like dict wrapper) gives
    its rings. A polygon with holes is refused: only :func:`triangulate`
    takes one.
    """
    source = _source(vertices)
    if isinstance(source, _Holed):
        raise InvalidPolygonError(
            f"the polygon has {len(source.holes)} hole(s); this function takes simple "
            f"polygons (optri.triangulate takes polygons with holes)"
        )
    return as_polygon(source)


@dataclass(frozen=True)
class _Holed:
    exterior: Any
    holes: Sequence[Any]


def _source(vertices: Any) -> Any:
    """Vertex data for :func:`as_polygon`, or the rings of a polygon with holes (``_Holed``)."""
    if isinstance(vertices, Domain):
        return _Holed(vertices, ())
    rings = None
    if isinstance(vertices, (str, os.PathLike)):
        rings = read_rings(vertices)
    elif hasattr(vertices, "__geo_interface__"):  # shapely or any GeoJSON-like geometry
        rings = geo_polygon_rings(vertices)
    elif is_ring_pair(vertices):
        rings = [vertices[0], *vertices[1]]
    if rings is None:
        return vertices
    return _Holed(rings[0], rings[1:]) if len(rings) > 1 else rings[0]


_NOT_FINITE = (
    "with a valid polygon this means the weights are infinite or overflow float64 "
    "(at coordinates of magnitude near 1e308 lengths and sums exceed it); scale the "
    "coordinates down"
)


def _require_finite(cost: Any) -> None:
    """Refuse an optimum that is not a finite number (never return inf as an answer)."""
    values = cost if isinstance(cost, tuple) else (cost,)
    if not all(v == -math.inf or math.isfinite(v) for v in values):  # -inf: no triangle
        raise NoTriangulationError(
            f"the optimal cost {cost} is not a finite number: {_NOT_FINITE}", None
        )


def solution_result(
    problem: Problem, method: str, solution: Solution, seconds: float = 0.0
) -> Triangulation:
    """The :class:`Triangulation` of an engine's answer, built as :func:`triangulate` does.

    Triangles in input vertex indices; :meth:`Triangulation.check` recomputes the cost.
    """
    return _to_result(
        problem,
        solution.cost,
        solution.triangles,
        method,
        seconds,
        solution.table,
        solution.stats,
    )


def _report_degenerate(problem: Problem, triangles: NDArray[np.int64], stats: Any) -> None:
    """Record the mask's size and time and zero-area triangles (none for a simple polygon)."""
    pts = problem.polygon.planar_points
    count = zero_area_triangles(pts, triangles) if pts is not None else 0
    if isinstance(stats, dict):
        stats["zero_area_triangles"] = count
        assert problem.allowed is not None
        stats["valid_diagonals"] = int(np.count_nonzero(problem.allowed)) // 2 - problem.n
        if "mask_seconds" in problem.options:
            stats["mask_seconds"] = problem.options["mask_seconds"]
    if count:
        warnings.warn(
            f"{count} zero-area triangle(s) in the optimal triangulation: collinear "
            f"vertices left no alternative",
            RuntimeWarning,
            stacklevel=3,
        )


def _to_result(
    problem: Problem,
    cost: Any,
    triangles: NDArray[np.int64],
    method: str,
    seconds: float,
    table: Any = None,
    stats: Any = None,
) -> Triangulation:
    polygon, objective = problem.polygon, problem.objective
    tris = polygon.order[triangles] if len(triangles) else triangles.reshape(0, 3)
    names = tuple(w.name for w in problem.weights)
    weight = objective.finalize(cost)
    if problem.integer_costs:  # exact: a float engine was used only below 2**53
        weight = tuple(map(int, weight)) if isinstance(weight, tuple) else int(weight)
    return Triangulation(
        vertices=polygon.vertices,
        triangles=tris.astype(np.int64),
        weight=weight,
        method=method,
        weight_name=names if objective.is_lex else names[0],
        objective=objective.name,
        orientation=polygon.orientation,
        table=table,
        order=polygon.order,
        stats=dict(stats or {}),
        seconds=seconds,
        _recompute=recompute_cost(_lazy_evaluator(problem), objective, polygon.order),
        optimality="proven",
        bound=objective.finalize(cost),
        gap=0.0,
    )


def _lazy_evaluator(problem: Problem) -> Any:
    """``problem.evaluator()``, bound on first use.

    Compiled engines never need it unless ``Triangulation.check()`` runs, and
    binding costs O(n^2) for n <= 1500.
    """
    bound: list[Any] = []

    def w(i: int, k: int, j: int) -> Any:
        if not bound:
            bound.append(problem.evaluator())
        return bound[0](i, k, j)

    return w
