"""What the CLI shows on stderr while it works: a progress bar and the compile notice.

The bar appears once a run has taken ``config.CLI_PROGRESS_DELAY`` seconds
(about one), whatever the input's size, and only on a terminal; it speaks the
library's ``progress(done, total)`` protocol and pulses with the elapsed time
while no report has come. The compile notice is one line, once per process,
printed when numba compiles a user's own ``numba.njit`` weight for the compiled
core (built-in weights run on code compiled with the package: no notice).
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from typing import Any

import click

from .. import config
from ..engines.problem import ProgressFn
from ..engines.progress import on_compile

__all__ = ["COMPILE_NOTICE", "announce", "compile_notice", "progress_bar"]

COMPILE_NOTICE = "optri: compiling your numba weight..."
_ANNOUNCED: dict[str, bool] = {}  # outside a click context (another thread)


def announce(line: str = COMPILE_NOTICE) -> None:
    """Print the compile notice (or a more specific ``line``) once per command run."""
    ctx = click.get_current_context(silent=True)
    seen = ctx.meta if ctx is not None else _ANNOUNCED
    if not seen.get("optri.compile_announced"):
        seen["optri.compile_announced"] = True
        click.echo(line, err=True)


@contextlib.contextmanager
def compile_notice(enabled: bool = True) -> Iterator[None]:
    """While inside, a kernel compile prints :data:`COMPILE_NOTICE` (once per process)."""
    if not enabled:
        yield
        return
    stop = on_compile(announce)
    try:
        yield
    finally:
        stop()


@contextlib.contextmanager
def progress_bar(
    description: str, enabled: bool = True, *, counts: bool = False, console: Any = None
) -> Iterator[ProgressFn | None]:
    """Yield a ``progress(done, total)`` callback; a bar shows on stderr after ~1 s.

    ``counts=True`` adds done/total and items per second (batches). Nothing is
    drawn when ``enabled`` is false or stderr is not a terminal (``console``
    replaces stderr's, for tests).
    """
    from rich.console import Console

    console = console or Console(stderr=True)
    if not enabled or not console.is_terminal:
        yield None
        return
    bar, task = _make_bar(description, counts, console)
    lock = threading.Lock()
    state = {"shown": False, "closed": False}

    def show() -> None:
        with lock:
            if not state["closed"]:
                state["shown"] = True
                bar.start()

    timer = threading.Timer(config.CLI_PROGRESS_DELAY, show)
    timer.daemon = True
    timer.start()

    def update(done: int, total: int) -> None:
        bar.update(task, completed=done, total=total)
        if counts:
            speed = bar.tasks[0].speed
            bar.update(task, rate=f"{speed:,.0f}/s" if speed else "")

    try:
        yield update
    finally:
        timer.cancel()
        with lock:
            state["closed"] = True
            if state["shown"]:
                bar.stop()


def _make_bar(description: str, counts: bool, console: Any) -> tuple[Any, Any]:
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    columns: list[Any] = ["[progress.description]{task.description}", BarColumn()]
    if counts:
        columns.append(MofNCompleteColumn())
    columns.append(TaskProgressColumn())
    if counts:
        columns.append(TextColumn("{task.fields[rate]}"))
    columns += [TimeElapsedColumn(), TimeRemainingColumn()]
    bar = Progress(*columns, console=console, transient=True)
    return bar, bar.add_task(description, total=None, rate="")
