"""Part files in every output format, reading them back, and joining them into one file.

JSON parts (NDJSON, GeoJSON) are written here, compactly and with a fixed key
order, one record (feature) per line, so identical input gives identical bytes
apart from ``seconds``; table parts (GeoParquet, GeoPackage, FlatGeobuf) through
:mod:`.tablefiles`. Every part is written under a temporary name and renamed
once complete, so a part file that exists is whole; parts are not synced to
the disk one by one (see :mod:`.layout` for what vouches for them instead).

Both JSON formats hold GeoJSON Features: a FeatureCollection (``.geojson``)
or a GeoJSON text sequence, one Feature per line (``.ndjson``, what GDAL's
GeoJSONSeq driver reads). A Feature holds the attributes and the batch's fields
side by side in its ``properties`` (an attribute named like a batch field gets
``_input`` appended) and the triangles as a GeometryCollection of Polygons.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any

from ..errors import BatchInputError
from ..io.atomic import atomic_write
from .layer import Layer, geojson_crs_member, renamed_columns
from .records import Item, json_safe
from .tablefiles import assemble_tables, flavor_of, read_table_records, write_table
from .tables import TRIANGLE, explode_table, records_table

__all__ = [
    "OUTPUT_FORMATS",
    "PART_FORMATS",
    "SINGLE_FILE_SUFFIXES",
    "assemble",
    "exploded_features",
    "feature_of",
    "read_part",
    "write_part",
]

#: Output format -> suffix of its part files (and of a single output file).
OUTPUT_FORMATS = {
    "ndjson": ".ndjson",
    "geojson": ".geojson",
    "parquet": ".parquet",
    "gpkg": ".gpkg",
    "fgb": ".fgb",
}
#: Suffixes that select a single output file of that format.
SINGLE_FILE_SUFFIXES = {
    ".ndjson": "ndjson",
    ".jsonl": "ndjson",
    ".geojson": "geojson",
    ".json": "geojson",
    ".parquet": "parquet",
    ".geoparquet": "parquet",
    ".gpkg": "gpkg",
    ".fgb": "fgb",
}
#: Format of the hidden parts a single file of each format is assembled from.
PART_FORMATS = {
    "ndjson": "ndjson",
    "geojson": "geojson",
    "parquet": "parquet",
    "gpkg": "parquet",
    "fgb": "parquet",
}

_FC_TAIL = "]}\n"
# how each feature line starts (the FeatureCollection head line does not match it)
_FEATURE = '{"type":"Feature",'


def dumps(obj: Any) -> str:
    """Compact, deterministic JSON (no NaN: costs that are infinite are strings)."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


def feature_of(record: dict, coords: Any, props: dict | None = None) -> dict:
    """A GeoJSON Feature: the triangles as a GeometryCollection of Polygons, attributes and record.

    (A GeometryCollection, as shapely's ``constrained_delaunay_triangles`` gives:
    a MultiPolygon's parts may not share edges, so triangles as one would be invalid.)

    >>> rec = {"id": 1, "status": "ok", "triangles": [[0, 1, 2]]}
    >>> feature_of(rec, [[0, 0], [1, 0], [0, 1]])["geometry"]["geometries"][0]["coordinates"]
    [[[0, 0], [1, 0], [0, 1], [0, 0]]]
    >>> feature_of(rec, [[0, 0], [1, 0], [0, 1]], {"status": "built"})["properties"]
    {'status_input': 'built', 'status': 'ok', 'triangles': [[0, 1, 2]]}
    """
    geometry = None
    if record["status"] == "ok":
        pts = coords.tolist() if hasattr(coords, "tolist") else coords
        polys = [
            {"type": "Polygon", "coordinates": [[pts[a], pts[b], pts[c], pts[a]]]}
            for a, b, c in record["triangles"]
        ]
        geometry = {"type": "GeometryCollection", "geometries": polys}
    attrs = json_safe(props) or {}
    renames = renamed_columns(list(attrs))
    out = {renames.get(k, k): v for k, v in attrs.items()}
    out.update((k, v) for k, v in record.items() if k != "id")
    return {"type": "Feature", "id": record["id"], "geometry": geometry, "properties": out}


def exploded_features(record: dict, coords: Any, props: dict | None = None) -> list[dict]:
    """One GeoJSON Feature per triangle of ``record`` (a Polygon each), or one for an error.

    Each holds the feature's id, attributes and fields, ``triangle`` (the
    triangle's number within the feature, from 0) instead of ``triangles`` and
    ``diagonals``.

    >>> rec = {"id": 1, "status": "ok", "triangles": [[0, 1, 2], [0, 2, 3]], "diagonals": [[0, 2]]}
    >>> feats = exploded_features(rec, [[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> [(f["id"], f["properties"]["triangle"], f["geometry"]["type"]) for f in feats]
    [(1, 0, 'Polygon'), (1, 1, 'Polygon')]
    """
    whole = feature_of(record, coords, props)
    fields = {k: v for k, v in whole["properties"].items() if k not in ("triangles", "diagonals")}
    if whole["geometry"] is None or not whole["geometry"]["geometries"]:
        return [{**whole, "geometry": None, "properties": {**fields, TRIANGLE: None}}]
    return [
        {**whole, "geometry": poly, "properties": {**fields, TRIANGLE: k}}
        for k, poly in enumerate(whole["geometry"]["geometries"])
    ]


def write_part(
    path: Path,
    fmt: str,
    records: Sequence[dict],
    items: Sequence[Item],
    layer: Layer,
    target_fmt: str | None = None,
    explode: bool = False,
) -> None:
    """Write one partition's records as a ``fmt`` file, atomically.

    ``items`` are the chunk's input Items (coordinates and attributes);
    ``target_fmt`` is the format the part will be assembled into (it picks the
    table flavour of a Parquet part), by default ``fmt`` itself. ``explode``
    writes one row per triangle (:func:`exploded_features`,
    :func:`~optri.batch.tables.explode_table`).
    """
    if fmt in ("parquet", "gpkg", "fgb"):
        table = records_table(records, items, layer, flavor_of(target_fmt or fmt))
        if explode:
            table = explode_table(table)
        write_table(path, table, fmt, layer, path.parent, durable=False)
        return
    with atomic_write(path, "w", durable=False) as fh:
        if explode:
            pairs = zip(records, items)
            feats: Iterable[dict] = (
                f for r, it in pairs for f in exploded_features(r, it.coords, it.props)
            )
        else:
            feats = (feature_of(r, it.coords, it.props) for r, it in zip(records, items))
        if fmt == "ndjson":  # a GeoJSON text sequence: one Feature per line
            fh.writelines(dumps(feat) + "\n" for feat in feats)
        else:
            _write_features(fh, feats, layer)


def _collection_head(layer: Layer) -> str:
    crs = geojson_crs_member(layer)
    member = f'"crs":{dumps(crs)},' if crs is not None else ""
    return '{"type":"FeatureCollection",' + member + '"features":[\n'


def _write_features(fh: IO[str], features: Iterable[dict], layer: Layer) -> None:
    fh.write(_collection_head(layer))
    for i, feat in enumerate(features):
        fh.write(("," if i else "") + dumps(feat) + "\n")
    fh.write(_FC_TAIL)


def read_part(path: str | os.PathLike[str], fmt: str) -> Iterator[dict]:
    """Records of a part (or assembled) file written by this module, in order."""
    p = Path(path)
    if fmt in ("parquet", "gpkg", "fgb"):
        yield from read_table_records(p, fmt)
        return
    with p.open(encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, start=1):
            text = line.strip().lstrip(",")
            if not text.startswith(_FEATURE):
                continue  # the FeatureCollection's head and tail lines
            try:
                obj = json.loads(text)
            except json.JSONDecodeError as exc:
                raise BatchInputError(f"{p}:{lineno}: invalid JSON ({exc.msg})") from None
            yield {"id": obj["id"], **obj["properties"]}


def assemble(parts: Sequence[Path], fmt: str, target: Path, layer: Layer, temp_dir: Path) -> None:
    """Join part files, in order, into one ``fmt`` file at ``target``, atomically."""
    if fmt in ("parquet", "gpkg", "fgb"):
        assemble_tables(parts, fmt, target, layer, temp_dir)
        return
    with atomic_write(target, "w") as out:
        if fmt == "ndjson":
            for part in parts:
                with open(part, encoding="utf-8") as src:
                    shutil.copyfileobj(src, out)
            return
        out.write(_collection_head(layer))
        first = True
        for part in parts:
            with open(part, encoding="utf-8") as src:
                for line in src:
                    text = line.lstrip(",")
                    if text.startswith(_FEATURE):
                        out.write(("" if first else ",") + text)
                        first = False
        out.write(_FC_TAIL)
