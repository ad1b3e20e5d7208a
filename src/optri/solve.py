"""``triangulate``: validate -> weights -> engine -> :class:`Triangulation`."""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Sequence
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .engines import select_engine
from .engines.problem import Problem, ProgressFn, Solution
from .io.files import read_polygon
from .io.geo import geo_polygon_coords
from .objective import Objective, ObjectiveLike, as_objective
from .polygon import Polygon, as_polygon
from .result import Triangulation, recompute_cost
from .simple import allowed_chords, zero_area_triangles
from .weights import WeightLike, resolve_weights

__all__ = ["build_problem", "load_polygon", "solution_result", "solve_problem", "triangulate"]

PolygonLike = ArrayLike | Polygon | str | os.PathLike[str]


def triangulate(
    vertices: PolygonLike,
    weight: WeightLike | Sequence[WeightLike] = "perimeter",
    objective: ObjectiveLike = "sum",
    method: str = "auto",
    *,
    progress: ProgressFn | None = None,
    keep_table: bool | None = None,
    dtype: Any = np.float64,
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
        for value weights such as ``"product"``, or a path to a CSV/JSON file.
    weight : str, callable or pair
        A name from :data:`optri.weights.WEIGHTS` (default ``"perimeter"``, the
        paper's Eq. 1), a callable ``w(i, k, j)`` / ``w(vertices, i, k, j)``
        over input indices, or one weight per component of a lexicographic
        objective.
    objective : {"sum", "max"} or pair
        How triangle weights combine: total, bottleneck, or lexicographic.
    method : {"auto", "memo", "table", "naive", "brute", "fast", "gpu"}
        ``"memo"``: the paper's top-down memoization; ``"table"``: bottom-up
        square matrix; ``"naive"``: the recursion without its table (3^(n-2)
        calls, n <= 12, for teaching); ``"brute"``: all triangulations (n <= 13); ``"fast"``:
        compiled; ``"gpu"``: CUDA; ``"auto"``: the fastest that can take it.
    progress : callable, optional
        ``progress(done, total)`` called as the table fills.
    keep_table : bool, optional
        Keep the n x n table (default: the Python engines keep it).
    dtype : numpy dtype
        Float type of compiled tables (float64, or float32 to halve memory).

    Returns
    -------
    Triangulation
        ``weight``, ``triangles`` (input indices, counter-clockwise),
        ``diagonals``, ``table``, ``stats``...

    Raises
    ------
    InvalidPolygonError
        Fewer than 3 vertices, NaN/inf, repeated vertices, a polygon the
        method cannot take.
    WeightError
        Unknown weight, weight not fitting the input, a weight returning NaN.
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
    >>> optri.triangulate([1, 3, 1, 4, 1, 5], weight="product").weight
    13.0
    """
    polygon = load_polygon(vertices)
    problem = build_problem(
        polygon, weight, objective, progress=progress, keep_table=keep_table, dtype=dtype
    )
    start = time.perf_counter()
    name, solution = solve_problem(problem, method)
    seconds = time.perf_counter() - start
    if problem.allowed is not None:
        _report_degenerate(problem, solution.triangles, solution.stats)
    return _to_result(
        problem, solution.cost, solution.triangles, name, seconds, solution.table, solution.stats
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
            gates=(*problem.gates, (problem.weights[0], first_cost)),
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

    A path is read by :func:`optri.io.read_polygon`; an object with
    ``__geo_interface__`` (a shapely Polygon, a GeoJSON-like dict wrapper) gives
    its exterior ring.
    """
    if isinstance(vertices, (str, os.PathLike)):
        return as_polygon(read_polygon(vertices))
    if hasattr(vertices, "__geo_interface__"):  # shapely or any GeoJSON-like geometry
        return as_polygon(geo_polygon_coords(vertices))
    return as_polygon(vertices)  # type: ignore[arg-type]


def solution_result(
    problem: Problem, method: str, solution: Solution, seconds: float = 0.0
) -> Triangulation:
    """The :class:`Triangulation` of an engine's answer, built as :func:`triangulate` does.

    Triangles in input vertex indices; :meth:`Triangulation.check` recomputes the cost.
    """
    return _to_result(
        problem, solution.cost, solution.triangles, method, seconds, solution.table,
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
    return Triangulation(
        vertices=polygon.vertices,
        triangles=tris.astype(np.int64),
        weight=objective.finalize(cost),
        method=method,
        weight_name=names if objective.is_lex else names[0],
        objective=objective.name,
        orientation=polygon.orientation,
        table=table,
        order=polygon.order,
        stats=dict(stats or {}),
        seconds=seconds,
        _recompute=recompute_cost(_lazy_evaluator(problem), objective, polygon.order),
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
