"""Every exception and warning optri raises on purpose, and the parameter checks.

One root, :class:`OptriError`, so a caller can catch them all at once or pick
one precisely. Input errors also derive from the built-in class a Python user
would expect (``ValueError``, ``ImportError``, ``MemoryError``), so code written
against those keeps working.

Public functions check their parameters up front, before any work, with the
``check_*`` functions at the end of this module: each returns the value in the
form the caller needs (a plain ``int``, a ``numpy.dtype``) or raises
:class:`InvalidParameterError` (a ``ValueError``) or :class:`ParameterTypeError`
(also a ``TypeError``) naming the parameter and what it takes.

>>> import optri
>>> try:
...     optri.triangulate([[0, 0], [1, 0]])
... except optri.OptriError as exc:
...     print(type(exc).__name__)
InvalidPolygonError
>>> check_count(3, "k")
3
>>> check_count("3", "k")
Traceback (most recent call last):
...
optri.errors.ParameterTypeError: k must be an integer, got str '3'
"""

from __future__ import annotations

import inspect
import math
import numbers
import random
import signal
from collections.abc import Callable
from typing import Any, Literal, overload

import numpy as np

__all__ = [
    "BatchFailedError",
    "BatchInputError",
    "BatchLockedError",
    "BatchWarning",
    "DuplicateIdWarning",
    "EngineUnavailableError",
    "GeographicCRSWarning",
    "HoleSkippedWarning",
    "InvalidParameterError",
    "InvalidPolygonError",
    "MissingDependencyError",
    "NoTriangulationError",
    "OptriError",
    "OutputExistsError",
    "ParameterTypeError",
    "TableTooLargeError",
    "Terminated",
    "UnknownSampleError",
    "WeightError",
    "accepts_positional",
    "check_callback",
    "check_choice",
    "check_count",
    "check_flag",
    "check_float_dtype",
    "check_seconds",
    "check_seed",
]


class OptriError(Exception):
    """Root of every error optri raises on purpose."""


class InvalidPolygonError(OptriError, ValueError):
    """The input is not a polygon the chosen method can triangulate."""


class InvalidParameterError(OptriError, ValueError):
    """A parameter of a public function has a value it cannot take (``k=0``, ``dtype="x"``).

    Raised up front, before any work; the message names the parameter and what it takes.
    """


class ParameterTypeError(InvalidParameterError, TypeError):
    """A parameter has the wrong type (``k="3"``, a progress callback that is not callable)."""


class WeightError(OptriError, ValueError):
    """A weight is unknown, does not fit the input, returned a non-number or NaN, or raised.

    A user weight's own exception is chained (``__cause__``) and the message names the
    triangle ``(i, k, j)`` (input indices) it was asked about.
    """


class NoTriangulationError(InvalidPolygonError, WeightError):
    """Every split of some sub-polygon has an infinite or invalid cost.

    Cannot happen for a valid simple polygon and a finite weight; raised rather
    than returning a partial triangulation. Both an input and a weight problem,
    so either ``except`` catches it. ``chord`` is the sub-polygon
    ``(i, j)`` (engine indices) where the search found no split.
    """

    def __init__(self, message: str, chord: tuple[int, int] | None = None) -> None:
        super().__init__(message)
        self.chord = chord


class EngineUnavailableError(OptriError, RuntimeError):
    """The requested engine cannot run here (device missing, problem not supported)."""


class MissingDependencyError(OptriError, ImportError):
    """An optional package is not installed; the message names the extra that brings it."""


class TableTooLargeError(OptriError, MemoryError):
    """The DP table would not fit in memory; raised before it is allocated."""


class BatchInputError(OptriError, ValueError):
    """A batch input (file, layer or collection) or output cannot be used at all.

    The message names the file and line, or the argument, and the way out.
    """


class OutputExistsError(OptriError, FileExistsError):
    """An output would replace a file optri did not write; ``overwrite`` says it may."""


class BatchLockedError(BatchInputError):
    """The output is being written by another batch run (its lock file names the pid)."""


class BatchFailedError(OptriError):
    """``strict=True`` and some polygons got error records; ``summary`` has the counts."""

    def __init__(self, message: str, summary: Any = None) -> None:
        super().__init__(message)
        self.summary = summary


class UnknownSampleError(OptriError, LookupError):
    """No bundled sample file has that name (:mod:`optri.data`); the message lists them."""


class Terminated(KeyboardInterrupt):
    """A stop signal (SIGTERM, SIGHUP) raised as an exception, so that it unwinds like Ctrl-C.

    Raised in the main thread while the CLI or :func:`optri.batch` runs
    (:func:`optri.engines.interrupts.stop_signals_unwind`): ``finally`` blocks
    remove temporary files as they do on Ctrl-C. A ``KeyboardInterrupt``, so
    code that catches Ctrl-C catches it too; ``signum`` is the signal's number,
    and the CLI exits with status ``128 + signum`` (143 for SIGTERM, 129 for
    SIGHUP), as a shell reports a process that signal ended.

    >>> import signal
    >>> exc = Terminated(signal.SIGTERM)
    >>> isinstance(exc, KeyboardInterrupt), exc.signum, str(exc)
    (True, 15, 'SIGTERM')
    """

    def __init__(self, signum: int) -> None:
        self.signum = int(signum)
        try:
            name = signal.Signals(self.signum).name
        except ValueError:
            name = f"signal {self.signum}"
        super().__init__(name)

    def __reduce__(self) -> tuple[type[Terminated], tuple[int]]:
        return (type(self), (self.signum,))  # pickles (a process pool's result) as itself


class HoleSkippedWarning(UserWarning):
    """A mesh hole was left open (over ``max_hole_edges``, or it cannot be filled)."""


class BatchWarning(UserWarning):
    """Something about a whole batch a user should know (renamed columns, a CRS not written)."""


class GeographicCRSWarning(BatchWarning):
    """The layer's coordinates are longitude/latitude: costs would be in degrees."""


class DuplicateIdWarning(BatchWarning):
    """Several input features carry the same id."""


# ------------------------------------------------ checks of public parameters

_FLOAT_DTYPES = (np.dtype(np.float64), np.dtype(np.float32))


def _shown(value: Any) -> str:
    text = repr(value)
    return f"{type(value).__name__} {text if len(text) <= 40 else text[:37] + '...'}"


def check_count(value: Any, name: str, minimum: int = 1, maximum: int | None = None) -> int:
    """``value`` as an ``int`` in ``[minimum, maximum]`` (bools and floats refused).

    >>> check_count(0, "k")
    Traceback (most recent call last):
    ...
    optri.errors.InvalidParameterError: k must be at least 1, got 0
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ParameterTypeError(f"{name} must be an integer, got {_shown(value)}")
    value = int(value)
    if value < minimum:
        raise InvalidParameterError(f"{name} must be at least {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise InvalidParameterError(f"{name} must be at most {maximum}, got {value}")
    return value


@overload
def check_seconds(
    value: Any, name: str, allow_none: Literal[False], allow_zero: bool = False
) -> float: ...


@overload
def check_seconds(
    value: Any, name: str, allow_none: bool = True, allow_zero: bool = False
) -> float | None: ...


def check_seconds(
    value: Any, name: str, allow_none: bool = True, allow_zero: bool = False
) -> float | None:
    """None (where allowed), or a positive finite number of seconds as a float.

    ``allow_zero``: 0 is accepted as well.

    >>> check_seconds(-1, "time_limit")
    Traceback (most recent call last):
    ...
    optri.errors.InvalidParameterError: time_limit must be a positive number of seconds, got -1
    >>> check_seconds(0, "warmup", allow_none=False, allow_zero=True)
    0.0
    """
    if value is None and allow_none:
        return None
    what = "0 or a positive number" if allow_zero else "a positive number"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        alone = f"{what} of seconds" if not allow_none else "a number of seconds or None"
        raise ParameterTypeError(f"{name} must be {alone}, got {_shown(value)}")
    seconds = float(value)
    if not (math.isfinite(seconds) and (seconds > 0 or (allow_zero and seconds == 0))):
        raise InvalidParameterError(f"{name} must be {what} of seconds, got {value}")
    return seconds


def check_flag(value: Any, name: str, allow_none: bool = True) -> bool | None:
    """A bool (or None where allowed); ``"yes"`` or ``1`` are refused.

    >>> check_flag(None, "keep_table") is None
    True
    """
    if value is None and allow_none:
        return None
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterTypeError(f"{name} must be True or False, got {_shown(value)}")
    return bool(value)


def check_float_dtype(value: Any, name: str = "dtype") -> np.dtype[Any]:
    """``numpy.float64`` or ``numpy.float32`` as a dtype; anything else refused.

    >>> check_float_dtype("float32")
    dtype('float32')
    """
    try:
        dtype = np.dtype(value)
    except (TypeError, ValueError) as exc:
        raise InvalidParameterError(
            f"{name} must be numpy.float64 or numpy.float32, got {_shown(value)}"
        ) from exc
    if dtype not in _FLOAT_DTYPES:
        raise InvalidParameterError(f"{name} must be numpy.float64 or numpy.float32, got {dtype}")
    return dtype


def check_choice(value: Any, name: str, choices: Any) -> str:
    """``value`` if it is one of the strings ``choices``.

    >>> check_choice("svg", "style", ("paper", "plain"))
    Traceback (most recent call last):
    ...
    optri.errors.InvalidParameterError: unknown style 'svg'; choose one of: paper, plain
    """
    if not isinstance(value, str):
        raise ParameterTypeError(f"{name} must be a string, got {_shown(value)}")
    if value not in choices:
        raise InvalidParameterError(
            f"unknown {name} {value!r}; choose one of: {', '.join(choices)}"
        )
    return value


def check_seed(value: Any, name: str = "seed") -> random.Random:
    """A ``random.Random`` from None, an int or a ``random.Random``."""
    if isinstance(value, random.Random):
        return value
    if value is None:
        return random.Random()
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ParameterTypeError(
            f"{name} must be an integer, a random.Random or None, got {_shown(value)}"
        )
    return random.Random(int(value))


def accepts_positional(func: Callable[..., Any], count: int) -> bool:
    """True if ``func`` can be called with ``count`` positional arguments (True if unknown)."""
    try:
        signature = inspect.signature(func)
    except (TypeError, ValueError):
        return True  # builtins and C callables without a signature: find out when called
    try:
        signature.bind(*range(count))
    except TypeError:
        return False
    return True


def check_callback(value: Any, name: str, count: int) -> Callable[..., Any] | None:
    """None, or a callable taking ``count`` positional arguments.

    >>> check_callback(lambda: None, "progress", 2)
    Traceback (most recent call last):
    ...
    optri.errors.ParameterTypeError: progress must be a callable taking 2 positional arguments ...
    """
    if value is None:
        return None
    if not callable(value) or not accepts_positional(value, count):
        what = "is not callable" if not callable(value) else "cannot take them"
        raise ParameterTypeError(
            f"{name} must be a callable taking {count} positional arguments "
            f"(or None); {_shown(value)} {what}"
        )
    return value
