"""Errors of a batch run as a whole (a bad polygon is a record, never an exception)."""

from __future__ import annotations

from typing import Any

from ..errors import OptriError

__all__ = ["BatchFailedError", "BatchInputError"]


class BatchInputError(OptriError, ValueError):
    """An input or output file cannot be used at all; the message names file and line."""


class BatchFailedError(OptriError):
    """``strict=True`` and some polygons got error records; ``summary`` has the counts."""

    def __init__(self, message: str, summary: Any = None) -> None:
        super().__init__(message)
        self.summary = summary
