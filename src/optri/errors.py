"""Exception types raised by optri.

Every error the library raises on purpose derives from :class:`OptriError`, so a
caller can catch them all at once or pick one precisely.
"""

from __future__ import annotations

__all__ = [
    "EngineUnavailableError",
    "InvalidPolygonError",
    "OptriError",
    "TableTooLargeError",
    "WeightError",
]


class OptriError(Exception):
    """Root of every error optri raises on purpose."""


class InvalidPolygonError(OptriError, ValueError):
    """The input is not a polygon the chosen method can triangulate."""


class WeightError(OptriError, ValueError):
    """A weight is unknown, does not fit the input, or returned NaN."""


class EngineUnavailableError(OptriError, RuntimeError):
    """The requested engine cannot run here (missing package or device)."""


class TableTooLargeError(OptriError, MemoryError):
    """The DP table would not fit in memory; raised before it is allocated."""
