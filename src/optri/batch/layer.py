"""What a batch knows about its input layer as a whole: format, CRS, attribute columns.

The CRS is kept as the text it was read as (``"EPSG:32633"``, WKT, PROJJSON,
a GeoJSON ``urn``) and handed to pyproj only where a writer or ``--project``
needs it, so JSON in and JSON out needs no geo package at all. pyproj parses a
given CRS text once per process (:func:`parsed_crs`; a PROJJSON parse costs
tens of milliseconds), and its WKT and PROJJSON forms are derived once from that
parse: writing a part never parses a CRS again. A GeoJSON
FeatureCollection without a ``"crs"`` member is in OGC:CRS84 (longitude,
latitude), as RFC 7946 says and GDAL reads it; NDJSON lines carry no CRS.
"""

from __future__ import annotations

import contextvars
import functools
import json
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from ..errors import BatchWarning, GeographicCRSWarning
from .project import parsed_crs
from .records import RESULT_FIELDS

__all__ = [
    "GEOJSON_DEFAULT_CRS",
    "Layer",
    "crs_name",
    "geojson_crs_member",
    "is_geographic",
    "projjson",
    "projjson_text",
    "renamed_columns",
    "GEOGRAPHIC_WARNED",
    "warn_geographic",
]

#: The CRS of a GeoJSON file without a "crs" member (RFC 7946).
GEOJSON_DEFAULT_CRS = "OGC:CRS84"
# geographic CRSs recognised without pyproj (JSON in, JSON out, no geo extra)
_GEOGRAPHIC = {
    "ogc:crs84",
    "epsg:4326",
    "urn:ogc:def:crs:ogc:1.3:crs84",
    "urn:ogc:def:crs:ogc::crs84",
    "urn:ogc:def:crs:epsg::4326",
}


@dataclass
class Layer:
    """The input layer's header: format, CRS and attribute columns.

    Attributes
    ----------
    fmt : str
        Input format (``geojson``, ``ndjson``, ``parquet``, ``gpkg``, ``fgb``, ``shp``).
    crs : str or None
        The CRS as read (any text pyproj accepts); None when unknown.
    geojson_crs : dict or None
        A GeoJSON ``"crs"`` member as read, written back verbatim to GeoJSON.
    schema : pyarrow.Schema or None
        Types of the attribute columns (Arrow inputs); None for JSON inputs,
        whose attribute types are inferred chunk by chunk.
    renames : dict
        Attribute columns renamed because a batch field has their name.
    crs_json : str or None
        ``crs`` as PROJJSON text when already known (a worker gets the parent's,
        so it never parses the CRS, nor imports pyproj, itself); None: derived
        from ``crs`` on use (:meth:`projjson`).
    """

    fmt: str
    crs: str | None = None
    geojson_crs: dict | None = None
    schema: Any = None
    renames: dict[str, str] = field(default_factory=dict)
    crs_json: str | None = None

    def projjson(self) -> Any:
        """The CRS as PROJJSON (for GeoParquet metadata), or None when unknown."""
        if self.crs_json is not None:
            return json.loads(self.crs_json)
        return projjson(self.crs)

    @property
    def attribute_names(self) -> list[str]:
        """Attribute column names (Arrow inputs), renamed where needed."""
        if self.schema is None:
            return []
        return [self.renames.get(n, n) for n in self.schema.names]


def _parsed_or_none(crs: str) -> Any:
    """:func:`parsed_crs`, or None when pyproj is missing or refuses the text."""
    pyproj = _pyproj()
    if pyproj is None:
        return None
    try:
        return parsed_crs(crs)
    except pyproj.exceptions.CRSError:
        return None


@functools.lru_cache(maxsize=16)
def crs_wkt(crs: str) -> str:
    """``crs`` as WKT (for GDAL writers), derived once from :func:`parsed_crs`."""
    return str(parsed_crs(crs).to_wkt())


@functools.lru_cache(maxsize=16)
def _projjson_text(crs: str) -> str:
    return str(parsed_crs(crs).to_json())


def crs_name(crs: str) -> str:
    """A short name for ``crs``: ``"WGS 84 (EPSG:4326)"``; the text itself without pyproj."""
    obj = _parsed_or_none(crs)
    if obj is None:
        return crs
    auth = obj.to_authority()
    return f"{obj.name} ({auth[0]}:{auth[1]})" if auth else obj.name


def is_geographic(crs: str | None) -> bool | None:
    """True for longitude/latitude CRSs, False for projected ones, None when unknown.

    >>> is_geographic("OGC:CRS84"), is_geographic(None)
    (True, None)
    """
    if crs is None:
        return None
    if _pyproj() is None:
        return True if crs.strip().lower() in _GEOGRAPHIC else None
    obj = _parsed_or_none(crs)
    return None if obj is None else bool(obj.is_geographic)


#: What a batch suggests against costs in degrees.
PROJECT_HINT = "pass --project (project=True) to measure each polygon in metres"


#: True where a caller has warned once for a whole dataset already, so that its parts,
#: solved on any thread, do not warn again: a context variable, each thread's own (a
#: ``warnings.catch_warnings`` filter is the process's, and threads would race on it).
GEOGRAPHIC_WARNED: contextvars.ContextVar[bool] = contextvars.ContextVar(
    "optri_geographic_warned", default=False
)


def warn_geographic(
    crs: str | None, project: bool, what: str = "the layer's", hint: str = PROJECT_HINT
) -> None:
    """Warn once that costs will be in degrees, unless ``project`` measures in metres."""
    if project or GEOGRAPHIC_WARNED.get() or not is_geographic(crs):
        return
    assert crs is not None
    warnings.warn(
        f"{what} CRS is geographic ({crs_name(crs)}): lengths and areas are in "
        f"degrees, not metres; {hint}",
        GeographicCRSWarning,
        stacklevel=3,
    )


def geojson_crs_member(layer: Layer) -> dict | None:
    """The ``"crs"`` member a GeoJSON output gets: none for longitude/latitude (RFC 7946)."""
    if layer.geojson_crs is not None:
        return layer.geojson_crs
    if layer.crs is None or is_geographic(layer.crs):
        return None
    obj = _parsed_or_none(layer.crs)
    auth = obj.to_authority() if obj is not None else None
    if auth is None:
        warnings.warn(
            f"GeoJSON cannot name the CRS {crs_name(layer.crs)} (no authority code); "
            "write .gpkg, .fgb or .parquet to keep it",
            BatchWarning,
            stacklevel=2,
        )
        return None
    return {"type": "name", "properties": {"name": f"urn:ogc:def:crs:{auth[0]}::{auth[1]}"}}


def crs_from_geojson_member(member: Any) -> str | None:
    """The CRS text of a GeoJSON ``"crs"`` member (the 2008 spec's named CRS).

    >>> crs_from_geojson_member({"type": "name", "properties": {"name": "EPSG:3857"}})
    'EPSG:3857'
    """
    if not isinstance(member, dict):
        return None
    props = member.get("properties")
    name = props.get("name") if isinstance(props, dict) else None
    return name if isinstance(name, str) else None


def projjson(crs: str | None) -> Any:
    """``crs`` as PROJJSON (for GeoParquet metadata), or None when unknown."""
    text = projjson_text(crs)
    return None if text is None else json.loads(text)


def projjson_text(crs: str | None) -> str | None:
    """:func:`projjson` as JSON text (parsed once per CRS), for :attr:`Layer.crs_json`."""
    if crs is None or _pyproj() is None:
        return None
    return _projjson_text(crs)


def renamed_columns(names: Iterable[str], reserved: Iterable[str] = RESULT_FIELDS) -> dict:
    """``{old: new}`` for attribute names a batch field already has: ``status`` -> ``status_input``.

    >>> renamed_columns(["name", "status", "status_input"])
    {'status': 'status_input_1'}
    """
    taken = set(names) | set(reserved)
    out = {}
    for name in names:
        if name in reserved:
            new, k = f"{name}_input", 0
            while new in taken:
                k += 1
                new = f"{name}_input_{k}"
            taken.add(new)
            out[name] = new
    return out


def warn_renamed(renames: dict[str, str]) -> None:
    """Say once which attribute columns were renamed to make room for the batch's fields."""
    if renames:
        pairs = ", ".join(f"{a!r} -> {b!r}" for a, b in renames.items())
        warnings.warn(
            f"attribute columns renamed, their names are batch fields: {pairs}",
            BatchWarning,
            stacklevel=3,
        )


def _pyproj() -> Any:
    try:
        import pyproj
    except ImportError:
        return None
    return pyproj
