"""The compiled solver for many small polygons: one call of the core per chunk of polygons.

:func:`solve_compiled` has the signature of every chunk solver
(``solver(arrays, options) -> results``, see :mod:`optri.batch.solver`). The
polygons it can take (2-D vertex arrays of at most ``config.MANY_MAX_N``
vertices, a built-in weight on coordinates, objective ``"sum"`` or ``"max"``,
method ``"auto"``, ``"table"``, ``"memo"`` or ``"fast"``) go to
:func:`optri._core.many.solve` as ragged arrays (all vertices concatenated,
plus where each polygon starts), ``config.MANY_KERNEL_CHUNK`` at a time: the
input checks, the exact simplicity test, the chord mask and the DP run there,
in parallel over polygons, with the engines' own fills; it returns columns
(statuses, sizes, orientations, costs, triangles), not objects. Everything else, and every polygon
the kernel declines (a failed check, a non-finite optimum), is solved by
:func:`~optri.batch.each.solve_each`, i.e. :func:`optri.triangulate`, so
error messages and warnings are exactly its own.

The kernel reproduces the arithmetic of the engine ``optri.triangulate``
would pick for each polygon (the Python engines below
``config.FAST_AUTO_MIN_N`` vertices with ``method="auto"``, the compiled
engine's min-plus table from there on or with ``method="fast"``): the same
triangles in the same order and the same cost, bit for bit. The results'
``method`` is ``"many"``; they carry no table, and ``stats["wall_seconds"]``
is the chunk's kernel time shared in proportion to n^3.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..engines.threads import available
from ..errors import OptriError
from ..objective import Objective, as_objective
from ..polygon import as_polygon
from ..result import Triangulation, recompute_cost
from ..solve import build_problem
from ..weights import WeightCode, resolve_weights
from .each import Polygonal, Result, SolveOptions, solve_each

__all__ = [
    "STATUS",
    "ManyPlan",
    "kernel_result",
    "many_plan",
    "mode_of",
    "run_kernel",
    "solve_compiled",
]

#: Methods whose results the kernel reproduces.
_METHODS = ("auto", "table", "memo", "fast")
#: ``modes[n]`` of the kernel: how it solves an n-gon (``_MODE_NONE``: not at all).
_MODE_NONE, _MODE_PYTHON, _MODE_FAST = 0, 1, 2
#: The kernel's status codes, by name: 0 is solved, any other falls back to
#: :func:`~optri.batch.each.solve_each` (src/core/many.cpp's ``Status``).
STATUS = {
    "ok": 0,
    "non-finite": 1,
    "too few vertices": 2,
    "repeated vertex": 3,
    "no turn at the lowest vertex": 4,
    "not simple": 5,
    "size not taken": 6,
    "mask walk failed": 7,
    "no finite optimum": 8,
    "zero-area triangle": 9,
}


@dataclass(frozen=True)
class ManyPlan:
    """What the kernel needs from :class:`SolveOptions` (see :func:`many_plan`)."""

    code: int
    is_max: bool
    minplus: bool
    modes: NDArray[np.int64]
    objective: Objective
    weights: Any
    weight_name: str


def mode_of(method: str, n: int) -> int:
    """How the kernel solves an n-gon under ``method``: 0 not at all, 1 Python, 2 compiled.

    Mirrors the engine :func:`optri.engines.select_engine` picks for a polygon
    of n vertices with a built-in weight (tests hold the two together).

    >>> mode_of("auto", 10), mode_of("fast", 10), mode_of("brute", 10)
    (1, 2, 0)
    """
    if method == "auto":
        if n >= config.GPU_AUTO_MIN_N:
            return _MODE_NONE  # the GPU engine may take it
        method = "fast" if n >= config.FAST_AUTO_MIN_N else "table"
    if method in ("table", "memo"):
        return _MODE_PYTHON
    return _MODE_FAST if method == "fast" else _MODE_NONE


def many_plan(options: SolveOptions) -> ManyPlan | None:
    """The kernel's plan for ``options``, or None when it cannot take them.

    None for a custom or value weight, a lexicographic objective, another
    method, or ``config.MANY_COMPILED`` false.

    >>> many_plan(SolveOptions()).minplus, many_plan(SolveOptions(method="brute"))
    (True, None)
    """
    if not config.MANY_COMPILED or not isinstance(options.method, str):
        return None
    if options.method not in _METHODS:
        return None
    try:
        objective = as_objective(options.objective)
        weights = resolve_weights(options.weight, len(objective.components))
    except OptriError:  # the per-polygon path reports it, row by row
        return None
    if objective.is_lex:
        return None
    w = weights[0]
    if w.code in (WeightCode.CUSTOM, WeightCode.PRODUCT) or w.needs != "points":
        return None
    is_max = objective.components[0] == "max"
    top = int(config.MANY_MAX_N)
    modes = np.array([mode_of(options.method, n) for n in range(top + 1)], dtype=np.int64)
    return ManyPlan(
        int(w.code), is_max, w.edge_decomposable and not is_max, modes, objective, weights, w.name
    )


def solve_compiled(arrays: Sequence[Polygonal], options: SolveOptions) -> list[Result]:
    """Solve many vertex arrays, the small ones in compiled chunks; one result per array.

    Equal, polygon by polygon, to :func:`~optri.batch.each.solve_each` (and
    so to :func:`optri.triangulate`): the same triangles, the same cost bits,
    the same errors.

    >>> from optri.batch.each import SolveOptions
    >>> import numpy as np
    >>> square = np.array([[0, 0], [2, 0], [2, 1], [0, 1]], dtype=float)
    >>> bowtie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], dtype=float)
    >>> out = solve_compiled([square, bowtie], SolveOptions())
    >>> round(out[0].weight, 6), out[0].triangles.tolist(), out[0].method
    (10.472136, [[0, 1, 3], [1, 2, 3]], 'many')
    >>> str(out[1]).split(";")[0]
    'polygon is not simple: edges 0-1 and 2-3 cross'
    """
    plan = many_plan(options)
    results: list[Result | None] = [None] * len(arrays)
    take = [i for i, a in enumerate(arrays) if _fits(a)] if plan is not None else []
    rest = sorted(set(range(len(arrays))) - set(take))
    step = max(1, int(config.MANY_KERNEL_CHUNK))
    for lo in range(0, len(take), step):
        assert plan is not None
        rest += _solve_chunk(plan, arrays, take[lo : lo + step], options, results)
    rest.sort()
    for i, res in zip(rest, solve_each([arrays[i] for i in rest], options)):
        results[i] = res
    return results  # type: ignore[return-value]  # every slot is filled above


def _fits(arr: Any) -> bool:
    """A float64 2-D polygon the kernel may take (a closing vertex allowed past MANY_MAX_N).

    Anything else (lists, 3-D, other dtypes) goes to :func:`solve_each` as given.
    """
    return (
        isinstance(arr, np.ndarray)
        and arr.dtype == np.float64
        and arr.ndim == 2
        and arr.shape[1] == 2
        and 3 <= arr.shape[0] <= config.MANY_MAX_N + 1
    )


def _solve_chunk(
    plan: ManyPlan,
    arrays: Sequence[Polygonal],
    idx: list[int],
    options: SolveOptions,
    results: list[Result | None],
) -> list[int]:
    """Run the kernel on ``arrays[idx]``, fill ``results``; returns the indices it declined."""
    counts = np.array([arrays[i].shape[0] for i in idx], dtype=np.int64)
    starts = np.zeros(len(idx), dtype=np.int64)
    np.cumsum(counts[:-1], out=starts[1:])
    xy = np.ascontiguousarray(np.concatenate([arrays[i] for i in idx]))
    start = time.perf_counter()
    status, sizes, cw, costs, tris, first = run_kernel(plan, options, xy, starts, counts)
    seconds = time.perf_counter() - start
    work = sizes.astype(np.float64) ** 3
    share = seconds / max(float(work[status == 0].sum()), 1.0)
    declined = []
    for r, i in enumerate(idx):
        if status[r] != 0:
            declined.append(i)
            continue
        n, t0 = int(sizes[r]), int(first[r])
        s = int(starts[r])  # vertices from the chunk's own copy: never the caller's array
        results[i] = kernel_result(
            plan, options, xy[s : s + n], tris[t0 : t0 + n - 2], float(costs[r]), bool(cw[r])
        )
        results[i].stats["wall_seconds"] = share * work[r]  # type: ignore[union-attr]
    return declined


def run_kernel(
    plan: ManyPlan,
    options: SolveOptions,
    xy: NDArray[np.float64],
    starts: NDArray[np.int64],
    counts: NDArray[np.int64],
) -> tuple[NDArray[Any], ...]:
    """One call of ``optri._core.many.solve`` on rows ``starts[p]:starts[p] + counts[p]`` of xy.

    ``xy`` is a C-contiguous ``(m, 2)`` float64 array; returns the kernel's
    columns ``(status, sizes, cw, costs, triangles, first)`` (see src/core/many.cpp),
    on ``options.threads`` threads (None: all), at most one per polygon.
    """
    from .._core import many

    wanted = available() if options.threads is None else int(options.threads)
    threads = max(1, min(wanted, len(starts)))
    return tuple(
        many.solve(
            xy,
            np.ascontiguousarray(starts, dtype=np.int64),
            np.ascontiguousarray(counts, dtype=np.int64),
            plan.modes,
            plan.code,
            plan.is_max,
            plan.minplus,
            threads,
        )
    )


def kernel_result(
    plan: ManyPlan,
    options: SolveOptions,
    vertices: NDArray[np.float64],
    triangles: NDArray[np.int64],
    cost: float,
    cw: bool,
) -> Triangulation:
    """The Triangulation of one polygon the kernel solved (its raw cost and orientation)."""
    n = len(vertices)
    order = np.arange(n, dtype=np.int64)
    if cw:
        order[1:] = order[:0:-1]
    weight = plan.objective.finalize(cost)
    return Triangulation(
        vertices=vertices,
        triangles=triangles,
        weight=weight,
        method="many",
        weight_name=plan.weight_name,
        objective=plan.objective.name,  # type: ignore[arg-type]
        orientation="cw" if cw else "ccw",
        order=order,
        stats={},
        _recompute=_lazy_recompute(vertices, options),
        optimality="proven",
        bound=weight,
        gap=0.0,
    )


def _lazy_recompute(vertices: NDArray[np.float64], options: SolveOptions) -> Any:
    """The cost of triangles from scratch, as :meth:`Triangulation.check` asks (built on use)."""

    def again(triangles: NDArray[np.int64]) -> Any:
        problem = build_problem(as_polygon(vertices), options.weight, options.objective)
        return recompute_cost(problem.evaluator(), problem.objective, problem.polygon.order)(
            triangles
        )

    return again
