"""Run chunk tasks in-process, on local threads or processes, or on Dask, in-flight work bounded.

Every backend runs the same :func:`solve_task` (records of a chunk of Items, or
the output table of an Arrow chunk: :mod:`.chunks`) and hands results back to
the calling process, which writes their part files; a chunk of an Arrow layer
on the local workers is read, solved and written by its worker, which hands
back only what the ledger and the summary need (:mod:`.partwork`). Local
workers are threads of this process when the compiled kernel does the work and
they are few (:data:`~optri.config.BATCH_THREADS`), else processes. At most
``config.BATCH_IN_FLIGHT_PER_WORKER * workers`` chunks are queued at once, so memory does not
grow with the input.

A worker process that dies (killed by the system, as the out-of-memory killer
does) loses the chunks it held, and with a process pool every chunk in flight.
Those chunks are retried once, one at a time, so a chunk that kills its worker
alone is known to be the culprit; it is then split into its polygons, each tried
once alone, and a polygon that still kills its worker gets an error record that
names it. Every chunk is tried at most three times, so a run always ends.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses
import importlib
import logging
import multiprocessing
import os
import select
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Any

from .. import config
from .._optional import import_optional
from ..errors import BatchInputError
from .chunks import TableTask, solve_table
from .partwork import ReadTask, solve_read
from .records import ChunkTask, error_record, solve_chunk

__all__ = ["Backend", "default_workers", "open_backend", "run_tasks", "start_pool_server"]


Result = tuple[int, Any]
Task = ChunkTask | TableTask | ReadTask


def solve_task(task: Task) -> Result:
    """Solve one task: ``(index, records)`` of a ChunkTask, ``(index, table)`` of a TableTask.

    A ReadTask's worker reads and writes its part itself: ``(index, PartWritten)``
    (:mod:`.partwork`).
    """
    if isinstance(task, ReadTask):
        return solve_read(task)
    if isinstance(task, TableTask):
        return solve_table(task)
    return solve_chunk(task)


class WorkerDied(Exception):
    """The process solving a task ended without an answer (killed, out of memory)."""


def default_workers() -> int:
    """CPU cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


class Backend:
    """Submit chunk tasks and wait for any of them: the one interface every scheduler has."""

    workers = 1
    #: A dead worker loses every task in flight (a process pool), not only its own.
    shared_fate = False

    def submit(self, task: Task) -> Any:
        """Start ``task``; return a handle for :meth:`wait_any`."""
        raise NotImplementedError

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        """Block until at least one handle is done; return the done ones."""
        raise NotImplementedError

    def result(self, handle: Any) -> Result:
        """The ``(index, records)`` of a finished handle; :class:`WorkerDied` if none came."""
        return handle.result()

    def recover(self) -> None:
        """Be ready for new tasks after a worker died (a pool makes new processes)."""

    def cancel(self, handles: Iterable[Any]) -> None:
        """Drop work not yet started (on interruption)."""
        for h in handles:
            h.cancel()


class _Inline(Backend):
    """Runs each chunk at once in this process (``workers=1``; also for custom weights)."""

    def submit(self, task: Task) -> Any:
        fut: cf.Future[Result] = cf.Future()
        fut.set_result(solve_task(task))
        return fut

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        return set(handles)


class _Pool(Backend):
    shared_fate = True

    def __init__(self, make: Callable[[], cf.Executor], workers: int) -> None:
        self.make, self.workers = make, workers
        self.executor = make()

    def submit(self, task: Task) -> Any:
        return self.executor.submit(solve_task, task)

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        done, _ = cf.wait(list(handles), return_when=cf.FIRST_COMPLETED)
        return set(done)

    def result(self, handle: Any) -> Result:
        try:
            return handle.result()  # type: ignore[no-any-return]
        except cf.process.BrokenProcessPool:
            raise WorkerDied from None

    def recover(self) -> None:
        self.executor.shutdown(wait=True, cancel_futures=True)
        self.executor = self.make()


class _Threads(_Pool):
    """Runs chunks on threads of this process: for the compiled kernel, which releases the GIL.

    No process to start or import in, nothing pickled; a worker that fails raises
    in its task like any exception (there is no process to lose).
    """

    shared_fate = False

    def __init__(self, workers: int) -> None:
        super().__init__(
            lambda: cf.ThreadPoolExecutor(workers, thread_name_prefix="optri-batch"), workers
        )


class _Dask(Backend):
    def __init__(self, client: Any, workers: int) -> None:
        self.client, self.workers = client, workers
        self.distributed = import_optional("distributed")

    def submit(self, task: Task) -> Any:
        # pure=False: a rerun must recompute, never reuse a cached key
        return self.client.submit(solve_task, task, pure=False)

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        """Wait for a task; give up when the cluster has had no worker for a while."""
        handles = list(handles)
        alone = None
        while True:
            try:
                done, _ = self.distributed.wait(
                    handles, timeout=config.BATCH_DASK_POLL_SECONDS, return_when="FIRST_COMPLETED"
                )
                return set(done)
            except TimeoutError:
                pass
            if self.client.scheduler_info().get("workers"):
                alone = None
                continue
            alone = alone or time.monotonic()
            if time.monotonic() - alone > config.BATCH_DASK_NO_WORKER_SECONDS:
                raise BatchInputError(
                    f"the Dask cluster has had no worker for "
                    f"{config.BATCH_DASK_NO_WORKER_SECONDS:g} s; rerun to resume"
                )

    def result(self, handle: Any) -> Result:
        try:
            return handle.result()  # type: ignore[no-any-return]
        except self.distributed.KilledWorker:
            raise WorkerDied from None


def _worker_init(parent: int) -> None:
    # Ctrl-C reaches the whole process group: only the parent handles it, and it
    # stops the workers itself once the chunks in progress are written or dropped.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _die_with(parent)


def _die_with(parent: int) -> None:
    """End this worker (and the forkserver it came from) as soon as ``parent`` ends.

    A parent killed by SIGKILL cannot stop its pool, and forkserver workers are
    children of the forkserver, not of the parent, so the kernel's parent-death
    signal alone would not reach them: a daemon thread waits on a pidfd of the
    parent (Linux), or polls it, and exits the process when it is gone.
    """
    try:
        fd = os.pidfd_open(parent)  # type: ignore[attr-defined]  # Linux >= 5.3
    except (AttributeError, OSError):
        fd = None
        if not _alive(parent):
            os._exit(1)

    def watch() -> None:
        if fd is not None:
            select.select([fd], [], [])
        else:
            while _alive(parent):
                time.sleep(config.BATCH_WATCHDOG_SECONDS)
        server = os.getppid()
        if server not in (1, parent):  # the forkserver: orphaned and useless now
            with contextlib.suppress(OSError):
                os.kill(server, signal.SIGKILL)
        os._exit(1)

    threading.Thread(target=watch, name="optri-parent-watch", daemon=True).start()


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:  # a zombie is dead, only not yet reaped
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


#: What a worker's first chunk imports: workers get them imported beforehand (a forkserver
#: preloads them; thread workers' process imports them before the threads start). pandas
#: because pyarrow imports it, where installed, on its first array conversion.
WORKER_IMPORTS = ("pyarrow.parquet", "shapely", "pandas")
#: What the local pool's forkserver imports once, before it forks any worker: each
#: worker then starts with them instead of importing them itself ("__main__" is
#: multiprocessing's own default; a module that is not installed is skipped).
FORKSERVER_PRELOAD = ("__main__", "optri.batch.runner", *WORKER_IMPORTS)


def _pool_context() -> Any:
    """The start method of local pools: a forkserver where there is one.

    Forkserver workers never inherit the parent's threads (the progress bar's)
    or locks. The forkserver imports :data:`FORKSERVER_PRELOAD` when it starts
    (unless something in this process started it before).
    """
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context()
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(list(FORKSERVER_PRELOAD))
    return ctx


def start_pool_server(scheduler: Any, workers: int | None, *, threads: bool = False) -> None:
    """Start the forkserver a local pool will fork its workers from, now, in the background.

    Its imports then overlap with what this process does before the first chunk
    (reading the layer's metadata, hashing the input). A no-op for Dask, one
    worker, workers that are threads (``threads``, as for :func:`open_backend`), or
    a platform without a forkserver.
    """
    n = workers or default_workers()
    if scheduler not in (None, "local", "processes") or n <= 1 or _on_threads(threads, n):
        return
    if _pool_context().get_start_method() == "forkserver":
        from multiprocessing import forkserver

        forkserver.ensure_running()


@contextmanager
def open_backend(
    scheduler: Any, workers: int | None, *, threads: bool = False
) -> Iterator[Backend]:
    """The backend for ``scheduler`` (None/"local", "dask", "dask://host:port", or a Client).

    ``threads``: the compiled kernel does the work (see :func:`dask_client`).
    """
    if scheduler in (None, "local", "processes"):
        n = workers or default_workers()
        if n <= 1:
            yield _Inline()
            return
        if _on_threads(threads, n):
            _import_before_threads()
            pool: _Pool = _Threads(n)
        else:
            ctx = _pool_context()

            def make() -> cf.ProcessPoolExecutor:
                return cf.ProcessPoolExecutor(
                    n, mp_context=ctx, initializer=_worker_init, initargs=(os.getpid(),)
                )

            pool = _Pool(make, n)
        try:
            yield pool
        finally:
            pool.executor.shutdown(wait=True, cancel_futures=True)
        return
    with dask_client(scheduler, workers, config.BATCH_WORKER_RETRIES, threads=threads) as client:
        yield _Dask(client, workers or cluster_threads(client))


def _on_threads(threads: bool, workers: int) -> bool:
    """Whether ``workers`` local workers are threads: compiled work (``threads``), few of them."""
    return threads and workers <= config.BATCH_THREADS


def _import_before_threads() -> None:
    """Import here, before worker threads start, what their first chunk would import.

    Importing pandas (which pyarrow does at its first ``pa.array``) enters
    ``warnings.catch_warnings``, process-wide state that must not be entered by two
    threads at once (:data:`~optri.batch.each.WARNINGS_LOCK`); imported now, no worker
    thread enters it that way.
    """
    for name in WORKER_IMPORTS:
        with contextlib.suppress(ImportError):
            importlib.import_module(name)


def cluster_threads(client: Any) -> int:
    """How many tasks ``client``'s cluster runs at once: its workers' threads, at least 1."""
    info = client.scheduler_info().get("workers", {})
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.values()))


@contextmanager
def dask_client(
    scheduler: Any, workers: int | None, allowed_failures: int, *, threads: bool = False
) -> Iterator[Any]:
    """A ``distributed.Client``: the one given, at an address, or on a LocalCluster made here.

    ``allowed_failures``: how often the LocalCluster's scheduler reruns a task whose
    worker died before raising ``KilledWorker``. ``threads``: the compiled kernel
    does the work; a LocalCluster made here of at most
    :data:`~optri.config.BATCH_THREADS` workers is then one worker of that
    many threads in this process, which starts at once (worker processes take
    seconds to start and import). Otherwise each worker is a process: a Python
    weight holds the GIL, and a worker it takes down takes down its own tasks only.
    """
    if scheduler is not None and not isinstance(scheduler, str):  # a Client the caller owns
        yield scheduler
        return
    distributed = import_optional("distributed")
    if scheduler in (None, "dask"):
        n = workers or default_workers()
        if _on_threads(threads, n):
            _import_before_threads()
            cluster = distributed.LocalCluster(
                n_workers=1,
                threads_per_worker=n,
                processes=False,
                dashboard_address=":0",  # a free port: never "8787 is already in use"
                silence_logs=logging.ERROR,
            )
            with cluster, distributed.Client(cluster) as client:
                yield client
            return
        dask = import_optional("dask")
        settings: dict[str, Any] = {"distributed.scheduler.allowed-failures": allowed_failures}
        if "forkserver" in multiprocessing.get_all_start_methods():
            settings["distributed.worker.multiprocessing-method"] = "forkserver"
        with dask.config.set(settings):
            _preload_forkserver(distributed)
            cluster = distributed.LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",  # a free port: never "8787 is already in use"
                silence_logs=logging.ERROR,  # its INFO/WARNING chatter would bury the progress bar
            )
        with cluster, distributed.Client(cluster) as client:
            yield client
        return
    if scheduler.startswith(("dask://", "tcp://", "tls://", "inproc://")):
        address = scheduler.replace("dask://", "tcp://", 1)
        with distributed.Client(address) as client:
            yield client
        return
    raise BatchInputError(
        f"unknown scheduler {scheduler!r}; use 'local', 'dask' or 'tcp://host:port'"
    )


#: What the forkserver of a LocalCluster made here imports once, before it forks each
#: worker: workers start with them loaded instead of importing them one by one.
WORKER_PRELOAD = ("distributed", "numpy", *WORKER_IMPORTS, "optri.batch.dasklayer")


def _preload_forkserver(distributed: Any) -> None:
    """Have the forkserver Dask starts workers from import :data:`WORKER_PRELOAD` first.

    Dask sets its own preload list the first time it asks for the start method's
    context; the list set after it stands (a forkserver already running keeps its own).
    """
    ctx = distributed.utils.get_mp_context()
    if ctx.get_start_method() == "forkserver":
        ctx.set_forkserver_preload(list(WORKER_PRELOAD))


def run_tasks(
    backend: Backend,
    tasks: Iterable[Task],
    on_done: Callable[[Task, Any], None],
) -> None:
    """Run every task on ``backend``, calling ``on_done(task, records)`` as each finishes.

    Keeps at most ``config.BATCH_IN_FLIGHT_PER_WORKER * backend.workers`` tasks submitted; on any
    exception (KeyboardInterrupt included) work not yet started is cancelled. Tasks lost
    with a dead worker are retried as the module's docstring says.
    """
    limit = max(1, config.BATCH_IN_FLIGHT_PER_WORKER * backend.workers)
    run = _Run(backend, on_done)
    try:
        for task in tasks:
            run.pending[backend.submit(task)] = task
            while len(run.pending) >= limit:
                run.collect()
            run.retry_lost()
        while run.pending or run.lost:
            if run.pending:
                run.collect()
            run.retry_lost()
    except BaseException:
        backend.cancel(run.pending)
        raise


class _Run:
    """The tasks in flight, those lost with a dead worker, and chunks solved polygon by polygon."""

    def __init__(self, backend: Backend, on_done: Callable[[Task, Any], None]):
        self.backend, self.on_done = backend, on_done
        self.pending: dict[Any, Task] = {}
        self.lost: deque[Task] = deque()
        # chunk index -> (the whole chunk, its records so far) while solved polygon by polygon
        self.split: dict[int, tuple[Task, list[Any]]] = {}

    def collect(self) -> None:
        """Wait for some tasks; finish in index order among the done ones (equal runs alike)."""
        backend, pending = self.backend, self.pending
        done = sorted(backend.wait_any(pending), key=lambda h: pending[h].index)
        for handle in done:
            task = pending.pop(handle)
            try:
                _, records = backend.result(handle)
            except WorkerDied:
                self.lost.append(task)
                if backend.shared_fate:  # the pool is broken: everything in it is lost
                    self.lost.extend(pending[h] for h in sorted(pending, key=lambda h: id(h)))
                    pending.clear()
                    backend.recover()
                    return
                continue
            self.finish(task, records)

    def retry_lost(self) -> None:
        """Once nothing else runs, retry each lost task alone, so a death names its culprit."""
        if not self.lost or self.pending:
            return
        while self.lost:
            task = self.lost.popleft()
            handle = self.backend.submit(task)
            self.pending[handle] = task
            self.backend.wait_any([handle])
            del self.pending[handle]
            try:
                _, records = self.backend.result(handle)
            except WorkerDied:
                self.backend.recover()
                self.lost.extendleft(reversed(self.blame(task)))
                continue
            self.finish(task, records)

    def blame(self, task: Task) -> list[Task]:
        """A task that killed its worker alone: its polygons one by one, or an error record."""
        if len(task.items) > 1 and task.offset is None:
            self.split[task.index] = (task, [None] * len(task.items))
            if isinstance(task, ReadTask):  # each row read by its own worker, too
                return [
                    dataclasses.replace(task, first=task.first + k, count=1, offset=k)
                    for k in task.items
                ]
            if isinstance(task, TableTask):
                return [
                    dataclasses.replace(task, table=row, first=task.first + k, offset=k)
                    for k, row in enumerate(task.items)
                ]
            return [
                dataclasses.replace(task, items=[item], offset=k)
                for k, item in enumerate(task.items)
            ]
        if isinstance(task, ReadTask):  # its row, read here: the worker that read it died
            task = task.table_task()
        ident = task.ids()[0] if isinstance(task, TableTask) else task.items[0].id
        reason = (
            f"the worker process died while solving polygon {ident!r} (killed by the "
            "system, for example for lack of memory); it was retried once"
        )
        if isinstance(task, TableTask):
            self.finish(task, killed_row(task, reason))
        else:
            self.finish(task, [error_record(ident, reason)])
        return []

    def finish(self, task: Task, result: Any) -> None:
        if task.offset is None:
            self.on_done(task, result)
            return
        whole, got = self.split[task.index]
        got[task.offset] = result if isinstance(task, (TableTask, ReadTask)) else result[0]
        if all(r is not None for r in got):
            del self.split[task.index]
            done = [r for r in got if r is not None]
            if isinstance(whole, (TableTask, ReadTask)):
                pa = import_optional("pyarrow")
                self.on_done(whole, pa.concat_tables(done, promote_options="permissive"))
            else:
                self.on_done(whole, done)


def killed_row(task: TableTask, reason: str) -> Any:
    """The output of a one-row table task whose polygon killed its worker: an error row."""
    pa = import_optional("pyarrow")
    table = task.table
    k = table.schema.get_field_index(task.geometry)
    table = table.set_column(k, table.schema.field(k), pa.nulls(1, table.schema.field(k).type))
    _, out = solve_table(dataclasses.replace(task, table=table))
    k = out.schema.get_field_index("reason")
    return out.set_column(k, out.schema.field(k), pa.array([reason], pa.string()))
