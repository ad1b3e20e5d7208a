"""``optri data``: the sample files bundled with the package (list, locate, copy)."""

from __future__ import annotations

import json

import click

from .. import data as samples
from .app import main
from .options import output_option


@main.command("data")
@click.argument("names", nargs=-1)
@output_option(
    "dir",
    "Copy the samples (all, or NAMES) into this folder instead of printing paths.",
    required=False,
)
@click.option("--json", "as_json", is_flag=True, help="Print {name: path} as one JSON object.")
@click.option(
    "--overwrite", is_flag=True, help="With -o: replace files of the same name with other contents."
)
def data_command(
    names: tuple[str, ...], output: str | None, as_json: bool, overwrite: bool
) -> None:
    """Locate or copy the bundled sample files.

    With no NAMES, list every sample and its path; with NAMES, print each path
    (for the shell: optri solve "$(optri data octagon.csv)"). With -o DIR, copy
    them into DIR: "optri data -o examples" makes the README's commands work in
    any folder; a file of yours there is never replaced without --overwrite.
    """
    chosen = list(names) or samples.names()
    if output is not None:
        paths = [str(p) for p in samples.copy_to(output, chosen, overwrite)]
    else:
        paths = [str(samples.path(name)) for name in chosen]
    if as_json:
        click.echo(json.dumps(dict(zip(chosen, paths))))
    elif output is not None or names:
        for path in paths:
            click.echo(path)
    else:
        width = max(len(name) for name in chosen)
        for name, path in zip(chosen, paths):
            click.echo(f"{name:<{width}}  {path}")


__all__ = ["data_command"]
