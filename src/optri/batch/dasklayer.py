"""Layers on a Dask cluster: workers read partitions, solve them and write GeoParquet parts.

:func:`dask_layer` is what ``optri batch --scheduler dask`` runs for GeoParquet,
GeoPackage, FlatGeobuf and shapefile inputs written as GeoParquet. The parent
plans the partitions from the input's metadata (row groups, feature counts) and
the output's schema, and sends each worker where its rows are, not the rows:
one task per partition (:func:`solve_part`) reads them as Arrow (pyarrow, or
pyogrio), solves them on the columnar path of :func:`optri.triangulate_many`
(ragged arrays, the compiled kernel, triangles built as WKB by numpy) and writes
them as one GeoParquet file. Workers never build a pandas frame or a shapely
geometry per row and never import dask.dataframe, so a task costs little more
than its read, its solve and its write. The rows and columns are those of
:func:`optri.triangulate_many` on the layer read by geopandas: the attributes
(columns named ``status``, ``cost`` or ``reason`` renamed), the triangles as the
geometry, then ``status``, ``cost`` and ``reason``.

Every row is written exactly once, even when a worker dies and Dask reruns its
tasks elsewhere: a part is written under a temporary name and renamed to
``part.NNNNN.parquet`` (its partition number) only once complete, so a rerun
replaces a part, never adds a second one, and half-written files never carry a
part's name. The parts are made in a hidden folder beside the output
(``.OUT.dask-parts``); only when every partition is done is that folder renamed
to the output directory, or its parts joined into the output file, so the
output never exists half made.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import shutil
import time
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._optional import import_optional
from ..errors import BatchInputError
from ..io.atomic import fsync_path
from .columns import ragged_from_arrow, solve_ragged, triangle_wkb
from .compiled import many_plan
from .daskframe import cost_dtype
from .each import SolveOptions
from .geo import count_rows, open_arrow_batches, wkb_geometry
from .layer import renamed_columns, warn_geographic, warn_renamed
from .layout import output_lock, plan_layout
from .many import MANY_COLUMNS, with_error_rows
from .partwork import LayerRows, read_rows
from .readers import detect_input_format
from .runner import dask_client
from .solver import check_options
from .summary import BatchSummary

__all__ = [
    "DASK_INPUTS",
    "Frame",
    "Part",
    "PartDone",
    "dask_layer",
    "plan_parts",
    "solve_part",
    "wants_dask_layer",
]

#: Input formats whose partitions Dask workers read themselves (GeoParquet through
#: pyarrow, the others through pyogrio); JSON inputs keep the streaming reader,
#: which turns a bad feature into an error row instead of failing the read.
DASK_INPUTS = ("parquet", "gpkg", "fgb", "shp")
#: Default Dask scheduler retries of a task whose worker died, for clusters made here.
ALLOWED_FAILURES = 3
#: Most rows in a partition by default: a GeoPackage, FlatGeobuf or shapefile is
#: cut in partitions of this many rows, and a larger GeoParquet row group too.
DEFAULT_CHUNKSIZE = 50_000
_PART = "part.{:05d}.parquet"
_SUCCESS = "_SUCCESS"


def wants_dask_layer(
    scheduler: Any,
    inp: str | os.PathLike[str],
    out: str | os.PathLike[str],
    fmt: str | None,
    out_fmt: str | None,
) -> bool:
    """Whether ``optri.batch`` hands this run to :func:`dask_layer`.

    True for a Dask scheduler (``"dask"``, an address, or a ``distributed.Client``),
    an input Dask reads by partitions (:data:`DASK_INPUTS`) and a GeoParquet output
    (a ``.parquet`` file, or a directory with ``out_fmt="parquet"``).

    >>> wants_dask_layer("dask", "roofs.gpkg", "out.parquet", None, None)
    True
    >>> wants_dask_layer("local", "roofs.gpkg", "out.parquet", None, None)
    False
    >>> wants_dask_layer("dask", "roofs.ndjson", "out.parquet", None, None)
    False
    """
    if scheduler is None or scheduler in ("local", "processes"):
        return False
    try:
        kind = detect_input_format(inp, fmt)
        layout = plan_layout(out, out_fmt)
    except BatchInputError:
        return False  # the ordinary path reports it
    return kind in DASK_INPUTS and layout.fmt == "parquet"


@dataclass(frozen=True)
class Frame:
    """What every partition's task shares: the input's geometry, the output's schema, options.

    ``schema`` is the output's Arrow schema (attributes, the geometry as WKB,
    ``status``, ``cost``, ``reason``); ``columns`` maps each output column to
    the input column it comes from (None for the result columns); ``crs`` is the
    GeoParquet ``crs`` member written for the geometry (``...`` when the input's
    GeoParquet metadata has none, which means OGC:CRS84).
    """

    geometry: str
    schema: Any
    columns: tuple[tuple[str, str | None], ...]
    options: SolveOptions
    explode: bool
    crs: Any
    folder: str
    durable: bool
    compression: str | None


@dataclass(frozen=True)
class Part:
    """One partition: rows ``first`` to ``first + count - 1`` of ``source``, its number."""

    number: int
    source: LayerRows
    first: int
    count: int


@dataclass(frozen=True)
class PartDone:
    """What a worker reports of a part it wrote: counts and the bounds of its triangles."""

    number: int
    rows: int
    ok: int
    bbox: tuple[float, float, float, float] | None
    has_z: bool


def dask_layer(
    inp: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    project: bool = False,
    scheduler: Any = None,
    workers: int | None = None,
    npartitions: int | None = None,
    chunksize: int | None = None,
    layer: str | None = None,
    fmt: str | None = None,
    overwrite: bool = False,
    progress: Any = None,
    explode: bool = False,
) -> BatchSummary:
    """Triangulate a layer on a Dask cluster: workers read, solve and write GeoParquet parts.

    Parameters
    ----------
    inp : path
        GeoParquet (a file or a directory of files), GeoPackage, FlatGeobuf or
        shapefile; every worker must see it at the same path (shared storage).
    out : path
        A ``.parquet`` file, or a directory (a path ending in ``/`` or without a
        suffix) that receives ``part.00000.parquet``, ... and ``_SUCCESS``: a
        GeoParquet dataset ``geopandas.read_parquet`` and
        ``dask_geopandas.read_parquet`` open. Workers write into a hidden folder
        beside it, so it too must be on shared storage.
    weight, objective, method, project
        As for :func:`optri.triangulate_many`.
    scheduler : {None, "dask", "tcp://host:port", "dask://host:port"} or distributed.Client
        ``None`` or ``"dask"``: a LocalCluster made for the run: one worker of
        ``workers`` threads in this process when the compiled kernel solves the
        polygons and ``workers`` is at most
        :data:`~optri.config.BATCH_THREADS`, else ``workers`` processes
        (Dask reruns a task whose worker died up to :data:`ALLOWED_FAILURES`
        times); an address: that cluster (its workers already running: no
        start-up cost); a client: its cluster.
    workers : int, optional
        Threads or processes of the LocalCluster (default: every core).
    npartitions, chunksize : int, optional
        Partitions of the input (``chunksize``: rows per partition). GeoParquet
        is read one row group per partition (row groups over
        :data:`DEFAULT_CHUNKSIZE` rows cut) unless one of them is given; other
        formats default to :data:`DEFAULT_CHUNKSIZE` rows. A partition never
        spans two files of a GeoParquet directory.
    layer : str, optional
        The layer of a GeoPackage holding several.
    fmt : str, optional
        The input format, overriding the suffix.
    overwrite : bool
        Replace an existing output (otherwise an existing output is an error).
    progress : callable, optional
        ``progress(done, total)`` in features, called as partitions finish.
    explode : bool
        One row per triangle (:func:`optri.triangulate_many` with ``explode=True``);
        the summary still counts features.

    Returns
    -------
    BatchSummary

    Raises
    ------
    BatchInputError
        A format Dask does not read here, a missing input, an existing output
        without ``overwrite``, an output that is the input, an unknown scheduler.
    BatchLockedError
        Another run is writing the same output.

    Warns
    -----
    GeographicCRSWarning
        The CRS is longitude/latitude and ``project`` is false.

    Examples
    --------
    >>> import geopandas, shapely, tempfile, pathlib
    >>> from optri.batch import dask_layer
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> geopandas.GeoDataFrame(
    ...     {"name": ["a", "b"]}, geometry=[shapely.box(0, 0, 1, 1), shapely.box(0, 0, 2, 1)],
    ...     crs=32633).to_parquet(d / "in.parquet")
    >>> s = dask_layer(d / "in.parquet", d / "out.parquet", workers=1)  # doctest: +SKIP
    >>> geopandas.read_parquet(d / "out.parquet")["status"].tolist()  # doctest: +SKIP
    ['ok', 'ok']
    """
    start = time.perf_counter()
    src = Path(inp)
    kind = detect_input_format(src, fmt)
    if kind not in DASK_INPUTS:
        raise BatchInputError(
            f"{src}: Dask reads {', '.join(DASK_INPUTS)} inputs by partitions, not {kind}; "
            "use the local scheduler or convert the layer to GeoParquet"
        )
    if not src.exists():
        raise BatchInputError(f"{src}: no such file")
    if (npartitions is not None and npartitions < 1) or (chunksize is not None and chunksize < 1):
        raise BatchInputError("npartitions and chunk size must be at least 1")
    layout = plan_layout(out, "parquet")
    layout.check_paths(src)
    target = layout.target
    check_options(weight, objective, method)  # refused before the lock is taken
    options = dict(weight=weight, objective=objective, method=method)
    with output_lock(layout.lock, target):
        if target.exists() and not overwrite:
            raise BatchInputError(f"{target} exists; pass --overwrite to replace it")
        staging = target.parent / f".{target.name}.dask-parts"
        shutil.rmtree(staging, ignore_errors=True)  # a crashed run's parts: not vouched for
        staging.mkdir(parents=True)
        try:
            frame, parts = plan_parts(
                src,
                staging,
                **options,
                project=project,
                explode=explode,
                npartitions=npartitions,
                chunksize=chunksize,
                layer=layer,
                fmt=kind,
                scratch=layout.single,
            )
            done = _run(parts, frame, scheduler, workers, progress)
            _publish(staging, target, frame, done, layout.single)
        finally:
            shutil.rmtree(staging, ignore_errors=True)
    total, ok = sum(d.rows for d in done), sum(d.ok for d in done)
    return BatchSummary(total, ok, total - ok, len(done), 0, time.perf_counter() - start, target)


def _run(
    parts: list[Part], frame: Frame, scheduler: Any, workers: int | None, progress: Any
) -> list[PartDone]:
    """Every part through :func:`solve_part` on the cluster; their reports in partition order."""
    distributed = import_optional("distributed", "dask")
    total = sum(p.count for p in parts)
    run = uuid.uuid4().hex[:12]
    keys = [f"optri-part-{run}-{p.number}" for p in parts]
    done: list[PartDone] = []
    threads = many_plan(frame.options) is not None  # the compiled kernel does the work
    with dask_client(scheduler, workers, ALLOWED_FAILURES, threads=threads) as client:
        futures = client.map(solve_part, parts, frame=frame, key=keys)
        for future in distributed.as_completed(futures):
            done.append(future.result())
            if progress is not None:
                progress(sum(d.rows for d in done), total)
    return sorted(done, key=lambda d: d.number)


def plan_parts(
    inp: str | os.PathLike[str],
    folder: str | os.PathLike[str],
    *,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    project: bool = False,
    explode: bool = False,
    npartitions: int | None = None,
    chunksize: int | None = None,
    layer: str | None = None,
    fmt: str | None = None,
    scratch: bool = False,
) -> tuple[Frame, list[Part]]:
    """The partitions of a layer and what their tasks share: ``solve_part(part, frame)`` each.

    Reads only the input's metadata (row groups, the feature count, the schema).
    Parts are written into ``folder``; ``scratch`` parts (to be joined into
    one file) are written uncompressed and not fsynced. Options as for
    :func:`dask_layer`.

    Warns
    -----
    GeographicCRSWarning
        The CRS is longitude/latitude and ``project`` is false.
    BatchWarning
        Attribute columns renamed because a result column has their name.

    Examples
    --------
    >>> import geopandas, shapely, tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> geopandas.GeoDataFrame(
    ...     {"name": ["a", "b"]}, geometry=[shapely.box(0, 0, 1, 1), shapely.box(0, 0, 2, 1)],
    ...     crs=32633).to_parquet(d / "in.parquet", row_group_size=1)
    >>> frame, parts = plan_parts(d / "in.parquet", d)
    >>> [(p.number, p.first, p.count) for p in parts], frame.schema.names
    ([(0, 0, 1), (1, 1, 1)], ['name', 'geometry', 'status', 'cost', 'reason'])
    >>> done = [solve_part(p, frame) for p in parts]  # what each Dask task does
    >>> [(d.rows, d.ok) for d in done]
    [(1, 1), (1, 1)]
    >>> round(float(geopandas.read_parquet(d / "part.00001.parquet").cost[0]), 6)
    10.472136
    """
    src = Path(inp)
    kind = detect_input_format(src, fmt)
    options = check_options(weight, objective, method)
    frame, parts, crs = _plan(src, kind, layer, options, project, explode, Path(folder))
    if scratch:
        frame = dataclasses.replace(frame, durable=False, compression="none")
    warn_geographic(crs, project)
    return frame, _cut(parts, npartitions, chunksize)


def _plan(
    src: Path,
    kind: str,
    layer: str | None,
    options: dict[str, Any],
    project: bool,
    explode: bool,
    staging: Path,
) -> tuple[Frame, list[Part], str | None]:
    """The output's schema and the input's natural partitions; and the CRS as text."""
    pa = import_optional("pyarrow", "geo")
    if kind == "parquet":
        files = _parquet_files(src)
        if not files:
            raise BatchInputError(f"{src}: no Parquet files in it")
        header, source = open_arrow_batches(files[0], kind)
        schemas: list[Any] = []
        parts: list[Part] = []
        pq = import_optional("pyarrow.parquet", "geo")
        for path in files:
            try:
                pf = pq.ParquetFile(path)
            except Exception as exc:  # pyarrow's own error zoo
                raise BatchInputError(f"{path}: not a Parquet file ({exc})") from None
            groups = tuple(pf.metadata.row_group(k).num_rows for k in range(pf.num_row_groups))
            encoding = (
                source.encoding if path == files[0] else open_arrow_batches(path, kind)[1].encoding
            )
            rows = LayerRows(str(path), kind, sum(groups), row_groups=groups, encoding=encoding)
            first = 0
            for size in groups or (0,):
                parts.append(Part(len(parts), rows, first, size))
                first += size
            schemas.append(pf.schema_arrow)
        schema = pa.unify_schemas(schemas, promote_options="permissive")
        dropped = {source.geometry, *_index_columns(schema)}
        crs_member = _crs_member(schema.metadata, source.geometry)
        geometry = source.geometry
    else:
        header, source = open_arrow_batches(src, kind, layer)
        total = count_rows(src, kind, layer)
        if total is None:
            raise BatchInputError(f"{src}: the layer does not say how many features it holds")
        query = tuple(sorted(source.query.items()))
        stamps = tuple(sorted(source.stamps.items()))
        rows = LayerRows(str(src), kind, total, query=query, stamps=stamps)
        parts = [Part(0, rows, 0, total)]
        schema = header.schema.append(pa.field(source.geometry, pa.binary()))
        dropped = {source.geometry}
        crs_member = _projjson(header.crs)
        geometry = "geometry"  # as geopandas names it
    names = [f.name for f in schema if f.name not in dropped]
    renames = renamed_columns(names, MANY_COLUMNS)
    warn_renamed(renames)
    fields, columns = [], []
    for f in schema:
        if f.name == source.geometry:
            fields.append(pa.field(geometry, pa.binary()))
            columns.append((geometry, None))
        elif f.name not in dropped:
            fields.append(f.with_name(renames.get(f.name, f.name)))
            columns.append((fields[-1].name, f.name))
    cost = pa.list_(pa.float64()) if cost_dtype(options) == "object" else pa.float64()
    for name, kind_ in zip(MANY_COLUMNS, (pa.string(), cost, pa.string()), strict=True):
        fields.append(pa.field(name, kind_))
        columns.append((name, None))
    crs = header.crs
    solve = SolveOptions(**options, project=crs if project else None, threads=1)
    if project and crs is None:
        raise BatchInputError(f"{src}: project=True needs a CRS and the layer has none")
    out = pa.schema(fields)
    frame = Frame(
        source.geometry, out, tuple(columns), solve, explode, crs_member, str(staging), True, None
    )
    return frame, parts, crs


def _cut(parts: list[Part], npartitions: int | None, chunksize: int | None) -> list[Part]:
    """``parts`` cut (or merged, within a file) to ``chunksize`` rows, or into ``npartitions``."""
    total = sum(p.count for p in parts)
    if npartitions is not None and chunksize is None:
        chunksize = max(1, -(-total // npartitions))
    merge = chunksize is not None
    size = chunksize or DEFAULT_CHUNKSIZE
    out: list[Part] = []
    files: dict[str, list[Part]] = {}
    for p in parts:
        files.setdefault(p.source.path, []).append(p)
    for group in files.values():
        spans = (
            [(group[0].first, sum(p.count for p in group))]
            if merge
            else [(p.first, p.count) for p in group]
        )
        for first, count in spans:
            pieces = max(1, -(-count // size))
            step = -(-count // pieces) if count else 0
            for k in range(pieces):
                lo = first + k * step
                n = max(0, min(step, first + count - lo))
                if n or not count:
                    out.append(Part(len(out), group[0].source, lo, n))
    return out


def _index_columns(schema: Any) -> list[str]:
    """Columns pandas stored its index in (``__index_level_0__``): not attributes."""
    raw = (schema.metadata or {}).get(b"pandas")
    try:
        return [c for c in json.loads(raw)["index_columns"] if isinstance(c, str)] if raw else []
    except (ValueError, KeyError, TypeError):
        return []


def _crs_member(metadata: Any, geometry: str) -> Any:
    """The input's GeoParquet ``crs`` member as is (``...`` when absent: OGC:CRS84)."""
    try:
        column = json.loads((metadata or {})[b"geo"])["columns"][geometry]
    except (KeyError, ValueError, TypeError):
        return None  # plain Parquet with a WKB column: CRS unknown
    return column.get("crs", ...)


def _projjson(crs: str | None) -> Any:
    if crs is None:
        return None
    pyproj = import_optional("pyproj", "geo")
    return json.loads(pyproj.CRS.from_user_input(crs).to_json())


def _parquet_files(src: Path) -> list[Path]:
    return sorted(src.rglob("*.parquet")) if src.is_dir() else [src]


def solve_part(part: Part, frame: Frame) -> PartDone:
    """Read, solve and write one partition as ``part.NNNNN.parquet`` in ``frame.folder``.

    Runs on a worker. The file is written under a temporary name and renamed,
    so the part's name only ever holds a complete part, and a task Dask reruns
    (its worker died) replaces the part instead of adding rows. Returns the
    part's feature count, ok count and the bounds of its triangles; the rows of
    an ``explode``-d feature follow one another.
    """
    pa = import_optional("pyarrow", "geo")
    pq = import_optional("pyarrow.parquet", "geo")
    if part.count:  # native GeoArrow geometry is read as WKB
        table = wkb_geometry(
            read_rows(part.source, part.first, part.count), frame.geometry, part.source.encoding
        )
    else:  # an empty layer still gives a part, with the schema
        table = pa.table({frame.geometry: pa.array([], pa.binary())})
    ragged = ragged_from_arrow(table.column(frame.geometry))
    solved = solve_ragged(ragged, frame.options)
    wkb, rows = triangle_wkb(ragged, solved, frame.explode)
    if frame.explode:
        wkb, rows = with_error_rows(wkb, rows, solved)
    ok = solved.status == 0
    results = {
        "status": pa.array(np.where(ok, "ok", "error")[rows].tolist(), pa.string()),
        "cost": _cost_column(pa, solved, ok, frame.schema.field("cost").type).take(rows),
        "reason": pa.array(solved.reason[rows].tolist(), pa.string()),
    }
    take = pa.array(rows, pa.int64())
    arrays = []
    for (name, source), f in zip(frame.columns, frame.schema, strict=True):
        if source is not None:
            col = table.column(source) if source in table.column_names else pa.nulls(len(table))
            arrays.append(col.take(take).cast(f.type))
        elif name in results:
            arrays.append(results[name])
        else:
            arrays.append(pa.array(wkb.tolist(), pa.binary()))
    has_z = bool(ragged.has_z and ragged.row_z[ok].any())
    bbox = _bbox(ragged, ok)
    meta = {b"geo": json.dumps(_geo(frame, [bbox], has_z)).encode()}
    out = pa.Table.from_arrays(arrays, schema=frame.schema.with_metadata(meta))
    final = Path(frame.folder) / _PART.format(part.number)
    temp = final.with_name(f".{final.name}.{uuid.uuid4().hex}.tmp")
    try:
        pq.write_table(out, temp, compression=frame.compression or "snappy")
        if frame.durable:
            fsync_path(temp)
        os.replace(temp, final)
    finally:
        with contextlib.suppress(FileNotFoundError):
            temp.unlink()
    return PartDone(part.number, len(solved), int(np.count_nonzero(ok)), bbox, has_z)


def _cost_column(pa: Any, solved: Any, ok: Any, kind: Any) -> Any:
    """Costs as ``triangulate_many`` gives them: NaN, or a null pair, on an error row."""
    if solved.cost.ndim == 2:
        return pa.array([list(map(float, c)) if g else None for c, g in zip(solved.cost, ok)], kind)
    return pa.array(np.where(ok, solved.cost, np.nan), kind)


def _bbox(ragged: Any, ok: Any) -> tuple[float, float, float, float] | None:
    """The x-y bounds of the part's triangles: those of its ok rows' vertices."""
    if not ok.any():
        return None
    xy = ragged.coords[:, :2]
    if not ok.all():  # each row's vertices, kept where the row is ok
        ends = ragged.ring_offsets[ragged.part_offsets[ragged.row_offsets]]
        xy = xy[np.repeat(ok, np.diff(ends))]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))


def _geo(frame: Frame, boxes: list[Any], has_z: bool) -> dict:
    """GeoParquet 1.1 metadata for the output's geometry: types, CRS, bounds of ``boxes``."""
    kind = "Polygon" if frame.explode else "GeometryCollection"
    kinds = [f"{kind} Z" if has_z else kind]
    name = next(n for n, s in frame.columns if s is None and n not in MANY_COLUMNS)
    column: dict[str, Any] = {"encoding": "WKB", "geometry_types": kinds}
    if frame.crs is not ...:
        column["crs"] = frame.crs
    found = [b for b in boxes if b is not None]
    if found:
        column["bbox"] = [
            min(b[0] for b in found),
            min(b[1] for b in found),
            max(b[2] for b in found),
            max(b[3] for b in found),
        ]
    return {"version": "1.1.0", "primary_column": name, "columns": {name: column}}


def _publish(staging: Path, target: Path, frame: Frame, done: list[PartDone], single: bool) -> None:
    """Make the output appear whole: every part there, once, with one schema."""
    parts = [staging / _PART.format(d.number) for d in done]
    missing = [p.name for p in parts if not p.is_file()]
    if missing or len({d.number for d in done}) != len(done):
        raise BatchInputError(f"{target}: parts missing or repeated after the run: {missing}")
    for stray in staging.glob(".*.tmp"):  # left by a worker that died while writing
        stray.unlink()
    geo = _geo(frame, [d.bbox for d in done], any(d.has_z for d in done))
    if single:
        schema = frame.schema.with_metadata({b"geo": json.dumps(geo).encode()})
        _join(parts, schema, staging / ".joined.tmp")
        os.replace(staging / ".joined.tmp", target)
        return
    summary = {
        "rows": sum(d.rows for d in done),
        "ok": sum(d.ok for d in done),
        "partitions": len(parts),
    }
    (staging / _SUCCESS).write_text(json.dumps(summary) + "\n")
    if target.exists():
        shutil.rmtree(target)
    os.rename(staging, target)


def _join(parts: list[Path], schema: Any, dest: Path) -> None:
    """Stream every part, in partition order, into one GeoParquet file."""
    pq = import_optional("pyarrow.parquet", "geo")
    with pq.ParquetWriter(dest, schema) as writer:
        for p in parts:
            table = pq.read_table(p)
            if table.num_rows:
                writer.write_table(table.replace_schema_metadata(schema.metadata))
    fsync_path(dest)
