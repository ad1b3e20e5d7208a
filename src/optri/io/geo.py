"""Geometry interop: shapely polygons in, shapely triangles out, GeoJSON and WKT text.

The ``*_rings`` readers return every ring of a polygon, exterior first, then
its holes (closing vertices dropped), as :func:`optri.triangulate` takes them.
The one-ring readers (``polygon_from_*``, :func:`geo_polygon_coords`) return
the exterior of a polygon without holes and refuse one with holes, naming the
ring reader: a hole is never dropped silently. shapely is imported lazily
(extra ``optri[shapely]``); GeoJSON and WKT polygons are parsed without it.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from ..errors import InvalidPolygonError

if TYPE_CHECKING:  # pragma: no cover
    from ..result import Triangulation

__all__ = [
    "geo_polygon_coords",
    "geo_polygon_rings",
    "polygon_from_geojson",
    "polygon_from_wkt",
    "rings_from_geojson",
    "rings_from_wkt",
    "to_shapely",
]

Rings = list[NDArray[np.float64]]

_HOLES = (
    "the polygon has {k} hole(s) and this reader returns one ring; read every ring with "
    "{reader}, or give the polygon to optri.triangulate, which triangulates polygons with "
    "holes"
)


def _one_ring(rings: Rings, reader: str) -> NDArray[np.float64]:
    if len(rings) > 1:
        raise InvalidPolygonError(_HOLES.format(k=len(rings) - 1, reader=reader))
    return rings[0]


def geo_polygon_coords(obj: Any) -> NDArray[np.float64]:
    """Exterior ring of an object with ``__geo_interface__`` (e.g. ``shapely.Polygon``).

    The closing vertex is dropped; triangle indices refer to the ring's vertices.

    Raises
    ------
    InvalidPolygonError
        Not a single polygon, or a polygon with holes (see :func:`geo_polygon_rings`).

    Examples
    --------
    >>> class P:
    ...     ring = [(0, 0), (1, 0), (0, 1), (0, 0)]
    ...     __geo_interface__ = {"type": "Polygon", "coordinates": [ring]}
    >>> geo_polygon_coords(P()).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    """
    return _one_ring(geo_polygon_rings(obj), "geo_polygon_rings")


def geo_polygon_rings(obj: Any) -> Rings:
    """Every ring of an object with ``__geo_interface__``: exterior first, then the holes.

    >>> class P:
    ...     __geo_interface__ = {"type": "Polygon", "coordinates": [
    ...         [(0, 0), (4, 0), (0, 4), (0, 0)], [(1, 1), (2, 1), (1, 2), (1, 1)]]}
    >>> [r.shape for r in geo_polygon_rings(P())]
    [(3, 2), (3, 2)]
    """
    return rings_from_geojson(obj.__geo_interface__)


def polygon_from_geojson(data: Any) -> NDArray[np.float64]:
    """Exterior ring of a GeoJSON Polygon, Feature or FeatureCollection of one polygon.

    A MultiPolygon or collection must hold exactly one polygon; a polygon with
    holes is refused (see :func:`rings_from_geojson`).
    """
    return _one_ring(rings_from_geojson(data), "rings_from_geojson")


def rings_from_geojson(data: Any) -> Rings:
    """Every ring of a GeoJSON Polygon (Feature, collection of one): exterior, then holes."""
    if not isinstance(data, dict):
        raise InvalidPolygonError("expected a GeoJSON object")
    kind = data.get("type")
    if kind == "Feature":
        return rings_from_geojson(data.get("geometry"))
    if kind in ("FeatureCollection", "GeometryCollection"):
        items = data.get("features") if kind == "FeatureCollection" else data.get("geometries")
        if not isinstance(items, list) or len(items) != 1:
            count = len(items) if isinstance(items, list) else 0
            raise InvalidPolygonError(f"expected a {kind} of one polygon, got {count} items")
        return rings_from_geojson(items[0])
    if kind == "MultiPolygon":
        polys = data.get("coordinates") or []
        if not isinstance(polys, list) or len(polys) != 1:
            count = len(polys) if isinstance(polys, list) else 0
            raise InvalidPolygonError(f"expected one polygon, got a MultiPolygon of {count}")
        return _rings(polys[0])
    if kind == "Polygon":
        return _rings(data.get("coordinates") or [])
    raise InvalidPolygonError(f"expected a GeoJSON Polygon, got type {kind!r}")


_WKT_HEAD = re.compile(r"^\s*(MULTI)?POLYGON\s*(Z|M|ZM)?\s*\(", re.IGNORECASE)


def polygon_from_wkt(text: str) -> NDArray[np.float64]:
    """Exterior ring of a WKT ``POLYGON`` (or a ``MULTIPOLYGON`` of one polygon).

    A polygon with holes is refused (see :func:`rings_from_wkt`).

    >>> polygon_from_wkt("POLYGON ((0 0, 2 0, 1 1, 0 0))").tolist()
    [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]]
    """
    return _one_ring(rings_from_wkt(text), "rings_from_wkt")


def rings_from_wkt(text: str) -> Rings:
    """Every ring of a WKT ``POLYGON`` (or ``MULTIPOLYGON`` of one): exterior, then holes.

    >>> [r.tolist() for r in rings_from_wkt("POLYGON ((0 0, 9 0, 0 9, 0 0), (1 1, 2 1, 1 2))")]
    [[[0.0, 0.0], [9.0, 0.0], [0.0, 9.0]], [[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]]]
    """
    head = _WKT_HEAD.match(text)
    if head is None:
        raise InvalidPolygonError(f"expected WKT POLYGON, got {text.strip()[:40]!r}")
    body = text[head.end() - 1 :].strip()
    if head.group(1):  # MULTIPOLYGON (((...)), ...): one polygon only
        polys = _split_groups(body[1:-1])
        if len(polys) != 1:
            raise InvalidPolygonError(f"expected one polygon, got a MULTIPOLYGON of {len(polys)}")
        body = polys[0]
    try:
        rings = [
            [[float(v) for v in pt.split()] for pt in ring.strip("() ").split(",")]
            for ring in _split_groups(body.strip()[1:-1])
        ]
    except ValueError as exc:
        raise InvalidPolygonError(f"WKT coordinates are not numbers: {exc}") from exc
    return _rings(rings)


def to_shapely(tri: Triangulation) -> Any:
    """The triangles of ``tri`` as a ``shapely.GeometryCollection`` of Polygons.

    The same shape shapely's own ``constrained_delaunay_triangles`` returns;
    triangle ``m`` is ``tri.triangles[m]``, counter-clockwise.
    """
    if tri.vertices.ndim != 2:
        raise TypeError("a triangulation of vertex values has no geometry")
    shapely = import_optional("shapely")
    rings = tri.vertices[tri.triangles]  # (n-2, 3, d)
    return shapely.GeometryCollection(list(shapely.polygons(rings)))


def _rings(rings: Any) -> Rings:
    if not isinstance(rings, (list, tuple, np.ndarray)):
        raise InvalidPolygonError(
            f"polygon coordinates must be a list of rings, got {type(rings).__name__}"
        )
    if len(rings) == 0:
        raise InvalidPolygonError("the polygon has no exterior ring")
    return [_ring(r) for r in rings]


def _ring(coords: Any) -> NDArray[np.float64]:
    try:
        ring = np.asarray(coords, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"polygon ring is not a list of positions: {exc}") from exc
    if ring.ndim != 2 or ring.shape[1] not in (2, 3):
        raise InvalidPolygonError(f"polygon ring must hold 2-D or 3-D positions, got {ring.shape}")
    if len(ring) > 3 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    return ring


def _split_groups(text: str) -> list[str]:
    """Split ``(a), (b (c))`` at top-level commas into ``["(a)", "(b (c))"]``."""
    parts, depth, start = [], 0, 0
    for pos, ch in enumerate(text):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth < 0:
                raise InvalidPolygonError("unbalanced parentheses in WKT")
        elif ch == "," and depth == 0:
            parts.append(text[start:pos].strip())
            start = pos + 1
    parts.append(text[start:].strip())
    if depth != 0:
        raise InvalidPolygonError("unbalanced parentheses in WKT")
    return [p for p in parts if p]
