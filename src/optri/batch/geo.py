"""Arrow layers in: GeoParquet (pyarrow) and GeoPackage, FlatGeobuf, shapefiles (pyogrio).

Both are read one Arrow record batch at a time (``ParquetFile.iter_batches``,
``pyogrio.open_arrow``), with every attribute column: the batch keeps the
attribute schema in its :class:`~optri.batch.layer.Layer`, so writers give each
column back its exact type. The CRS comes from the GeoParquet metadata (no
``crs`` key means OGC:CRS84, as the GeoParquet spec says; ``null`` means
unknown) or from GDAL. GeoParquet's native (GeoArrow) encodings are read as
well as WKB: :func:`wkb_geometry` turns such a column into WKB as it is read.
pyarrow, pyogrio and shapely are imported lazily (``pip install 'optri[geo]'``).
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import config
from .._optional import import_optional
from ..errors import BatchInputError, OptriError
from .layer import Layer, renamed_columns, warn_renamed
from .records import RESULT_FIELDS, Item, feature_vertices, json_id

__all__ = [
    "ArrowSource",
    "count_rows",
    "first_line",
    "ogr_timestamps",
    "open_arrow_batches",
    "open_arrow_layer",
    "parse_timestamps",
    "wkb_geometry",
]

#: GeoParquet's native (GeoArrow) encodings: the list levels above the coordinates.
NATIVE_ENCODINGS = {
    "point": 0,
    "linestring": 1,
    "multipoint": 1,
    "polygon": 2,
    "multilinestring": 2,
    "multipolygon": 3,
}

_OGR_DRIVERS = {"gpkg": "GeoPackage", "fgb": "FlatGeobuf", "shp": "shapefile"}


@dataclass(frozen=True)
class ArrowSource:
    """An Arrow layer's record batches (date-times typed again), its geometry and FID columns.

    ``query`` and ``stamps`` say how an OGR layer was read (the ``open_arrow``
    arguments that pick the layer, the date-time columns' types: see
    :func:`ogr_timestamps`), so a worker can read rows of it the same way.
    """

    geometry: str
    fid: str | None
    batches: Iterator[Any]
    query: dict = field(default_factory=dict)
    stamps: dict = field(default_factory=dict)
    encoding: str = "WKB"  # the geometry as stored (the batches hold WKB)


def open_arrow_layer(
    path: Path, kind: str, name: str | None = None
) -> tuple[Layer, Iterator[Item]]:
    """The header and the Items of a GeoParquet file or an OGR layer.

    ``name`` picks the layer of a file holding several (a GeoPackage); without
    it such a file is refused, its layers listed.
    """
    layer, source = open_arrow_batches(path, kind, name)

    def items() -> Iterator[Item]:
        index = 0
        for batch in source.batches:
            yield from _batch_items(batch, source.geometry, source.fid, index, layer, path)
            index += batch.num_rows

    return layer, items()


def open_arrow_batches(path: Path, kind: str, name: str | None = None) -> tuple[Layer, ArrowSource]:
    """The header and the record batches of a GeoParquet file or an OGR layer."""
    if kind == "parquet":
        return _open_parquet(path)
    return _open_ogr(path, kind, name)


def _open_parquet(path: Path) -> tuple[Layer, ArrowSource]:
    pq = import_optional("pyarrow.parquet")
    try:
        pf = pq.ParquetFile(path)
    except Exception as exc:  # pyarrow raises its own ArrowInvalid/OSError zoo
        raise BatchInputError(f"{path}: not a Parquet file ({first_line(exc)})") from None
    schema = pf.schema_arrow
    geom_col, crs, encoding = _geoparquet_column(schema.metadata or {}, schema.names, path)
    attrs = schema.remove(schema.get_field_index(geom_col))
    layer = _layer("parquet", crs, attrs)
    batches = pf.iter_batches(batch_size=config.BATCH_ROWS_PER_READ)
    if encoding != "WKB":
        batches = (wkb_geometry(b, geom_col, encoding) for b in batches)
    return layer, ArrowSource(geom_col, None, batches, encoding=encoding)


def _open_ogr(path: Path, kind: str, name: str | None) -> tuple[Layer, ArrowSource]:
    pyogrio = import_optional("pyogrio")
    info = _ogr_info(path, kind, name)
    query = _query(pyogrio, path, kind) or {"layer": info["layer"]}
    with pyogrio.open_arrow(path, use_pyarrow=True, batch_size=1, return_fids=True, **query) as (
        meta,
        r,
    ):
        schema = r.schema
    fid_col = schema.names[0]  # return_fids puts the FID first
    geom_col = _wkb_column(schema, path)
    stamps = ogr_timestamps(path, schema, query)
    schema = pa_schema_with(schema, stamps)
    attrs = schema.remove(schema.get_field_index(geom_col)).remove(0)
    layer = _layer(kind, info.get("crs"), attrs)

    def batches() -> Iterator[Any]:
        with pyogrio.open_arrow(
            path,
            use_pyarrow=True,
            batch_size=config.BATCH_ROWS_PER_READ,
            return_fids=True,
            datetime_as_string=bool(stamps),
            **query,
        ) as (_, reader):
            for batch in reader:
                yield parse_timestamps(batch, stamps)

    return layer, ArrowSource(geom_col, fid_col, batches(), query, stamps)


def ogr_timestamps(path: Path, schema: Any, query: dict) -> dict[str, Any]:
    """``{column: Arrow type}`` of an OGR layer's date-time columns, naive or zoned as stored.

    GDAL's Arrow stream gives one time zone per column (a GeoPackage's are all
    "UTC", a FlatGeobuf's none), so naive values would come back in UTC and
    zoned ones lose their zone; read as text (``datetime_as_string``) each value
    keeps its own. A column is zoned (in the first value's offset) when its
    first non-null value has an offset, else naive.
    """
    pa = import_optional("pyarrow")
    pyogrio = import_optional("pyogrio")
    names = [f.name for f in schema if pa.types.is_timestamp(f.type)]
    if not names:
        return {}
    out = {name: pa.timestamp("ms") for name in names}
    todo = set(names)
    with pyogrio.open_arrow(
        path,
        use_pyarrow=True,
        datetime_as_string=True,
        read_geometry=False,
        batch_size=config.BATCH_ROWS_PER_READ,
        **query,
    ) as (_, reader):
        for batch in reader:
            for name in list(todo):
                first = next((v for v in batch.column(name).to_pylist() if v), None)
                if first is not None:
                    zone = _fromiso(first).tzinfo
                    if zone is not None:
                        out[name] = pa.timestamp("ms", tz=_offset(zone, first))
                    todo.discard(name)
            if not todo:
                break
    return out


def pa_schema_with(schema: Any, types: dict[str, Any]) -> Any:
    """``schema`` with the types of the named columns replaced."""
    return import_optional("pyarrow").schema(
        [f.with_type(types[f.name]) if f.name in types else f for f in schema],
        metadata=schema.metadata,
    )


def parse_timestamps(batch: Any, types: dict[str, Any]) -> Any:
    """``batch`` with its date-time columns read as text (``datetime_as_string``) typed again."""
    if not types:
        return batch
    pa = import_optional("pyarrow")
    arrays = [
        pa.array([None if v is None else _fromiso(v) for v in col.to_pylist()], types[name])
        if name in types
        else col
        for name, col in zip(batch.schema.names, batch.columns)
    ]
    return pa.RecordBatch.from_arrays(arrays, schema=pa_schema_with(batch.schema, types))


def _fromiso(text: str) -> Any:
    import datetime

    return datetime.datetime.fromisoformat(text)


def _offset(zone: Any, text: str) -> str:
    """The ``+HH:MM`` of a value's zone (Arrow's fixed-offset time zone)."""
    delta = zone.utcoffset(_fromiso(text))
    minutes = int(delta.total_seconds() // 60)
    sign = "-" if minutes < 0 else "+"
    return f"{sign}{abs(minutes) // 60:02d}:{abs(minutes) % 60:02d}"


def _query(pyogrio: Any, path: Path, kind: str) -> dict:
    """Extra ``open_arrow`` arguments: FlatGeobuf goes through GDAL's SQLite dialect.

    GDAL's own FlatGeobuf Arrow reader returns corrupt offsets for null
    geometries (GDAL 3.12; see OSGeo/gdal#7401 for the family of bugs); the
    SQLite dialect reads the same features through the generic path, with the
    same column types, and streams just as well.
    """
    if kind != "fgb":
        return {}
    name = str(pyogrio.list_layers(path)[0][0]).replace('"', '""')
    return {"sql": f'SELECT * FROM "{name}"', "sql_dialect": "SQLITE"}


def _layer(kind: str, crs: str | None, attrs: Any) -> Layer:
    renames = renamed_columns(attrs.names, RESULT_FIELDS)
    warn_renamed(renames)
    return Layer(kind, crs=crs, schema=attrs, renames=renames)


def _batch_items(
    batch: Any, geom_col: str, fid_col: str | None, start: int, layer: Layer, path: Path
) -> Iterator[Item]:
    shapely = import_optional("shapely")
    wkb = batch.column(geom_col).to_numpy(zero_copy_only=False)
    geoms = shapely.from_wkb(wkb, on_invalid="ignore")
    names = layer.schema.names
    rows = batch.select(names).to_pylist() if names else [{}] * batch.num_rows
    fids = batch.column(fid_col).to_pylist() if fid_col else None
    for k, (raw, geom, row) in enumerate(zip(wkb, geoms, rows)):
        fallback = fids[k] if fids is not None else start + k
        item_id = json_id(row.get("id"), fallback)
        props = {layer.renames.get(n, n): v for n, v in row.items()} if names else None
        if raw is not None and geom is None:
            yield Item(item_id, reason="invalid WKB geometry", props=props)
            continue
        try:
            yield Item(item_id, feature_vertices(geom), props=props)
        except OptriError as exc:
            yield Item(item_id, reason=str(exc), props=props)


def count_rows(path: Path, kind: str, name: str | None = None) -> int | None:
    """Number of rows (Parquet metadata) or features (OGR layer info; None if unknown)."""
    if kind == "parquet":
        pq = import_optional("pyarrow.parquet")
        try:
            return int(pq.ParquetFile(path).metadata.num_rows)
        except Exception as exc:
            raise BatchInputError(f"{path}: not a Parquet file ({first_line(exc)})") from None
    count = int(_ogr_info(path, kind, name)["features"])
    return count if count >= 0 else None


def _ogr_info(path: Path, kind: str, name: str | None = None) -> dict:
    """The OGR layer's info (``"layer"``: its name): the only one, or the one named."""
    pyogrio = import_optional("pyogrio")
    try:
        layers = [str(row[0]) for row in pyogrio.list_layers(path)]
        if name is None and len(layers) > 1:
            raise BatchInputError(
                f"{path}: holds {len(layers)} layers ({', '.join(layers)}); "
                "choose one with --layer NAME"
            )
        if name is not None and name not in layers:
            raise BatchInputError(f"{path}: no layer {name!r}; its layers are {', '.join(layers)}")
        layer = name if name is not None else (layers[0] if layers else 0)
        info = pyogrio.read_info(path, layer=layer)
    except BatchInputError:
        raise
    except Exception as exc:
        driver = _OGR_DRIVERS.get(kind, kind)
        raise BatchInputError(f"{path}: not a {driver} layer ({first_line(exc)})") from None
    if not info.get("geometry_type"):
        raise BatchInputError(f"{path}: not a polygon layer (no geometry column)")
    return {**info, "layer": layer}


def _wkb_column(schema: Any, path: Path) -> str:
    for fld in schema:
        meta = fld.metadata or {}
        if meta.get(b"ARROW:extension:name") == b"geoarrow.wkb":
            return str(fld.name)
    raise BatchInputError(f"{path}: not a polygon layer (no geometry column)")


def _geoparquet_column(meta: dict, names: list[str], path: Path) -> tuple[str, str | None, str]:
    """The geometry column, CRS text and encoding of a GeoParquet file's ``geo`` metadata."""
    raw = meta.get(b"geo")
    if not raw:
        if "geometry" in names:
            return "geometry", None, "WKB"  # plain Parquet with a WKB column: CRS unknown
        raise BatchInputError(f"{path}: not a polygon layer (no GeoParquet geometry column)")
    try:
        geo = json.loads(raw)
        col = str(geo["primary_column"])
        spec = geo["columns"][col]
    except (ValueError, KeyError, TypeError):
        raise BatchInputError(f"{path}: unreadable GeoParquet metadata") from None
    if col not in names:
        raise BatchInputError(f"{path}: GeoParquet primary column {col!r} is missing")
    encoding = spec.get("encoding", "WKB")
    if encoding != "WKB" and encoding not in NATIVE_ENCODINGS:
        raise BatchInputError(
            f"{path}: unknown geometry encoding {str(encoding)[:40]!r} (GeoParquet has WKB, "
            f"{', '.join(NATIVE_ENCODINGS)})"
        )
    if "crs" not in spec:
        return col, "OGC:CRS84", encoding  # the GeoParquet default
    crs = spec["crs"]
    text = None if crs is None else (crs if isinstance(crs, str) else json.dumps(crs))
    return col, text, encoding


def wkb_geometry(table: Any, column: str, encoding: str) -> Any:
    """``table`` (an Arrow Table or RecordBatch) with column ``column`` as WKB.

    ``encoding`` is the GeoParquet encoding of the column: ``"WKB"`` (returned
    as is) or a native GeoArrow one (:data:`NATIVE_ENCODINGS`): nested lists over
    coordinates, separated (a struct of ``x``, ``y`` and maybe ``z``; ``m`` is
    dropped) or interleaved (fixed-size lists of 2 or 3 values). Null rows stay
    null.

    Examples
    --------
    >>> import pyarrow as pa
    >>> ring = [{"x": 0.0, "y": 0.0}, {"x": 1.0, "y": 0.0}, {"x": 0.0, "y": 1.0},
    ...         {"x": 0.0, "y": 0.0}]
    >>> t = pa.table({"geometry": [[ring], None]})
    >>> import shapely
    >>> [None if w is None else shapely.from_wkb(w).wkt
    ...  for w in wkb_geometry(t, "geometry", "polygon").column("geometry").to_pylist()]
    ['POLYGON ((0 0, 1 0, 0 1, 0 0))', None]
    """
    if encoding == "WKB":
        return table
    pa = import_optional("pyarrow")
    shapely = import_optional("shapely")
    k = table.schema.get_field_index(column)
    arr = table.column(k)
    if isinstance(arr, pa.ChunkedArray):
        arr = arr.combine_chunks() if arr.num_chunks else pa.array([], arr.type)
    if isinstance(arr.type, pa.ExtensionType):
        arr = arr.storage
    nulls = arr.is_null().to_numpy(zero_copy_only=False)
    offsets = []
    values = arr
    try:
        for _ in range(NATIVE_ENCODINGS[encoding]):  # one list level: offsets from 0
            off = np.asarray(values.offsets, dtype=np.int64)
            values = values.values.slice(int(off[0]), int(off[-1] - off[0]))
            offsets.append(off - off[0])
        coords = _coordinates(pa, values)
    except (AttributeError, KeyError, TypeError, ValueError) as exc:
        raise BatchInputError(
            f"geometry column {column!r} is not {encoding!r} GeoArrow data ({first_line(exc)})"
        ) from None
    kind = getattr(shapely.GeometryType, encoding.upper())
    if not len(coords):  # every row null or empty (shapely cannot rebuild from nothing)
        geoms = np.full(len(arr), None, dtype=object)
    elif encoding == "point":
        geoms = shapely.points(coords)
    else:
        geoms = shapely.from_ragged_array(kind, coords, tuple(reversed(offsets)))
    wkb = shapely.to_wkb(geoms).astype(object)
    wkb[nulls] = None
    field = table.schema.field(k)
    metadata = {
        key: v for key, v in (field.metadata or {}).items() if not key.startswith(b"ARROW:")
    }
    new = pa.field(field.name, pa.binary(), nullable=True, metadata=metadata or None)
    return table.set_column(k, new, pa.array(wkb, pa.binary()))


def _coordinates(pa: Any, values: Any) -> Any:
    """The (n, 2) or (n, 3) float64 coordinates of a GeoArrow coordinate array."""
    if pa.types.is_struct(values.type):
        names = [values.type.field(i).name for i in range(values.type.num_fields)]
        dims = ["x", "y", "z"] if "z" in names else ["x", "y"]
        cols = [values.field(names.index(d)).to_numpy(zero_copy_only=False) for d in dims]
        return np.column_stack(cols).astype(np.float64)
    size = values.type.list_size  # interleaved: fixed-size lists named xy, xyz, xym, xyzm
    dims = values.type.value_field.name
    has_z = "z" in dims if set(dims) <= set("xyzm") and len(dims) == size else size > 2
    flat = values.values.slice(values.offset * size, len(values) * size)  # null slots too
    xyz = flat.to_numpy(zero_copy_only=False).astype(np.float64).reshape(-1, size)
    return xyz[:, : 3 if has_z else 2]


def first_line(exc: BaseException) -> str:
    """The first line of an exception's message (or its type name)."""
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__
