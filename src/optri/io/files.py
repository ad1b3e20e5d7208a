"""Reading polygon vertices from CSV, JSON, GeoJSON and WKT files (or standard input)."""

from __future__ import annotations

import codecs
import json
import os
import re
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import InvalidParameterError, InvalidPolygonError
from .delimited import parse_delimited
from .geo import rings_from_geojson, rings_from_wkt

__all__ = ["decode_text", "read_polygon", "read_rings", "read_rings_and_crs", "read_text"]

#: The name that reads standard input wherever a file is read.
STDIN = "-"
_WKT = re.compile(r"^\s*(SRID=\d+;\s*)?(MULTI)?POLYGON\b", re.IGNORECASE)
_BINARY_PROBE = 8192


def read_polygon(
    path: str | os.PathLike[str], columns: Sequence[str] | None = None
) -> NDArray[np.float64]:
    """Read polygon vertices from a CSV, JSON, GeoJSON or WKT file.

    CSV: ``x,y`` or ``x,y,z`` per line, ``#`` comments; the delimiter (``,``,
    ``;``, tab, spaces), a header line and the coordinate columns are found by
    :func:`optri.io.delimited.parse_delimited`, or named by ``columns``; a
    single column is read as vertex values. JSON: a list of pairs or numbers,
    or an object with a ``vertices``/``coordinates``/``points``/``values`` key.
    GeoJSON (an object with a ``type``) and ``.wkt`` files: the exterior ring of
    one polygon. A polygon with holes is refused here, never cut down to its
    exterior: :func:`read_rings` reads its every ring. ``"-"`` reads standard
    input (the format told from the content); a UTF-8 byte-order mark is skipped.

    Raises
    ------
    InvalidPolygonError
        Missing file, unparsable content, holes; the message names the file and line.
    """
    rings = read_rings(path, columns)
    if len(rings) > 1:
        raise InvalidPolygonError(
            f"{path}: the polygon has {len(rings) - 1} hole(s) and read_polygon returns one "
            f"ring; read every ring with read_rings, or give the file to optri.triangulate"
        )
    return rings[0]


def read_rings(
    path: str | os.PathLike[str], columns: Sequence[str] | None = None
) -> list[NDArray[np.float64]]:
    """Read a polygon's rings from a file: the exterior first, then its holes.

    The formats of :func:`read_polygon`; a GeoJSON or WKT polygon gives every
    ring, a JSON object ``{"exterior": [...], "holes": [[...], ...]}`` too.
    Other files hold one ring. A file whose suffix is none of ``.csv``, ``.tsv``,
    ``.txt``, ``.json``, ``.geojson``, ``.wkt`` (and standard input, ``"-"``) is
    told apart by its content: JSON starts with ``{`` or ``[``, WKT with ``POLYGON``.

    Raises
    ------
    InvalidPolygonError
        Missing file, binary or non-UTF-8 content, unparsable content; the
        message names the file and line.
    """
    return read_rings_and_crs(path, columns)[0]


def read_rings_and_crs(
    path: str | os.PathLike[str], columns: Sequence[str] | None = None
) -> tuple[list[NDArray[np.float64]], str | None]:
    """:func:`read_rings`, and the CRS the file names, as text (None: it names none).

    A GeoJSON object names its CRS by a ``"crs"`` member, and without one it is
    in longitude/latitude (``"OGC:CRS84"``, RFC 7946); other formats name none.
    """
    text = read_text(path)
    stdin = str(path) == STDIN
    p = Path("standard input" if stdin else path)
    suffix = "" if stdin else p.suffix.lower()
    if suffix not in (".wkt", ".json", ".geojson", ".csv", ".tsv", ".txt"):
        head = text.lstrip()[:1]
        suffix = ".json" if head in ("{", "[") else ".wkt" if _WKT.match(text) else ".csv"
    if suffix == ".wkt":
        return rings_from_wkt(text), None
    if suffix in (".json", ".geojson"):
        return _parse_json(text, p)
    return [parse_delimited(text, str(p), columns)], None


#: Environment variable: the most bytes read from standard input (a number; ``k``, ``M``,
#: ``G`` suffixes allowed). Input that never ends stops there with a clear error.
MAX_INPUT_ENV = "OPTRI_MAX_INPUT_BYTES"
_UNITS = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def max_input_bytes() -> int:
    """The limit on standard input: ``$OPTRI_MAX_INPUT_BYTES`` or ``config.MAX_INPUT_BYTES``.

    >>> max_input_bytes() > 0
    True
    """
    text = os.environ.get(MAX_INPUT_ENV, "").strip().upper().removesuffix("B")
    if not text:
        return config.MAX_INPUT_BYTES
    unit = text[-1] if text[-1] in _UNITS else ""
    try:
        value = int(text[: len(text) - len(unit)]) * _UNITS[unit]
    except ValueError:
        value = 0
    if value <= 0:
        raise InvalidParameterError(
            f"{MAX_INPUT_ENV}={os.environ[MAX_INPUT_ENV]!r}: give a positive number of bytes "
            "(suffixes K, M, G allowed)"
        )
    return value


def copy_stdin(out: BinaryIO | None = None) -> bytes:
    """Read standard input up to :func:`max_input_bytes`, into ``out`` (or returned).

    Raises
    ------
    InvalidPolygonError
        The input goes on past the limit (it may never end: ``yes | optri solve -``).
    """
    limit = max_input_bytes()
    chunks, size = [], 0
    src = sys.stdin.buffer
    while True:
        block = src.read(min(1 << 20, limit + 1 - size))
        if not block:
            break
        size += len(block)
        if size > limit:
            raise InvalidPolygonError(
                f"standard input is longer than {limit} bytes; pass a file, or raise the "
                f"limit with {MAX_INPUT_ENV}"
            )
        if out is None:
            chunks.append(block)
        else:
            out.write(block)
    return b"".join(chunks)


def read_text(path: str | os.PathLike[str]) -> str:
    """The text of a file (``"-"``: standard input), by :func:`decode_text`.

    Raises
    ------
    InvalidPolygonError
        The file cannot be read, or is not text.
    """
    try:
        if str(path) == STDIN:
            data = copy_stdin()
        else:
            data = Path(path).read_bytes()
    except OSError as exc:
        raise InvalidPolygonError(f"cannot read {path}: {exc.strerror or exc}") from exc
    return decode_text(data, "standard input" if str(path) == STDIN else str(path))


def decode_text(data: bytes, name: str) -> str:
    r"""UTF-8 (or UTF-16 with a byte-order mark) bytes as text, without the mark.

    >>> decode_text(b"\xef\xbb\xbfx,y", "f.csv")
    'x,y'

    Raises
    ------
    InvalidPolygonError
        Binary content (NUL bytes) or bytes that are not UTF-8; the message
        names the file and the first bad byte.
    """
    for bom, codec in ((codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be")):
        if data.startswith(bom):
            try:
                return data[len(bom) :].decode(codec)
            except UnicodeDecodeError:
                break
    if data.startswith(codecs.BOM_UTF8):
        data = data[len(codecs.BOM_UTF8) :]
    if b"\x00" in data[:_BINARY_PROBE]:
        raise InvalidPolygonError(
            f"{name}: a binary file, not a text polygon file (CSV, JSON, GeoJSON or WKT)"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InvalidPolygonError(
            f"{name}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); "
            f"save the file as UTF-8"
        ) from None


def _parse_json(text: str, path: Path) -> tuple[list[NDArray[np.float64]], str | None]:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidPolygonError(f"{path}:{exc.lineno}: invalid JSON ({exc.msg})") from exc
    except RecursionError as exc:
        raise InvalidPolygonError(f"{path}: JSON nested too deeply") from exc
    if isinstance(data, dict) and "type" in data:  # GeoJSON: every ring
        return rings_from_geojson(data), _geojson_crs(data.get("crs"))
    if isinstance(data, dict) and "exterior" in data:
        holes = data.get("holes") or []
        if not isinstance(holes, list):
            raise InvalidPolygonError(f"{path}: 'holes' must be a list of rings")
        return [_as_array(r, path) for r in [data["exterior"], *holes]], None
    if isinstance(data, dict):
        for key in ("vertices", "coordinates", "points", "values"):
            if key in data:
                data = data[key]
                break
    return [_as_array(data, path)], None


def _geojson_crs(member: object) -> str | None:
    """The CRS of a GeoJSON object: its named ``"crs"`` member, else OGC:CRS84 (RFC 7946).

    >>> _geojson_crs(None), _geojson_crs({"type": "name", "properties": {"name": "EPSG:3857"}})
    ('OGC:CRS84', 'EPSG:3857')
    """
    if member is None:
        return "OGC:CRS84"
    props = member.get("properties") if isinstance(member, dict) else None
    name = props.get("name") if isinstance(props, dict) else None
    return name if isinstance(name, str) else None


def _as_array(data: object, path: Path) -> NDArray[np.float64]:
    try:
        arr = np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidPolygonError(f"{path}: expected a list of [x, y] pairs or numbers") from exc
    if arr.ndim not in (1, 2):
        raise InvalidPolygonError(f"{path}: expected a list of [x, y] pairs or numbers")
    return arr
