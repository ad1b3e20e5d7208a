"""``optri count``, ``optri enumerate`` and ``optri best``."""

from __future__ import annotations

import itertools
import json
from typing import Any

import click

from ..enumeration import best_triangulations, count_triangulations, enumerate_triangulations
from ..io.files import read_polygon
from ..result import Triangulation
from ..weights import WEIGHTS
from .app import main

_WEIGHT_HELP = f"Triangle weight ({', '.join(sorted(WEIGHTS))})."


def _polygon_or_n(source: str) -> Any:
    """An int n (the regular n-gon) or the vertices read from a file."""
    if source.isdigit():
        return int(source)
    return read_polygon(source)


def _line(index: int, tri: Triangulation, with_weight: bool) -> str:
    diags = " ".join(f"{a}-{b}" for a, b in tri.diagonals.tolist())
    head = f"{index:>6}  "
    return head + (f"{tri.weight:<14.10g}  " if with_weight else "") + diags


@main.command()
@click.argument("source")
def count(source: str) -> None:
    """Number of triangulations of the n-gon (SOURCE = N) or of the polygon in a file."""
    click.echo(str(count_triangulations(_polygon_or_n(source))))


@main.command(name="enumerate")
@click.argument("source")
@click.option("--weight", "-w", default=None, help=_WEIGHT_HELP + " Default: none.")
@click.option("--objective", "-o", default="sum", show_default=True, help="sum or max.")
@click.option(
    "--limit", "-k", type=click.IntRange(min=0), default=None, help="Stop after this many."
)
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
def enumerate_cmd(
    source: str, weight: str | None, objective: str, limit: int | None, as_json: bool
) -> None:
    """Every triangulation of SOURCE (a polygon file, or N for the regular n-gon).

    Streams in Hurtado-Noy order; each line lists the diagonals (input indices).
    """
    items = enumerate_triangulations(_polygon_or_n(source), weight=weight, objective=objective)
    for index, tri in enumerate(itertools.islice(items, limit), 1):
        if as_json:
            row = {"index": index, "diagonals": tri.diagonals.tolist()}
            row["triangles"] = tri.triangles.tolist()
            if weight is not None:
                row["weight"] = tri.weight
            click.echo(json.dumps(row))
        else:
            click.echo(_line(index, tri, weight is not None))


@main.command()
@click.argument("source")
@click.option("--k", "-k", "k", type=int, default=10, show_default=True, help="How many.")
@click.option("--weight", "-w", default="perimeter", show_default=True, help=_WEIGHT_HELP)
@click.option("--objective", "-o", default="sum", show_default=True, help="sum or max.")
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
def best(source: str, k: int, weight: str, objective: str, as_json: bool) -> None:
    """The K cheapest triangulations of SOURCE, cheapest first."""
    if k < 1:
        raise click.BadParameter("must be at least 1", param_hint="--k")
    for rank, tri in enumerate(best_triangulations(_polygon_or_n(source), weight, k, objective), 1):
        if as_json:
            click.echo(json.dumps({"rank": rank, **tri.to_dict()}))
        else:
            click.echo(_line(rank, tri, True))


__all__ = ["best", "count", "enumerate_cmd"]
