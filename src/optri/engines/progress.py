"""Progress reporting of the engines: ``progress(done, total)`` over the table's cells.

Also the compile hook: :mod:`optri.engines.compiled` calls :func:`announce_compile`
when numba starts compiling a kernel (no cached copy on disk), and whoever
registered with :func:`on_compile` (the CLI's "compiling kernels" line) hears of
it, without importing numba itself.
"""

from __future__ import annotations

from collections.abc import Callable

from .problem import Problem

__all__ = ["announce_compile", "cell_reporter", "on_compile", "table_cells"]

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
    """Tell the :func:`on_compile` listeners that numba is compiling a kernel."""
    for callback in list(_COMPILE_LISTENERS):
        callback()


def table_cells(n: int) -> int:
    """Chords (i, j), j - i >= 2, of an n-gon: the cells every engine fills.

    >>> table_cells(5)
    6
    """
    return (n - 1) * (n - 2) // 2


def cell_reporter(problem: Problem) -> Callable[[int], None] | None:
    """A throttled ``report(cells_done)`` calling ``problem.progress``, or None."""
    if problem.progress is None:
        return None
    total = table_cells(problem.n)
    step = max(1, total // _REPORTS)
    cb = problem.progress

    def report(done: int) -> None:
        if done % step == 0 or done >= total:
            cb(min(done, total), total)

    return report
