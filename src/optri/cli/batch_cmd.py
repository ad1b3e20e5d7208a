"""``optri batch IN -o OUT``: triangulate every polygon of a file on all cores."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator

import click

from ..batch import BatchFailedError, batch
from ..batch.readers import INPUT_FORMATS
from ..batch.writers import OUTPUT_FORMATS
from ..engines.problem import ProgressFn
from . import main
from .options import engine_options, parse_pair

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
    with _batch_progress(not quiet and sys.stderr.isatty()) as progress:
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


@contextlib.contextmanager
def _batch_progress(enabled: bool) -> Iterator[ProgressFn | None]:
    """A rich bar on stderr: polygons done / total, polygons per second, ETA."""
    if not enabled:
        yield None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TaskProgressColumn(),
        TextColumn("{task.fields[rate]}"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task("polygons", total=None, rate="")

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)
            speed = bar.tasks[0].speed
            bar.update(task, rate=f"{speed:,.0f}/s" if speed else "")

        yield update
