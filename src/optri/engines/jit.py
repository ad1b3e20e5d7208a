"""The compiled engine (``method="fast"``): numba kernels on one n x n table.

The table holds each chord's cost above the diagonal and its transpose below,
so both operands of every split stream along contiguous rows (see
:mod:`optri.engines._jit_kernels`). The sum of an edge-decomposable weight
(perimeter, diagonal) runs as a cache-blocked min-plus product
(the compiled core, :mod:`optri.engines.core`); every other
compiled weight and the ``"max"`` and lexicographic objectives run the generic
recurrence (a lexicographic pair uses a second table). Split vertices are not
stored: the O(n) cells on the optimal path are re-scanned afterwards.

Each fill is one kernel call; a long one runs in a helper thread while the
calling thread reports progress and takes Ctrl-C, which stops the fill at its
next tile (min-plus) or tile-diagonal (generic). Compiled code is cached on
disk (:mod:`optri.engines.compiled`), so only the first process ever pays the
compilation.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import EngineUnavailableError, NoTriangulationError, OptriError, WeightError
from ..weights import Weight, WeightCode, compiled_weight_error, edge_weight
from .interrupts import interruptible, is_loaded, watched
from .memory import new_table, release_table, require_memory
from .problem import Problem, Solution, with_sides
from .progress import diagonal_work, table_work, tile_work, work_reporter

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
_NO_GATE = -2  # mirrors _jit_kernels.NO_GATE without importing numba

_DTYPES = (np.dtype(np.float64), np.dtype(np.float32))
_OVERHEAD = 8 << 20  # vertex copies, traceback stack, numba's thread pool


def unavailable() -> str | None:
    """Why the compiled engine cannot run here (numba missing), or None.

    Looks numba up without importing it (0.3 s), which only a solve needs.
    """
    if sys.modules.get("numba") is not None:  # imported by an earlier solve
        return None
    try:
        found = importlib.util.find_spec("numba") is not None
    except (ImportError, ValueError) as exc:
        return f"numba cannot be imported ({exc}); install it with: pip install numba"
    if not found:
        return "numba is not installed; install it with: pip install numba"
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
    """``method="auto"`` uses this engine from ``config.FAST_AUTO_MIN_N`` vertices on.

    Below that, starting numba costs more than the Python DP itself.
    """
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
    """
    reason = unsupported(problem)
    if reason is not None:
        raise EngineUnavailableError(f"method='fast' cannot take this problem: {reason}")
    for w in problem.weights:
        w.check(problem.polygon)
    import numba

    from . import _jit_kernels as K

    n, lex = problem.n, problem.objective.is_lex
    dtype = np.dtype(problem.dtype)
    minplus = _is_minplus(problem)
    previous = numba.get_num_threads()
    threads = _threads(numba, problem, minplus, previous)
    require_memory(
        estimate_bytes(n, dtype, lex, bool(problem.keep_table))
        + (n * n if problem.allowed is not None else 0)  # a possible copy of the mask
        + (threads * _worker_bytes(n, dtype) if minplus else 0),
        f"the fast engine's {n} x {n} {dtype.name} table{'s' if lex else ''}",
        "use dtype=float32 (half the memory) or method='gpu'",
    )
    if threads != previous:  # 6-48 us a call of set_num_threads right after a fill
        numba.set_num_threads(threads)
    try:
        with interruptible():  # Ctrl-C: KeyboardInterrupt; a numba weight's error: itself
            return _solve(K, problem, minplus, threads)
    except Exception as exc:
        wrapped = _user_weight_error(problem, exc)
        if wrapped is exc:
            raise
        raise wrapped from exc
    finally:
        if threads != previous:
            numba.set_num_threads(previous)


def _user_weight_error(problem: Problem, exc: Exception) -> Exception:
    """``exc`` as a :class:`WeightError` when it came from a user's numba weight."""
    if isinstance(exc, OptriError):
        return exc
    for w in problem.weights:
        if w.compiled is not None:
            return compiled_weight_error(w, problem.polygon, problem.allowed, exc)
    return exc


def _solve(K: Any, problem: Problem, minplus: bool, threads: int) -> Solution:
    n, lex = problem.n, problem.objective.is_lex
    dtype = np.dtype(problem.dtype)
    args = _Args(problem, K)
    tables = (new_table(n, dtype), np.empty((n, n) if lex else (1, 1), dtype=dtype))
    T1, T2 = tables
    if minplus:
        # before the fill, which pushes the interpreter's data out of the caches
        e_last = edge_weight(problem.weights[0].code, args.pts, 0, n - 1)
        _fill_minplus(K, problem, T1, args, threads)
        cost: Any = float(T1[0, n - 1]) - e_last
    else:
        _fill_generic(problem, tables, args, threads)
        cost = (float(T1[0, n - 1]), float(T2[0, n - 1])) if lex else float(T1[0, n - 1])
    tris, bad = args.kernel("trace")(tables, *args.walk(minplus))
    args.raise_on_nan()
    if bad[0] >= 0:
        raise NoTriangulationError(
            f"no valid triangulation of sub-polygon ({bad[0]}, {bad[1]}): every split has "
            f"an infinite or invalid cost",
            (int(bad[0]), int(bad[1])),
        )
    table = _export(K, problem, tables, args, minplus) if problem.keep_table else None
    release_table(T1)  # read no more; not on an error, where a kernel may still run
    stats = {
        "cells": (n - 1) * (n - 2) // 2,
        "threads": threads,
        "minplus": int(minplus),
        "tile": minplus_tile(n) if minplus else int(config.FAST_GENERIC_TILE),
    }
    return Solution(cost, tris.astype(np.int64, copy=False), table, stats)


# --- helpers -----------------------------------------------------------------------


def _threads(numba: Any, problem: Problem, minplus: bool, available: int) -> int:
    """Threads for this problem: ``options["threads"]``, else all above the size threshold.

    ``available``: numba's thread count for the calling thread, read once a call.
    """
    wanted = problem.options.get("threads")
    if wanted is None:
        small = config.FAST_PARALLEL_MIN_N if minplus else config.FAST_GENERIC_PARALLEL_MIN_N
        wanted = available if problem.n >= small else 1
    return max(1, min(int(wanted), numba.config.NUMBA_NUM_THREADS))


def _worker_bytes(n: int, dtype: Any) -> int:
    """Each thread's buffers in the min-plus fill: a tile of edge weights, the copied operand.

    >>> _worker_bytes(500, np.float64), _worker_bytes(8000, np.float64)
    (164352, 1050624)
    """
    from .core import minplus as core_minplus

    return int(core_minplus.worker_bytes(minplus_tile(n), np.dtype(dtype).itemsize))


def minplus_tile(n: int) -> int:
    """Tile side of the min-plus fill: ``config.FAST_TILE``, else 64, 128 or 256 by n.

    64 below 800 vertices, 128 below 4000, 256 from there. Larger tiles do
    more work per byte read from memory and per value of the far products'
    copied operand (the far products dominate at large n); smaller ones leave
    less work to the near splits (a larger share at small n). Measured on the
    Xeon of ``docs/fast-engine.md``, whole calls: 128 against 64 is 5 % faster
    at n = 900, 2-3 % at 1000, 4-9 % at 1500-2000, the same at 700; 256
    against 128 is 2-5 % faster at 4000-5000, 2-3 % slower at 3000-3500.

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


class _Args:
    """The kernels' packed arguments (see :mod:`optri.engines._jit_kernels`).

    ``weigh = (pts, codes, gate, verts, order, wfn1, wfn2, wfng)``,
    ``rule = (is_max, lex, nan)``; ``mask``, the allowed chords, None when all are.
    """

    def __init__(self, problem: Problem, kernels: Any) -> None:
        ws = problem.weights
        second = ws[1] if len(ws) > 1 else ws[0]
        self.names = [w.name for w in ws]
        gate_w, thr = problem.gates[0] if problem.gates else (None, math.inf)
        gate_code = _NO_GATE if gate_w is None else gate_w.code
        codes = np.array([ws[0].code, second.code, gate_code], dtype=np.int64)
        gate = np.array([_gate_threshold(thr, problem.dtype)], dtype=np.float64)
        lex = problem.objective.is_lex
        fns = (
            _compiled_fn(ws[0]),
            _compiled_fn(second) if lex else None,
            None if gate_w is None else _compiled_fn(gate_w),
        )
        self.custom = any(f is not None for f in fns)
        data = np.asarray(problem.polygon.data, dtype=np.float64)
        self.pts = np.ascontiguousarray(data.reshape(len(data), -1))
        verts = _user_vertices(problem) if self.custom else self.pts
        order = np.ascontiguousarray(problem.polygon.order, dtype=np.int64)
        self.weigh = (self.pts, codes, gate, verts, order, *fns)
        comps = problem.objective.components
        is_max = np.array([comps[0] == "max", comps[-1] == "max"], dtype=np.bool_)
        self.nan = np.zeros(1, dtype=np.int64)
        self.rule = (is_max, lex, self.nan)
        self.mask = None if problem.allowed is None else with_sides(problem.allowed)
        self.K = kernels

    def kernel(self, name: str) -> Any:
        """Kernel ``name``; its uncached twin when a user's numba weight is involved."""
        return self.K.uncached(name) if self.custom else getattr(self.K, name)

    def walk(self, minplus: bool) -> tuple[Any, Any]:
        """``(weigh, rule)`` of ``trace`` and ``split_table``; ``(None, None)``: min-plus."""
        return (None, None) if minplus else (self.weigh, self.rule)

    def raise_on_nan(self) -> None:
        if self.nan[0]:
            names = " or ".join(repr(x) for x in dict.fromkeys(self.names))
            raise WeightError(f"weight {names} returned NaN for a triangle")


def _gate_threshold(thr: float, dtype: Any) -> float:
    """The gate's bound; from a float32 table, widened by its rounding (one float32 ulp)."""
    if np.dtype(dtype) == np.float32 and math.isfinite(thr):
        return float(np.nextafter(np.float32(thr), np.float32(np.inf)))
    return float(thr)


def _compiled_fn(weight: Weight) -> Any:
    if weight.code != WeightCode.CUSTOM:
        return None
    return weight.compiled


def _user_vertices(problem: Problem) -> NDArray[np.float64]:
    verts = np.asarray(problem.polygon.vertices, dtype=np.float64)
    return np.ascontiguousarray(verts)


def _fill_minplus(K: Any, problem: Problem, T: NDArray[Any], args: _Args, threads: int) -> None:
    """The min-plus fill of the compiled core: one call, watched from this thread when long.

    Every tile-diagonal runs in one parallel region, so no thread waits at the
    end of a call for another's last tile. Beyond ``config.FAST_WATCH_WORK``
    min-plus steps the fill runs in a helper thread (it releases the GIL) while
    this one reports progress and takes Ctrl-C (:func:`~.interrupts.watched`).
    """
    from .core import minplus as core_minplus

    n = problem.n
    code = int(problem.weights[0].code)
    tile = minplus_tile(n)
    done, stop = core_minplus.tile_flags(n, tile)

    def fill() -> None:
        core_minplus.fill(T, args.pts, code, args.mask, tile, threads, done, stop)

    report = work_reporter(problem) or _no_report
    if n**3 / 6 <= config.FAST_WATCH_WORK:
        fill()
    else:
        work = tile_work(n, tile)
        watched(fill, threads, stop, lambda: report(int(work @ done)))
    report(table_work(n))


def _no_report(done: int) -> None:
    """``report(done)`` where nobody listens."""


def _fill_generic(
    problem: Problem, tables: tuple[NDArray[Any], NDArray[Any]], args: _Args, threads: int
) -> None:
    """The generic fill: one kernel call, watched from this thread when it is long.

    A weight evaluation costs about 20 min-plus steps, which ``config.FAST_WATCH_WORK``
    counts in. The kernel checks the stop flag, and a NaN weight, between tile-diagonals.
    """
    n = problem.n
    neutral = problem.objective.neutral
    neutrals = neutral if isinstance(neutral, tuple) else (neutral,)
    idx = np.arange(n - 1)
    for T, v in zip(tables, neutrals):
        T[idx, idx + 1] = T[idx + 1, idx] = v
    kernel = args.kernel("generic_tiles")
    tile = int(config.FAST_GENERIC_TILE)
    stop, reached = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64)

    def fill() -> None:
        kernel(tables, args.weigh, args.rule, args.mask, tile, stop, reached)

    report = work_reporter(problem) or _no_report
    loaded = is_loaded(kernel, tables[0].dtype, args.mask is not None)
    if 20 * n**3 / 6 <= config.FAST_WATCH_WORK and loaded:
        fill()
    else:  # splits of tile-diagonals 0 .. d - 1, for d = reached[0]
        work = diagonal_work(n, tile)
        watched(fill, threads, stop, lambda: report(int(work[reached[0]])))
    args.raise_on_nan()
    report(table_work(n))


def _export(
    K: Any,
    problem: Problem,
    tables: tuple[NDArray[Any], NDArray[Any]],
    args: _Args,
    minplus: bool,
) -> NDArray[np.float64]:
    """The paper's table: costs (primary component) above the diagonal, splits below."""
    out = np.triu(tables[0], 1).astype(np.float64)  # the diagonal is never written
    if minplus:  # the table holds E = cost + e(i, j), above the diagonal only
        from .core import minplus as core_minplus

        core_minplus.subtract_edges(out, args.pts, int(problem.weights[0].code))
        core_minplus.mirror_table(tables[0])  # split_table reads column j as row j below
    out[np.isneginf(out)] = 0.0
    splits = args.kernel("split_table")(tables, *args.walk(minplus))
    out += np.tril(splits.T.astype(np.float64), -1)
    return out
