"""Progress reporting of the engines: ``progress(done, total)`` over the table's cells."""

from __future__ import annotations

from collections.abc import Callable

from .problem import Problem

__all__ = ["cell_reporter", "table_cells"]

#: Reports per run at most (about): the callback may redraw a bar each time.
_REPORTS = 200


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
