"""Streaming readers: every input format becomes a :class:`Layer` and an iterator of Items.

JSON formats are read here (NDJSON line by line, a FeatureCollection feature
by feature through :mod:`.jsonstream`); GeoParquet, GeoPackage, FlatGeobuf and
shapefiles (the ``geo`` extra) in :mod:`.geo`. No reader holds more than one
feature (JSON) or one record batch (Arrow) in memory at a time.

Reading goes record by record: a line that is not UTF-8, not JSON, nested too
deeply, or not a polygon becomes an Item with a ``reason`` (and the line number)
and the run goes on. Only a file that cannot be read at all (missing, not a
layer, a FeatureCollection cut short) raises :class:`BatchInputError`.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from .. import config
from ..errors import BatchInputError, OptriError
from . import geo
from .jsonstream import BadValue, read_feature_collection
from .layer import GEOJSON_DEFAULT_CRS, Layer, crs_from_geojson_member
from .records import Item, json_id, json_safe, multi_parts
from .solver import polygon_rings, polygon_vertices

__all__ = [
    "INPUT_FORMATS",
    "count_items",
    "detect_input_format",
    "item_from_geojson",
    "open_layer",
    "read_items",
]

#: Input format -> file suffixes that select it.
INPUT_FORMATS = {
    "geojson": (".geojson", ".json"),
    "ndjson": (".ndjson", ".jsonl", ".geojsonl", ".geojsons"),
    "parquet": (".parquet", ".geoparquet", ".pq"),
    "gpkg": (".gpkg",),
    "fgb": (".fgb",),
    "shp": (".shp",),
}
# keys of the bare {"id", "coordinates"} form that are not attributes
_BARE_KEYS = {"id", "type", "coordinates", "geometry", "properties"}
# an id worth recovering from a line that is not JSON
_ID = re.compile(rb'"id"\s*:\s*("(?:[^"\\\n]|\\.){0,200}"|-?\d{1,30}(?:\.\d{1,30})?)')


def detect_input_format(path: str | os.PathLike[str], fmt: str | None = None) -> str:
    """The input format named by ``fmt`` or by the file's suffix.

    >>> detect_input_format("roofs.jsonl")
    'ndjson'
    """
    if fmt is not None:
        if fmt not in INPUT_FORMATS:
            known = list(INPUT_FORMATS)
            raise BatchInputError(f"unknown input format {fmt!r}; choose one of {known}")
        return fmt
    suffix = Path(path).suffix.lower()
    for name, suffixes in INPUT_FORMATS.items():
        if suffix in suffixes:
            return name
    raise BatchInputError(f"{path}: cannot tell the input format from {suffix!r}; pass --format")


def open_layer(
    path: str | os.PathLike[str], fmt: str | None = None, layer: str | None = None
) -> tuple[Layer, Iterator[Item]]:
    """The layer header of ``path`` and a stream of its polygons as Items, in file order.

    For a FeatureCollection the header's CRS is filled in when its ``"crs"``
    member is read (before the features, as GDAL writes it). ``layer`` names
    the layer of a file holding several (GeoPackage).
    """
    p = Path(path)
    kind = detect_input_format(p, fmt)
    if not p.is_file():
        raise BatchInputError(f"{p}: no such file")
    _check_layer_name(p, kind, layer)
    if kind == "ndjson":
        return Layer(kind), _read_ndjson(p)
    if kind == "geojson":
        header = Layer(kind, crs=GEOJSON_DEFAULT_CRS)
        return header, _read_feature_collection(p, header)
    return geo.open_arrow_layer(p, kind, layer)


def _check_layer_name(path: Path, kind: str, layer: str | None) -> None:
    if layer is not None and kind not in ("gpkg", "fgb", "shp"):
        raise BatchInputError(f"{path}: a {kind} file holds one layer; --layer is for GeoPackage")


def read_items(path: str | os.PathLike[str], fmt: str | None = None) -> Iterator[Item]:
    """Stream the polygons of ``path`` as :class:`Item` in file order."""
    return open_layer(path, fmt)[1]


def count_items(
    path: str | os.PathLike[str], fmt: str | None = None, layer: str | None = None
) -> int | None:
    """A quick count (or estimate) of the polygons in ``path``, for progress bars."""
    p = Path(path)
    kind = detect_input_format(p, fmt)
    if kind == "ndjson":
        return sum(1 for line in _binary_lines(p) if line.strip())
    if kind == "geojson":  # every feature carries "type": "Feature"
        return _count_bytes(p, b'"Feature"')
    return geo.count_rows(p, kind, layer)


def item_from_geojson(obj: Any, index: int) -> Item:
    """An :class:`Item` from a GeoJSON Feature, a bare geometry or ``{"id", "coordinates"}``.

    The id is the feature's ``id``, else ``properties.id``, else ``index``.
    A Feature's ``properties`` (or the bare form's other keys) are its
    attributes. A Polygon contributes its rings (exterior, then holes:
    :class:`~optri.batch.solver.HoledRings`), a MultiPolygon its parts
    (:class:`~optri.batch.records.PolygonParts`); anything else becomes an
    item with a ``reason``.

    >>> item_from_geojson({"id": "a", "coordinates": [[0, 0], [1, 0], [0, 1]]}, 0).coords.shape
    (3, 2)
    >>> square = [[0, 0], [3, 0], [3, 3], [0, 3], [0, 0]]
    >>> hole = [[1, 1], [1, 2], [2, 2], [2, 1], [1, 1]]
    >>> item_from_geojson({"type": "Polygon", "coordinates": [square, hole]}, 4).coords.sizes
    (4, 4)
    """
    if not isinstance(obj, dict):
        return Item(index, reason=f"expected a JSON object, got {_json_type(obj)}")
    props = obj.get("properties")
    item_id = obj.get("id")
    if item_id is None and isinstance(props, dict):
        item_id = props.get("id")
    item_id = json_id(item_id, index)
    if obj.get("type") == "Feature":
        attrs = props if isinstance(props, dict) else None
        geom = obj.get("geometry")
    else:
        extra = {k: v for k, v in obj.items() if k not in _BARE_KEYS}
        attrs = {**(props if isinstance(props, dict) else {}), **extra} or None
        geom = obj
    try:
        attrs = json_safe(attrs)
    except ValueError as exc:
        return Item(item_id, reason=str(exc))
    if geom is None:
        return Item(item_id, reason="feature has no geometry", props=attrs)
    if not isinstance(geom, dict) or "coordinates" not in geom:
        missing = "no 'coordinates' (or Feature 'geometry') in the object"
        return Item(item_id, reason=missing, props=attrs)
    rings, reason = _rings(geom.get("type"), geom["coordinates"])
    coords = rings
    if reason is None:
        try:
            if geom.get("type") is None:
                coords = polygon_vertices(rings)
            elif geom.get("type") == "MultiPolygon" and len(geom["coordinates"]) > 1:
                coords = multi_parts(rings, polygon_rings)
            else:
                coords = polygon_rings(rings)
        except OptriError as exc:
            reason = str(exc)
    return Item(item_id, coords, reason, attrs)


def _rings(gtype: Any, coords: Any) -> tuple[Any, str | None]:
    """The rings of GeoJSON coordinates (the bare form: one ring), or why there are none."""
    if not isinstance(coords, list):
        return coords, f"coordinates must be a list, got {_json_type(coords)}"
    if gtype is None:  # the bare {"id", "coordinates": [[x, y], ...]} form
        return coords, None
    if gtype == "MultiPolygon":
        if not coords:
            return None, "MultiPolygon without parts"
        if not all(isinstance(part, list) and part for part in coords):
            return None, "MultiPolygon part must be a non-empty list of rings"
        if len(coords) > 1:
            return coords, None  # solved part by part
        gtype, coords = "Polygon", coords[0]
    if gtype != "Polygon":
        return None, f"geometry type {gtype!r} is not a Polygon or MultiPolygon"
    if not coords:
        return None, "Polygon without rings"
    return coords, None


def _json_type(obj: Any) -> str:
    return {dict: "object", list: "list", str: "string", bool: "boolean"}.get(
        type(obj), "null" if obj is None else type(obj).__name__
    )


def _read_ndjson(path: Path) -> Iterator[Item]:
    index = 0
    with path.open("rb") as fh:
        for lineno, raw in enumerate(fh, start=1):
            if lineno == 1 and raw.startswith(b"\xef\xbb\xbf"):
                raw = raw[3:]  # a byte-order mark
            if not raw.strip():
                continue
            yield _item_from_line(raw, lineno, index)
            index += 1


def _item_from_line(raw: bytes, lineno: int, index: int) -> Item:
    """One NDJSON line as an Item; a line that cannot be read is an error item."""
    raw = raw.rstrip(b"\r\n")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        return Item(
            _recover_id(raw, index), reason=f"line {lineno}: not UTF-8 text (byte {exc.start})"
        )
    try:
        obj = json.loads(text)
    except RecursionError:
        return Item(_recover_id(raw, index), reason=f"line {lineno}: nested too deeply to read")
    except json.JSONDecodeError as exc:
        where = f"{exc.msg.removesuffix(' at')} at column {exc.colno}"
        return Item(_recover_id(raw, index), reason=f"line {lineno}: invalid JSON ({where})")
    except ValueError as exc:  # an integer too long to convert
        reason = f"line {lineno}: invalid JSON ({str(exc).split(':')[0]})"
        return Item(_recover_id(raw, index), reason=reason)
    item = item_from_geojson(obj, index)
    if item.reason is not None:
        return Item(item.id, item.coords, f"line {lineno}: {item.reason}", item.props)
    return item


def _recover_id(raw: bytes, index: int) -> Any:
    m = _ID.search(raw, 0, 4096)
    if m is None:
        return index
    try:
        return json_id(json.loads(m.group(1)), index)
    except ValueError:
        return index


def _read_feature_collection(path: Path, layer: Layer) -> Iterator[Item]:
    def on_member(key: str, value: Any) -> None:
        if key == "crs":
            layer.geojson_crs = value if isinstance(value, dict) else None
            layer.crs = crs_from_geojson_member(value)

    for index, (obj, line) in enumerate(read_feature_collection(path, on_member)):
        if isinstance(obj, BadValue):
            yield Item(index, reason=f"line {obj.line}: {obj.reason}")
            continue
        item = item_from_geojson(obj, index)
        if item.reason is not None:
            item = Item(item.id, item.coords, f"line {line}: {item.reason}", item.props)
        yield item


def _binary_lines(path: Path) -> Iterator[bytes]:
    with path.open("rb") as fh:
        yield from fh


def _count_bytes(path: Path, needle: bytes) -> int:
    count, tail = 0, b""
    with path.open("rb") as fh:
        while block := fh.read(config.BATCH_READ_BLOCK):
            data = tail + block
            count += data.count(needle)
            # keep a tail shorter than the needle so no match is counted twice
            tail = data[-(len(needle) - 1) :]
    return count
