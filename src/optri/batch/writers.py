"""Writers for part files (NDJSON, GeoJSON, Parquet), reading them back, and assembly.

Every part is written through :func:`optri.io.atomic_write`: a temporary name
renamed over the final one only once complete, so a part file that exists is
whole. JSON is written compactly with a fixed key order, one record (feature)
per line, so identical input gives identical bytes apart from ``seconds``.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any

from .._optional import import_optional
from ..errors import BatchInputError
from ..io.atomic import atomic_write
from .geo import read_parquet_records, write_parquet

__all__ = [
    "OUTPUT_FORMATS",
    "assemble",
    "feature_of",
    "read_part",
    "write_part",
]

#: Output format -> suffix of its part files (and of a single output file).
OUTPUT_FORMATS = {"ndjson": ".ndjson", "geojson": ".geojson", "parquet": ".parquet"}
#: Suffixes that select a single output file of that format.
SINGLE_FILE_SUFFIXES = {
    ".ndjson": "ndjson",
    ".jsonl": "ndjson",
    ".geojson": "geojson",
    ".json": "geojson",
    ".parquet": "parquet",
    ".geoparquet": "parquet",
}

_FC_HEAD = '{"type":"FeatureCollection","features":[\n'
_FC_TAIL = "]}\n"
# how each feature line starts (the FeatureCollection head line does not match it)
_FEATURE = '{"type":"Feature",'


def dumps(obj: Any) -> str:
    """Compact, deterministic JSON (no NaN: costs that are infinite are strings)."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


def feature_of(record: dict, coords: Any) -> dict:
    """A GeoJSON Feature: the triangles as a MultiPolygon, the record as properties.

    >>> rec = {"id": 1, "status": "ok", "triangles": [[0, 1, 2]]}
    >>> feature_of(rec, [[0, 0], [1, 0], [0, 1]])["geometry"]["coordinates"]
    [[[[0, 0], [1, 0], [0, 1], [0, 0]]]]
    """
    geometry = None
    if record["status"] == "ok":
        polys = [[[coords[a], coords[b], coords[c], coords[a]]] for a, b, c in record["triangles"]]
        geometry = {"type": "MultiPolygon", "coordinates": polys}
    props = {k: v for k, v in record.items() if k != "id"}
    return {"type": "Feature", "id": record["id"], "geometry": geometry, "properties": props}


def write_part(
    path: str | os.PathLike[str], fmt: str, records: Sequence[dict], coords: Sequence[Any]
) -> None:
    """Write one partition's records atomically; ``coords`` are the input rings."""
    if fmt == "parquet":
        with atomic_write(path, "wb") as fh:
            write_parquet(fh, records, coords)
        return
    with atomic_write(path, "w") as fh:
        if fmt == "ndjson":
            for rec in records:
                fh.write(dumps(rec) + "\n")
        else:
            _write_features(fh, (feature_of(r, c) for r, c in zip(records, coords)))


def _write_features(fh: IO[str], features: Iterable[dict]) -> None:
    fh.write(_FC_HEAD)
    for i, feat in enumerate(features):
        fh.write(("," if i else "") + dumps(feat) + "\n")
    fh.write(_FC_TAIL)


def read_part(path: str | os.PathLike[str], fmt: str) -> Iterator[dict]:
    """Records of a part (or assembled) file written by this module, in order."""
    p = Path(path)
    if fmt == "parquet":
        yield from read_parquet_records(p)
        return
    with p.open(encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, start=1):
            text = line.strip().lstrip(",")
            if fmt == "geojson" and not text.startswith(_FEATURE):
                continue  # the FeatureCollection's head and tail lines
            if not text:
                continue
            try:
                obj = json.loads(text)
            except json.JSONDecodeError as exc:
                raise BatchInputError(f"{p}:{lineno}: invalid JSON ({exc.msg})") from None
            yield {"id": obj["id"], **obj["properties"]} if fmt == "geojson" else obj


def assemble(parts: Sequence[Path], fmt: str, target: Path) -> None:
    """Join part files, in order, into one file of the same format, atomically."""
    if fmt == "parquet":
        pq = import_optional("pyarrow.parquet")
        with atomic_write(target, "wb") as fh:
            writer = None
            for part in parts:
                table = pq.read_table(part)
                if writer is None:
                    writer = pq.ParquetWriter(fh, table.schema)
                writer.write_table(table)
            if writer is None:  # no input at all: still a valid, empty file
                        write_parquet(fh, [], [])
            else:
                writer.close()
        return
    with atomic_write(target, "w") as out:
        if fmt == "ndjson":
            for part in parts:
                with open(part, encoding="utf-8") as src:
                    shutil.copyfileobj(src, out)
            return
        out.write(_FC_HEAD)
        first = True
        for part in parts:
            with open(part, encoding="utf-8") as src:
                for line in src:
                    text = line.lstrip(",")
                    if text.startswith(_FEATURE):
                        out.write(("" if first else ",") + text)
                        first = False
        out.write(_FC_TAIL)
