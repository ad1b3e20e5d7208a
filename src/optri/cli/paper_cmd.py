"""``optri paper``: regenerate the paper's tables and figures into a folder."""

from __future__ import annotations

import json
import time

import click

from ..paper import PaperConfig, write_report
from .app import main
from .options import output_option
from .progress import compile_notice, progress_bar


@main.command()
@output_option(
    "dir", "Folder for report.md and the PNGs (created if missing).  [required]", legacy="--out"
)
@click.option("--quick", is_flag=True, help="A seconds-long run (small n, one repeat).")
@click.option("--no-figures", is_flag=True, help="Skip the PNGs.")
@click.option("--json", "as_json", is_flag=True, help="Print the report's path and time as JSON.")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def paper(output: str, quick: bool, no_figures: bool, as_json: bool, quiet: bool) -> None:
    """Reproduce Selimi et al. (2019): Tables 2-4, Figures 1-7, notes on the paper."""
    cfg = PaperConfig.quick() if quick else PaperConfig()
    cfg.figures = not no_figures
    start = time.perf_counter()
    with (
        compile_notice(not quiet),
        progress_bar("reproducing the paper", not quiet) as progress,
    ):
        path = write_report(output, cfg, progress)
    seconds = time.perf_counter() - start
    if as_json:
        click.echo(json.dumps({"report": str(path), "seconds": seconds}))
    else:
        click.echo(f"report written to {path} ({seconds:.1f} s)")


__all__ = ["paper"]
