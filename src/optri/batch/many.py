"""``triangulate_many``: many polygons in memory, one result per polygon, bad rows as errors."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .._optional import import_optional
from ..errors import BatchInputError
from ..result import Triangulation
from .daskframe import triangulate_dask
from .layer import renamed_columns, warn_geographic, warn_renamed
from .records import one_line
from .solver import Result, SolveOptions, check_options, solve_polygons

__all__ = ["triangulate_many"]

#: Columns triangulate_many adds to a GeoDataFrame.
MANY_COLUMNS = ("status", "cost", "reason")


def triangulate_many(
    geoms: Any,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    *,
    project: bool = False,
    crs: Any = None,
) -> Any:
    """Optimal triangulations of many polygons at once, bad rows as error rows.

    Parameters
    ----------
    geoms : GeoSeries, GeoDataFrame, dask GeoDataFrame, sequence or array
        A geopandas GeoSeries or GeoDataFrame (its active geometry column), a
        ``dask_geopandas.GeoDataFrame`` (the result is then a lazy dask
        GeoDataFrame, see :func:`optri.batch.daskframe.triangulate_dask`), a
        sequence or numpy array of shapely Polygons, or a list of ``(n, 2)``
        (or ``(n, 3)``) vertex arrays.
    weight, objective, method
        As for :func:`optri.triangulate`; checked before any polygon is solved.
    project : bool
        Measure each polygon in metres in a local azimuthal equidistant
        projection (see :mod:`optri.batch.project`); needs the input's CRS.
    crs : optional
        The CRS of a plain sequence (anything pyproj reads); geopandas input
        carries its own.

    Returns
    -------
    GeoDataFrame or list
        For geopandas input a GeoDataFrame with the input's index, CRS and (for
        a GeoDataFrame) attribute columns, plus ``status`` ("ok" or "error"),
        ``cost`` and ``reason`` (the error, or the warnings of an ok row), and
        the triangles as a MultiPolygon geometry in the input coordinates
        (None for an error row). For other input a list with, per polygon, a
        :class:`~optri.result.Triangulation` or the
        :class:`~optri.errors.OptriError` saying why there is none.

    Raises
    ------
    WeightError, EngineUnavailableError
        Unknown weight, objective or method.
    BatchInputError
        ``project=True`` without a CRS.

    Warns
    -----
    GeographicCRSWarning
        The CRS is longitude/latitude and ``project`` is false.

    See Also
    --------
    optri.triangulate : one polygon; ``gdf.geometry.apply(optri.triangulate)``
        gives a Series of Triangulations but stops at the first bad row.
    optri.batch : the same for files too large for memory.

    Examples
    --------
    >>> import optri
    >>> out = optri.triangulate_many([[[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 0], [1, 1]]])
    >>> round(out[0].weight, 6), out[0].triangles.tolist()
    (6.828427, [[0, 1, 3], [1, 2, 3]])
    >>> type(out[1]).__name__, str(out[1])
    ('InvalidPolygonError', 'a polygon needs at least 3 vertices, got 2')
    """
    if type(geoms).__module__.startswith("dask_geopandas"):  # lazy, partition by partition
        chosen = dict(weight=weight, objective=objective, method=method)
        return triangulate_dask(geoms, triangulate_many, chosen, project)
    options = SolveOptions(**check_options(weight, objective, method))
    frame, series = _geopandas_parts(geoms)
    if series is not None:
        crs = series.crs
        polygons: Sequence[Any] = list(series.array)
    else:
        polygons = list(geoms)
    crs_text = _crs_text(crs)
    if project and crs_text is None:
        raise BatchInputError("project=True needs a CRS: pass crs=, or a GeoSeries with one")
    warn_geographic(crs_text, project)
    if project:
        options = SolveOptions(options.weight, options.objective, options.method, crs_text)
    results = solve_polygons(polygons, options)
    if series is None:
        return results
    return _as_frame(frame, series, results)


def _geopandas_parts(geoms: Any) -> tuple[Any, Any]:
    """``(GeoDataFrame or None, GeoSeries or None)`` without importing geopandas needlessly."""
    module = type(geoms).__module__
    if not module.startswith("geopandas"):
        return None, None
    gpd = import_optional("geopandas")
    if isinstance(geoms, gpd.GeoDataFrame):
        return geoms, geoms.geometry
    if isinstance(geoms, gpd.GeoSeries):
        return None, geoms
    return None, None


def _crs_text(crs: Any) -> str | None:
    if crs is None:
        return None
    if isinstance(crs, str):
        return crs
    to_wkt = getattr(crs, "to_wkt", None)  # a pyproj CRS
    if to_wkt is not None:
        return str(to_wkt())
    pyproj = import_optional("pyproj")
    return str(pyproj.CRS.from_user_input(crs).to_wkt())


def _as_frame(frame: Any, series: Any, results: list[Result]) -> Any:
    gpd = import_optional("geopandas")
    geometry = gpd.GeoSeries(
        [_multipolygon(r) for r in results], index=series.index, crs=series.crs
    )
    columns = {
        "status": ["ok" if isinstance(r, Triangulation) else "error" for r in results],
        "cost": [r.weight if isinstance(r, Triangulation) else None for r in results],
        "reason": [_reason(r) for r in results],
    }
    if frame is None:
        return gpd.GeoDataFrame(columns, geometry=geometry, index=series.index)
    out = frame.copy()
    renames = renamed_columns([str(c) for c in out.columns], MANY_COLUMNS)
    warn_renamed(renames)
    out = out.rename(columns=renames)
    out[frame.geometry.name] = geometry
    for name, values in columns.items():
        out[name] = values
    return out


def _reason(result: Result) -> str | None:
    if not isinstance(result, Triangulation):
        return one_line(str(result))
    notes = result.stats.get("warnings")
    return one_line("warning: " + "; ".join(notes)) if notes else None  # type: ignore[arg-type]


def _multipolygon(result: Result) -> Any:
    if not isinstance(result, Triangulation):
        return None
    shapely = import_optional("shapely")
    rings = np.asarray(result.vertices, dtype=np.float64)[result.triangles]
    closed = np.concatenate([rings, rings[:, :1]], axis=1)
    return shapely.multipolygons(shapely.polygons(closed))
