"""``optri solve`` and ``optri chain``."""

from __future__ import annotations

import json
import time
from typing import Any

import click

from .. import config
from ..batch.layer import warn_geographic
from ..chain import matrix_chain
from ..drawing import format_table, save_figure
from ..io.files import read_rings_and_crs
from ..solve import triangulate
from .app import main
from .batch_cmd import warnings_as_lines
from .options import PlotPath, columns_option, engine_options, input_path, parse_pair
from .progress import compile_notice, progress_bar


@main.command()
@click.argument("file", type=input_path)
@engine_options
@columns_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option(
    "--plot",
    "plot_path",
    type=PlotPath(),
    help="Write a drawing of the triangulation (.png, .svg, .pdf, ...).",
)
@click.option(
    "--table",
    "show_table",
    is_flag=True,
    help=f"Print the n x n table like the paper's Table 1 (n <= {config.CLI_TABLE_MAX_N}).",
)
@click.option(
    "--one-based",
    is_flag=True,
    help="Number vertices from 1, as the paper does, in the table and the lines above it "
    "(default: from 0, as the API and --json).",
)
@click.option("--float32", is_flag=True, help="Compiled engines: float32 table.")
@click.option(
    "--time-limit",
    type=click.FloatRange(min=0, min_open=True),
    default=None,
    help="Polygon with holes: seconds for the search; then the best found, labelled heuristic.",
)
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def solve(
    file: str,
    weight: str,
    objective: str,
    method: str,
    columns: tuple[str, ...] | None,
    as_json: bool,
    plot_path: str | None,
    show_table: bool,
    one_based: bool,
    float32: bool,
    time_limit: float | None,
    quiet: bool,
) -> None:
    """Optimal triangulation of the polygon in FILE (CSV, JSON, GeoJSON, WKT; - for stdin).

    A CSV's delimiter, header and coordinate columns are sniffed (or named with
    --columns). A GeoJSON or WKT polygon with holes is triangulated with its holes.
    Vertices are numbered from 0 (as in --json and the Python API), or from 1 with
    --one-based (the paper's labels), in every line printed.
    """
    rings, crs = read_rings_and_crs(file, columns)
    with warnings_as_lines(quiet):
        warn_geographic(crs, False, "the polygon's", _DEGREES_HINT)
    n = sum(len(r) for r in rings)
    if show_table:
        _check_table(n, len(rings))
    source = (rings[0], rings[1:]) if len(rings) > 1 else rings[0]
    start = time.perf_counter()
    with (
        compile_notice(not quiet),
        progress_bar(f"solving n={n}", not quiet) as progress,
    ):
        tri = triangulate(
            source,
            weight=parse_pair(weight),
            objective=parse_pair(objective),
            method=method,
            progress=progress,
            keep_table=True if show_table else None,
            dtype="float32" if float32 else "float64",
            time_limit=time_limit,
        )
    seconds = time.perf_counter() - start
    if plot_path:
        save_figure(tri.plot(), plot_path)
    if as_json:
        out = tri.to_dict()
        out["seconds"] = seconds
        click.echo(json.dumps(out))
        return
    w = tri.weight
    click.echo(
        f"n = {tri.n}   method = {tri.method}   weight = {tri.weight_name}   "
        f"objective = {tri.objective}"
    )
    click.echo(f"optimal weight: {w!r}" if isinstance(w, tuple) else f"optimal weight: {w:.12g}")
    click.echo(f"orientation: {tri.orientation}   seconds: {seconds:.4f}")
    if tri.holes:
        click.echo(f"holes: {tri.holes}   rings: {' '.join(map(str, tri.rings))}")
        click.echo(f"optimality: {tri.optimality}   bound: {tri.bound!r}   gap: {tri.gap:.3g}")
    base = 1 if one_based else 0
    diagonals, triangles = tri.diagonals + base, tri.triangles + base
    click.echo(f"vertices numbered from {base}" + (" (the paper's labels)" if base else ""))
    click.echo("diagonals: " + " ".join(f"{a}-{b}" for a, b in diagonals.tolist()))
    click.echo("triangles: " + " ".join(f"({a},{b},{c})" for a, b, c in triangles.tolist()))
    if show_table:
        click.echo(
            "table: above the diagonal, (r, c) = optimal weight of v_r ... v_c+1; "
            "below, the splits of chord v_c v_r (* the best)"
        )
        click.echo(format_table(tri, base=base))
    if plot_path:
        click.echo(f"plot written to {plot_path}")


_DEGREES_HINT = (
    "project it to a metric CRS first (or triangulate a layer with optri batch --project)"
)


def _check_table(n: int, rings: int) -> None:
    """Refuse --table before any work where no table exists or it would be too big to read."""
    if rings > 1:
        raise click.UsageError("--table needs a simple polygon: a polygon with holes has no table")
    if n > config.CLI_TABLE_MAX_N:
        raise click.UsageError(
            f"--table prints tables up to n = {config.CLI_TABLE_MAX_N} (this polygon has "
            f"n = {n}; the text grows as n^3); leave out --table, or from Python use "
            f"optri.triangulate(..., keep_table=True).table"
        )


@main.command()
@click.argument("dims", nargs=-1, type=int, required=True)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--tables", is_flag=True, help="Also print CLRS's cost table m and split table s.")
def chain(dims: tuple[int, ...], as_json: bool, tables: bool) -> None:
    """Cheapest matrix-chain order for dimensions D0 D1 ... Dn."""
    order = matrix_chain(list(dims))
    if as_json:
        out: dict[str, object] = {"cost": order.cost, "parenthesization": order.parenthesization}
        if tables:
            out["m"] = [[int(v) for v in row[1:]] for row in order.m[1:]]
            out["s"] = [[int(v) for v in row[1:]] for row in order.s[1:]]
        click.echo(json.dumps(out))
        return
    click.echo(f"cost: {order.cost}")
    click.echo(f"order: {order.parenthesization}")
    if tables:
        size = order.m.shape[0] - 1
        click.echo("m[i, j]: fewest scalar multiplications for A_i ... A_j (CLRS 15.2)")
        click.echo(_clrs_table(order.m, range(1, size + 1), range(1, size + 1), 0))
        click.echo("s[i, j]: the optimal product splits after A_k")
        click.echo(_clrs_table(order.s, range(1, size), range(2, size + 1), 1))


def _clrs_table(table: Any, rows: range, cols: range, gap: int) -> str:
    """CLRS's upper-triangular layout: 1-based labels, cells with j >= i + gap shown."""
    texts = [[str(int(table[i, j])) if j >= i + gap else "" for j in cols] for i in rows]
    width = max(len(str(cols[-1])), *(len(t) for row in texts for t in row))
    label = len(str(rows[-1]))
    lines = [" " * label + " " + " ".join(str(j).rjust(width) for j in cols)]
    for i, row in zip(rows, texts):
        lines.append((str(i).rjust(label) + " " + " ".join(t.rjust(width) for t in row)).rstrip())
    return "\n".join(lines)


__all__ = ["chain", "solve"]
