"""Options shared by the commands: one spelling and one meaning each.

The scheme (docs and ``tests/test_cli_habits.py`` hold every command to it):
``-o/--output`` the path written; ``-w/--weight``; ``-O/--objective``;
``-m/--method``; ``-k/--k`` how many best; ``-n/--limit`` stop after this
many; ``-j/--workers``; ``-q/--quiet``; ``-h/--help``. ``-`` reads standard
input wherever a file is read.
"""

from __future__ import annotations

import functools
import os
import stat
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from ..domains import METHODS as DOMAIN_METHODS
from ..engines import ENGINES
from ..errors import InvalidPolygonError
from ..io.delimited import parse_columns
from ..weights import WEIGHTS

__all__ = [
    "OutputPath",
    "PlotPath",
    "columns_option",
    "engine_options",
    "input_path",
    "output_option",
    "parse_pair",
]

#: Input files: ``-`` is standard input; a missing file is reported by the reader.
input_path = click.Path(dir_okay=False, allow_dash=True)


def parse_pair(value: str) -> str | tuple[str, ...]:
    """``"max,sum"`` -> ``("max", "sum")``; a single name stays a string."""
    parts = tuple(p.strip() for p in value.split(","))
    return parts if len(parts) > 1 else parts[0]


def objective_option(default: str = "sum", help: str | None = None) -> Any:
    """``-O/--objective``: ``-o`` is the output path in every command."""
    return click.option(
        "--objective",
        "-O",
        default=default,
        show_default=True,
        help=help or "sum, max, or a lexicographic pair such as max,sum.",
    )


def engine_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """Add ``-w/--weight``, ``-O/--objective`` and ``-m/--method`` to a command."""
    decorators = [
        click.option(
            "--weight",
            "-w",
            default="perimeter",
            show_default=True,
            help=f"Triangle weight ({', '.join(sorted(WEIGHTS))}); 'a,b' for a lexicographic pair.",
        ),
        objective_option(),
        click.option(
            "--method",
            "-m",
            default="auto",
            show_default=True,
            type=click.Choice(["auto", *ENGINES, *(m for m in DOMAIN_METHODS if m != "auto")]),
            help="Engine (a polygon with holes: auto, ip or bridge).",
        ),
    ]
    for decorate in reversed(decorators):
        func = decorate(func)
    return func


def _columns(ctx: click.Context, param: click.Parameter, value: str | None) -> Any:
    if value is None:
        return None
    try:
        return parse_columns(value)
    except InvalidPolygonError as exc:
        raise click.BadParameter(str(exc)) from None


#: ``--columns x,y``: the CSV columns holding the coordinates (names or 1-based numbers).
columns_option = click.option(
    "--columns",
    callback=_columns,
    metavar="X,Y[,Z]",
    help="CSV: the coordinate columns, by header name or number (default: sniffed).",
)


class OutputPath(click.ParamType):
    """A path optri may write: a regular file (``kind="file"``), a folder (``"dir"``) or either.

    An existing path of another kind (a directory, a device, a FIFO, a socket)
    is refused before any work, so an output never replaces a special file.
    """

    name = "path"

    def __init__(self, kind: str = "file") -> None:
        self.kind = kind

    def convert(self, value: Any, param: Any, ctx: Any) -> str:
        """The path, or a one-line usage error when it exists and is of the wrong kind."""
        path = os.fspath(value)
        try:
            mode = os.stat(path).st_mode
        except FileNotFoundError:
            return path
        except OSError as exc:
            self.fail(f"{path}: {exc.strerror}", param, ctx)
        if stat.S_ISDIR(mode):
            if self.kind == "file":
                self.fail(f"{path} is a directory; give a file name", param, ctx)
            return path
        if self.kind == "dir":
            self.fail(f"{path} exists and is not a directory", param, ctx)
        if not stat.S_ISREG(mode):
            self.fail(
                f"{path} is not a regular file (a device, FIFO or socket); optri replaces "
                f"regular files only",
                param,
                ctx,
            )
        return path


class PlotPath(OutputPath):
    """An output file whose suffix names a format matplotlib writes (png, svg, pdf, ...)."""

    def convert(self, value: Any, param: Any, ctx: Any) -> str:
        """The path, or a one-line usage error naming the formats matplotlib writes."""
        path = super().convert(value, param, ctx)
        suffix = Path(path).suffix.lower().lstrip(".")
        formats = _plot_formats()
        if suffix not in formats:
            self.fail(
                f"{path}: unknown picture format {suffix or '(no suffix)'!r}; use one of "
                f"{', '.join('.' + f for f in sorted(formats))}",
                param,
                ctx,
            )
        return path


@functools.cache
def _plot_formats() -> frozenset[str]:
    from matplotlib.backend_bases import FigureCanvasBase

    return frozenset(FigureCanvasBase.get_supported_filetypes())


def output_option(
    kind: str, help: str, *, required: bool = True, legacy: str | None = None
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Add ``-o/--output`` (an :class:`OutputPath`) as the command's ``output`` argument.

    ``legacy`` names an old spelling (``"--out"``) still accepted, hidden from
    the help, with a one-line deprecation warning.
    """

    def decorate(func: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(func)
        def command(*args: Any, **kwargs: Any) -> Any:
            old = kwargs.pop("legacy_output", None)
            if old is not None:
                click.echo(f"optri: warning: {legacy} is deprecated; use -o/--output", err=True)
                kwargs["output"] = kwargs["output"] or old
            if required and kwargs["output"] is None:
                raise click.UsageError(
                    "Missing option '-o' / '--output'.", click.get_current_context()
                )
            return func(*args, **kwargs)

        wrapped = click.option("--output", "-o", "output", type=OutputPath(kind), help=help)(
            command
        )
        if legacy is not None:
            hidden = click.option(legacy, "legacy_output", type=OutputPath(kind), hidden=True)
            wrapped = hidden(wrapped)
        return wrapped

    return decorate
