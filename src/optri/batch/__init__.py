"""Batch triangulation: a file of polygons in, one record per polygon out, on all cores.

``batch(inp, out)`` streams polygons from GeoJSON, NDJSON, GeoParquet or
GeoPackage, solves them in chunks on a process pool or a Dask cluster, and
writes each chunk to its own part file atomically, so an interrupted run
resumes where it stopped. See :func:`batch` and ``docs/batch.md``.

Modules: :mod:`.readers` and :mod:`.geo` (input), :mod:`.records` (the
per-polygon record and the chunk function), :mod:`.writers` and
:mod:`.layout` (parts, manifest, single-file assembly), :mod:`.runner`
(pool / Dask backends), :mod:`.driver` (the ``batch`` function).
"""

from __future__ import annotations

from ..errors import BatchFailedError, BatchInputError
from .driver import BatchSummary, batch, iter_records
from .records import TIMING_FIELDS, strip_timing

__all__ = [
    "TIMING_FIELDS",
    "BatchFailedError",
    "BatchInputError",
    "BatchSummary",
    "batch",
    "iter_records",
    "strip_timing",
]
