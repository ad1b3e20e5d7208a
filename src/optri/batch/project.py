"""Measuring in metres: each polygon in its own local azimuthal equidistant projection.

``--project`` (``project=True``) takes every polygon of a layer from the
layer's CRS to geodetic longitude/latitude on the CRS's own ellipsoid, then to
an azimuthal equidistant projection centred on the polygon (the mean of its
vertices' longitudes and latitudes): x = s sin(a), y = s cos(a) for the
geodesic distance s and azimuth a from the centre (pyproj's ``Geod.inv``,
Karney's algorithm), which is what PROJ's ellipsoidal ``+proj=aeqd`` computes.
Distances from the centre are exact and others are within a few parts per
million over a polygon tens of kilometres across, so perimeters and areas come
out in metres. Triangles are returned as vertex indices, so they stay in the
input coordinates.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import BatchInputError, InvalidPolygonError

__all__ = ["local_centre", "local_projector"]

Projector = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@functools.lru_cache(maxsize=16)
def parsed_crs(crs: str) -> Any:
    """``pyproj.CRS`` of the text ``crs``, parsed once per process; None without pyproj.

    Raises ``pyproj.exceptions.CRSError`` for text pyproj does not accept (not
    cached: each call raises again).
    """
    try:
        import pyproj
    except ImportError:
        return None
    return pyproj.CRS.from_user_input(crs)


@functools.lru_cache(maxsize=8)
def local_projector(crs: str) -> Projector:
    """A function taking one polygon's ``(n, 2+)`` coordinates in ``crs`` to metres.

    Raises
    ------
    BatchInputError
        ``crs`` is not a CRS pyproj knows, or has no ellipsoid.

    Examples
    --------
    >>> to_m = local_projector("EPSG:4326")
    >>> xy = to_m(np.array([[0.0, 0.0], [0.001, 0.0], [0.0, 0.001]]))
    >>> round(float(np.hypot(*(xy[1] - xy[0]))), 1)   # 0.001 degree of longitude
    111.3
    """
    pyproj = import_optional("pyproj")
    try:
        source = parsed_crs(crs)
        geodetic = source.geodetic_crs
        geod = source.get_geod()
    except pyproj.exceptions.CRSError as exc:
        raise BatchInputError(f"cannot project from CRS {crs!r}: {exc}") from None
    if geodetic is None or geod is None:
        raise BatchInputError(f"cannot project from CRS {source.name!r}: it has no ellipsoid")
    to_lonlat = pyproj.Transformer.from_crs(source, geodetic, always_xy=True)

    def project(coords: NDArray[np.float64]) -> NDArray[np.float64]:
        lon, lat = to_lonlat.transform(coords[:, 0], coords[:, 1], errcheck=False)
        lon, lat = np.asarray(lon, np.float64), np.asarray(lat, np.float64)
        if not (np.isfinite(lon).all() and np.isfinite(lat).all()):
            raise InvalidPolygonError(
                f"a vertex cannot be placed on the ellipsoid of {source.name!r} "
                "(outside the CRS's area, or not finite)"
            )
        lon0, lat0 = local_centre(lon, lat)
        az, _, dist = geod.inv(np.full_like(lon, lon0), np.full_like(lat, lat0), lon, lat)
        az = np.radians(np.asarray(az, np.float64))
        dist = np.asarray(dist, np.float64)
        return np.column_stack((dist * np.sin(az), dist * np.cos(az)))

    return project


def local_centre(lon: NDArray[np.float64], lat: NDArray[np.float64]) -> tuple[float, float]:
    """Mean longitude and latitude of a polygon.

    Longitudes are unwrapped around the first vertex, so the antimeridian is harmless.

    >>> local_centre(np.array([179.0, -179.0]), np.array([10.0, 12.0]))
    (180.0, 11.0)
    """
    unwrapped = lon[0] + (lon - lon[0] + 180.0) % 360.0 - 180.0
    return float(np.mean(unwrapped)), float(np.mean(lat))
