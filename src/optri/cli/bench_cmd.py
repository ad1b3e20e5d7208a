"""``optri bench``: the compiled engine against the C and pure-Python yardsticks."""

from __future__ import annotations

import json

import click

from ..bench import run_benchmark
from .app import main

__all__ = ["bench"]


@main.command()
@click.argument("sizes", nargs=-1, type=int)
@click.option("--quick", is_flag=True, help="Small sizes only (100 200 500).")
@click.option("--naive-max", default=500, show_default=True, help="Largest n for naive_memo.py.")
@click.option("--repeats", default=3, show_default=True, help="Best of this many runs (n <= 2000).")
@click.option("--float32", is_flag=True, help="float32 table.")
@click.option("--json", "as_json", is_flag=True, help="Print the rows as JSON.")
def bench(
    sizes: tuple[int, ...], quick: bool, naive_max: int, repeats: int, float32: bool, as_json: bool
) -> None:
    """Time method='fast', ref_mwt.c and naive_memo.py on the same polygons.

    SIZES default to 500 1000 2000 4000. The yardsticks are looked up in
    $OPTRI_BENCH_DIR, then ../shared/bench beside the repository.
    """
    chosen = sizes or ((100, 200, 500) if quick else (500, 1000, 2000, 4000))
    rows = run_benchmark(
        chosen,
        naive_max=naive_max,
        repeats=repeats,
        dtype="float32" if float32 else "float64",
        log=None if as_json else click.echo,
    )
    if as_json:
        click.echo(json.dumps([r.to_dict() for r in rows]))
