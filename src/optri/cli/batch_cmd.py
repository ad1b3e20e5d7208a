"""``optri batch IN -o OUT``: triangulate every polygon of a file on all cores."""

from __future__ import annotations

import sys

import click

from ..batch import BatchFailedError, batch
from ..batch.readers import INPUT_FORMATS
from ..batch.writers import OUTPUT_FORMATS
from .app import main
from .options import engine_options, parse_pair
from .progress import progress_bar

__all__ = ["batch_command"]


@main.command("batch")
@click.argument("inp", metavar="IN", type=click.Path(dir_okay=False))
@click.option(
    "--out",
    "-o",
    "out",
    required=True,
    type=click.Path(),
    help="Output directory of part files, or one .ndjson/.geojson/.parquet file.",
)
@click.option("--format", "fmt", type=click.Choice(list(INPUT_FORMATS)), help="Input format.")
@click.option(
    "--out-format", type=click.Choice(list(OUTPUT_FORMATS)), help="Output format (directories)."
)
@engine_options
@click.option("--workers", "-j", type=click.IntRange(min=1), help="Processes (default: all cores).")
@click.option("--chunk-size", type=click.IntRange(min=1), help="Polygons per part (default: auto).")
@click.option(
    "--scheduler", default="local", show_default=True, help="local, dask, or dask://host:port."
)
@click.option("--resume/--no-resume", default=True, show_default=True, help="Keep completed parts.")
@click.option("--overwrite", is_flag=True, help="Delete earlier output and redo everything.")
@click.option("--strict", is_flag=True, help="Exit with status 1 if any polygon failed.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar and no summary.")
def batch_command(
    inp: str,
    out: str,
    fmt: str | None,
    out_format: str | None,
    weight: str,
    objective: str,
    method: str,
    workers: int | None,
    chunk_size: int | None,
    scheduler: str,
    resume: bool,
    overwrite: bool,
    strict: bool,
    quiet: bool,
) -> None:
    """Triangulate every polygon in IN (GeoJSON, NDJSON, GeoParquet, GeoPackage).

    Writes one record per polygon (id, status, cost, triangles, diagonals, reason,
    seconds). Bad polygons get status "error" and a reason; the run goes on.
    Rerunning the same command resumes an interrupted run.
    """
    # no bar when stderr is a file or pipe: it would only add blank lines to logs
    with progress_bar("polygons", not quiet and sys.stderr.isatty(), counts=True) as progress:
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
            )
        except BatchFailedError as exc:
            summary = exc.summary
            click.echo(f"optri: {summary}", err=True)
            sys.exit(1)
    if not quiet:
        click.echo(str(summary), err=True)
