"""A chunk of an Arrow layer solved as columns: an Arrow table in, an Arrow table out.

The path of Arrow layers (GeoParquet, GeoPackage, FlatGeobuf) into table outputs
(Parquet parts): a chunk is a slice of the layer's record batches, attributes
and WKB geometry included; :func:`solve_table` reads its geometry column into a
:class:`~optri.batch.columns.Ragged`, solves every row at once
(:func:`~optri.batch.columns.solve_ragged`) and builds the output table from
the columns: the attributes as read, ``status``, ``n``, ``cost``, ``reason``,
``triangles``, ``diagonals``, ``seconds`` and the geometry, as WKB built by
shapely's vectorised calls. No Python object is made per row. The table is the
one :func:`~optri.batch.tables.records_table` makes from records (same columns,
types and values), so parts of either path assemble alike.

Triangles and diagonals index each row's own vertices as
:func:`optri.triangulate` numbers them (ring after ring, part after part,
closing vertices dropped): the kernel's indices into all the chunk's
coordinates are mapped back in one pass.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._optional import import_optional
from .columns import OK, Ragged, Solved, ragged_from_arrow, solve_ragged, triangle_wkb
from .records import TaskOptions
from .tables import GEOMETRY, OPTRI_META, explode_table, ogr_column

__all__ = ["TableTask", "local_indices", "row_diagonals", "solve_table"]


@dataclass(frozen=True)
class TableTask(TaskOptions):
    """One chunk of an Arrow layer: its index, rows (an Arrow table) and how to solve them.

    ``ids`` names the id column already in ``table`` (``"id"``), or None: the ids
    are then ``first`` + the row's position, or the FID column ``fid``.
    """

    index: int
    table: Any
    geometry: str
    first: int
    fid: str | None
    renames: dict[str, str]
    flavor: str
    explode: bool = False

    @property
    def items(self) -> list[Any]:
        """The rows as one-row tables (for the runner, which splits a killing chunk)."""
        return [self.table.slice(k, 1) for k in range(self.table.num_rows)]

    def ids(self) -> list[Any]:
        """The ids of the rows (for error rows of a worker that died)."""
        if "id" in self.table.column_names and self.fid is None:
            return list(self.table.column("id").to_pylist())
        if self.fid is not None:
            return list(self.table.column(self.fid).to_pylist())
        return list(range(self.first, self.first + self.table.num_rows))


def solve_table(task: TableTask) -> tuple[int, Any]:
    """Solve one chunk; returns ``(task.index, output table)``.

    With ``task.explode`` the table has one row per triangle
    (:func:`~optri.batch.tables.explode_table`).
    """
    pa = import_optional("pyarrow")
    table = task.table
    ragged = ragged_from_arrow(table.column(task.geometry))
    solved = solve_ragged(ragged, task.options)
    cols: dict[str, Any] = {}
    if task.fid is not None:
        cols["id"] = table.column(task.fid)
    elif "id" not in table.column_names:
        cols["id"] = pa.array(np.arange(task.first, task.first + table.num_rows), pa.int64())
    for name in table.column_names:
        if name in (task.geometry, task.fid):
            continue
        col = table.column(name).combine_chunks()
        cols[task.renames.get(name, name)] = ogr_column(pa, col) if task.flavor == "ogr" else col
    if "id" in cols:  # id first, as records_table orders it
        cols = {"id": cols.pop("id"), **cols}
    ok = solved.status == OK
    cols["status"] = pa.array(np.where(ok, "ok", "error").tolist(), pa.string())
    usable = np.array([r is None for r in ragged.reason], dtype=bool)
    cols["n"] = pa.array(solved.n, pa.int64(), mask=~usable)
    cols["cost"] = _costs(pa, solved, ok, task.flavor)
    cols["reason"] = pa.array(solved.reason.tolist(), pa.string())
    tris = local_indices(ragged, solved)
    counts = np.diff(solved.triangle_offsets)
    cols["triangles"] = _index_lists(pa, tris, counts, ok, task.flavor)
    if task.flavor == "parquet":
        diag, diag_counts = row_diagonals(tris, counts)
        cols["diagonals"] = _index_lists(pa, diag, diag_counts, ok, "parquet")
    cols["seconds"] = pa.array(solved.seconds, pa.float64())
    wkb, _ = triangle_wkb(ragged, solved)
    cols[GEOMETRY] = pa.array(wkb.tolist(), pa.binary())
    out = pa.table(cols)
    z = bool(ragged.has_z and ragged.row_z[ok].any())
    out = out.replace_schema_metadata({OPTRI_META: json.dumps({"has_z": z})})
    return task.index, explode_table(out) if task.explode else out


def local_indices(ragged: Ragged, solved: Solved) -> NDArray[np.int64]:
    """``solved.triangles`` as indices into each row's own vertices (closing vertices dropped).

    A coordinate ``c`` in ring ``r`` of row ``i`` is vertex
    ``c - first_coordinate(i) - (r - first_ring(i))`` of its row: every earlier
    ring of the row has one closing vertex fewer than it has coordinates.
    """
    tris = solved.triangles
    if not len(tris):
        return tris.reshape(0, 3)
    row = solved.triangle_row
    first_ring = ragged.part_offsets[ragged.row_offsets[:-1]]
    first_coord = ragged.ring_offsets[first_ring]
    ring = np.searchsorted(ragged.ring_offsets, tris, side="right") - 1
    return (tris - first_coord[row][:, None] - (ring - first_ring[row][:, None])).astype(np.int64)


def row_diagonals(
    tris: NDArray[np.int64], counts: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Each row's diagonals (edges two of its triangles share), sorted; and their count per row.

    >>> d, c = row_diagonals(np.array([[0, 1, 3], [1, 2, 3]]), np.array([2]))
    >>> d.tolist(), c.tolist()
    ([[1, 3]], [1])
    """
    rows = len(counts)
    if not len(tris):
        return np.zeros((0, 2), np.int64), np.zeros(rows, np.int64)
    row = np.tile(np.repeat(np.arange(rows, dtype=np.int64), counts), 3)
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    lo, hi = edges.min(axis=1), edges.max(axis=1)
    m = int(hi.max()) + 1
    keys = np.sort((row * m + lo) * m + hi)  # one integer per edge: a 1-D sort
    inner = keys[1:][keys[1:] == keys[:-1]]  # an edge two triangles share: a diagonal
    diag = np.column_stack([(inner // m) % m, inner % m])
    return diag.astype(np.int64), np.bincount(inner // (m * m), minlength=rows)


def _index_lists(
    pa: Any, flat: NDArray[np.int64], counts: NDArray[np.int64], ok: NDArray[np.bool_], flavor: str
) -> Any:
    """Per row, a list of index lists (parquet) or its JSON text (ogr); null on error rows."""
    width = flat.shape[1] if flat.ndim == 2 else 3
    inner = pa.FixedSizeListArray.from_arrays(pa.array(flat.reshape(-1), pa.int64()), width)
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32)
    lists = pa.ListArray.from_arrays(
        pa.array(offsets), inner.cast(pa.list_(pa.int64())), mask=pa.array(~ok)
    )
    if flavor == "parquet":
        return lists
    text = [None if v is None else json.dumps(v) for v in lists.to_pylist()]
    return pa.array(text, pa.string())


def _costs(pa: Any, solved: Solved, ok: NDArray[np.bool_], flavor: str) -> Any:
    cost = solved.cost
    if cost.ndim == 2:  # a lexicographic objective
        values = [list(map(float, c)) if good else None for c, good in zip(cost, ok)]
        if flavor == "ogr":
            return pa.array([None if v is None else json.dumps(v) for v in values], pa.string())
        return pa.array(values, pa.list_(pa.float64()))
    return pa.array(cost, pa.float64(), mask=~ok)
