"""Streaming readers: every input format becomes an iterator of :class:`Item`.

JSON formats are read here; GeoParquet and GeoPackage (the ``geo`` extra) in
:mod:`optri.batch.geo`. No reader holds more than one feature (NDJSON, GeoJSON)
or one row group / page (Parquet, GeoPackage) in memory at a time.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from .. import config
from ..errors import BatchInputError
from . import geo
from .records import Item

__all__ = [
    "INPUT_FORMATS",
    "count_items",
    "detect_input_format",
    "item_from_geojson",
    "read_items",
]

#: Input format -> file suffixes that select it.
INPUT_FORMATS = {
    "geojson": (".geojson", ".json"),
    "ndjson": (".ndjson", ".jsonl", ".geojsonl", ".geojsons"),
    "parquet": (".parquet", ".geoparquet", ".pq"),
    "gpkg": (".gpkg",),
}



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


def read_items(path: str | os.PathLike[str], fmt: str | None = None) -> Iterator[Item]:
    """Stream the polygons of ``path`` as :class:`Item` in file order."""
    p = Path(path)
    if not p.is_file():
        raise BatchInputError(f"{p}: no such file")
    kind = detect_input_format(p, fmt)
    if kind == "ndjson":
        return _read_ndjson(p)
    if kind == "geojson":
        return _read_feature_collection(p)
    return geo.read_parquet(p) if kind == "parquet" else geo.read_gpkg(p)


def count_items(path: str | os.PathLike[str], fmt: str | None = None) -> int | None:
    """A quick count (or estimate) of the polygons in ``path``, for progress bars."""
    p = Path(path)
    kind = detect_input_format(p, fmt)
    if kind == "ndjson":
        return sum(1 for line in _binary_lines(p) if line.strip())
    if kind == "geojson":  # every feature carries "type": "Feature"
        return _count_bytes(p, b'"Feature"')
    return geo.count_rows(p, kind)


def item_from_geojson(obj: Any, index: int) -> Item:
    """An :class:`Item` from a GeoJSON Feature, a bare geometry or ``{"id", "coordinates"}``.

    The id is the feature's ``id``, else ``properties.id``, else ``index``.
    A Polygon contributes its exterior ring; a polygon with holes, a multi-part
    MultiPolygon or anything else becomes an item with a ``reason``.

    >>> item_from_geojson({"id": "a", "coordinates": [[0, 0], [1, 0], [0, 1]]}, 0).coords
    [[0, 0], [1, 0], [0, 1]]
    >>> item_from_geojson({"type": "Polygon", "coordinates": [[[0, 0]], [[1, 1]]]}, 4).reason
    'polygon has 1 hole(s); exact optimal triangulation with holes is not supported'
    """
    if not isinstance(obj, dict):
        return Item(index, reason=f"expected a JSON object, got {type(obj).__name__}")
    props = obj.get("properties")
    item_id = obj.get("id")
    if item_id is None and isinstance(props, dict):
        item_id = props.get("id")
    if item_id is None:
        item_id = index
    geom = obj.get("geometry", obj) if obj.get("type") == "Feature" else obj
    if geom is None:
        return Item(item_id, reason="feature has no geometry")
    if not isinstance(geom, dict) or "coordinates" not in geom:
        return Item(item_id, reason="no 'coordinates' (or Feature 'geometry') in the object")
    return _from_coordinates(item_id, geom.get("type"), geom["coordinates"])


def _from_coordinates(item_id: Any, gtype: Any, coords: Any) -> Item:
    if not isinstance(coords, list):
        return Item(item_id, reason=f"coordinates must be a list, got {type(coords).__name__}")
    if gtype is None:  # the bare {"id", "coordinates": [[x, y], ...]} form
        return Item(item_id, coords)
    if gtype == "MultiPolygon":
        if not isinstance(coords, list) or len(coords) != 1:
            parts = len(coords) if isinstance(coords, list) else "?"
            return Item(item_id, reason=f"MultiPolygon with {parts} parts; split it into Polygons")
        gtype, coords = "Polygon", coords[0]
    if gtype != "Polygon":
        return Item(item_id, reason=f"geometry type {gtype!r} is not a Polygon")
    if not coords:
        return Item(item_id, reason="Polygon without rings")
    if len(coords) > 1:
        return Item(item_id, reason=_holes_reason(len(coords) - 1))
    return Item(item_id, coords[0])


def _holes_reason(holes: int) -> str:
    # exact minimum-weight triangulation with holes is NP-hard: refuse, never drop a hole
    return f"polygon has {holes} hole(s); exact optimal triangulation with holes is not supported"


def _read_ndjson(path: Path) -> Iterator[Item]:
    index = 0
    with path.open("rb") as fh:
        for lineno, raw in enumerate(fh, start=1):
            if not raw.strip():
                continue
            try:
                obj = json.loads(raw)
            except (json.JSONDecodeError, UnicodeDecodeError) as exc:
                msg = getattr(exc, "msg", str(exc))
                raise BatchInputError(f"{path}:{lineno}: invalid JSON ({msg})") from None
            yield item_from_geojson(obj, index)
            index += 1


def _read_feature_collection(path: Path) -> Iterator[Item]:
    """Stream ``features`` of a FeatureCollection one at a time (bounded memory)."""
    stream = _JsonStream(path)
    stream.expect("{")
    seen_features = False
    while True:
        if stream.peek() == "}":
            break
        key = stream.value()
        stream.expect(":")
        if key == "features":
            stream.expect("[")
            index = 0
            while stream.peek() != "]":
                if index:
                    stream.expect(",")
                yield item_from_geojson(stream.value(), index)
                index += 1
            stream.expect("]")
            seen_features = True
        else:
            value = stream.value()
            if key == "type" and value != "FeatureCollection":
                stream.fail(f"not a polygon layer: type is {value!r}, expected FeatureCollection")
        if stream.peek() == ",":
            stream.expect(",")
    if not seen_features:
        stream.fail("not a polygon layer: no 'features' array")


class _JsonStream:
    """Just enough of an incremental JSON reader to walk one top-level object.

    Values are decoded with :meth:`json.JSONDecoder.raw_decode` from a buffer that
    grows from the file only while a value is incomplete; consumed text is
    dropped, so memory is bounded by the largest single feature.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self.fh = path.open(encoding="utf-8-sig")  # tolerate a byte-order mark
        self.buf = ""
        self.pos = 0
        self.lines_before = 0  # newlines in text already dropped from buf
        self.eof = False
        self.decoder = json.JSONDecoder()

    def _more(self) -> bool:
        if self.eof:
            return False
        try:
            block = self.fh.read(config.BATCH_READ_BLOCK)
        except UnicodeDecodeError as exc:
            self.fail(f"not UTF-8 text ({exc.reason})")
        if not block:  # keep buf as is: error positions still point into it
            self.eof = True
            self.fh.close()
            return False
        self.lines_before += self.buf.count("\n", 0, self.pos)
        self.buf = self.buf[self.pos :] + block
        self.pos = 0
        return True

    def _skip_space(self) -> None:
        while True:
            while self.pos < len(self.buf) and self.buf[self.pos] in " \t\r\n":
                self.pos += 1
            if self.pos < len(self.buf) or not self._more():
                return

    def peek(self) -> str:
        self._skip_space()
        if self.pos >= len(self.buf):
            self.fail("unexpected end of file (truncated JSON?)")
        return self.buf[self.pos]

    def expect(self, char: str) -> None:
        got = self.peek()
        if got != char:
            self.fail(f"invalid JSON: expected {char!r}, found {got!r}")
        self.pos += 1

    def value(self) -> Any:
        self.peek()
        while True:
            try:
                obj, end = self.decoder.raw_decode(self.buf, self.pos)
            except json.JSONDecodeError as exc:
                if self._more():
                    continue
                if not self.buf[exc.pos :].strip():
                    self.fail("unexpected end of file (truncated JSON?)", exc.pos)
                self.fail(f"invalid JSON ({exc.msg})", exc.pos)
            # a number could continue in the next block: only trust a value that ends early
            if end < len(self.buf) or not self._more():
                self.pos = end
                return obj

    def fail(self, message: str, at: int | None = None) -> None:
        at = self.pos if at is None else at
        line = self.lines_before + self.buf.count("\n", 0, at) + 1
        if not self.eof:
            self.fh.close()
        raise BatchInputError(f"{self.path}:{line}: {message}")


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
