"""Ctrl-C and exceptions inside compiled kernels, turned back into what they are.

A signal that arrives while a numba kernel runs is noticed only when the kernel
returns; if the kernel returns a value, numba's wrapper then reports
``SystemError: ... returned a result with an exception set`` with the
``KeyboardInterrupt`` as its cause. An exception raised inside a user's
``@numba.njit`` weight can surface the same way. :func:`interruptible` unwraps
both: a ``KeyboardInterrupt`` comes out as a plain ``KeyboardInterrupt`` (the CLI
prints "interrupted" and exits 130); any other cause is re-raised as itself
(its ``__cause__`` kept) so callers can wrap it in their own error.

>>> with interruptible():
...     raise SystemError("kernel returned a result with an exception set") from ValueError("w")
Traceback (most recent call last):
...
ValueError: w
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["interruptible", "kernel_cause"]


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
        if isinstance(cause, KeyboardInterrupt):
            raise KeyboardInterrupt from None
        if cause is not None:
            raise cause from exc
        raise
