"""``optri paper``: regenerate the paper's tables and figures into a folder."""

from __future__ import annotations

import time

import click

from ..paper import PaperConfig, write_report
from .app import main
from .progress import progress_bar


@main.command()
@click.option(
    "--out",
    "out",
    required=True,
    type=click.Path(file_okay=False),
    help="Folder for report.md and the PNGs (created if missing).",
)
@click.option("--quick", is_flag=True, help="A seconds-long run (small n, one repeat).")
@click.option("--no-figures", is_flag=True, help="Skip the PNGs.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def paper(out: str, quick: bool, no_figures: bool, quiet: bool) -> None:
    """Reproduce Selimi et al. (2019): Tables 2-4, Figures 1-7, notes on the paper."""
    cfg = PaperConfig.quick() if quick else PaperConfig()
    cfg.figures = not no_figures
    start = time.perf_counter()
    with progress_bar("reproducing the paper", not quiet) as progress:
        path = write_report(out, cfg, progress)
    click.echo(f"report written to {path} ({time.perf_counter() - start:.1f} s)")


__all__ = ["paper"]
