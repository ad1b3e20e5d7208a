"""Progress reporting of the engines: ``progress(done, total)`` in split evaluations.

Every DP engine reports the split evaluations of its table done so far, out of
those of the whole table: chord (i, j) takes ``j - i - 1``, so the count grows
in proportion to the fill's time, whatever order the chords are filled in (by
length, by tile, by recursion). Counted in chords, a bar read 38-52 % a quarter
of the way through a fill and 62-74 % halfway; in split evaluations, 19-24 %
and 42-49 % (the compiled engine counts a tile once it is finished).

Also the compile hook: the compiled engine calls :func:`announce_compile`
when numba starts compiling a kernel (no cached copy on disk), and whoever
registered with :func:`on_compile` (the CLI's "compiling kernels" line) hears of
it, without importing numba itself.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from .problem import Problem

__all__ = [
    "announce_compile",
    "diagonal_work",
    "on_compile",
    "table_work",
    "tile_work",
    "work_reporter",
]

#: Reports per run at most (about): the callback may redraw a bar each time.
_REPORTS = 200
_COMPILE_LISTENERS: list[Callable[[], None]] = []


def on_compile(callback: Callable[[], None]) -> Callable[[], None]:
    """Call ``callback()`` whenever a kernel starts compiling; returns the unregister function.

    >>> heard = []
    >>> stop = on_compile(lambda: heard.append(1))
    >>> announce_compile(); stop(); announce_compile()
    >>> heard
    [1]
    """
    _COMPILE_LISTENERS.append(callback)
    return lambda: _COMPILE_LISTENERS.remove(callback)


def announce_compile() -> None:
    """Tell the :func:`on_compile` listeners that numba is compiling a user's weight."""
    for callback in list(_COMPILE_LISTENERS):
        callback()


def table_work(n: int) -> int:
    """Split evaluations of a full table of an n-gon: one per triangle ``i < k < j``.

    The ``total`` of ``progress(done, total)``; chord (i, j) takes ``j - i - 1``.

    >>> table_work(5), sum(j - i - 1 for i in range(5) for j in range(i + 2, 5))
    (10, 10)
    """
    return n * (n - 1) * (n - 2) // 6


def tile_work(n: int, tile: int) -> NDArray[np.int64]:
    """Split evaluations of each tile (ti, tj) of ``tile x tile`` cells, at ``ti * nt + tj``.

    ``nt = ceil(n / tile)``; the sum over tiles is :func:`table_work`. In closed
    form: with ``FF(x) = (c + 1) c (c - 1) / 6``, ``c = max(x, 0)``, the chords of
    rows ``[i0, i1)`` and columns ``[j0, j1)`` take
    ``FF(j1 - 1 - i0) - FF(j1 - 1 - i1) - FF(j0 - 1 - i0) + FF(j0 - 1 - i1)``.

    >>> tile_work(10, 4).reshape(3, 3).tolist()
    [[4, 48, 48], [0, 4, 16], [0, 0, 0]]
    """
    nt = -(-n // tile)
    cuts = np.minimum(np.arange(nt + 1, dtype=np.int64) * tile, n)
    i0, i1 = cuts[:-1, None], cuts[1:, None]
    j0, j1 = cuts[None, :-1], cuts[None, 1:]

    def ff(x: NDArray[np.int64]) -> NDArray[np.int64]:
        c = np.maximum(x, 0)
        return (c + 1) * c * (c - 1) // 6

    work = ff(j1 - 1 - i0) - ff(j1 - 1 - i1) - ff(j0 - 1 - i0) + ff(j0 - 1 - i1)
    return work.reshape(-1)


def diagonal_work(n: int, tile: int) -> NDArray[np.int64]:
    """Split evaluations of tile-diagonals ``0 .. d - 1`` at ``[d]``: ``nt + 1`` values.

    For fills that finish a whole tile-diagonal at a time (the generic
    compiled kernel, the GPU engine).

    >>> diagonal_work(10, 4).tolist()
    [0, 8, 72, 120]
    """
    grid = tile_work(n, tile).reshape(-(-n // tile), -1)
    per_diagonal = [int(np.trace(grid, d)) for d in range(len(grid))]
    return np.concatenate(([0], np.cumsum(per_diagonal))).astype(np.int64)


def work_reporter(problem: Problem) -> Callable[[int], None] | None:
    """A ``report(done)`` passing split evaluations to ``problem.progress``, or None.

    About ``_REPORTS`` calls a run (the callback may redraw a bar each time), each
    with more done than the one before, and always the last, ``done == total``:
    an engine calls ``report(total)`` when it finishes, since a chord mask
    leaves some chords, and their splits, out.
    """
    if problem.progress is None:
        return None
    total = table_work(problem.n)
    step = max(1, total // _REPORTS)
    cb = problem.progress
    last = [0, 0]  # done last reported, done at which to report next

    def report(done: int) -> None:
        done = min(done, total)
        if done > last[0] and (done >= last[1] or done == total):
            last[0], last[1] = done, done + step
            cb(done, total)

    return report
