"""Options shared by the commands that solve polygons (``solve``, ``batch``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from ..domains import METHODS as DOMAIN_METHODS
from ..engines import ENGINES
from ..weights import WEIGHTS

__all__ = ["engine_options", "parse_pair"]


def parse_pair(value: str) -> str | tuple[str, ...]:
    """``"max,sum"`` -> ``("max", "sum")``; a single name stays a string."""
    parts = tuple(p.strip() for p in value.split(","))
    return parts if len(parts) > 1 else parts[0]


def engine_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """Add ``--weight``, ``--objective`` and ``--method`` to a command."""
    decorators = [
        click.option(
            "--weight",
            "-w",
            default="perimeter",
            show_default=True,
            help=f"Triangle weight ({', '.join(sorted(WEIGHTS))}); 'a,b' for a lexicographic pair.",
        ),
        click.option(
            "--objective",  # no short flag: -o means the output file elsewhere
            default="sum",
            show_default=True,
            help="sum, max, or a lexicographic pair such as max,sum.",
        ),
        click.option(
            "--method",
            "-m",
            default="auto",
            show_default=True,
            type=click.Choice(["auto", *ENGINES, *(m for m in DOMAIN_METHODS if m != "auto")]),
            help="Engine (a polygon with holes: auto, ip or bridge).",
        ),
    ]
    for decorate in reversed(decorators):
        func = decorate(func)
    return func
