"""The ``optri`` command group: error handling shared by every command.

Library errors become one line on stderr and exit status 2; each command
lives in its own module and registers itself on :data:`main`.
"""

from __future__ import annotations

import sys
from typing import Any

import click

from .._version import __version__
from ..errors import OptriError

__all__ = ["main"]


class _Group(click.Group):
    """A click group that turns library errors into one line and exit 2."""

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except OptriError as exc:
            _fail(str(exc))
        except OSError as exc:
            _fail(f"{getattr(exc, 'filename', None) or ''}: {exc.strerror or exc}".lstrip(": "))
        except KeyboardInterrupt:
            _interrupted()
        except SystemError as exc:  # a Ctrl-C noticed as a compiled kernel returned
            if not isinstance(exc.__cause__ or exc.__context__, KeyboardInterrupt):
                raise
            _interrupted()


def _interrupted() -> None:
    click.echo("optri: interrupted", err=True)
    sys.exit(130)


def _fail(message: str) -> None:
    first = " ".join(message.split())
    click.echo(f"optri: error: {first}", err=True)
    sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="optri")
def main() -> None:
    """Optimal triangulation of polygons by dynamic programming."""
