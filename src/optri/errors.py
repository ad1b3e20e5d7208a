"""Every exception and warning optri raises on purpose.

One root, :class:`OptriError`, so a caller can catch them all at once or pick
one precisely. Input errors also derive from the built-in class a Python user
would expect (``ValueError``, ``ImportError``, ``MemoryError``), so code written
against those keeps working.

>>> import optri
>>> try:
...     optri.triangulate([[0, 0], [1, 0]])
... except optri.OptriError as exc:
...     print(type(exc).__name__)
InvalidPolygonError
"""

from __future__ import annotations

import signal
from typing import Any

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
