"""GeoParquet and GeoPackage input and Parquet output (the optional ``geo`` extra).

pyarrow, shapely and pyogrio are imported lazily through
:func:`optri._optional.import_optional`, so ``import optri.batch`` never needs them.
Parquet is read one record batch at a time (``ParquetFile.iter_batches``) and
GeoPackage one page at a time (pyogrio ``skip_features``/``max_features``).
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, Any

from .. import config
from .._optional import import_optional
from ..errors import BatchInputError
from .records import Item

__all__ = ["count_rows", "item_from_shapely", "read_gpkg", "read_parquet", "write_parquet"]



def item_from_shapely(geom: Any, item_id: Any) -> Item:
    """An :class:`Item` from a shapely geometry: a Polygon's exterior ring, or a reason."""
    if geom is None or geom.is_empty:
        return Item(item_id, reason="empty or missing geometry")
    gtype = geom.geom_type
    if gtype == "MultiPolygon":
        if len(geom.geoms) != 1:
            return Item(item_id, reason=f"MultiPolygon with {len(geom.geoms)} parts; split it")
        geom, gtype = geom.geoms[0], "Polygon"
    if gtype != "Polygon":
        return Item(item_id, reason=f"geometry type {gtype!r} is not a Polygon")
    if len(geom.interiors):
        return Item(
            item_id,
            reason=f"polygon has {len(geom.interiors)} hole(s); exact optimal "
            "triangulation with holes is not supported",
        )
    return Item(item_id, [list(c) for c in geom.exterior.coords])


def read_parquet(path: Path) -> Iterator[Item]:
    """Stream a GeoParquet file's polygons, one record batch at a time."""
    pq = import_optional("pyarrow.parquet")
    shapely = import_optional("shapely")
    try:
        pf = pq.ParquetFile(path)
    except Exception as exc:  # pyarrow raises its own ArrowInvalid/OSError zoo
        raise BatchInputError(f"{path}: not a Parquet file ({_first_line(exc)})") from None
    names = pf.schema_arrow.names
    geom_col = _geometry_column(pf.schema_arrow.metadata or {}, names, path)
    columns = [geom_col] + (["id"] if "id" in names else [])
    index = 0
    for batch in pf.iter_batches(batch_size=config.BATCH_ROWS_PER_READ, columns=columns):
        try:
            geoms = shapely.from_wkb(batch.column(geom_col).to_numpy(zero_copy_only=False))
        except Exception as exc:
            raise BatchInputError(f"{path}: row {index}: bad WKB ({_first_line(exc)})") from None
        ids = batch.column("id").to_pylist() if "id" in names else [None] * len(geoms)
        for geom, item_id in zip(geoms, ids):
            yield item_from_shapely(geom, index if item_id is None else item_id)
            index += 1


def read_gpkg(path: Path) -> Iterator[Item]:
    """Stream a GeoPackage (its first layer) page by page through pyogrio."""
    pyogrio = import_optional("pyogrio")
    total = count_rows(path, "gpkg")
    index = 0
    while index < total:
        try:
            df = pyogrio.read_dataframe(
                path,
                skip_features=index,
                max_features=config.BATCH_ROWS_PER_READ,
                fid_as_index=True,
            )
        except Exception as exc:
            raise BatchInputError(f"{path}: feature {index}: {_first_line(exc)}") from None
        if len(df) == 0:
            break
        ids = df["id"].tolist() if "id" in df.columns else df.index.tolist()
        for geom, item_id in zip(df.geometry.values, ids):
            yield item_from_shapely(geom, _plain(item_id))
            index += 1


def count_rows(path: Path, kind: str) -> int:
    """Number of rows (Parquet metadata) or features (GeoPackage layer info)."""
    if kind == "parquet":
        pq = import_optional("pyarrow.parquet")
        try:
            return int(pq.ParquetFile(path).metadata.num_rows)
        except Exception as exc:
            raise BatchInputError(f"{path}: not a Parquet file ({_first_line(exc)})") from None
    pyogrio = import_optional("pyogrio")
    try:
        info = pyogrio.read_info(path)
    except Exception as exc:
        raise BatchInputError(f"{path}: not a GeoPackage layer ({_first_line(exc)})") from None
    if not info.get("geometry_type"):
        raise BatchInputError(f"{path}: not a polygon layer (no geometry column)")
    return int(info["features"])


def write_parquet(fh: IO[bytes], records: Sequence[dict], coords: Sequence[Any]) -> None:
    """Write records as GeoParquet: triangle MultiPolygons in ``geometry`` (WKB).

    ``id`` is stored as text (ids of one file may mix numbers and strings);
    ``cost`` is a float, or a list of floats for a lexicographic objective.
    """
    pa = import_optional("pyarrow")
    pq = import_optional("pyarrow.parquet")
    index_lists = pa.list_(pa.list_(pa.int64()))
    table = pa.table(
        {
            "id": pa.array([str(r["id"]) for r in records], pa.string()),
            "status": pa.array([r["status"] for r in records], pa.string()),
            "n": pa.array([r["n"] for r in records], pa.int64()),
            "cost": _cost_array(pa, records),
            "triangles": pa.array([r["triangles"] for r in records], index_lists),
            "diagonals": pa.array([r["diagonals"] for r in records], index_lists),
            "reason": pa.array([r["reason"] for r in records], pa.string()),
            "seconds": pa.array([r["seconds"] for r in records], pa.float64()),
            "geometry": pa.array(_wkb(records, coords), pa.binary()),
        }
    )
    meta = {
        "version": "1.0.0",
        "primary_column": "geometry",
        # crs null = "unknown": the input's CRS is not tracked through the batch
        "columns": {
            "geometry": {"encoding": "WKB", "geometry_types": ["MultiPolygon"], "crs": None}
        },
    }
    table = table.replace_schema_metadata({"geo": json.dumps(meta)})
    pq.write_table(table, fh)


def read_parquet_records(path: Path) -> Iterator[dict]:
    """Read back records written by :func:`write_parquet` (geometry left out)."""
    pq = import_optional("pyarrow.parquet")
    pf = pq.ParquetFile(path)
    names = [c for c in pf.schema_arrow.names if c != "geometry"]
    for batch in pf.iter_batches(batch_size=config.BATCH_ROWS_PER_READ, columns=names):
        yield from batch.to_pylist()


def _cost_array(pa: Any, records: Sequence[dict]) -> Any:
    costs = [r["cost"] for r in records]
    if any(isinstance(c, list) for c in costs):
        return pa.array([_floats(c) for c in costs], pa.list_(pa.float64()))
    return pa.array([None if c is None else float(c) for c in costs], pa.float64())


def _floats(cost: Any) -> Any:
    return None if cost is None else [float(c) for c in cost]


def _wkb(records: Sequence[dict], coords: Sequence[Any]) -> list[bytes | None]:
    shapely = import_optional("shapely")
    out: list[bytes | None] = []
    for rec, pts in zip(records, coords):
        if rec["status"] != "ok":
            out.append(None)
            continue
        tris = [shapely.Polygon([pts[a], pts[b], pts[c]]) for a, b, c in rec["triangles"]]
        out.append(shapely.to_wkb(shapely.MultiPolygon(tris)))
    return out


def _geometry_column(meta: dict, names: list[str], path: Path) -> str:
    raw = meta.get(b"geo")
    if raw:
        try:
            return str(json.loads(raw)["primary_column"])
        except (ValueError, KeyError):
            pass
    if "geometry" in names:
        return "geometry"
    raise BatchInputError(f"{path}: not a polygon layer (no GeoParquet geometry column)")


def _plain(value: Any) -> Any:
    # numpy scalars -> Python, so ids serialize as JSON
    return value.item() if hasattr(value, "item") else value


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__
