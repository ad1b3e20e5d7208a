"""``triangulate_many`` on a dask GeoDataFrame: lazy, one call per partition, a typed ``meta``.

:func:`triangulate_dask` maps a solve function (``triangulate_many``, passed in
so this module stays below :mod:`.many`) over the partitions. Its ``meta`` has the
result's columns and dtypes: ``status`` and ``reason`` text, ``cost`` a float (an
object column of sequences for lexicographic objectives); every partition is
cast to them, so a partition of only error rows has the same schema as the others.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .._optional import import_optional
from ..solve import triangulate
from .layer import GEOGRAPHIC_WARNED, warn_geographic
from .solver import check_options

__all__ = ["cost_dtype", "triangulate_dask"]

_RESULT_COLUMNS = ("status", "cost", "reason")


def triangulate_dask(
    ddf: Any,
    solve: Callable[..., Any],
    options: dict[str, Any],
    project: bool = False,
) -> Any:
    """``solve`` (``triangulate_many``) of every partition of a dask GeoDataFrame, lazily.

    Parameters
    ----------
    ddf : dask_geopandas.GeoDataFrame
        The polygons (its active geometry column), with attributes and CRS.
    solve : callable
        ``solve(gdf, weight=, objective=, method=, project=)`` for one partition:
        :func:`optri.triangulate_many` (a module-level function: workers unpickle it).
    options : dict
        ``weight``, ``objective`` and ``method`` as for :func:`optri.triangulate_many`;
        checked now, before any task runs.
    project : bool
        As for :func:`optri.triangulate_many`.

    Returns
    -------
    dask_geopandas.GeoDataFrame
        Lazy: the input's columns and CRS plus ``status``, ``cost`` and ``reason``,
        one row per input row, partition for partition.

    Warns
    -----
    GeographicCRSWarning
        The CRS is longitude/latitude and ``project`` is false (once, here, not
        once per partition).

    Examples
    --------
    >>> import dask_geopandas, geopandas, optri, shapely
    >>> gdf = geopandas.GeoDataFrame(
    ...     {"name": ["a", "b"]},
    ...     geometry=[shapely.box(0, 0, 1, 1), shapely.box(0, 0, 2, 1)], crs=32633)
    >>> lazy = optri.triangulate_many(dask_geopandas.from_geopandas(gdf, npartitions=2))
    >>> out = lazy.compute(scheduler="sync")
    >>> out["status"].tolist(), out["cost"].round(6).tolist(), out.crs.to_epsg()
    (['ok', 'ok'], [6.828427, 10.472136], 32633)
    """
    options = check_options(**options)
    meta = _result_meta(ddf._meta, solve, options, project)
    warn_geographic(_crs_wkt(ddf.crs), project)
    return ddf.map_partitions(_solve_partition, solve, options, project, meta, meta=meta)


def _result_meta(empty: Any, solve: Callable[..., Any], options: dict, project: bool) -> Any:
    """The empty frame a partition's result looks like, with the dtypes every partition gets."""
    pd = import_optional("pandas", "geo")
    meta = _quietly(solve, empty, options, project)
    text = pd.Series(["ok"]).dtype  # object, or pandas' own string dtype
    dtypes = {"status": text, "reason": text, "cost": cost_dtype(options)}
    return _with_dtypes(meta, dtypes)


def _with_dtypes(frame: Any, dtypes: dict[str, Any]) -> Any:
    """``frame`` with those columns cast, one by one.

    (``DataFrame.astype`` compares the frames' ``attrs``, which Dask's readers may
    fill with arrays, and fails.)
    """
    for column, dtype in dtypes.items():
        frame[column] = frame[column].astype(dtype)
    return frame


def cost_dtype(options: dict[str, Any]) -> str:
    """float64 for one objective, object for a lexicographic one (a list per row)."""
    try:
        cost = triangulate([[0, 0], [1, 0], [0, 1]], **options).weight
    except Exception:  # a weight that fails on every polygon gives error rows: no cost
        return "float64"
    return "object" if isinstance(cost, (tuple, list)) else "float64"


def _solve_partition(
    part: Any, solve: Callable[..., Any], options: dict, project: bool, meta: Any
) -> Any:
    """One partition through ``solve``, its columns and dtypes made those of ``meta``."""
    out = _quietly(solve, part, options, project)
    return _with_dtypes(out[list(meta.columns)], {c: meta[c].dtype for c in _RESULT_COLUMNS})


def _quietly(solve: Callable[..., Any], frame: Any, options: dict, project: bool) -> Any:
    """``solve`` without the geographic-CRS warning, said once for the whole frame.

    Dask may run partitions on threads: a context variable, not a warnings filter.
    """
    token = GEOGRAPHIC_WARNED.set(True)
    try:
        return solve(frame, **options, project=project)
    finally:
        GEOGRAPHIC_WARNED.reset(token)


def _crs_wkt(crs: Any) -> str | None:
    return None if crs is None else str(crs.to_wkt())
