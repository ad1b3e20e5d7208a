"""Benchmarks of the compiled engine against its own yardsticks, for ``optri bench``.

The yardsticks ship with the package: a C reference of the O(n³) programme and a
min-plus peak microbenchmark (``yardsticks/*.c``, built with the system's C
compiler at run time) and the plain-Python recursion (:mod:`optri.bench.naive`).
"""

from __future__ import annotations

from .compare import BenchRow, convex_polygon, format_rows, run_benchmark

__all__ = ["BenchRow", "convex_polygon", "format_rows", "run_benchmark"]
