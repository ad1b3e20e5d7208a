"""``optri count``, ``optri enumerate`` and ``optri best``."""

from __future__ import annotations

import itertools
import json
import sys
import time
from typing import Any

import click

from ..enumeration import best_triangulations, count_triangulations, enumerate_triangulations
from ..io.files import read_polygon
from ..result import Triangulation
from ..weights import WEIGHTS
from .app import main
from .options import columns_option, objective_option
from .progress import progress_bar

_WEIGHT_HELP = f"Triangle weight ({', '.join(sorted(WEIGHTS))})."
_SOURCE_HELP = "SOURCE is N (the regular n-gon), a polygon file, or - for standard input."


def _polygon_or_n(source: str, columns: tuple[str, ...] | None = None) -> Any:
    """An int n (the regular n-gon) or the vertices read from a file ("-": stdin)."""
    if source.isdigit():
        return int(source)
    return read_polygon(source, columns)


def _line(index: int, tri: Triangulation, with_weight: bool) -> str:
    diags = " ".join(f"{a}-{b}" for a, b in tri.diagonals.tolist())
    head = f"{index:>6}  "
    return head + (f"{tri.weight:<14.10g}  " if with_weight else "") + diags


@main.command()
@click.argument("source")
@columns_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def count(source: str, columns: tuple[str, ...] | None, as_json: bool, quiet: bool) -> None:
    """Number of triangulations of the n-gon (SOURCE = N) or of the polygon in a file.

    The count is printed in full, however many digits it has.
    """
    polygon = _polygon_or_n(source, columns)
    start = time.perf_counter()
    with progress_bar("counting", not quiet):
        total = count_triangulations(polygon)
    seconds = time.perf_counter() - start
    text = full_digits(total)
    if as_json:
        n = polygon if isinstance(polygon, int) else len(polygon)
        click.echo(f'{{"n": {n}, "count": {text}, "digits": {len(text)}, "seconds": {seconds}}}')
    else:
        click.echo(text)


def full_digits(value: int) -> str:
    """Every decimal digit of ``value``, past Python's 4300-digit ``str(int)`` limit.

    >>> len(full_digits(10**5000))
    5001
    """
    limit = getattr(sys, "get_int_max_str_digits", lambda: 0)()
    if limit == 0:
        return str(value)
    sys.set_int_max_str_digits(0)
    try:
        return str(value)
    finally:
        sys.set_int_max_str_digits(limit)


@main.command(name="enumerate", epilog=_SOURCE_HELP)
@click.argument("source")
@click.option("--weight", "-w", default=None, help=_WEIGHT_HELP + " Default: none.")
@objective_option(help="sum or max.")
@click.option(
    "--limit", "-n", type=click.IntRange(min=0), default=None, help="Stop after this many."
)
@columns_option
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
def enumerate_cmd(
    source: str,
    weight: str | None,
    objective: str,
    limit: int | None,
    columns: tuple[str, ...] | None,
    as_json: bool,
) -> None:
    """Every triangulation of SOURCE (a polygon file, or N for the regular n-gon).

    Streams in Hurtado-Noy order; each line lists the diagonals (input indices).
    """
    polygon = _polygon_or_n(source, columns)
    items = enumerate_triangulations(polygon, weight=weight, objective=objective)
    for index, tri in enumerate(itertools.islice(items, limit), 1):
        if as_json:
            row = {"index": index, "diagonals": tri.diagonals.tolist()}
            row["triangles"] = tri.triangles.tolist()
            if weight is not None:
                row["weight"] = tri.weight
            click.echo(json.dumps(row))
        else:
            click.echo(_line(index, tri, weight is not None))


@main.command(epilog=_SOURCE_HELP)
@click.argument("source")
@click.option(
    "--k", "-k", "k", type=click.IntRange(min=1), default=10, show_default=True, help="How many."
)
@click.option("--weight", "-w", default="perimeter", show_default=True, help=_WEIGHT_HELP)
@objective_option(help="sum or max.")
@columns_option
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def best(
    source: str,
    k: int,
    weight: str,
    objective: str,
    columns: tuple[str, ...] | None,
    as_json: bool,
    quiet: bool,
) -> None:
    """The K cheapest triangulations of SOURCE, cheapest first."""
    polygon = _polygon_or_n(source, columns)
    start = time.perf_counter()
    with progress_bar(f"{k} best", not quiet):
        found = best_triangulations(polygon, weight, k, objective)
    seconds = time.perf_counter() - start
    for rank, tri in enumerate(found, 1):
        if as_json:
            row = {"rank": rank, **tri.to_dict(), "seconds": seconds}
            row["stats"] = {"k": k, "found": len(found)}
            click.echo(json.dumps(row))
        else:
            click.echo(_line(rank, tri, True))


__all__ = ["best", "count", "enumerate_cmd", "full_digits"]
