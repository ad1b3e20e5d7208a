"""Chunks a worker reads, solves and writes itself: the parent sends where, not what.

On the local process pool (and in-process) a chunk of an Arrow layer goes to its
worker as a :class:`ReadTask`: the file and how to read it (:class:`LayerRows`),
the chunk's first row and row count, the solve options and the part's path. The
worker reads those rows itself (GeoParquet: the row groups holding them,
``ParquetFile.read_row_groups``; GeoPackage, FlatGeobuf, shapefile:
``pyogrio.read_arrow(skip_features=, max_features=)``, read as the parent's
stream reads them), solves them as :func:`~optri.batch.chunks.solve_table` does,
writes the part file atomically and answers with a :class:`PartWritten`: the
part's row count, SHA-256, and its ids' hashes and ok count for the summary. The
parent keeps the ledger, the progress bar and the assembly, and never holds a
chunk's attributes or geometry.

A one-row task cut from a chunk that killed its worker (``offset`` set) reads its
row itself too, but answers with its output table: the parent writes the part
once every row of the chunk is back (:mod:`.runner`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._optional import import_optional
from .chunks import TableTask, solve_table
from .geo import parse_timestamps, wkb_geometry
from .layer import Layer, renamed_columns
from .layout import file_sha256
from .records import TaskOptions
from .summary import id_hash
from .tablefiles import write_table
from .tables import TRIANGLE

__all__ = ["LayerRows", "PartWritten", "ReadTask", "ids_of", "read_rows", "solve_read"]


@dataclass(frozen=True)
class LayerRows:
    """Where an Arrow layer is, its row count, and how its rows are read (picklable).

    ``row_groups`` are the rows of each row group (GeoParquet); ``query`` picks an
    OGR layer (``{"layer": name}``, or FlatGeobuf's SQL), ``stamps`` its
    date-time columns' types (:func:`~optri.batch.geo.ogr_timestamps`).
    """

    path: str
    kind: str
    rows: int
    row_groups: tuple[int, ...] = ()
    query: tuple[tuple[str, Any], ...] = ()
    stamps: tuple[tuple[str, Any], ...] = ()
    encoding: str = "WKB"  # GeoParquet's geometry encoding (native ones are read as WKB)


@dataclass(frozen=True)
class ReadTask(TaskOptions):
    """One chunk a worker reads, solves and writes: rows ``first`` to ``first + count - 1``."""

    index: int
    source: LayerRows
    first: int
    count: int
    geometry: str
    fid: str | None
    renames: dict[str, str]
    flavor: str
    explode: bool
    part: str
    crs: str | None

    @property
    def items(self) -> list[int]:
        """The rows' positions in the chunk (for the runner, which splits a killing chunk)."""
        return list(range(self.count))

    def table_task(self) -> TableTask:
        """The chunk as a :class:`~optri.batch.chunks.TableTask`, its rows read now."""
        rows = read_rows(self.source, self.first, self.count)
        rows = wkb_geometry(rows, self.geometry, self.source.encoding)
        fid, table = ids_of(rows, self.fid, self.first)
        return TableTask(
            self.index,
            table,
            self.geometry,
            self.first,
            fid,
            self.renames,
            self.flavor,
            self.explode,
            weight=self.weight,
            objective=self.objective,
            method=self.method,
            project=self.project,
            offset=self.offset,
        )

    def ids(self) -> list[Any]:
        """The ids of the rows (for the error row of a worker that died)."""
        return self.table_task().ids()


@dataclass(frozen=True)
class PartWritten:
    """What a worker that wrote a part tells the parent: enough for the ledger and the summary."""

    name: str
    rows: int
    sha256: str
    hashes: Any  # int64 array: id_hash of each feature's id
    ok: int


def solve_read(task: ReadTask) -> tuple[int, Any]:
    """Read, solve and write one chunk; ``(index, PartWritten)``, or the table of a one-row task."""
    _, table = solve_table(task.table_task())
    if task.offset is not None:
        return task.index, table
    part = Path(task.part)
    layer = Layer(task.source.kind, crs=task.crs)
    write_table(part, table, "parquet", layer, part.parent, durable=False)
    features = table
    if task.explode:  # count features: the first row of each
        pc = import_optional("pyarrow.compute")
        features = table.filter(pc.fill_null(pc.equal(table.column(TRIANGLE), 0), True))
    hashes = np.array([id_hash(v) for v in features.column("id").to_pylist()], dtype=np.int64)
    ok = int(np.count_nonzero(np.asarray(features.column("status").to_pylist()) == "ok"))
    written = PartWritten(part.name, features.num_rows, file_sha256(part), hashes, ok)
    return task.index, written


def read_rows(source: LayerRows, first: int, count: int) -> Any:
    """Rows ``first`` to ``first + count - 1`` of the layer, as the parent's stream gives them."""
    if source.kind == "parquet":
        offsets = np.concatenate([[0], np.cumsum(source.row_groups)]).astype(np.int64)
        lo = int(np.searchsorted(offsets, first, side="right")) - 1
        hi = int(np.searchsorted(offsets, first + count, side="left"))
        pq = import_optional("pyarrow.parquet")
        table = pq.ParquetFile(source.path).read_row_groups(list(range(lo, hi)))
        return table.slice(first - int(offsets[lo]), count)
    pa = import_optional("pyarrow")
    pyogrio = import_optional("pyogrio")
    stamps = dict(source.stamps)
    _, table = pyogrio.read_arrow(
        source.path,
        skip_features=first,
        max_features=count,
        return_fids=True,
        datetime_as_string=bool(stamps),
        **dict(source.query),
    )
    if not stamps or not table.num_rows:
        return table
    return pa.Table.from_batches([parse_timestamps(b, stamps) for b in table.to_batches()])


def ids_of(table: Any, fid: str | None, first: int) -> tuple[str | None, Any]:
    """Where a chunk's ids are: its ``id`` column (nulls filled as positions), or the FID.

    As for Items (:func:`~optri.batch.records.json_id`): an ``id`` attribute,
    else the FID, else the position in the layer.
    """
    if "id" not in table.column_names:
        return fid, table
    pa = import_optional("pyarrow")
    if fid is not None:
        fallback = table.column(fid).to_pylist()
        table = table.drop_columns([fid])
    else:
        fallback = list(range(first, first + table.num_rows))
    col = table.column("id")
    if col.null_count:  # the ids differ from the attribute: it stays, renamed (as for Items)
        values = [v if v is not None else f for v, f in zip(col.to_pylist(), fallback)]
        if pa.types.is_string(col.type):
            values = [str(v) for v in values]
        k = table.schema.get_field_index("id")
        kept = renamed_columns(table.column_names, ("id",))["id"]
        table = table.set_column(k, kept, col).append_column("id", pa.array(values, col.type))
    return None, table
