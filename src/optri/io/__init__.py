"""Input and output: polygon files, GeoJSON/WKT/shapely, mesh files, contours, atomic writes.

Nothing here runs an algorithm: readers turn files and geometry objects into
vertex arrays, writers put results on disk atomically.
"""

from __future__ import annotations

from .atomic import atomic_write, write_json
from .contours import read_contours, rtstruct_rois
from .files import read_polygon, read_rings
from .geo import (
    geo_polygon_coords,
    geo_polygon_rings,
    polygon_from_geojson,
    polygon_from_wkt,
    rings_from_geojson,
    rings_from_wkt,
    to_shapely,
)
from .meshes import MESH_FORMATS, read_mesh, write_mesh

__all__ = [
    "MESH_FORMATS",
    "atomic_write",
    "geo_polygon_coords",
    "geo_polygon_rings",
    "polygon_from_geojson",
    "polygon_from_wkt",
    "read_mesh",
    "read_contours",
    "read_polygon",
    "read_rings",
    "rings_from_geojson",
    "rings_from_wkt",
    "rtstruct_rois",
    "to_shapely",
    "write_json",
    "write_mesh",
]
