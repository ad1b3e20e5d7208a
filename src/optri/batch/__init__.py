"""Batch triangulation: whole GIS layers in and out, and many polygons in memory.

``batch(inp, out)`` streams the features of a GeoJSON, NDJSON, GeoParquet,
GeoPackage, FlatGeobuf or shapefile layer, solves them in chunks on a process
pool or a Dask cluster, and writes one row per feature (its attributes and
CRS kept, ``status``, ``cost``, ``reason`` and the triangles added) through
part files that resume; :func:`triangulate_many` does the same for polygons
already in memory (a GeoSeries, a GeoDataFrame, arrays). See
``docs/batch.md``.

Modules: :mod:`.readers`, :mod:`.jsonstream` and :mod:`.geo` (input),
:mod:`.layer` (CRS, attribute columns), :mod:`.solver` (the per-chunk solver
seam), :mod:`.project` (metres from longitude/latitude), :mod:`.records` (the
per-polygon record and the chunk function), :mod:`.writers`,
:mod:`.tables`, :mod:`.tablefiles` and :mod:`.layout` (parts, manifest, lock,
single-file assembly), :mod:`.runner` (pool / Dask backends),
:mod:`.summary`, :mod:`.driver` (the ``batch`` function), :mod:`.many`
(``triangulate_many``), :mod:`.daskframe` (``triangulate_many`` on a dask
GeoDataFrame) and :mod:`.dasklayer` (``dask_layer``: Dask workers read, solve
and write GeoParquet parts).
"""

from __future__ import annotations

from ..errors import (
    BatchFailedError,
    BatchInputError,
    BatchLockedError,
    DuplicateIdWarning,
    GeographicCRSWarning,
)
from .dasklayer import dask_layer
from .driver import batch, iter_records
from .many import triangulate_many
from .records import TIMING_FIELDS, strip_timing
from .summary import BatchSummary

__all__ = [
    "TIMING_FIELDS",
    "BatchFailedError",
    "BatchInputError",
    "BatchLockedError",
    "BatchSummary",
    "DuplicateIdWarning",
    "GeographicCRSWarning",
    "batch",
    "dask_layer",
    "iter_records",
    "strip_timing",
    "triangulate_many",
]
