"""Reading polygon vertices from CSV, JSON, GeoJSON and WKT files."""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InvalidPolygonError
from .geo import rings_from_geojson, rings_from_wkt

__all__ = ["read_polygon", "read_rings"]


def read_polygon(path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """Read polygon vertices from a CSV, JSON, GeoJSON or WKT file.

    CSV: ``x,y`` or ``x,y,z`` per line, an optional header, ``#`` comments; a
    single column is read as vertex values. JSON: a list of pairs or numbers,
    or an object with a ``vertices``/``coordinates``/``points``/``values`` key.
    GeoJSON (an object with a ``type``) and ``.wkt`` files: the exterior ring of
    one polygon. A polygon with holes is refused here, never cut down to its
    exterior: :func:`read_rings` reads its every ring.

    Raises
    ------
    InvalidPolygonError
        Missing file, unparsable content, holes; the message names the file and line.
    """
    rings = read_rings(path)
    if len(rings) > 1:
        raise InvalidPolygonError(
            f"{path}: the polygon has {len(rings) - 1} hole(s) and read_polygon returns one "
            f"ring; read every ring with read_rings, or give the file to optri.triangulate"
        )
    return rings[0]


def read_rings(path: str | os.PathLike[str]) -> list[NDArray[np.float64]]:
    """Read a polygon's rings from a file: the exterior first, then its holes.

    The formats of :func:`read_polygon`; a GeoJSON or WKT polygon gives every
    ring, a JSON object ``{"exterior": [...], "holes": [[...], ...]}`` too.
    Other files hold one ring.

    Raises
    ------
    InvalidPolygonError
        Missing file, unparsable content; the message names the file and line.
    """
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise InvalidPolygonError(f"cannot read {p}: {exc.strerror or exc}") from exc
    suffix = p.suffix.lower()
    if suffix == ".wkt":
        return rings_from_wkt(text)
    if suffix in (".json", ".geojson"):
        return _parse_json(text, p)
    return [_parse_csv(text, p)]


def _parse_json(text: str, path: Path) -> list[NDArray[np.float64]]:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidPolygonError(f"{path}:{exc.lineno}: invalid JSON ({exc.msg})") from exc
    if isinstance(data, dict) and "type" in data:  # GeoJSON: every ring
        return rings_from_geojson(data)
    if isinstance(data, dict) and "exterior" in data:
        holes = data.get("holes") or []
        if not isinstance(holes, list):
            raise InvalidPolygonError(f"{path}: 'holes' must be a list of rings")
        return [_as_array(r, path) for r in [data["exterior"], *holes]]
    if isinstance(data, dict):
        for key in ("vertices", "coordinates", "points", "values"):
            if key in data:
                data = data[key]
                break
    return [_as_array(data, path)]


def _as_array(data: object, path: Path) -> NDArray[np.float64]:
    try:
        return np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidPolygonError(f"{path}: expected a list of [x, y] pairs or numbers") from exc


def _parse_csv(text: str, path: Path) -> NDArray[np.float64]:
    rows: list[list[float]] = []
    for lineno, row in enumerate(csv.reader(text.splitlines()), start=1):
        cells = [c.strip() for c in row if c.strip() != ""]
        if not cells or cells[0].startswith("#"):
            continue
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if not rows:  # a header line
                continue
            raise InvalidPolygonError(f"{path}:{lineno}: not a number in {row!r}") from None
    if not rows:
        raise InvalidPolygonError(f"{path}: no vertices found")
    width = {len(r) for r in rows}
    if len(width) != 1:
        raise InvalidPolygonError(f"{path}: rows have different numbers of columns {sorted(width)}")
    arr = np.asarray(rows, dtype=np.float64)
    return arr[:, 0] if arr.shape[1] == 1 else arr
