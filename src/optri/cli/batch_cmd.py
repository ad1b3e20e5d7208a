"""``optri batch IN -o OUT``: triangulate every polygon of a layer on all cores."""

from __future__ import annotations

import contextlib
import dataclasses
import json
import sys
import warnings
from collections.abc import Iterator
from typing import Any

import click

from ..batch import BatchFailedError, BatchSummary, batch
from ..batch.readers import INPUT_FORMATS
from ..batch.writers import OUTPUT_FORMATS
from ..errors import BatchWarning
from .app import main
from .options import engine_options, output_option, parse_pair
from .progress import progress_bar
from .stdin import STDIN, layer_input

__all__ = ["batch_command"]


@main.command("batch")
@click.argument("inp", metavar="IN", type=click.Path(allow_dash=True))
@output_option(
    "any",
    "Output file (.gpkg, .fgb, .parquet, .geojson, .ndjson), or a directory of "
    "resumable parts (a path ending in / or without a suffix).  [required]",
    legacy="--out",
)
@click.option("--format", "fmt", type=click.Choice(list(INPUT_FORMATS)), help="Input format.")
@click.option("--layer", help="The layer to read, in a GeoPackage holding several.")
@click.option(
    "--out-format",
    type=click.Choice(list(OUTPUT_FORMATS)),
    help="Output format, whatever the suffix (for a directory: the parts' format).",
)
@engine_options
@click.option(
    "--project",
    is_flag=True,
    help="Measure in metres: each polygon in its own local equidistant projection.",
)
@click.option(
    "--explode",
    is_flag=True,
    help="One row per triangle (a Polygon) with its feature's id and attributes.",
)
@click.option("--workers", "-j", type=click.IntRange(min=1), help="Processes (default: all cores).")
@click.option("--chunk-size", type=click.IntRange(min=1), help="Polygons per part (default: auto).")
@click.option(
    "--scheduler", default="local", show_default=True, help="local, dask, or dask://host:port."
)
@click.option("--resume/--no-resume", default=True, show_default=True, help="Keep completed parts.")
@click.option("--overwrite", is_flag=True, help="Delete earlier output and redo everything.")
@click.option("--strict", is_flag=True, help="Exit with status 1 if any polygon failed.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar, summary or warnings.")
def batch_command(
    inp: str,
    output: str,
    fmt: str | None,
    layer: str | None,
    out_format: str | None,
    weight: str,
    objective: str,
    method: str,
    project: bool,
    explode: bool,
    workers: int | None,
    chunk_size: int | None,
    scheduler: str,
    resume: bool,
    overwrite: bool,
    strict: bool,
    as_json: bool,
    quiet: bool,
) -> None:
    """Triangulate every polygon in IN (GeoJSON, NDJSON, GeoParquet, GeoPackage, FlatGeobuf).

    IN may be - (standard input; the format from --format or the content; such
    a run does not resume).

    Writes one row per input feature, in input order, with its attributes and
    CRS, plus id, status, cost, reason and the triangles (a GeometryCollection
    of Polygons, and as vertex index triples). Bad features, even lines that are not JSON, get
    status "error" and a reason; the run goes on. Rerunning the same command
    resumes an interrupted run.
    """
    with (
        layer_input(inp, fmt) as source,
        warnings_as_lines(quiet),
        progress_bar("polygons", not quiet, counts=True) as progress,
    ):
        try:
            summary = batch(
                source,
                output,
                weight=parse_pair(weight),
                objective=parse_pair(objective),
                method=method,
                workers=workers,
                chunk_size=chunk_size,
                scheduler=scheduler,
                resume=resume and inp != STDIN,
                overwrite=overwrite,
                strict=strict,
                progress=progress,
                fmt=fmt,
                out_fmt=out_format,
                project=project,
                layer=layer,
                explode=explode,
            )
        except BatchFailedError as exc:
            _report(exc.summary, as_json, f"optri: {exc.summary}")
            sys.exit(1)
    _report(summary, as_json, None if quiet else str(summary))


def _report(summary: BatchSummary, as_json: bool, line: str | None) -> None:
    """The summary as JSON on stdout (--json), or as a line on stderr."""
    if as_json:
        fields = dataclasses.asdict(summary)
        click.echo(json.dumps({**fields, "output": str(summary.output)}))
    elif line is not None:
        click.echo(line, err=True)


@contextlib.contextmanager
def warnings_as_lines(quiet: bool) -> Iterator[None]:
    """Show optri's batch warnings as ``optri: warning: ...`` lines, once each."""
    shown: set[str] = set()

    def show(message: Any, category: Any, *args: Any, **kwargs: Any) -> None:
        text = " ".join(str(message).split())
        if not quiet and text not in shown:
            shown.add(text)
            click.echo(f"optri: warning: {text}", err=True)

    with warnings.catch_warnings():
        warnings.simplefilter("always", BatchWarning)
        warnings.showwarning = show
        yield
