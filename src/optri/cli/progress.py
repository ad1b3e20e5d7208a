"""A rich progress bar that speaks the library's ``progress(done, total)`` protocol."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from ..engines.problem import ProgressFn

__all__ = ["progress_bar"]


@contextlib.contextmanager
def progress_bar(description: str, enabled: bool = True) -> Iterator[ProgressFn | None]:
    """Yield a ``progress(done, total)`` callback drawing a bar on stderr, or None."""
    if not enabled:
        yield None
        return
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TaskProgressColumn, TimeRemainingColumn

    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        TaskProgressColumn(),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(description, total=None)

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield update
