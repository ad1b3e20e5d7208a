"""``triangulate``: validate -> weights -> engine -> :class:`Triangulation`."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .engines import select_engine
from .engines.problem import Problem, ProgressFn
from .errors import WeightError
from .geometry import Polygon, as_polygon, require_convex
from .objective import Objective, ObjectiveLike, as_objective
from .result import Triangulation, recompute_cost
from .weights import Weight, WeightLike, get_weight

__all__ = ["build_problem", "triangulate"]

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
    method : {"auto", "memo", "table", "brute", "fast", "gpu"}
        ``"memo"``: the paper's top-down memoization; ``"table"``: bottom-up
        square matrix; ``"brute"``: all triangulations (n <= 13); ``"fast"``:
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
    polygon = _load(vertices)
    problem = build_problem(
        polygon, weight, objective, progress=progress, keep_table=keep_table, dtype=dtype
    )
    name, solve = select_engine(method, problem)
    if problem.keep_table is None:
        problem.keep_table = name in ("memo", "table")
    start = time.perf_counter()
    solution = solve(problem)
    seconds = time.perf_counter() - start
    return _to_result(
        problem, solution.cost, solution.triangles, name, seconds, solution.table, solution.stats
    )


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
    weights = _weights_for(weight, obj)
    if allowed is None:
        allowed = allowed_chords(polygon)
    return Problem(
        polygon,
        weights,
        obj,
        allowed,
        progress,
        keep_table,  # type: ignore[arg-type]
        np.dtype(dtype),
    )


def allowed_chords(polygon: Polygon) -> NDArray[np.bool_] | None:
    """Chords a triangulation may use: None (all) for convex input.

    Non-convex polygons are refused here until the simple-polygon support
    computes their valid diagonals.
    """
    if polygon.convex:
        return None
    require_convex(polygon)
    return None  # pragma: no cover


def _weights_for(weight: Any, objective: Objective) -> tuple[Weight, ...]:
    pair = isinstance(weight, (tuple, list)) and not isinstance(weight, str)
    weights = tuple(get_weight(w) for w in weight) if pair else (get_weight(weight),)
    if len(weights) != len(objective.components):
        raise WeightError(
            f"objective {objective.name!r} has {len(objective.components)} component(s) "
            f"but {len(weights)} weight(s) were given; give one weight per component"
        )
    return weights


def _load(vertices: PolygonLike) -> Polygon:
    if isinstance(vertices, (str, os.PathLike)):
        from .io import read_polygon

        return as_polygon(read_polygon(vertices))
    return as_polygon(vertices)  # type: ignore[arg-type]


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
