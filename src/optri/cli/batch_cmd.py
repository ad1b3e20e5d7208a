"""``optri batch IN -o OUT``: triangulate every polygon of a layer on all cores."""

from __future__ import annotations

import contextlib
import sys
import warnings
from collections.abc import Iterator
from typing import Any

import click

from ..batch import BatchFailedError, batch
from ..batch.readers import INPUT_FORMATS
from ..batch.writers import OUTPUT_FORMATS
from ..errors import BatchWarning
from .app import main
from .options import engine_options, parse_pair
from .progress import progress_bar

__all__ = ["batch_command"]


@main.command("batch")
@click.argument("inp", metavar="IN", type=click.Path())
@click.option(
    "--out",
    "-o",
    "out",
    required=True,
    type=click.Path(),
    help="Output file (.gpkg, .fgb, .parquet, .geojson, .ndjson), or a directory of "
    "resumable parts (a path ending in / or without a suffix).",
)
@click.option("--format", "fmt", type=click.Choice(list(INPUT_FORMATS)), help="Input format.")
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
@click.option("--workers", "-j", type=click.IntRange(min=1), help="Processes (default: all cores).")
@click.option("--chunk-size", type=click.IntRange(min=1), help="Polygons per part (default: auto).")
@click.option(
    "--scheduler", default="local", show_default=True, help="local, dask, or dask://host:port."
)
@click.option("--resume/--no-resume", default=True, show_default=True, help="Keep completed parts.")
@click.option("--overwrite", is_flag=True, help="Delete earlier output and redo everything.")
@click.option("--strict", is_flag=True, help="Exit with status 1 if any polygon failed.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar, summary or warnings.")
def batch_command(
    inp: str,
    out: str,
    fmt: str | None,
    out_format: str | None,
    weight: str,
    objective: str,
    method: str,
    project: bool,
    workers: int | None,
    chunk_size: int | None,
    scheduler: str,
    resume: bool,
    overwrite: bool,
    strict: bool,
    quiet: bool,
) -> None:
    """Triangulate every polygon in IN (GeoJSON, NDJSON, GeoParquet, GeoPackage, FlatGeobuf).

    Writes one row per input feature, in input order, with its attributes and
    CRS, plus id, status, cost, reason and the triangles (a MultiPolygon, or
    index triples in NDJSON). Bad features, even lines that are not JSON, get
    status "error" and a reason; the run goes on. Rerunning the same command
    resumes an interrupted run.
    """
    # no bar when stderr is a file or pipe: it would only add blank lines to logs
    with (
        _warnings_as_lines(quiet),
        progress_bar("polygons", not quiet and sys.stderr.isatty(), counts=True) as progress,
    ):
        try:
            summary = batch(
                inp,
                out,
                weight=parse_pair(weight),
                objective=parse_pair(objective),
                method=method,
                workers=workers,
                chunk_size=chunk_size,
                scheduler=scheduler,
                resume=resume,
                overwrite=overwrite,
                strict=strict,
                progress=progress,
                fmt=fmt,
                out_fmt=out_format,
                project=project,
            )
        except BatchFailedError as exc:
            summary = exc.summary
            click.echo(f"optri: {summary}", err=True)
            sys.exit(1)
    if not quiet:
        click.echo(str(summary), err=True)


@contextlib.contextmanager
def _warnings_as_lines(quiet: bool) -> Iterator[None]:
    """Show the batch's warnings as ``optri: warning: ...`` lines, once each."""
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
