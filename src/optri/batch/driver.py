"""``batch``: stream a layer, triangulate it in chunks, write parts, resume, assemble."""

from __future__ import annotations

import itertools
import json
import os
import pickle
import shutil
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import config
from .._optional import import_optional
from .._version import __version__
from ..engines.interrupts import stop_signals_unwind
from ..errors import BatchFailedError, BatchInputError
from ..io.atomic import write_json
from .chunks import TableTask
from .compiled import many_plan
from .dasklayer import dask_layer, wants_dask_layer
from .geo import ArrowSource, count_rows, open_arrow_batches
from .layer import Layer, projjson_text, warn_geographic
from .layout import Layout, file_sha256, job_key, output_lock, plan_layout
from .partwork import LayerRows, PartWritten, ReadTask, ids_of
from .project import local_projector
from .readers import count_items, detect_input_format, open_layer
from .records import ChunkTask, Item
from .runner import open_backend, run_tasks, start_pool_server
from .solver import SolveOptions, check_options
from .summary import BatchSummary, Counter, report_duplicates
from .tablefiles import PartJoiner, flavor_of, write_table
from .tables import TRIANGLE, feature_rows
from .writers import SINGLE_FILE_SUFFIXES, assemble, read_part, write_part

__all__ = ["BatchSummary", "batch", "iter_records"]

#: Input formats read as Arrow record batches (solved chunk by chunk as tables).
ARROW_INPUTS = ("parquet", "gpkg", "fgb", "shp")


@dataclass(frozen=True)
class _Settings:
    """Everything ``batch`` was asked, in one place."""

    options: dict[str, Any]
    workers: int | None
    chunk_size: int | None
    scheduler: Any
    resume: bool
    overwrite: bool
    progress: Callable[[int, int], None] | None
    fmt: str | None
    out_fmt: str | None
    project: bool
    layer: str | None
    explode: bool = False


def batch(
    inp: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    weight: Any = "perimeter",
    objective: Any = "sum",
    method: str = "auto",
    workers: int | None = None,
    chunk_size: int | None = None,
    scheduler: Any = None,
    resume: bool = True,
    overwrite: bool = False,
    strict: bool = False,
    progress: Callable[[int, int], None] | None = None,
    fmt: str | None = None,
    out_fmt: str | None = None,
    project: bool = False,
    layer: str | None = None,
    explode: bool = False,
) -> BatchSummary:
    r"""Triangulate every polygon of a layer, in parallel, into one record per feature.

    Parameters
    ----------
    inp : path
        GeoJSON FeatureCollection (``.geojson``/``.json``), NDJSON (``.ndjson``/
        ``.jsonl``: one ``{"id", "coordinates"}`` object or GeoJSON Feature per
        line), GeoParquet (``.parquet``), GeoPackage (``.gpkg``), FlatGeobuf
        (``.fgb``) or shapefile (``.shp``; the last four need
        ``pip install 'optri[geo]'``).
    out : path
        One file, its format from its suffix (``.gpkg``, ``.fgb``, ``.parquet``,
        ``.geojson``, ``.ndjson``) or from ``out_fmt``; or a directory of part
        files (a path ending in ``/``, or without a suffix) that can be resumed.
    weight, objective, method
        As for :func:`optri.triangulate`; checked before anything is read.
    workers : int, optional
        Processes (default: every core; 1 runs in this process).
    chunk_size : int, optional
        Polygons per part (default: tuned from the sizes of the first polygons).
    scheduler : {None, "local", "dask", "dask://host:port"} or distributed.Client
        Local process pool (default), a Dask LocalCluster made for the run, an
        existing Dask scheduler, or a client you already hold.
    resume : bool
        Keep parts an earlier run of the same command completed (default).
        With ``resume=False`` existing output is an error unless ``overwrite``.
    overwrite : bool
        Delete earlier output first and redo everything.
    strict : bool
        Raise :class:`BatchFailedError` at the end if any polygon failed.
    progress : callable, optional
        ``progress(done, total)`` in polygons.
    fmt, out_fmt : str, optional
        Input format (geojson, ndjson, parquet, gpkg, fgb, shp) and output
        format (ndjson, geojson, parquet, gpkg, fgb), overriding the suffixes.
    project : bool
        Measure each polygon in metres, in a local azimuthal equidistant
        projection of the layer's CRS (see :mod:`optri.batch.project`).
    layer : str, optional
        The layer to read from a file holding several (GeoPackage); such a
        file without ``layer`` is refused, its layers listed.
    explode : bool
        One output row per triangle (a Polygon) instead of one per feature: each
        with the feature's id, attributes, ``status``, ``n``, ``cost``,
        ``reason``, ``seconds`` and ``triangle`` (its number within the feature,
        from 0); an error row stays one row without geometry. The summary still
        counts features.

    Returns
    -------
    BatchSummary

    Raises
    ------
    BatchInputError
        Unreadable input (the message names file and line), output written with
        other options or input (or not by a batch at all), an output that is the
        input, a work folder or lock file that is a link or another user's,
        unknown format, suffix, layer or scheduler.
    BatchLockedError
        Another run is writing the same output.
    WeightError, EngineUnavailableError
        Unknown weight, objective or method (before anything is read).
    BatchFailedError
        ``strict=True`` and some polygons got error records.

    Warns
    -----
    GeographicCRSWarning
        The layer is in longitude/latitude and ``project`` is false.
    DuplicateIdWarning
        Some features share an id (also counted in the summary).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "in.ndjson").write_text(
    ...     '{"id": "a", "coordinates": [[0, 0], [1, 0], [1, 1], [0, 1]]}\n'
    ...     '{"id": "b", "coordinates": [[0, 0], [1, 1]]}\n'
    ...     '{"id": "c", "coordinates": [[0, 0], [1, 0\n')
    >>> s = batch(d / "in.ndjson", d / "out.ndjson", workers=1)
    >>> s.ok, s.errors
    (1, 2)
    >>> [(r["id"], r["status"], r["diagonals"]) for r in iter_records(d / "out.ndjson")]
    [('a', 'ok', [[1, 3]]), ('b', 'error', None), ('c', 'error', None)]
    """
    options = check_options(weight, objective, method)
    if not (workers == 1 and scheduler in (None, "local")):
        _require_picklable(options)
    settings = _Settings(
        options,
        workers,
        chunk_size,
        scheduler,
        resume,
        overwrite,
        progress,
        fmt,
        out_fmt,
        project,
        layer,
        explode,
    )
    with stop_signals_unwind():  # kill and hang-up also remove half-written parts
        if wants_dask_layer(scheduler, inp, out, fmt, out_fmt):  # workers read and write
            summary = dask_layer(
                inp,
                out,
                **options,
                project=project,
                scheduler=scheduler,
                workers=workers,
                chunksize=chunk_size,
                layer=layer,
                fmt=fmt,
                overwrite=overwrite,
                progress=progress,
                explode=explode,
            )
        else:
            summary = _run(Path(inp), out, settings)
    if strict and summary.errors:
        raise BatchFailedError(f"{summary.errors} of {summary.total} polygons failed", summary)
    return summary


def _require_picklable(options: dict[str, Any]) -> None:
    # worker processes receive the options by pickle: say so now, not deep in a pool
    try:
        pickle.dumps(options)
    except Exception as exc:
        raise BatchInputError(
            f"the weight or objective cannot be sent to worker processes ({exc}); "
            "use workers=1 or a module-level function"
        ) from None


def _run(inp: Path, out: str | os.PathLike[str], s: _Settings) -> BatchSummary:
    start = time.perf_counter()
    kind = detect_input_format(inp, s.fmt)
    if not inp.is_file():
        what = "is a directory, not a layer file" if inp.is_dir() else "no such file"
        raise BatchInputError(f"{inp}: {what}")
    layout = plan_layout(out, s.out_fmt)
    columnar = kind in ARROW_INPUTS and layout.part_fmt == "parquet" and config.BATCH_COLUMNAR
    start_pool_server(s.scheduler, s.workers, threads=columnar and _compiled(s.options))
    layout.check_paths(inp)
    with output_lock(layout.lock, layout.target):
        layout.check_work_folder()
        job = _job(inp, kind, layout, s)
        if not s.overwrite:
            if layout.started() and not s.resume:
                raise BatchInputError(f"{layout.target} exists; pass --overwrite or --resume")
            if layout.single and layout.target.exists():
                layout.check_receipt(job)
                return _summary_of_existing(layout, start, s.explode)
        if columnar:
            layer, source = open_arrow_batches(inp, kind, s.layer)
            budget = _chunk_work(s.options)
            chunks, size = _table_chunks(
                source, s.chunk_size, None if s.overwrite else layout, budget
            )
        else:
            layer, items = open_layer(inp, kind, s.layer)
            items, size = _choose_chunk_size(items, s.chunk_size, None if s.overwrite else layout)
        crs = _projection(inp, layer, s.project)
        warn_geographic(layer.crs, s.project)
        if s.overwrite:  # only now: a bad input file must not cost the earlier output
            layout.clear()
        layout.prepare()
        manifest = {**job, "chunk_size": size}
        layout.check_manifest(manifest)
        layout.remove_stale_temporaries()
        recorded = layout.recorded(job_key(manifest))
        layout.drop_unrecorded(recorded)
        total = (count_items(inp, kind, s.layer) or 0) if s.progress is not None else 0
        counter = Counter(s.progress, total)
        work = _Work(layout, layer, size, job_key(manifest), recorded)
        join = (
            columnar
            and layout.single
            and layout.fmt == "parquet"
            and config.BATCH_JOIN_WHILE_SOLVING
        )
        with PartJoiner(layout.target, layer, layout.part) if join else _NoJoiner() as joiner:
            if columnar:
                reader = _rows_for_workers(inp, kind, source, s)
                _solve_tables(work, chunks, source, s, crs, counter, reader, joiner)
            else:
                _solve_all(work, items, s, crs, counter)
            if not layout.single:  # the parts are the product: on disk before _SUCCESS says so
                layout.sync()
            done = {"ok": counter.ok, "errors": counter.errors, "total": counter.n}
            write_json(layout.success, done)
            if layout.single:
                if not joiner.finish(layout.parts()):
                    assemble(layout.parts(), layout.fmt, layout.target, layer, layout.parts_dir)
                layout.write_receipt(manifest)
                shutil.rmtree(layout.parts_dir, ignore_errors=True)
        duplicates, repeated = counter.repeated_hashes()
        rows = iter_records(layout.target, layout.fmt)
        report_duplicates(duplicates, repeated, feature_rows(rows) if s.explode else rows)
        return counter.summary(layout.target, time.perf_counter() - start, duplicates)


class _NoJoiner:
    """Stands for a :class:`~optri.batch.tablefiles.PartJoiner` where parts are not joined early."""

    def __enter__(self) -> _NoJoiner:
        return self

    def __exit__(self, *exc: Any) -> None:
        return None

    def ready(self, index: int) -> None:
        """Nothing to do: the parts are assembled at the end."""

    def finish(self, parts: Any) -> bool:
        """False: the caller assembles the parts."""
        return False


@dataclass(frozen=True)
class _Work:
    """Where the parts of one job go, and which earlier parts the ledger vouches for."""

    layout: Layout
    layer: Layer
    size: int
    job: str
    recorded: dict[str, str]


def _solve_all(
    work: _Work, items: Iterator[Item], s: _Settings, crs: str | None, counter: Counter
) -> None:
    """Solve every pending chunk on the backend; the parent alone writes the parts."""
    in_flight: dict[int, list[Item]] = {}  # chunk index -> its Items (attributes included)
    layout = work.layout
    tasks = _pending_tasks(items, work, {**s.options, "project": crs}, counter, in_flight, s)

    def done(task: Any, records: Any) -> None:
        chunk = in_flight.pop(task.index)
        part = layout.part(task.index)
        write_part(part, layout.part_fmt, records, chunk, work.layer, layout.fmt, s.explode)
        layout.record(task.index, task.index * work.size, len(records), work.job)
        counter.add(records, reused=False)

    # processes: feature-by-feature Python (JSON, records) holds the GIL most of the time
    with open_backend(s.scheduler, s.workers) as backend:
        run_tasks(backend, tasks, done)


def _solve_tables(
    work: _Work,
    chunks: Iterator[Any],
    source: ArrowSource,
    s: _Settings,
    crs: str | None,
    counter: Counter,
    reader: LayerRows | None = None,
    joiner: PartJoiner | _NoJoiner | None = None,
) -> None:
    """Solve every pending chunk of an Arrow layer as a table (:mod:`.chunks`).

    With ``reader`` each chunk goes to a worker as a :class:`~optri.batch.partwork.ReadTask`
    (the worker reads its rows and writes its part); else the parent reads the
    chunks (``chunks``) and writes their parts. ``joiner`` hears of each part
    complete on disk, made now or kept from an earlier run.
    """
    joiner = joiner or _NoJoiner()
    layout = work.layout
    options = {**s.options, "project": crs}
    flavor = flavor_of(layout.fmt)
    renames = work.layer.renames
    crs_json = _crs_json(work.layer.crs) if reader is not None else None

    def task(index: int, table: Any) -> TableTask | ReadTask:
        first = index * work.size
        if reader is not None:
            count = min(work.size, reader.rows - first)
            part = str(layout.part(index))
            return ReadTask(
                index, reader, first, count, source.geometry, source.fid, renames, flavor,
                s.explode, part, work.layer.crs, crs_json, **options,
            )  # fmt: skip
        fid, table = ids_of(table, source.fid, first)
        return TableTask(
            index, table, source.geometry, first, fid, renames, flavor, s.explode, **options
        )

    def tasks() -> Iterator[TableTask | ReadTask]:
        count = -(-reader.rows // work.size) if reader is not None else 0
        for index, table in enumerate(itertools.repeat(None, count) if count else chunks):
            if layout.adopted(index, work.recorded):
                counter.add(_adopted(layout, index, s.explode), reused=True)
                joiner.ready(index)
                continue
            yield task(index, table)

    finished = _table_done(work, s, counter)

    def done(task: Any, table: Any) -> None:
        finished(task, table)
        joiner.ready(task.index)

    # threads where the compiled kernel solves the columns: it, Arrow and shapely release
    # the GIL (config.BATCH_THREADS)
    with open_backend(s.scheduler, s.workers, threads=_compiled(s.options)) as backend:
        run_tasks(backend, tasks(), done)


def _crs_json(crs: str | None) -> str | None:
    """``crs`` as PROJJSON for the workers; None (each worker derives it) when unparsable."""
    try:
        return projjson_text(crs)
    except Exception:  # pyproj's CRSError: the part writer raises it as before
        return None


def _table_done(work: _Work, s: _Settings, counter: Counter) -> Callable[[Any, Any], None]:
    """What the parent does with a finished table chunk: a part a worker wrote, or a table."""
    layout = work.layout

    def done(task: Any, table: Any) -> None:
        first = task.index * work.size
        if isinstance(table, PartWritten):  # the worker wrote the part and hashed it
            layout.record(task.index, first, table.rows, work.job, table.sha256)
            counter.add_counts(table.hashes, table.ok)
            return
        part = layout.part(task.index)
        write_table(part, table, layout.part_fmt, work.layer, layout.parts_dir, durable=False)
        if s.explode:  # count features: the first row of each
            pc = import_optional("pyarrow.compute")
            table = table.filter(pc.fill_null(pc.equal(table.column(TRIANGLE), 0), True))
        layout.record(task.index, first, table.num_rows, work.job)
        counter.add_rows(table.column("id").to_pylist(), table.column("status").to_pylist())

    return done


def _rows_for_workers(inp: Path, kind: str, source: ArrowSource, s: _Settings) -> LayerRows | None:
    """How workers read the layer's rows themselves; None when the parent must read them.

    The parent reads when asked to (``config.BATCH_WORKERS_READ``), for Dask (its
    workers need not share the parent's files) and when the row count is unknown.
    """
    if not config.BATCH_WORKERS_READ or s.scheduler not in (None, "local", "processes"):
        return None
    if kind == "parquet":
        pq = import_optional("pyarrow.parquet")
        meta = pq.ParquetFile(inp).metadata
        groups = tuple(meta.row_group(k).num_rows for k in range(meta.num_row_groups))
        return LayerRows(str(inp), kind, sum(groups), row_groups=groups, encoding=source.encoding)
    total = count_rows(inp, kind, s.layer)
    if total is None:
        return None
    query = tuple(sorted(source.query.items()))
    stamps = tuple(sorted(source.stamps.items()))
    return LayerRows(str(inp), kind, total, query=query, stamps=stamps)


def _compiled(options: dict[str, Any]) -> bool:
    """Whether the compiled many-polygon kernel solves polygons with these options."""
    return many_plan(SolveOptions(**options, threads=1)) is not None


def _chunk_work(options: dict[str, Any]) -> int:
    """Work per columnar chunk: larger when the compiled kernel solves it (see config)."""
    return config.BATCH_COMPILED_CHUNK_WORK if _compiled(options) else config.BATCH_CHUNK_WORK


def _table_chunks(
    source: ArrowSource, chunk_size: int | None, layout: Layout | None, work: int
) -> tuple[Iterator[Any], int]:
    """The layer's rows as tables of ``size`` rows (the last may be shorter), and ``size``."""
    pa = import_optional("pyarrow")
    shapely = import_optional("shapely")
    batches = iter(source.batches)
    head = list(itertools.islice(batches, 1))  # an unreadable file fails before any output
    size = chunk_size
    if size is not None and size < 1:
        raise BatchInputError(f"chunk size must be at least 1, got {size}")
    previous = None if layout is None else _manifest_value(layout, "chunk_size")
    if size is None and isinstance(previous, int):
        size = previous
    if size is None:
        column = head[0].column(source.geometry) if head else pa.array([], pa.binary())
        # to_pylist, not to_numpy: pyarrow's numpy conversion imports pandas
        raw = column.slice(0, config.BATCH_CHUNK_SAMPLE).to_pylist()
        geoms = shapely.from_wkb(np.array(raw, dtype=object), on_invalid="ignore")
        n = shapely.get_num_coordinates(geoms) - shapely.get_num_interior_rings(geoms) - 1
        size = auto_chunk_size([Item(0, [[0, 0]] * max(int(k), 0)) for k in n], work)

    def chunks() -> Iterator[Any]:
        held: list[Any] = []
        rows = 0
        for batch in itertools.chain(head, batches):
            held.append(batch)
            rows += batch.num_rows
            while rows >= size:
                table = pa.Table.from_batches(held)
                yield table.slice(0, size)
                rest = table.slice(size)
                held, rows = rest.to_batches(), rest.num_rows
        if rows:
            yield pa.Table.from_batches(held)

    return chunks(), size


def _projection(inp: Path, layer: Layer, project: bool) -> str | None:
    """The CRS the workers project from, checked now; None without ``project``."""
    if not project:
        return None
    if layer.crs is None:
        raise BatchInputError(
            f"{inp}: --project needs the layer's CRS and this {layer.fmt} layer names none; "
            "write it as GeoPackage, GeoParquet or a GeoJSON FeatureCollection with its CRS"
        )
    local_projector(layer.crs)  # an unknown CRS is refused before any work
    return layer.crs


def iter_records(path: str | os.PathLike[str], fmt: str | None = None) -> Iterator[dict]:
    """Records of a batch output (a directory of parts or a single file), in input order."""
    p = Path(path)
    if p.is_dir():
        kinds = [fmt] if fmt else [_manifest_value(Layout(p, p, "ndjson", False), "format")]
        for kind in kinds if kinds[0] else ["ndjson", "geojson", "parquet", "gpkg", "fgb"]:
            parts = Layout(p, p, kind, False).parts()
            if parts:
                for part in parts:
                    yield from read_part(part, kind)
                return
        return
    kind = fmt or SINGLE_FILE_SUFFIXES.get(p.suffix.lower())
    if kind is None:
        raise BatchInputError(f"{p}: not a batch output (unknown suffix)")
    yield from read_part(p, kind)


def _pending_tasks(
    items: Iterable[Item],
    work: _Work,
    options: dict[str, Any],
    counter: Counter,
    in_flight: dict[int, list[Item]],
    s: _Settings,
) -> Iterator[ChunkTask]:
    """Chunk tasks by input position, skipping (and counting) parts the ledger vouches for."""
    it = iter(items)
    layout = work.layout
    for index in itertools.count():
        chunk = list(itertools.islice(it, work.size))
        if not chunk:
            return
        if layout.adopted(index, work.recorded):
            counter.add(_adopted(layout, index, s.explode), reused=True)
            continue
        in_flight[index] = chunk
        yield ChunkTask(index, [item.for_worker() for item in chunk], **options)


def _choose_chunk_size(
    items: Iterator[Item], chunk_size: int | None, layout: Layout | None
) -> tuple[Iterator[Item], int]:
    # read the first polygon now: an unreadable file fails before any output is made
    items = itertools.chain(list(itertools.islice(items, 1)), items)
    if chunk_size is not None:
        if chunk_size < 1:
            raise BatchInputError(f"chunk size must be at least 1, got {chunk_size}")
        return items, chunk_size
    previous = None if layout is None else _manifest_value(layout, "chunk_size")
    if isinstance(previous, int):  # resuming: the parts on disk fix the partitioning
        return items, previous
    sample = list(itertools.islice(items, config.BATCH_CHUNK_SAMPLE))
    return itertools.chain(sample, items), auto_chunk_size(sample)


def auto_chunk_size(sample: list[Item], budget: int | None = None) -> int:
    """Polygons per chunk so one chunk is about ``budget`` work (O(n^3) per polygon).

    ``budget`` defaults to ``config.BATCH_CHUNK_WORK``.

    >>> auto_chunk_size([Item(0, [[0, 0]] * 64)]), auto_chunk_size([Item(0, [[0, 0]] * 8)])
    (9, 583)
    >>> auto_chunk_size([Item(0, [[0, 0]] * 64)], config.BATCH_COMPILED_CHUNK_WORK)
    451
    """
    lo, hi = config.BATCH_CHUNK_MIN, config.BATCH_CHUNK_MAX
    if not sample:
        return lo
    sizes = [len(it.coords) if it.reason is None and it.coords is not None else 0 for it in sample]
    work = sum(config.BATCH_POLYGON_WORK + n**3 / 6 for n in sizes) / len(sizes)
    budget = config.BATCH_CHUNK_WORK if budget is None else budget
    return int(min(hi, max(lo, budget // work)))


def _job(inp: Path, kind: str, layout: Layout, s: _Settings) -> dict[str, Any]:
    """What the records depend on: the input (path, size, time, content hash), options, version."""
    st = inp.stat()
    return {
        "input": str(inp.resolve()),
        "input_bytes": st.st_size,
        "input_mtime_ns": st.st_mtime_ns,
        "input_sha256": file_sha256(inp),
        "input_format": kind,
        "layer": s.layer,
        "format": layout.fmt,
        "weight": repr(s.options["weight"]),
        "objective": repr(s.options["objective"]),
        "method": s.options["method"],
        "project": s.project,
        "explode": s.explode,
        "optri": __version__,
    }


def _manifest_value(layout: Layout, key: str) -> Any:
    try:
        return json.loads(layout.manifest.read_text()).get(key)
    except (OSError, ValueError):
        return None


def _adopted(layout: Layout, index: int, explode: bool) -> Iterator[dict]:
    """The records of an earlier run's part ``index``: one per feature."""
    rows = read_part(layout.part(index), layout.part_fmt)
    return feature_rows(rows) if explode else rows


def _summary_of_existing(layout: Layout, start: float, explode: bool) -> BatchSummary:
    counter = Counter(None, 0)
    rows = read_part(layout.target, layout.fmt)
    counter.add(feature_rows(rows) if explode else rows, reused=True)
    return counter.summary(layout.target, time.perf_counter() - start)
