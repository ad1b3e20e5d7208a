"""Command-line interface: ``optri COMMAND ...`` (also ``python -m optri``).

The only place that prints or exits; it parses options, calls the library and
prints. Each command lives in its own module and registers itself on
:data:`main` (:mod:`optri.cli.app`).
"""

from __future__ import annotations

from . import (
    batch_cmd,
    bench_cmd,
    contours_cmd,
    data_cmd,
    enumerate_cmd,
    explore_cmd,
    fill_cmd,
    paper_cmd,
    solve_cmd,
)
from .app import main

__all__ = ["main"]

# importing a command module registers its commands on main
del batch_cmd, bench_cmd, contours_cmd
del data_cmd, enumerate_cmd, explore_cmd, fill_cmd, paper_cmd, solve_cmd
