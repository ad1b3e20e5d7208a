"""``batch``: stream polygons from a file, triangulate them in chunks, write parts, resume."""

from __future__ import annotations

import itertools
import json
import os
import pickle
import shutil
import signal
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import config
from .._version import __version__
from ..errors import BatchFailedError, BatchInputError
from ..io.atomic import write_json
from .layout import Layout, plan_layout
from .readers import count_items, detect_input_format, read_items
from .records import ChunkTask, Item
from .runner import open_backend, run_tasks
from .writers import SINGLE_FILE_SUFFIXES, assemble, read_part, write_part

__all__ = ["BatchSummary", "batch", "iter_records"]



@dataclass(frozen=True)
class BatchSummary:
    """Counts of a batch run.

    Attributes
    ----------
    total, ok, errors : int
        Polygons read, triangulated, and given error records.
    partitions, reused : int
        Part files in the output, and how many an earlier run had already written.
    seconds : float
        Wall time of this run.
    output : Path
        The output directory or file.

    Examples
    --------
    >>> import optri, tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "footprints.ndjson"
    >>> s = optri.batch(optri.data.path("footprints.ndjson"), out, workers=1)
    >>> s.total, s.ok, s.errors       # one bow-tie among the 31 footprints
    (31, 30, 1)
    """

    total: int
    ok: int
    errors: int
    partitions: int
    reused: int
    seconds: float
    output: Path

    def __str__(self) -> str:
        rate = self.total / self.seconds if self.seconds > 0 else 0.0
        return (
            f"{self.total} polygons: {self.ok} ok, {self.errors} errors in {self.seconds:.2f} s "
            f"({rate:.0f}/s; {self.partitions} partitions, {self.reused} reused) -> {self.output}"
        )


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
) -> BatchSummary:
    r"""Triangulate every polygon of a file, in parallel, into part files that resume.

    Parameters
    ----------
    inp : path
        GeoJSON FeatureCollection (``.geojson``/``.json``), NDJSON (``.ndjson``/
        ``.jsonl``: one ``{"id", "coordinates"}`` object or GeoJSON Feature per
        line), GeoParquet (``.parquet``) or GeoPackage (``.gpkg``; the last two
        need ``pip install 'optri[geo]'``).
    out : path
        A directory of part files (``part-00000.ndjson``, ..., ``_manifest.json``,
        ``_SUCCESS``), or a single ``.ndjson``/``.geojson``/``.parquet`` file
        joined from the parts at the end.
    weight, objective, method
        As for :func:`optri.triangulate`.
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
        Input format (geojson, ndjson, parquet, gpkg) and output format
        (ndjson, geojson, parquet) when the suffixes do not say.

    Returns
    -------
    BatchSummary

    Raises
    ------
    BatchInputError
        Unreadable input (the message names file and line), output written with
        other options, unknown format or scheduler.
    BatchFailedError
        ``strict=True`` and some polygons got error records.

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "in.ndjson").write_text(
    ...     '{"id": "a", "coordinates": [[0, 0], [1, 0], [1, 1], [0, 1]]}\n'
    ...     '{"id": "b", "coordinates": [[0, 0], [1, 1]]}\n')
    >>> s = batch(d / "in.ndjson", d / "out.ndjson", workers=1)
    >>> s.ok, s.errors
    (1, 1)
    >>> [(r["id"], r["status"], r["diagonals"]) for r in iter_records(d / "out.ndjson")]
    [('a', 'ok', [[1, 3]]), ('b', 'error', None)]
    """
    options = dict(weight=weight, objective=objective, method=method)
    if not (workers == 1 and scheduler in (None, "local")):
        _require_picklable(options)
    with _sigterm_interrupts():
        summary = _run(
            Path(inp),
            out,
            options,
            workers,
            chunk_size,
            scheduler,
            resume,
            overwrite,
            progress,
            fmt,
            out_fmt,
        )
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


def _run(
    inp: Path,
    out: str | os.PathLike[str],
    options: dict[str, Any],
    workers: int | None,
    chunk_size: int | None,
    scheduler: Any,
    resume: bool,
    overwrite: bool,
    progress: Callable[[int, int], None] | None,
    fmt: str | None,
    out_fmt: str | None,
) -> BatchSummary:

    start = time.perf_counter()
    kind = detect_input_format(inp, fmt)
    if not inp.is_file():
        raise BatchInputError(f"{inp}: no such file")
    layout = plan_layout(out, out_fmt)
    if not overwrite:
        if layout.started() and not resume:
            raise BatchInputError(f"{layout.target} exists; pass --overwrite or --resume")
        if layout.single and layout.target.exists():
            return _summary_of_existing(layout, start)
    items = read_items(inp, kind)
    items, size = _choose_chunk_size(items, chunk_size, None if overwrite else layout)
    if overwrite:  # only now: a bad input file must not cost the earlier output
        layout.clear()
    layout.parts_dir.mkdir(parents=True, exist_ok=True)
    layout.check_manifest(_manifest(inp, kind, layout, options, size))
    layout.remove_stale_temporaries()
    total = (count_items(inp, kind) or 0) if progress is not None else 0
    counter = _Counter(progress, total)
    tasks = _pending_tasks(items, size, layout, options, counter)

    def done(task: ChunkTask, records: list[dict]) -> None:
        write_part(layout.part(task.index), layout.fmt, records, [it.coords for it in task.items])
        counter.add(records, reused=False)

    with open_backend(scheduler, workers) as backend:
        run_tasks(backend, tasks, done)
    write_json(layout.success, {"ok": counter.ok, "errors": counter.errors, "total": counter.n})
    if layout.single:
        assemble(layout.parts(), layout.fmt, layout.target)
        shutil.rmtree(layout.parts_dir, ignore_errors=True)
    return counter.summary(layout.target, time.perf_counter() - start)


def iter_records(path: str | os.PathLike[str], fmt: str | None = None) -> Iterator[dict]:
    """Records of a batch output (a directory of parts or a single file), in input order."""
    p = Path(path)
    if p.is_dir():
        kinds = [fmt] if fmt else [_manifest_value(Layout(p, p, "ndjson", False), "format")]
        for kind in kinds if kinds[0] else ["ndjson", "geojson", "parquet"]:
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


class _Counter:
    """Running totals, reported to ``progress`` after each chunk."""

    def __init__(self, progress: Callable[[int, int], None] | None, total: int) -> None:
        self.progress, self.total = progress, total
        self.n = self.ok = self.errors = self.parts = self.reused = 0
        if progress is not None:
            progress(0, total)

    def add(self, records: Iterable[dict], reused: bool) -> None:
        for rec in records:
            self.n += 1
            self.ok += rec["status"] == "ok"
        self.errors = self.n - self.ok
        self.parts += 1
        self.reused += reused
        if self.progress is not None:
            self.progress(self.n, max(self.total, self.n))

    def summary(self, output: Path, seconds: float) -> BatchSummary:
        return BatchSummary(self.n, self.ok, self.errors, self.parts, self.reused, seconds, output)


def _pending_tasks(
    items: Iterable[Item],
    size: int,
    layout: Layout,
    options: dict[str, Any],
    counter: _Counter,
) -> Iterator[ChunkTask]:
    """Chunk tasks by input position, skipping (and counting) parts already written."""
    it = iter(items)
    for index in itertools.count():
        chunk = list(itertools.islice(it, size))
        if not chunk:
            return
        part = layout.part(index)
        if part.exists():
            counter.add(read_part(part, layout.fmt), reused=True)
            continue
        yield ChunkTask(index, chunk, **options)


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


def auto_chunk_size(sample: list[Item]) -> int:
    """Polygons per chunk so one chunk is about ``config.BATCH_CHUNK_WORK`` (O(n^3) per polygon).

    >>> auto_chunk_size([Item(0, [[0, 0]] * 64)]), auto_chunk_size([Item(0, [[0, 0]] * 8)])
    (9, 583)
    """
    lo, hi = config.BATCH_CHUNK_MIN, config.BATCH_CHUNK_MAX
    if not sample:
        return lo
    sizes = [len(it.coords) if isinstance(it.coords, list) else 0 for it in sample]
    work = sum(config.BATCH_POLYGON_WORK + n**3 / 6 for n in sizes) / len(sizes)
    return int(min(hi, max(lo, config.BATCH_CHUNK_WORK // work)))


def _manifest(
    inp: Path, kind: str, layout: Layout, options: dict[str, Any], size: int
) -> dict[str, Any]:
    st = inp.stat()
    return {
        "input": str(inp.resolve()),
        "input_bytes": st.st_size,
        "input_mtime_ns": st.st_mtime_ns,
        "input_format": kind,
        "format": layout.fmt,
        "weight": repr(options["weight"]),
        "objective": repr(options["objective"]),
        "method": options["method"],
        "chunk_size": size,
        "optri": __version__,
    }


def _manifest_value(layout: Layout, key: str) -> Any:
    try:
        return json.loads(layout.manifest.read_text()).get(key)
    except (OSError, ValueError):
        return None


def _summary_of_existing(layout: Layout, start: float) -> BatchSummary:
    counter = _Counter(None, 0)
    counter.add(read_part(layout.target, layout.fmt), reused=True)
    return counter.summary(layout.target, time.perf_counter() - start)


@contextmanager
def _sigterm_interrupts() -> Iterator[None]:
    """Make SIGTERM behave like Ctrl-C, so ``kill`` also removes half-written parts."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt(f"signal {signum}")

    old = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)
