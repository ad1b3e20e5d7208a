"""Table files: GeoParquet (pyarrow) and GeoPackage / FlatGeobuf (pyogrio), written atomically.

Every file is written under a temporary name in the same directory and renamed
over the target only once complete. A single-file output is assembled from
its Parquet parts as one Arrow stream (``pyarrow.RecordBatchReader`` into
``ParquetWriter`` or ``pyogrio.write_arrow``), so memory stays flat however
many features there are. FlatGeobuf is written without a spatial index: the
index cannot hold the null geometry of an error row, and it would keep every
feature's box in memory. A FlatGeobuf file has one dimension: when some rows
are 3-D, the 2-D rows are written with z = NaN (GeoPackage and GeoParquet keep
each row's own dimension).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

from .. import config
from .._optional import import_optional
from ..errors import BatchInputError
from ..io.atomic import atomic_write, fsync_path, kept_mode
from .geo import ogr_timestamps, parse_timestamps
from .layer import Layer, crs_wkt
from .tables import (
    GEOMETRY,
    conform,
    geo_metadata,
    geometry_type,
    has_z,
    is_exploded,
    records_table,
    unify,
)

__all__ = [
    "OGR_DRIVERS",
    "PartJoiner",
    "RowGroups",
    "assemble_tables",
    "read_table_records",
    "write_table",
]

#: Output format -> GDAL driver.
OGR_DRIVERS = {"gpkg": "GPKG", "fgb": "FlatGeobuf"}
_LAYER_OPTIONS = {"fgb": {"SPATIAL_INDEX": "NO"}}
_SIDECARS = ("-journal", "-wal", "-shm")


def flavor_of(fmt: str) -> str:
    """The table flavour a format stores: ``"parquet"`` or ``"ogr"``."""
    return "ogr" if fmt in OGR_DRIVERS else "parquet"


def write_table(
    path: Path, table: Any, fmt: str, layer: Layer, temp_dir: Path, *, durable: bool = True
) -> None:
    """Write one table as a ``fmt`` file (parquet, gpkg, fgb) at ``path``, atomically.

    ``durable=False`` skips the ``fsync`` (a part file, vouched for by its hash).
    """
    if fmt == "parquet":
        pq = import_optional("pyarrow.parquet")
        table = table.replace_schema_metadata(_parquet_metadata(table.schema, layer))
        with atomic_write(path, "wb", durable=durable) as fh:
            pq.write_table(table, fh)
        return
    _write_ogr(path, fmt, layer, table.schema, table.to_batches(), temp_dir, durable=durable)


def assemble_tables(
    parts: Sequence[Path], fmt: str, target: Path, layer: Layer, temp_dir: Path
) -> None:
    """Join Parquet parts, in order, into one ``fmt`` file at ``target``, atomically."""
    pq = import_optional("pyarrow.parquet")
    if parts:
        schema = unify([pq.read_schema(p) for p in parts])
    else:  # no input at all: still a valid, empty layer
        schema = records_table([], [], layer, flavor_of(fmt)).schema

    if fmt == "parquet":
        schema = schema.with_metadata(_parquet_metadata(schema, layer))
        with atomic_write(target, "wb") as fh, pq.ParquetWriter(fh, schema) as writer:
            groups = RowGroups(writer)
            for part in parts:
                groups.add(_part_table(part, schema))
            groups.flush()
        return
    batches = (b for part in parts for b in _part_table(part, schema).to_batches())
    _write_ogr(target, fmt, layer, schema, batches, temp_dir)


def _part_table(part: Path, schema: Any) -> Any:
    """A Parquet part's rows as a table of ``schema`` (:func:`conform`)."""
    pq = import_optional("pyarrow.parquet")
    # ParquetFile, not read_table: that one imports pyarrow.dataset (and pandas)
    with pq.ParquetFile(part) as pf:
        table = pf.read()
    return conform(table, schema)


class RowGroups:
    """Tables of one schema written to a ``ParquetWriter`` as row groups of a useful size.

    Tables are held until they make ``config.BATCH_ROW_GROUP_ROWS`` rows or
    ``config.BATCH_ROW_GROUP_BYTES`` Arrow bytes, then written as one row group
    (joined without a copy: the row group reads each table's chunks in turn);
    :meth:`flush` writes what is held. The rows and their order are the tables'.

    >>> import io, pyarrow as pa, pyarrow.parquet as pq
    >>> sink = io.BytesIO()
    >>> with pq.ParquetWriter(sink, pa.schema([("x", pa.int64())])) as w:
    ...     groups = RowGroups(w)
    ...     for k in range(3):
    ...         groups.add(pa.table({"x": [k, k]}))
    ...     groups.flush()
    >>> f = pq.ParquetFile(sink)
    >>> f.metadata.num_row_groups, f.read().column("x").to_pylist()
    (1, [0, 0, 1, 1, 2, 2])
    """

    def __init__(self, writer: Any) -> None:
        self.writer = writer
        self.held: list[Any] = []
        self.rows = self.bytes = 0

    def add(self, table: Any) -> None:
        """Hold ``table``; write the held tables once they make a row group."""
        self.held.append(table)
        self.rows += table.num_rows
        self.bytes += table.nbytes
        if self.rows >= config.BATCH_ROW_GROUP_ROWS or self.bytes >= config.BATCH_ROW_GROUP_BYTES:
            self.flush()

    def flush(self) -> None:
        """Write the held tables as one row group (nothing when none is held)."""
        if not self.held:
            return
        pa = import_optional("pyarrow")
        table = pa.concat_tables(self.held)
        self.writer.write_table(table, row_group_size=max(1, table.num_rows))
        self.held, self.rows, self.bytes = [], 0, 0


class PartJoiner:
    """A single GeoParquet output joined from its parts while later parts are still made.

    :meth:`ready` says part ``index`` is complete; parts are appended in index
    order, each as soon as every earlier one is in, into a temporary file beside
    the target (:func:`~optri.io.atomic.atomic_write`), so the join overlaps the
    solving instead of following it. :meth:`finish` keeps the file only when it
    is what :func:`assemble_tables` would write from the same parts: every part
    appended, in order, and the schema they unify to the one it was written
    with; it then syncs and renames it over the target and returns True. Else
    (a part whose columns or types change the unified schema, parts missing)
    it removes the file and returns False: the caller assembles the parts. An
    exception inside the ``with`` block removes the file too.
    """

    def __init__(self, target: Path, layer: Layer, part: Callable[[int], Path]) -> None:
        self.target, self.layer, self.part = target, layer, part
        self.joined: list[Path] = []
        self._schemas: list[Any] = []
        self._schema: Any = None
        self._waiting: set[int] = set()
        self._groups: RowGroups | None = None  # with its writer, once the first part is in
        self._stack = contextlib.ExitStack()
        self._fh: Any = None
        self.broken = False

    def __enter__(self) -> PartJoiner:
        self._fh = self._stack.enter_context(atomic_write(self.target, "wb"))
        return self

    def __exit__(self, *exc: Any) -> None:
        if self._fh is not None:  # not finished: the temporary file goes
            self._close(exc[1] if exc[0] is not None else _Abandoned())

    def ready(self, index: int) -> None:
        """Part ``index`` is complete on disk: append it and every waiting part after it."""
        self._waiting.add(index)
        while not self.broken and len(self.joined) in self._waiting:
            self._waiting.discard(len(self.joined))
            self._append(self.part(len(self.joined)))

    def finish(self, parts: Sequence[Path]) -> bool:
        """Rename the joined file over the target if it holds exactly ``parts``; see the class.

        The parts' unified schema needs no second reading: each append unified the
        joined parts' schemas and broke the join where that changed the one written.
        """
        whole = not self.broken and bool(parts) and [Path(p) for p in parts] == self.joined
        self._close(None if whole else _Abandoned())
        return whole

    def _append(self, path: Path) -> None:
        pq = import_optional("pyarrow.parquet")
        new = pq.read_schema(path)
        # unify depends on the distinct schemas only (in order of first appearance): parts
        # that repeat one are not kept again, so each append costs the same however many
        schemas = self._schemas
        if not any(new.equals(s, check_metadata=True) for s in schemas):
            schemas = [*schemas, new]
        schema = unify(schemas)
        if self._groups is None:
            written = schema.with_metadata(_parquet_metadata(schema, self.layer))
            self._groups = RowGroups(pq.ParquetWriter(self._fh, written))
        elif not schema.equals(self._schema, check_metadata=True):
            self.broken = True  # the first parts were written with other columns or types
            return
        self._schema, self._schemas = schema, schemas
        self._groups.add(_part_table(path, schema))
        self.joined.append(path)

    def _close(self, exc: BaseException | None) -> None:
        """Close the writer; rename the file into place (``exc`` None) or remove it."""
        self._fh = None
        try:
            if self._groups is not None:
                if exc is None:
                    self._groups.flush()
                self._groups.writer.close()
        except BaseException as err:
            exc = exc or err
            raise
        finally:
            if exc is None:
                self._stack.close()  # atomic_write syncs the file and renames it
            else:  # atomic_write removes it (and hands exc back, which ends here)
                self._stack.__exit__(type(exc), exc, exc.__traceback__)


class _Abandoned(Exception):
    """Raised into :func:`~optri.io.atomic.atomic_write` to drop a joined file."""


def _parquet_metadata(schema: Any, layer: Layer) -> dict:
    meta = dict(schema.metadata or {})
    meta[b"geo"] = json.dumps(geo_metadata(layer, has_z(schema), is_exploded(schema)))
    return meta


def _write_ogr(
    path: Path,
    fmt: str,
    layer: Layer,
    schema: Any,
    batches: Iterable[Any],
    temp_dir: Path,
    *,
    durable: bool = True,
) -> None:
    pa = import_optional("pyarrow")
    pyogrio = import_optional("pyogrio")
    temp_dir.mkdir(parents=True, exist_ok=True)
    # GDAL wants the format's own suffix; the name marks it as a temporary of ours
    tmp = temp_dir / f".part-{path.stem}.{os.getpid()}.tmp{path.suffix or '.' + fmt}"
    # GDAL has no column type for Arrow's null type: a column of nulls only is text
    typed = pa.schema(
        [f.with_type(pa.string()) if pa.types.is_null(f.type) else f for f in schema],
        metadata=schema.metadata,
    )
    z = has_z(schema)
    if z and fmt == "fgb":  # one dimension per FlatGeobuf file: 2-D rows get z = NaN
        batches = (_force_3d(b) for b in batches)
    reader = pa.RecordBatchReader.from_batches(typed, (b.cast(typed) for b in batches))
    try:
        with warnings.catch_warnings():
            # a layer without a CRS gives an output without one: nothing to warn about
            warnings.filterwarnings("ignore", message="'crs' was not provided")
            pyogrio.write_arrow(
                reader,
                tmp,
                driver=OGR_DRIVERS[fmt],
                layer=path.stem or "triangles",
                geometry_name=GEOMETRY,
                geometry_type=geometry_type(schema),
                crs=_wkt(layer.crs),
                layer_options=_LAYER_OPTIONS.get(fmt),
            )
        bits = kept_mode(path)
        if bits is not None:
            os.chmod(tmp, bits)
        if durable:
            fsync_path(tmp)
        os.replace(tmp, path)
    except pyogrio.errors.DataLayerError as exc:  # GDAL says "failed", seldom why
        raise BatchInputError(f"{path}: cannot write ({_why(exc, temp_dir)})") from None
    finally:
        for name in (str(tmp), *(str(tmp) + s for s in _SIDECARS)):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(name)


def _force_3d(batch: Any) -> Any:
    """``batch`` with its 2-D geometries made 3-D, z NaN ("no height"), 3-D ones untouched.

    The geometries are collections of triangles, or triangles (an exploded output).
    """
    pa = import_optional("pyarrow")
    shapely = import_optional("shapely")
    k = batch.schema.get_field_index(GEOMETRY)
    geoms = shapely.from_wkb(batch.column(k).to_numpy(zero_copy_only=False))
    flat = ~shapely.has_z(geoms) & ~shapely.is_missing(geoms)
    if not flat.any():
        return batch
    # our collections of triangles, rebuilt with a third coordinate (shapely's
    # force_3d refuses NaN; the constructors take it)
    parts, index = shapely.get_parts(geoms[flat], return_index=True)
    rings = shapely.get_coordinates(shapely.get_exterior_ring(parts), include_z=True)
    polys = shapely.polygons(rings.reshape(-1, 4, 3)[:, :3])  # closed by shapely (NaN != NaN)
    single = shapely.get_type_id(geoms[flat]) == 3  # a triangle of an exploded output
    geoms[flat] = polys if single.all() else shapely.geometrycollections(polys, indices=index)
    wkb = pa.array(shapely.to_wkb(geoms, output_dimension=3).tolist(), batch.schema.field(k).type)
    return batch.set_column(k, batch.schema.field(k), wkb)


def _why(exc: Exception, folder: Path) -> str:
    """GDAL's message, and the free space when the disk is what failed."""
    text = " ".join(str(exc).split())
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return text
    if free < config.BATCH_FULL_DISK_BYTES and os.strerror(errno.ENOSPC) not in text:
        text = f"{os.strerror(errno.ENOSPC)}: {free} bytes free; GDAL: {text}"
    return text


def _wkt(crs: str | None) -> str | None:
    if crs is None:
        return None
    import_optional("pyproj")  # a clear error when the geo extra is missing
    return crs_wkt(crs)


def read_table_records(path: Path, fmt: str) -> Iterator[dict]:
    """Rows of a table file written by a batch, geometry left out, as record dicts.

    ``triangles`` and a lexicographic ``cost`` stored as JSON text (GeoPackage,
    FlatGeobuf) come back as lists.
    """
    if fmt == "parquet":
        pq = import_optional("pyarrow.parquet")
        pf = pq.ParquetFile(path)
        names = [c for c in pf.schema_arrow.names if c != GEOMETRY]
        for batch in pf.iter_batches(batch_size=config.BATCH_ROWS_PER_READ, columns=names):
            yield from batch.to_pylist()
        return
    pyogrio = import_optional("pyogrio")
    with pyogrio.open_arrow(path, use_pyarrow=True, read_geometry=False, batch_size=1) as (_, r):
        stamps = ogr_timestamps(path, r.schema, {})
    with pyogrio.open_arrow(
        path,
        use_pyarrow=True,
        read_geometry=False,
        batch_size=config.BATCH_ROWS_PER_READ,
        datetime_as_string=bool(stamps),
    ) as (_, reader):
        for batch in reader:
            for row in parse_timestamps(batch, stamps).to_pylist():
                for key in ("triangles", "cost"):
                    if isinstance(row.get(key), str):
                        row[key] = json.loads(row[key])
                yield row
