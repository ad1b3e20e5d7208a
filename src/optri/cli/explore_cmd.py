"""``optri explore``: write the explorer page of a polygon."""

from __future__ import annotations

import json
import re
from pathlib import Path

import click
import numpy as np

from ..io.files import read_polygon
from ..teaching import explore as explore_page
from .app import main
from .options import columns_option, objective_option, output_option, parse_pair

__all__ = ["explore"]

_VALUES = re.compile(r"^\s*[-+0-9.eE]+(\s*,\s*[-+0-9.eE]+){2,}\s*$")


@main.command()
@click.argument("source", metavar="INPUT")
@click.option(
    "--weight",
    "-w",
    default="perimeter",
    show_default=True,
    help="Triangle weight (product for vertex values such as 5,1,5,1,5).",
)
@objective_option(help="sum or max.")
@click.option(
    "--method",
    "-m",
    default="memo",
    show_default=True,
    type=click.Choice(["memo", "table", "naive"]),
    help="Order shown first; memo and table are both in the page.",
)
@output_option("file", "The HTML file to write (one self-contained page).  [required]")
@columns_option
@click.option("--json", "as_json", is_flag=True, help="Print what was written as one JSON object.")
def explore(
    source: str,
    weight: str,
    objective: str,
    method: str,
    output: str,
    columns: tuple[str, ...] | None,
    as_json: bool,
) -> None:
    """Write an explorer page replaying the DP on INPUT step by step.

    INPUT is a polygon file (CSV, JSON, GeoJSON, WKT; - for stdin) or, when no such file
    exists, vertex values such as 5,1,5,1,5 (the paper's pentagon, with
    --weight product). The page needs no network: open it in any browser.
    """
    if not Path(source).exists() and _VALUES.match(source):
        vertices = np.array([float(v) for v in source.split(",")])
    else:
        vertices = read_polygon(source, columns)
    explore_page(vertices, weight, parse_pair(objective), method, path=output)
    if as_json:
        click.echo(json.dumps({"output": output, "n": len(vertices), "method": method}))
        return
    click.echo(f"explorer written to {output} (n = {len(vertices)}, {method} shown first)")
