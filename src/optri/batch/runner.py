"""Run chunk tasks in-process, on a local process pool, or on Dask, with bounded in-flight work.

All three backends run the same :func:`~optri.batch.records.solve_chunk` and hand
results back to the calling process, which alone writes part files. At most
``config.BATCH_IN_FLIGHT_PER_WORKER * workers`` chunks are queued at once, so memory does not
grow with the input.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import multiprocessing
import os
import select
import signal
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from typing import Any

from .. import config
from .._optional import import_optional
from ..errors import BatchInputError
from .records import ChunkTask, solve_chunk

__all__ = ["Backend", "default_workers", "open_backend", "run_tasks"]


Result = tuple[int, list[dict]]


def default_workers() -> int:
    """CPU cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


class Backend:
    """Submit chunk tasks and wait for any of them: the one interface every scheduler has."""

    workers = 1

    def submit(self, task: ChunkTask) -> Any:
        """Start ``task``; return a handle for :meth:`wait_any`."""
        raise NotImplementedError

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        """Block until at least one handle is done; return the done ones."""
        raise NotImplementedError

    def result(self, handle: Any) -> Result:
        """The ``(index, records)`` of a finished handle."""
        return handle.result()

    def cancel(self, handles: Iterable[Any]) -> None:
        """Drop work not yet started (on interruption)."""
        for h in handles:
            h.cancel()


class _Inline(Backend):
    """Runs each chunk at once in this process (``workers=1``; also for custom weights)."""

    def submit(self, task: ChunkTask) -> Any:
        fut: cf.Future[Result] = cf.Future()
        fut.set_result(solve_chunk(task))
        return fut

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        return set(handles)


class _Pool(Backend):
    def __init__(self, executor: cf.ProcessPoolExecutor, workers: int) -> None:
        self.executor, self.workers = executor, workers

    def submit(self, task: ChunkTask) -> Any:
        return self.executor.submit(solve_chunk, task)

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        done, _ = cf.wait(list(handles), return_when=cf.FIRST_COMPLETED)
        return set(done)


class _Dask(Backend):
    def __init__(self, client: Any, workers: int) -> None:
        self.client, self.workers = client, workers
        self.distributed = import_optional("distributed")

    def submit(self, task: ChunkTask) -> Any:
        # pure=False: a rerun must recompute, never reuse a cached key
        return self.client.submit(solve_chunk, task, pure=False)

    def wait_any(self, handles: Iterable[Any]) -> set[Any]:
        done, _ = self.distributed.wait(list(handles), return_when="FIRST_COMPLETED")
        return set(done)


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


@contextmanager
def open_backend(scheduler: Any, workers: int | None) -> Iterator[Backend]:
    """The backend for ``scheduler`` (None/"local", "dask", "dask://host:port", or a Client)."""
    if scheduler in (None, "local", "processes"):
        n = workers or default_workers()
        if n <= 1:
            yield _Inline()
            return
        # forkserver: workers never inherit the progress bar's thread or locks
        methods = multiprocessing.get_all_start_methods()
        ctx = multiprocessing.get_context("forkserver" if "forkserver" in methods else None)
        executor = cf.ProcessPoolExecutor(
            n, mp_context=ctx, initializer=_worker_init, initargs=(os.getpid(),)
        )
        try:
            yield _Pool(executor, n)
        finally:
            executor.shutdown(wait=True, cancel_futures=True)
        return
    with _dask_client(scheduler, workers) as client:
        n = workers or max(1, len(client.scheduler_info().get("workers", {})))
        yield _Dask(client, n)


@contextmanager
def _dask_client(scheduler: Any, workers: int | None) -> Iterator[Any]:
    if not isinstance(scheduler, str):  # a distributed.Client the caller owns
        yield scheduler
        return
    distributed = import_optional("distributed")
    if scheduler == "dask":
        n = workers or default_workers()
        cluster = distributed.LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
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
        f"unknown scheduler {scheduler!r}; use 'local', 'dask' or 'dask://host:port'"
    )


def run_tasks(
    backend: Backend,
    tasks: Iterable[ChunkTask],
    on_done: Callable[[ChunkTask, list[dict]], None],
) -> None:
    """Run every task on ``backend``, calling ``on_done(task, records)`` as each finishes.

    Keeps at most ``config.BATCH_IN_FLIGHT_PER_WORKER * backend.workers`` tasks submitted; on any
    exception (KeyboardInterrupt included) work not yet started is cancelled.
    """
    limit = max(1, config.BATCH_IN_FLIGHT_PER_WORKER * backend.workers)
    pending: dict[Any, ChunkTask] = {}
    try:
        for task in tasks:
            pending[backend.submit(task)] = task
            while len(pending) >= limit:
                _collect(backend, pending, on_done)
        while pending:
            _collect(backend, pending, on_done)
    except BaseException:
        backend.cancel(pending)
        raise


def _collect(
    backend: Backend,
    pending: dict[Any, ChunkTask],
    on_done: Callable[[ChunkTask, list[dict]], None],
) -> None:
    # finish in index order among the done ones, so equal runs write parts alike
    done = sorted(backend.wait_any(pending), key=lambda h: pending[h].index)
    for handle in done:
        task = pending.pop(handle)
        _, records = backend.result(handle)
        on_done(task, records)
