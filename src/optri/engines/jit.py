"""The compiled engine (``method="fast"``): the compiled core's kernels on one n x n table.

The table holds each chord's cost above the diagonal and its transpose below,
so both operands of every split stream along contiguous rows. The sum of an
edge-decomposable weight (perimeter, diagonal) runs as a cache-blocked min-plus
product (``optri._core.minplus``); every other built-in or numba-compiled weight
and the ``"max"`` and lexicographic objectives run the generic recurrence
(``optri._core.generic``; a lexicographic pair uses a second table). Split
vertices are not stored: the O(n) cells on the optimal path are re-scanned
afterwards.

Each fill is one kernel call that releases the GIL; a long one runs in a helper
thread while the calling thread reports progress and takes Ctrl-C, which stops
the fill at its next tile (min-plus) or tile-diagonal (generic). Threads:
:mod:`optri.engines.threads`. A user's ``numba.njit`` weight is compiled into a C
function (``numba.cfunc``) the core calls through a pointer; numba is imported
for that alone.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import (
    EngineUnavailableError,
    NoTriangulationError,
    OptriError,
    WeightError,
)
from ..objective import ObjectiveCode
from ..weights import Weight, WeightCode, compiled_weight_error, edge_weight
from .interrupts import interruptible, watched
from .memory import new_table, release_table, require_memory
from .problem import Problem, Solution, with_sides
from .progress import announce_compile, diagonal_work, table_work, tile_work, work_reporter
from .threads import threads_for

__all__ = [
    "SUPPORTS_GATES",
    "auto_accepts",
    "estimate_bytes",
    "minplus_tile",
    "solve",
    "unavailable",
    "unsupported",
]

#: The generic kernel honours :attr:`Problem.gates` (one gate: max-led lexicographic pairs).
SUPPORTS_GATES = True

_DTYPES = (np.dtype(np.float64), np.dtype(np.float32))
_OVERHEAD = 8 << 20  # vertex copies, traceback stack, the threads' stacks


def unavailable() -> str | None:
    """Why the compiled engine cannot run here (the compiled core missing), or None."""
    try:
        from .. import _core  # noqa: F401
    except ImportError as exc:
        return f"the compiled core optri._core cannot be imported ({exc}); reinstall optri"
    return None


def unsupported(problem: Problem) -> str | None:
    """Why the compiled engine cannot take ``problem``, or None.

    A plain Python weight cannot be called from compiled code; decorating it
    with ``numba.njit`` makes it run compiled.
    """
    if len(problem.gates) > 1:
        return "more than one triangle gate (lexicographic objectives of 3+ components)"
    for w in (*problem.weights, *(g for g, _ in problem.gates)):
        if w.code == WeightCode.CUSTOM and w.compiled is None:
            return (
                f"weight {w.name!r} is a plain Python callable, which compiled code cannot "
                f"call (decorate it with numba.njit to run it compiled)"
            )
    if np.dtype(problem.dtype) not in _DTYPES:
        return f"dtype {np.dtype(problem.dtype)} is not float64 or float32"
    return None


def auto_accepts(problem: Problem) -> bool:
    """``method="auto"`` uses this engine from ``config.FAST_AUTO_MIN_N`` vertices on."""
    return problem.n >= config.FAST_AUTO_MIN_N


def estimate_bytes(
    n: int, dtype: Any = np.float64, lex: bool = False, keep_table: bool = False
) -> int:
    """Peak bytes the engine allocates for ``n`` vertices.

    One ``n x n`` table (two for a lexicographic objective); an exported table
    adds a float64 copy and an int32 split table.

    >>> estimate_bytes(1000) // 10**6
    16
    """
    cells = n * n
    total = cells * np.dtype(dtype).itemsize * (2 if lex else 1) + _OVERHEAD
    if keep_table:
        total += cells * (8 + 4)
    return total


def solve(problem: Problem) -> Solution:
    """Solve ``problem`` with the compiled kernels; O(n^3) time, one n x n table.

    ``Solution.stats``: ``cells`` (chords computed), ``threads``, ``minplus``
    (1 on the min-plus path) and ``tile`` (its tile size).

    Raises
    ------
    EngineUnavailableError
        The problem needs what the engine cannot do (:func:`unsupported`).
    WeightError
        A weight returned NaN, or a user's compiled weight raised.
    NoTriangulationError
        No triangulation avoids the forbidden chords.
    TableTooLargeError
        The table would not fit ``config.MEMORY_LIMIT_BYTES``.
    """
    reason = unsupported(problem)
    if reason is not None:
        raise EngineUnavailableError(f"method='fast' cannot take this problem: {reason}")
    for w in problem.weights:
        w.check(problem.polygon)
    n, lex = problem.n, problem.objective.is_lex
    dtype = np.dtype(problem.dtype)
    minplus = _is_minplus(problem)
    small = config.FAST_PARALLEL_MIN_N if minplus else config.FAST_GENERIC_PARALLEL_MIN_N
    threads = threads_for(problem.options.get("threads"), n, small)
    kernels = _minplus_kernels() if minplus else None
    require_memory(
        estimate_bytes(n, dtype, lex, bool(problem.keep_table))
        + (n * n if problem.allowed is not None else 0)  # a possible copy of the mask
        + (threads * _worker_bytes(n, dtype, kernels) if minplus else 0),
        f"the fast engine's {n} x {n} {dtype.name} table{'s' if lex else ''}",
        "use dtype=float32 (half the memory) or method='gpu'",
    )
    with interruptible():  # Ctrl-C inside a kernel comes out as KeyboardInterrupt
        if minplus:
            return _solve_minplus(problem, kernels, threads)
        return _solve_generic(problem, threads)


def _solve_minplus(problem: Problem, K: Any, threads: int) -> Solution:
    n = problem.n
    code = int(problem.weights[0].code)  # an int: typing an IntEnum costs 0.2 ms a call
    pts = _points(problem)
    mask = None if problem.allowed is None else with_sides(problem.allowed)
    T = new_table(n, np.dtype(problem.dtype))
    # before the fill, which pushes the interpreter's data out of the caches
    e_last = edge_weight(code, pts, 0, n - 1)
    tile = minplus_tile(n)
    done, stop = K.tile_flags(n, tile)

    def fill() -> None:
        K.fill(T, pts, code, mask, tile, threads, done, stop)

    report = work_reporter(problem) or _no_report
    if n**3 / 6 <= config.FAST_WATCH_WORK:
        fill()
    else:
        work = tile_work(n, tile)
        watched(fill, threads, stop, lambda: report(int(work @ done)))
    report(table_work(n))
    cost = float(T[0, n - 1]) - e_last
    tris, bad = _walk(n, lambda i, j: K.split(T, i, j, False))
    _raise_if_bad(bad)
    table = None
    if problem.keep_table:
        out = np.triu(T, 1).astype(np.float64)  # the table holds E = cost + e(i, j)
        K.subtract_edges(out, pts, code)
        K.mirror_table(T)  # the splits read column j as row j of the lower half
        table = _export(out, K.split_table(T, threads))
    release_table(T)  # read no more; not on an error, where a kernel may still run
    return Solution(cost, tris, table, _stats(n, threads, 1, tile))


def _solve_generic(problem: Problem, threads: int) -> Solution:
    from .._core import generic as G

    n, lex = problem.n, problem.objective.is_lex
    dtype = np.dtype(problem.dtype)
    prob = _generic_problem(problem)
    T1 = new_table(n, dtype)
    T2 = np.empty((n, n) if lex else (1, 1), dtype=dtype)
    neutral = problem.objective.neutral
    idx = np.arange(n - 1)
    for T, v in zip((T1, T2), neutral if isinstance(neutral, tuple) else (neutral,)):
        T[idx, idx + 1] = T[idx + 1, idx] = v
    tile = int(config.FAST_GENERIC_TILE)
    stop, reached = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64)

    def fill() -> None:
        G.generic_tiles(T1, T2, prob, tile, threads, stop, reached)

    report = work_reporter(problem) or _no_report
    # a weight evaluation costs about 20 min-plus steps, which FAST_WATCH_WORK counts in
    if 20 * n**3 / 6 <= config.FAST_WATCH_WORK:
        fill()
    else:  # splits of tile-diagonals 0 .. d - 1, for d = reached[0]
        work = diagonal_work(n, tile)
        watched(fill, threads, stop, lambda: report(int(work[reached[0]])))
    _raise_on_flags(problem, prob)
    report(table_work(n))
    cost: Any = (float(T1[0, n - 1]), float(T2[0, n - 1])) if lex else float(T1[0, n - 1])
    tris, bad = G.trace(T1, T2, prob)
    _raise_on_flags(problem, prob)
    _raise_if_bad(bad)
    table = None
    if problem.keep_table:
        out = np.triu(T1, 1).astype(np.float64)  # the diagonal is never written
        table = _export(out, G.split_table(T1, T2, prob, threads))
    release_table(T1)
    return Solution(cost, tris, table, _stats(n, threads, 0, tile))


# --- helpers -----------------------------------------------------------------------


def _stats(n: int, threads: int, minplus: int, tile: int) -> dict[str, int]:
    return {"cells": (n - 1) * (n - 2) // 2, "threads": threads, "minplus": minplus, "tile": tile}


def _no_report(done: int) -> None:
    """``report(done)`` where nobody listens."""


def _points(problem: Problem) -> NDArray[np.float64]:
    """The vertices in internal order as an n x dims float64 array (values: n x 1)."""
    data = np.asarray(problem.polygon.data, dtype=np.float64)
    return np.ascontiguousarray(data.reshape(len(data), -1))


def _raise_if_bad(bad: tuple[int, int]) -> None:
    if bad[0] >= 0:
        raise NoTriangulationError(
            f"no valid triangulation of sub-polygon ({bad[0]}, {bad[1]}): every split has "
            f"an infinite or invalid cost",
            (int(bad[0]), int(bad[1])),
        )


def _export(out: NDArray[np.float64], splits: NDArray[np.int32]) -> NDArray[np.float64]:
    """The paper's table: costs (primary component) above the diagonal, splits below."""
    out[np.isneginf(out)] = 0.0
    out += np.tril(splits.T.astype(np.float64), -1)
    return out


def _walk(n: int, split: Any) -> tuple[NDArray[np.int64], tuple[int, int]]:
    """Optimal triangles from chord (0, n-1) down, ``split(i, j)`` giving each chord's k.

    Returns ``(triangles, bad)``, ``bad = (i, j)`` of a chord with no valid
    split, else ``(-1, -1)``; at most n - 2 triangles.
    """
    tris: list[tuple[int, int, int]] = []
    stack = [(0, n - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        k = int(split(i, j))
        if k <= i or k >= j or len(tris) >= n - 2:
            return np.array(tris, dtype=np.int64).reshape(-1, 3), (i, j)
        tris.append((i, k, j))
        stack += [(k, j), (i, k)]
    return np.array(tris, dtype=np.int64).reshape(-1, 3), (-1, -1)


def minplus_tile(n: int) -> int:
    """Tile side of the min-plus fill: ``config.FAST_TILE``, else 64, 128 or 256 by n.

    64 below 800 vertices, 128 below 4000, 256 from there. Larger tiles do
    more work per byte read from memory and per value of the far products'
    copied operand (the far products dominate at large n); smaller ones leave
    less work to the near splits (a larger share at small n).

    >>> minplus_tile(500), minplus_tile(1000), minplus_tile(4000)
    (64, 128, 256)
    """
    if config.FAST_TILE is not None:
        return int(config.FAST_TILE)
    return 64 if n < 800 else 128 if n < 4000 else 256


def _is_minplus(problem: Problem) -> bool:
    if problem.gates or problem.objective.components != ("sum",):
        return False
    return problem.weights[0].edge_decomposable


def _worker_bytes(n: int, dtype: Any, kernels: Any = None) -> int:
    """Each thread's buffers in the min-plus fill: a tile of edge weights, the copied operand.

    >>> _worker_bytes(500, np.float64), _worker_bytes(8000, np.float64)
    (164352, 1050624)
    """
    K = kernels if kernels is not None else _minplus_kernels()
    return int(K.worker_bytes(minplus_tile(n), np.dtype(dtype).itemsize))


# --- the min-plus kernels -----------------------------------------------------------


def _minplus_kernels() -> Any:
    """The min-plus kernels: ``optri._core.minplus`` (through :mod:`.core`: ``OPTRI_SIMD``)."""
    from . import core  # applies OPTRI_SIMD

    return core.minplus


# --- the generic kernel's problem ------------------------------------------------------


def _generic_problem(problem: Problem) -> Any:
    """The core's ``generic.Problem``: weights, gate, objective rules, mask, user weights."""
    from .._core import generic as G

    ws = problem.weights
    lex = problem.objective.is_lex
    second = ws[1] if lex else ws[0]
    gate_w, thr = problem.gates[0] if problem.gates else (None, math.inf)
    gate_code = G.NO_GATE if gate_w is None else int(gate_w.code)
    rules = problem.objective.component_codes
    slots = (ws[0], second if lex else None, gate_w)
    custom = [w is not None and w.code == WeightCode.CUSTOM for w in slots]
    vertices = order = None
    users = [0, 0, 0]
    if any(custom):
        vertices = np.ascontiguousarray(problem.polygon.vertices, dtype=np.float64)
        order = np.ascontiguousarray(problem.polygon.order, dtype=np.int64)
        for s, w in enumerate(slots):
            if custom[s]:
                assert w is not None
                users[s] = _user_address(w, problem, vertices.ndim)
    return G.Problem(
        _points(problem),
        (int(ws[0].code), int(second.code), gate_code),
        _gate_threshold(thr, problem.dtype),
        (int(rules[0]), int(rules[-1] if lex else ObjectiveCode.SUM)),
        lex,
        None if problem.allowed is None else with_sides(problem.allowed),
        vertices,
        order,
        tuple(users),
    )


def _raise_on_flags(problem: Problem, prob: Any) -> None:
    """A user weight's exception or a NaN weight, flagged by the kernel, as a WeightError."""
    if prob.error:
        slots = (problem.weights[0], problem.weights[-1], *(g for g, _ in problem.gates))
        err = compiled_weight_error(slots[prob.error - 1], problem.polygon, problem.allowed)
        raise err from err.__cause__
    if prob.nan:
        names = " or ".join(repr(w.name) for w in dict.fromkeys(problem.weights))
        raise WeightError(f"weight {names} returned NaN for a triangle")


def _gate_threshold(thr: float, dtype: Any) -> float:
    """The gate's bound; from a float32 table, widened by its rounding (one float32 ulp)."""
    if np.dtype(dtype) == np.float32 and math.isfinite(thr):
        return float(np.nextafter(np.float32(thr), np.float32(np.inf)))
    return float(thr)


#: ``(id(dispatcher), ndim)`` -> ``(dispatcher, cfunc)``: a user's weight compiled once a
#: process (the dispatcher is kept, so that its id is never reused).
_CFUNCS: dict[tuple[int, int], tuple[Any, Any]] = {}


def _user_address(weight: Weight, problem: Problem, ndim: int) -> int:
    """Address of ``weight``'s C function, ``w(vertices, shape, i, k, j, error)``.

    A compile error (the function cannot take a float64 vertex array and three
    int64 indices, or returns no number) is a :class:`WeightError` naming the
    first triangle on which the Python call fails.
    """
    func = weight.compiled
    key = (id(func), ndim)
    hit = _CFUNCS.get(key)
    if hit is None:
        try:
            hit = _CFUNCS[key] = (func, _cfunc(func, ndim))
        except OptriError:
            raise
        except Exception as exc:
            err = compiled_weight_error(weight, problem.polygon, problem.allowed, exc)
            raise err from exc
    return int(hit[1].address)


def _cfunc(func: Any, ndim: int) -> Any:
    """``func(vertices, i, k, j)`` (a numba dispatcher) as a C function for the core.

    An exception inside ``func`` sets ``error[0] = 1`` (the kernel stops and the
    engine calls ``func`` again from Python to name the triangle and the
    exception).
    """
    import numba
    from numba import types

    announce_compile()  # the one compilation left: the user's own numba weight
    signature = types.float64(
        types.CPointer(types.float64),
        types.CPointer(types.int64),
        types.int64,
        types.int64,
        types.int64,
        types.CPointer(types.int64),
    )
    if ndim == 1:

        def call(ptr, shape, i, k, j, error):  # type: ignore[no-untyped-def]
            vertices = numba.carray(ptr, (shape[0],))
            try:
                return float(func(vertices, i, k, j))
            except Exception:  # noqa: BLE001 - handed back as a flag
                error[0] = 1
                return math.nan

    else:

        def call(ptr, shape, i, k, j, error):  # type: ignore[no-untyped-def]
            vertices = numba.carray(ptr, (shape[0], shape[1]))
            try:
                return float(func(vertices, i, k, j))
            except Exception:  # noqa: BLE001 - handed back as a flag
                error[0] = 1
                return math.nan

    return numba.cfunc(signature, cache=False)(call)
