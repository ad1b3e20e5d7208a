"""Ctrl-C and exceptions inside compiled kernels, turned back into what they are.

A signal that arrives while a numba kernel runs is noticed only when the kernel
returns; if the kernel returns a value, numba's wrapper then reports
``SystemError: ... returned a result with an exception set`` with the
``KeyboardInterrupt`` as its cause. An exception raised inside a user's
``@numba.njit`` weight can surface the same way. :func:`interruptible` unwraps
both: a ``KeyboardInterrupt`` comes out as itself (the CLI prints "interrupted"
and exits 130; a :class:`~optri.errors.Terminated` from
:func:`stop_signals_unwind`, "terminated" and 143); any other cause is
re-raised as itself (its ``__cause__`` kept) so callers can wrap it in their
own error.

>>> with interruptible():
...     raise SystemError("kernel returned a result with an exception set") from ValueError("w")
Traceback (most recent call last):
...
ValueError: w
"""

from __future__ import annotations

import contextlib
import inspect
import signal
import sys
import threading
from collections.abc import Iterator
from typing import Any

import numpy as np

from .. import config
from ..errors import Terminated

__all__ = ["interruptible", "is_loaded", "kernel_cause", "stop_signals_unwind", "watched"]

#: The signals :func:`stop_signals_unwind` turns into :class:`~optri.errors.Terminated`.
STOP_SIGNALS = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


def kernel_cause(exc: BaseException) -> BaseException | None:
    """The exception a compiled kernel's ``SystemError`` stands for, or None if it is not one."""
    if not isinstance(exc, SystemError):
        return None
    cause = exc.__cause__ or exc.__context__
    if cause is None or isinstance(cause, SystemError):
        return None
    return cause


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """Around compiled kernel calls: a ``SystemError`` caused by X is raised as X."""
    try:
        yield
    except SystemError as exc:
        cause = kernel_cause(exc)
        if isinstance(cause, KeyboardInterrupt):  # Ctrl-C, or Terminated: as itself
            raise cause.with_traceback(None) from None
        if cause is not None:
            raise cause from exc
        raise


@contextlib.contextmanager
def stop_signals_unwind() -> Iterator[None]:
    """While it runs, SIGTERM and SIGHUP raise :class:`~optri.errors.Terminated`.

    So ``kill`` or a closed terminal unwinds like Ctrl-C: ``finally`` blocks
    and context managers run, and temporary files are removed. Only in the
    main thread (where Python delivers signals); elsewhere it does nothing.
    The previous handlers come back on exit, so uses nest.

    >>> import os, signal
    >>> try:
    ...     with stop_signals_unwind():
    ...         os.kill(os.getpid(), signal.SIGTERM)
    ... except KeyboardInterrupt as exc:
    ...     print(type(exc).__name__, exc.signum)
    Terminated 15
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: Any) -> None:
        raise Terminated(signum)

    old = {sig: signal.signal(sig, stop) for sig in STOP_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in old.items():
            if handler is not None:  # None: installed outside Python, cannot be put back
                signal.signal(sig, handler)


def is_loaded(kernel: Any, dtype: Any = None, masked: bool | None = None) -> bool:
    """Whether the numba dispatcher ``kernel`` has machine code in this process already.

    With ``dtype``: machine code for tables of that dtype, the type of its first
    argument (a table, or a tuple of tables). A specialization for another
    dtype (a first float32 solve after float64 ones) compiles, or loads from
    the disk cache, just as a first call does. With ``masked``: also for a
    chord mask (True: an array) or none (False: None) in its argument named
    ``mask``, which the fills compile apart. Anything else (a plain
    function: nothing to compile) counts as loaded.

    Its first call compiles it or loads it from the disk cache (seconds, or half
    of one), partly inside llvmlite's callbacks, where Python reports a Ctrl-C
    as "Exception ignored" and carries on: callers run that first call
    :func:`watched`, whatever its size.

    >>> import numba, numpy as np
    >>> first = numba.njit(lambda t: t[0])
    >>> is_loaded(first), first(np.zeros(2)), is_loaded(first), is_loaded(print)
    (False, 0.0, True, True)
    >>> is_loaded(first, np.float64), is_loaded(first, np.float32)
    (True, False)
    >>> pick = numba.njit(lambda t, mask: t[0] if mask is None else t[1])
    >>> pick(np.zeros(2), None), is_loaded(pick, np.float64, False)
    (0.0, True)
    >>> is_loaded(pick, np.float64, True)
    False
    """
    overloads = getattr(kernel, "overloads", None)
    if overloads is None:
        return True
    if not overloads:
        return False
    if dtype is None:
        return True
    key = (id(kernel), np.dtype(dtype), masked)
    if key in _LOADED:
        return True
    name = key[1].name
    at = None if masked is None else _mask_position(kernel)
    for signature in kernel.signatures:
        first = signature[0]
        table = first.types[0] if hasattr(first, "types") else first  # a tuple of tables
        if str(getattr(table, "dtype", "")) != name:
            continue
        if at is None or (str(signature[at]) != "none") == masked:
            _LOADED.add(key)  # machine code is never unloaded
            return True
    return False


def _mask_position(kernel: Any) -> int:
    """The position of ``kernel``'s argument named ``mask``."""
    return list(inspect.signature(kernel.py_func).parameters).index("mask")


#: ``(id(kernel), dtype, masked)`` found loaded by :func:`is_loaded`: a look through the
#: signatures takes 2-3 us, a look here 0.2 us.
_LOADED: set[tuple[int, np.dtype[Any], bool | None]] = set()


def watched(fill: Any, threads: int, stop: Any, poll: Any) -> None:
    """Run ``fill`` (a kernel call that releases the GIL) in a helper thread, polling meanwhile.

    ``poll()`` runs every ``config.FAST_PROGRESS_SECONDS``. Ctrl-C, a stop signal
    (:func:`stop_signals_unwind`) or an exception from ``poll`` sets
    ``stop[0] = 1``, which the kernel checks between pieces of its work (a tile, a
    row) to return early; once ``fill`` has returned, the exception goes on from
    here, where Python delivers signals. An exception in the helper is raised
    here too. ``threads``: numba threads for the helper (a per-thread setting), where
    numba is loaded.

    >>> import numpy as np
    >>> stop, out = np.zeros(1, dtype=np.int64), []
    >>> watched(lambda: out.append("filled"), 1, stop, lambda: None)
    >>> out, int(stop[0])
    (['filled'], 0)
    """
    numba = sys.modules.get("numba")  # kernels of the compiled core take threads as an argument
    failure: list[BaseException] = []
    finished = threading.Event()

    def target() -> None:
        if numba is not None:  # numba's thread count is per calling thread
            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        try:
            fill()
        except BaseException as exc:  # noqa: BLE001 - handed to the calling thread
            failure.append(exc)
        finally:
            finished.set()

    # an Event, not Thread.join: a join that Ctrl-C interrupts marks the thread as
    # stopped on Python 3.11 (threading's bpo-45274 handling), and the next join
    # returns at once while the kernel still writes the table
    threading.Thread(target=target, name="optri-fill", daemon=True).start()
    try:
        while not finished.wait(config.FAST_PROGRESS_SECONDS):
            poll()
        poll()
    except BaseException:
        stop[0] = 1
        finished.wait()
        raise
    if failure:
        raise failure[0]
