"""Records as Arrow tables: the input's attribute columns, the batch's fields, the triangles.

Two flavours of one table: ``"parquet"`` (GeoParquet: ``triangles`` and
``diagonals`` as lists of index lists, a lexicographic ``cost`` as a list) and
``"ogr"`` (GeoPackage, FlatGeobuf: no list columns there, so ``triangles`` and a
lexicographic ``cost`` are JSON text and ``diagonals`` are left out). Columns:
``id`` (unless an attribute ``id`` already holds the ids), the attributes in
input order, ``status``, ``n``, ``cost``, ``reason``, ``triangles``
(``diagonals``), ``seconds``, and ``geometry``: the triangles as a WKB
GeometryCollection of Polygons in the input coordinates (null for errors).

Attribute columns read from an Arrow layer keep their exact types; those of
JSON features are inferred per chunk (a column mixing types becomes text) and
unified over all parts when a single file is assembled (:func:`unify`).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

import numpy as np

from .._optional import import_optional
from .layer import Layer, renamed_columns
from .records import Item

__all__ = [
    "GEOMETRY",
    "conform",
    "explode_table",
    "feature_rows",
    "geo_metadata",
    "is_exploded",
    "records_table",
    "unify",
]

GEOMETRY = "geometry"
#: Columns a batch adds after the attributes, in order.
TAIL = (
    "status",
    "n",
    "cost",
    "reason",
    "triangles",
    "diagonals",
    "triangle",
    "seconds",
    GEOMETRY,
)
#: The column of an exploded row: the triangle's number within its feature (0, 1, ...).
TRIANGLE = "triangle"
#: Schema metadata key of optri's own notes on a part (3-D coordinates seen).
OPTRI_META = b"optri"


def records_table(records: Sequence[dict], items: Sequence[Item], layer: Layer, flavor: str) -> Any:
    """One chunk as an Arrow table of ``flavor`` ("parquet" or "ogr")."""
    pa = import_optional("pyarrow")
    ids = [r["id"] for r in records]
    attrs = _attributes(pa, [it.props for it in items], layer, flavor)
    cols: dict[str, Any] = {}
    if "id" in attrs and attrs["id"].to_pylist() == ids:
        cols["id"] = attrs.pop("id")  # the attribute holds the ids: keep it once, typed
    else:
        cols["id"] = _infer(pa, ids)
        if "id" in attrs:
            new = renamed_columns(list(attrs), ("id",))["id"]
            attrs = {(new if k == "id" else k): v for k, v in attrs.items()}
    cols.update(attrs)
    ok = [r["status"] == "ok" for r in records]
    cols["status"] = pa.array([r["status"] for r in records], pa.string())
    cols["n"] = pa.array([r["n"] for r in records], pa.int64())
    cols["cost"] = _costs(pa, [r["cost"] for r in records], flavor)
    cols["reason"] = pa.array([r["reason"] for r in records], pa.string())
    index_lists = pa.list_(pa.list_(pa.int64()))
    if flavor == "parquet":
        cols["triangles"] = pa.array([r["triangles"] for r in records], index_lists)
        cols["diagonals"] = pa.array([r["diagonals"] for r in records], index_lists)
    else:
        cols["triangles"] = pa.array(
            [json.dumps(r["triangles"]) if good else None for r, good in zip(records, ok)],
            pa.string(),
        )
    cols["seconds"] = pa.array([r["seconds"] for r in records], pa.float64())
    wkb, z = _wkb(records, items)
    cols[GEOMETRY] = pa.array(wkb, pa.binary())
    table = pa.table(cols)
    return table.replace_schema_metadata({OPTRI_META: json.dumps({"has_z": z})})


def _attributes(pa: Any, props: list[dict | None], layer: Layer, flavor: str) -> dict:
    """Attribute columns of a chunk: typed by the layer's schema, or inferred from JSON."""
    if layer.schema is not None:
        schema = pa.schema([f.with_name(layer.renames.get(f.name, f.name)) for f in layer.schema])
        rows = [p or {} for p in props]
        table = pa.Table.from_pylist(rows, schema=schema)
        cols = {name: table.column(name).combine_chunks() for name in schema.names}
    else:
        names: dict[str, None] = {}
        for p in props:
            names.update(dict.fromkeys(p or ()))
        renames = renamed_columns(list(names))
        cols = {renames.get(k, k): _infer(pa, [(p or {}).get(k) for p in props]) for k in names}
    if flavor == "ogr":
        cols = {k: ogr_column(pa, v) for k, v in cols.items()}
    return cols


def _infer(pa: Any, values: list[Any]) -> Any:
    """An Arrow array of JSON values: their common type, else text (nested values as JSON)."""
    if not any(isinstance(v, (dict, list)) for v in values):
        try:
            return pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError, OverflowError):
            pass
    return pa.array([_text(v) for v in values], pa.string())


def _text(value: Any) -> str | None:
    if value is None or isinstance(value, str):
        return value
    return json.dumps(value, separators=(",", ":"), allow_nan=True)


def ogr_column(pa: Any, arr: Any) -> Any:
    """A column GDAL can store: nested and decimal columns become text.

    (A column of nulls only stays typeless here, so parts still unify; it
    becomes text when the file is written.)
    """
    t = arr.type
    if pa.types.is_dictionary(t):
        arr, t = arr.dictionary_decode(), t.value_type
    if pa.types.is_nested(t) or pa.types.is_decimal(t):
        return pa.array([_text(v) for v in arr.to_pylist()], pa.string())
    return arr


def _costs(pa: Any, costs: list[Any], flavor: str) -> Any:
    if any(isinstance(c, list) for c in costs):
        if flavor == "ogr":
            return pa.array([None if c is None else json.dumps(c) for c in costs], pa.string())
        values = [None if c is None else [float(x) for x in c] for c in costs]
        return pa.array(values, pa.list_(pa.float64()))
    return pa.array([None if c is None else float(c) for c in costs], pa.float64())


def _wkb(records: Sequence[dict], items: Sequence[Item]) -> tuple[list[bytes | None], bool]:
    """WKB GeometryCollections of the ok rows' triangles (None for errors), and whether 3-D.

    Built for the whole chunk at once: every triangle's ring, then one Polygon
    per triangle and one collection per row, by shapely's vectorised calls.
    """
    shapely = import_optional("shapely")
    out: list[bytes | None] = [None] * len(records)
    rings_2d: list[np.ndarray] = []
    rings_3d: list[np.ndarray] = []
    rows_2d: list[np.ndarray] = []
    rows_3d: list[np.ndarray] = []
    for k, (rec, item) in enumerate(zip(records, items)):
        if rec["status"] != "ok":
            continue
        pts = np.asarray(item.coords, dtype=np.float64)
        tri = np.asarray(rec["triangles"], dtype=np.int64).reshape(-1, 3)
        rings, rows = (rings_3d, rows_3d) if pts.shape[1] == 3 else (rings_2d, rows_2d)
        rings.append(pts[tri[:, [0, 1, 2, 0]]])
        rows.append(np.full(len(tri), k, dtype=np.int64))
    for rings, rows in ((rings_2d, rows_2d), (rings_3d, rows_3d)):
        if not rings:
            continue
        row = np.concatenate(rows)
        polys = shapely.polygons(np.concatenate(rings))
        # one collection per row that has triangles (geometrycollections numbers rows 0..max)
        keys, dense = np.unique(row, return_inverse=True)
        collections = shapely.geometrycollections(polys, indices=dense)
        for k, wkb in zip(keys.tolist(), shapely.to_wkb(collections).tolist()):
            out[k] = wkb
    return out, bool(rings_3d)


def explode_table(table: Any) -> Any:
    """One row per triangle of a chunk's table: each a Polygon, with its feature's columns.

    ``table`` is a chunk as :func:`records_table` (or the columnar path) makes it,
    its geometry a GeometryCollection of triangles per row. Each triangle becomes
    a row holding the feature's id, attributes, ``status``, ``n``, ``cost``,
    ``reason`` and ``seconds``, ``triangle`` (its number within the feature,
    from 0) and the triangle as a Polygon; ``triangles`` and ``diagonals`` are
    left out. A row without triangles (an error row) stays one row, ``triangle``
    and geometry null. Rows keep the input order.

    >>> import pyarrow as pa, shapely
    >>> two = shapely.GeometryCollection([shapely.box(0, 0, 1, 1), shapely.box(1, 0, 2, 1)])
    >>> t = pa.table({"id": ["a", "b"], "geometry": [shapely.to_wkb(two), None]})
    >>> out = explode_table(t)
    >>> out.column("id").to_pylist(), out.column("triangle").to_pylist()
    (['a', 'a', 'b'], [0, 1, None])
    """
    pa = import_optional("pyarrow")
    shapely = import_optional("shapely")
    rows = table.num_rows
    geoms = shapely.from_wkb(table.column(GEOMETRY).to_numpy(zero_copy_only=False))
    parts, row = shapely.get_parts(geoms, return_index=True)
    counts = np.bincount(row, minlength=rows)
    lone = np.flatnonzero(counts == 0)  # error rows (and rows with nothing to draw)
    number = np.arange(len(row), dtype=np.int64) - (np.cumsum(counts) - counts)[row]
    source = np.concatenate([row, lone]).astype(np.int64)
    order = np.argsort(source, kind="stable")
    wkb = np.concatenate([shapely.to_wkb(parts), np.full(len(lone), None, dtype=object)])
    triangle = np.concatenate([number, np.zeros(len(lone), dtype=np.int64)])
    null = np.concatenate([np.zeros(len(row), bool), np.ones(len(lone), bool)])
    keep = [c for c in table.column_names if c not in ("triangles", "diagonals", GEOMETRY)]
    out = table.select(keep).take(pa.array(source[order]))
    k = out.schema.get_field_index("seconds")
    column = pa.array(triangle[order], pa.int64(), mask=null[order])
    out = out.add_column(k if k >= 0 else out.num_columns, TRIANGLE, column)
    out = out.append_column(GEOMETRY, pa.array(wkb[order].tolist(), pa.binary()))
    notes = json.loads((table.schema.metadata or {}).get(OPTRI_META, b"{}"))
    notes["explode"] = True
    return out.replace_schema_metadata({OPTRI_META: json.dumps(notes)})


def is_exploded(schema: Any) -> bool:
    """Whether a part's notes say it holds one row per triangle (:func:`explode_table`)."""
    raw = (schema.metadata or {}).get(OPTRI_META)
    return bool(raw and json.loads(raw).get("explode"))


def feature_rows(records: Iterable[dict]) -> Iterator[dict]:
    """The first row of each feature of an output: every row, unless it was exploded.

    An exploded feature's rows after its first have ``triangle`` 1, 2, ...
    """
    return (r for r in records if not r.get(TRIANGLE))


def geometry_type(schema: Any) -> str:
    """The OGC type of a part's geometry column: GeometryCollection, or Polygon when exploded."""
    kind = "Polygon" if is_exploded(schema) else "GeometryCollection"
    return f"{kind} Z" if has_z(schema) else kind


def geo_metadata(layer: Layer, has_z: bool, explode: bool = False) -> dict:
    """GeoParquet 1.1 metadata for the ``geometry`` column (``crs`` null when unknown)."""
    kind = "Polygon" if explode else "GeometryCollection"
    kind = f"{kind} Z" if has_z else kind
    column = {"encoding": "WKB", "geometry_types": [kind], "crs": layer.projjson()}
    return {"version": "1.1.0", "primary_column": GEOMETRY, "columns": {GEOMETRY: column}}


def has_z(schema: Any) -> bool:
    """Whether a part's notes say it holds 3-D triangles."""
    raw = (schema.metadata or {}).get(OPTRI_META)
    return bool(raw and json.loads(raw).get("has_z"))


def unify(schemas: Sequence[Any]) -> Any:
    """One schema for all parts: ``id``, attributes in order of appearance, then the tail.

    Types are promoted (null -> anything, int -> float); a column whose parts
    disagree otherwise becomes text.
    """
    pa = import_optional("pyarrow")
    types: dict[str, list[Any]] = {}
    for schema in schemas:
        for fld in schema:
            types.setdefault(fld.name, []).append(fld.type)
    order = ["id"] + [n for n in types if n not in TAIL and n != "id"] + list(TAIL)
    fields = []
    for name in order:
        if name not in types:
            continue
        try:
            merged = pa.unify_schemas(
                [pa.schema([pa.field(name, t)]) for t in types[name]], promote_options="permissive"
            ).field(name)
        except (pa.ArrowInvalid, pa.ArrowTypeError):
            merged = pa.field(name, pa.string())
        fields.append(merged)
    notes = {"has_z": any(has_z(s) for s in schemas)}
    if any(is_exploded(s) for s in schemas):
        notes["explode"] = True
    return pa.schema(fields, metadata={OPTRI_META: json.dumps(notes)})


def conform(table: Any, schema: Any) -> Any:
    """``table`` with ``schema``'s columns, order and types (missing columns null)."""
    pa = import_optional("pyarrow")
    cols = []
    for fld in schema:
        if fld.name not in table.column_names:
            cols.append(pa.nulls(table.num_rows, fld.type))
            continue
        col = table.column(fld.name)
        if col.type != fld.type:
            if pa.types.is_string(fld.type) and not _castable_to_text(pa, col.type):
                col = pa.array([_text(v) for v in col.to_pylist()], pa.string())
            else:
                col = col.cast(fld.type)
        cols.append(col)
    return pa.Table.from_arrays(cols, schema=schema)


def _castable_to_text(pa: Any, t: Any) -> bool:
    return not (pa.types.is_nested(t) or pa.types.is_binary(t))
