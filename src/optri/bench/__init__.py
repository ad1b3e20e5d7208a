"""Benchmarks of the compiled engine against yardsticks, for ``optri bench``."""

from __future__ import annotations

from .compare import BenchRow, find_yardsticks, format_rows, run_benchmark

__all__ = ["BenchRow", "find_yardsticks", "format_rows", "run_benchmark"]
