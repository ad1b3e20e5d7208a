"""``optri data``: the sample files bundled with the package (list, locate, copy)."""

from __future__ import annotations

import click

from .. import data as samples
from .app import main


@main.command("data")
@click.argument("names", nargs=-1)
@click.option(
    "--output",
    "-o",
    type=click.Path(file_okay=False),
    help="Copy the samples (all, or NAMES) into this folder instead of printing paths.",
)
def data_command(names: tuple[str, ...], output: str | None) -> None:
    """Locate or copy the bundled sample files.

    With no NAMES, list every sample and its path; with NAMES, print each path
    (for the shell: optri solve "$(optri data octagon.csv)"). With -o DIR, copy
    them into DIR: "optri data -o examples" makes the README's commands work in
    any folder.
    """
    chosen = list(names) or samples.names()
    if output is not None:
        for target in samples.copy_to(output, chosen):
            click.echo(str(target))
    elif names:
        for name in chosen:
            click.echo(str(samples.path(name)))
    else:
        width = max(len(name) for name in chosen)
        for name in chosen:
            click.echo(f"{name:<{width}}  {samples.path(name)}")


__all__ = ["data_command"]
