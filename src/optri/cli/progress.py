"""A rich progress bar that speaks the library's ``progress(done, total)`` protocol."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from ..engines.problem import ProgressFn

__all__ = ["progress_bar"]


@contextlib.contextmanager
def progress_bar(
    description: str, enabled: bool = True, *, counts: bool = False
) -> Iterator[ProgressFn | None]:
    """Yield a ``progress(done, total)`` callback drawing a bar on stderr, or None.

    ``counts=True`` adds done/total, items per second and elapsed time (batches).
    """
    if not enabled:
        yield None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    columns: list = ["[progress.description]{task.description}", BarColumn()]
    if counts:
        columns.append(MofNCompleteColumn())
    columns.append(TaskProgressColumn())
    if counts:
        columns += [TextColumn("{task.fields[rate]}"), TimeElapsedColumn()]
    columns.append(TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(description, total=None, rate="")

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)
            if counts:
                speed = bar.tasks[0].speed
                bar.update(task, rate=f"{speed:,.0f}/s" if speed else "")

        yield update
