"""``optri bench``: the compiled engine against its C and pure-Python yardsticks."""

from __future__ import annotations

import json

import click

from ..bench import run_benchmark
from .app import main

__all__ = ["bench"]


@main.command()
@click.argument("sizes", nargs=-1, type=click.IntRange(min=3))
@click.option("--quick", is_flag=True, help="Small sizes only (100 200 500).")
@click.option(
    "--naive-max",
    default=500,
    type=click.IntRange(min=0),
    show_default=True,
    help="Largest n for the plain-Python recursion.",
)
@click.option(
    "--repeats",
    default=3,
    type=click.IntRange(min=1),
    show_default=True,
    help="At least this many timed solves in one process, after the warm-up (the best counts).",
)
@click.option(
    "--warmup",
    default=0.25,
    type=click.FloatRange(min=0),
    show_default=True,
    help=(
        "Seconds of untimed solves before each window of timed ones (at least one; 0: none), "
        "which pay for fresh memory."
    ),
)
@click.option("--float32", is_flag=True, help="float32 table.")
@click.option("--json", "as_json", is_flag=True, help="Print the rows as JSON.")
@click.option(
    "--shared",
    type=click.Path(exists=True, file_okay=False),
    help="Also build and run DIR/ref_mwt.c and DIR/minplus_peak.c (a cross-check).",
)
@click.option(
    "--peak-seconds",
    default=1.0,
    type=click.FloatRange(min=0, min_open=True),
    show_default=True,
    help="Seconds each peak kernel runs per size, spread over the rounds.",
)
@click.option(
    "--rounds",
    default=3,
    type=click.IntRange(min=1),
    show_default=True,
    help="Rounds per size: a peak run, then a window of solves as long as one kernel's run.",
)
def bench(
    sizes: tuple[int, ...],
    quick: bool,
    naive_max: int,
    repeats: int,
    warmup: float,
    float32: bool,
    as_json: bool,
    shared: str | None,
    peak_seconds: float,
    rounds: int,
) -> None:
    """Time method='fast', the C reference and the Python recursion on the same polygons.

    SIZES default to 500 1000 2000 4000. The C yardsticks ship with optri and are
    built with gcc (or cc) at run time; without a compiler their columns stay empty.
    "of peak" is (n^3/6 / optri's best seconds) / the best min-plus peak rate, the two
    measured alternately over the same seconds: --rounds peak runs, each followed by a
    window of solves as long as each of its kernels ran. "calls" counts the timed solves;
    "xfer" is the GB/s at which one CPU read what another had just written, right after
    the window of the best solve: where it is well below the run's best, a note says the
    row was measured while the machine was slow to pass data between CPUs, which slows
    optri's threads and not the peak's.
    """
    chosen = sizes or ((100, 200, 500) if quick else (500, 1000, 2000, 4000))
    rows = run_benchmark(
        chosen,
        naive_max=naive_max,
        repeats=repeats,
        warmup=warmup,
        dtype="float32" if float32 else "float64",
        log=click.echo if not as_json else lambda line: click.echo(line, err=True),
        shared=shared,
        peak_seconds=peak_seconds,
        rounds=rounds,
    )
    if as_json:
        click.echo(json.dumps([r.to_dict() for r in rows]))
