"""``triangulate_many``: many polygons in memory, one result per polygon, bad rows as errors.

geopandas input takes the columnar path (:mod:`optri.batch.columns`): the
geometry column as ragged arrays, one compiled call per chunk, triangles back as
arrays and then as shapely geometry built in a few vectorised calls. Other input
(vertex arrays, ring pairs, shapely objects in a list) goes through
:func:`optri.batch.solver.solve_polygons` and returns Triangulations.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._optional import import_optional
from ..errors import BatchInputError
from .columns import Ragged, Solved, ragged_from_shapely, solve_ragged, triangle_geometries
from .daskframe import triangulate_dask
from .layer import renamed_columns, warn_geographic, warn_renamed
from .solver import SolveOptions, check_options, solve_polygons

__all__ = ["triangulate_many", "with_error_rows"]

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
    explode: bool = False,
) -> Any:
    """Optimal triangulations of many polygons at once, bad rows as error rows.

    Parameters
    ----------
    geoms : GeoSeries, GeoDataFrame, dask GeoDataFrame, sequence or array
        A geopandas GeoSeries or GeoDataFrame (its active geometry column: Polygons
        and MultiPolygons, with or without Z, holes allowed), a
        ``dask_geopandas.GeoDataFrame`` (the result is then a lazy dask
        GeoDataFrame, see :func:`optri.batch.daskframe.triangulate_dask`), a
        sequence or numpy array of shapely Polygons, or a list of ``(n, 2)`` (or
        ``(n, 3)``) vertex arrays or ``(exterior, [holes])`` pairs.
    weight, objective, method
        As for :func:`optri.triangulate`; checked before any polygon is solved.
    project : bool
        Measure each polygon in metres in a local azimuthal equidistant
        projection (see :mod:`optri.batch.project`); needs the input's CRS.
    crs : optional
        The CRS of a plain sequence (anything pyproj reads); geopandas input
        carries its own.
    explode : bool
        geopandas input only: one output row per triangle (a Polygon), with its
        source row's index, attributes, status, cost and reason; an error row stays
        one row with no geometry.

    Returns
    -------
    GeoDataFrame or list
        For geopandas input a GeoDataFrame with the input's index, CRS and (for
        a GeoDataFrame) attribute columns, plus ``status`` ("ok" or "error"),
        ``cost`` (NaN for an error; a tuple for a lexicographic objective) and
        ``reason`` (the error, or the warnings of an ok row), and as geometry
        the triangles as a valid GeometryCollection of Polygons per row, in the
        input coordinates with Z where the row has it (None for an error row).
        A MultiPolygon's parts are solved one by one: one row, its cost the
        objective's combination of theirs (see :mod:`optri.batch.columns`).
        For other input a list with, per polygon, a
        :class:`~optri.result.Triangulation` or the
        :class:`~optri.errors.OptriError` saying why there is none.

    Raises
    ------
    WeightError, EngineUnavailableError
        Unknown weight, objective or method.
    BatchInputError
        ``project=True`` without a CRS, or ``explode=True`` for input that is not
        geopandas.

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
        solve = functools.partial(triangulate_many, explode=True) if explode else triangulate_many
        return triangulate_dask(geoms, solve, chosen, project)
    options = SolveOptions(**check_options(weight, objective, method))
    frame, series = _geopandas_parts(geoms)
    if series is not None:
        crs = series.crs
    elif explode:
        raise BatchInputError("explode=True needs a GeoSeries or GeoDataFrame")
    crs_text = _crs_text(crs)
    if project and crs_text is None:
        raise BatchInputError("project=True needs a CRS: pass crs=, or a GeoSeries with one")
    warn_geographic(crs_text, project)
    if project:
        options = SolveOptions(options.weight, options.objective, options.method, crs_text)
    if series is None:
        polygons: Sequence[Any] = list(geoms)
        return solve_polygons(polygons, options)
    ragged = ragged_from_shapely(series.values)
    return _as_frame(frame, series, ragged, solve_ragged(ragged, options), explode)


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


def _as_frame(frame: Any, series: Any, ragged: Ragged, solved: Solved, explode: bool) -> Any:
    gpd = import_optional("geopandas")
    geoms, src = triangle_geometries(ragged, solved, explode)
    if explode:
        geoms, src = with_error_rows(geoms, src, solved)
    index = series.index.take(src) if explode else series.index
    status = np.where(solved.ok, "ok", "error").astype(object)
    if solved.cost.ndim == 1:
        cost: Any = solved.cost
    else:  # lexicographic: a tuple per row, as Triangulation.weight
        cost = np.empty(len(solved), dtype=object)
        cost[:] = [solved.cost_of(i) for i in range(len(solved))]
    columns = {"status": status[src], "cost": cost[src], "reason": solved.reason[src]}
    geometry = gpd.GeoSeries(geoms, index=index, crs=series.crs)
    if frame is None:
        return gpd.GeoDataFrame(columns, geometry=geometry, index=index)
    out = frame.take(src) if explode else frame.copy()
    renames = renamed_columns([str(c) for c in out.columns], MANY_COLUMNS)
    warn_renamed(renames)
    out = out.rename(columns=renames)
    out[frame.geometry.name] = geometry
    for name, values in columns.items():
        out[name] = values
    return out


def with_error_rows(geoms: Any, src: Any, solved: Solved) -> tuple[Any, Any]:
    """Exploded triangles plus one empty row per error row, in row order."""
    bad = np.flatnonzero(~solved.ok)
    if not len(bad):
        return geoms, src
    rows = np.concatenate([src, bad])
    order = np.argsort(rows, kind="stable")
    return np.concatenate([geoms, np.full(len(bad), None, dtype=object)])[order], rows[order]
