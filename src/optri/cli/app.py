"""The ``optri`` command group: one error style and exit status for every command.

Every failure, a click usage error included, ends as one ``optri: error: ...``
line on stderr and exit status 2; Ctrl-C ends with ``optri: interrupted`` and
130, SIGTERM with ``optri: terminated`` and 143, SIGHUP with ``optri: hung up``
and 129 (all unwind, so temporary files are removed); a reader that closes the
pipe early (``| head -1``) ends the run quietly with status 0. Status 1 is
left to ``--strict``. Each command lives in its own module and registers
itself on :data:`main`.
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Any

import click

from .._version import __version__
from ..engines.interrupts import kernel_cause, stop_signals_unwind
from ..errors import OptriError, Terminated

__all__ = ["main"]

#: Environment variable that lets unexpected exceptions through with their traceback.
DEBUG_ENV = "OPTRI_DEBUG"
#: What the CLI says when a stop signal ends it (:class:`~optri.errors.Terminated`).
_STOP_WORDS = {"SIGTERM": "terminated", "SIGHUP": "hung up"}


class _Group(click.Group):
    """A click group that turns every error into one line and exit 2."""

    def main(  # type: ignore[override]
        self,
        args: Any = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        with stop_signals_unwind():
            try:
                code = super().main(args, prog_name, complete_var, False, **extra)
                _flush_stdout()
            except click.exceptions.NoArgsIsHelpError as exc:
                click.echo(exc.ctx.get_help() if exc.ctx else "")
                code = 0
            except click.ClickException as exc:
                code = _usage_line(exc)
            except click.exceptions.Abort as exc:  # Ctrl-C outside a command (click's)
                cause = exc.__cause__ or exc.__context__
                code = _stop_status(cause if isinstance(cause, KeyboardInterrupt) else None)
            except SystemExit as exc:
                code = exc.code
        code = code if isinstance(code, int) else 0
        if standalone_mode:
            sys.exit(code)
        return code

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except (click.ClickException, click.exceptions.Exit, click.exceptions.Abort):
            raise
        except OptriError as exc:
            _fail(str(exc))
        except BrokenPipeError:
            _quiet_pipe()
            sys.exit(0)
        except OSError as exc:
            name = getattr(exc, "filename", None) or ""
            _fail(f"{name}: {exc.strerror or exc}".lstrip(": "))
        except KeyboardInterrupt as exc:
            sys.exit(_stop_status(exc))
        except MemoryError:
            _fail("out of memory; try a smaller input")
        except Exception as exc:
            cause = kernel_cause(exc)
            if isinstance(cause, KeyboardInterrupt):  # noticed as a compiled kernel returned
                sys.exit(_stop_status(cause))
            if os.environ.get(DEBUG_ENV):
                raise
            _fail(
                f"unexpected {type(exc).__name__}: {exc} (a bug in optri: please report it; "
                f"{DEBUG_ENV}=1 shows the traceback)"
            )

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """List each command with its whole first paragraph, never cut short."""
        rows = []
        for name in self.list_commands(ctx):
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                rows.append((name, summary(command)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


def summary(command: click.Command) -> str:
    """The command's one-line summary: its short help, else its docstring's first paragraph."""
    text = command.short_help or (command.help or "").split("\n\n")[0]
    return " ".join(text.split())


def _stop_status(exc: KeyboardInterrupt | None) -> int:
    """Say in one line why the run stopped; its exit status: 130 on Ctrl-C, else 128 + signum."""
    if isinstance(exc, Terminated):
        click.echo(f"optri: {_STOP_WORDS.get(str(exc), 'terminated')}", err=True)
        return 128 + exc.signum
    click.echo("optri: interrupted", err=True)
    return 130


def _fail(message: str) -> None:
    click.echo(f"optri: error: {' '.join(message.split())}", err=True)
    sys.exit(2)


def _usage_line(exc: click.ClickException) -> int:
    """A click error (bad option, missing argument, ...) as one line; status 2."""
    ctx = getattr(exc, "ctx", None)
    where = ""
    if ctx is not None and ctx.parent is not None:
        where = f"{ctx.info_name}: "
    hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
    text = " ".join(exc.format_message().split()).rstrip(".")
    click.echo(f"optri: error: {where}{text}{hint}", err=True)
    return 2


def _quiet_pipe() -> None:
    """The reader went away: send what is left for stdout nowhere, say nothing."""
    with contextlib.suppress(OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())


def _flush_stdout() -> None:
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _quiet_pipe()
    except (OSError, ValueError):
        pass


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="optri")
def main() -> None:
    """Optimal triangulation of polygons by dynamic programming.

    Every command reads "-" as standard input wherever it reads a file, and
    -o/--output is the path it writes. Errors are one "optri: error:" line
    and exit status 2 (130 on Ctrl-C, 143 on SIGTERM; 1 only for --strict).
    """
