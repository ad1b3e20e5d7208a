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
import signal
import threading
from collections.abc import Iterator
from typing import Any

from ..errors import Terminated

__all__ = ["interruptible", "kernel_cause", "stop_signals_unwind"]

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
