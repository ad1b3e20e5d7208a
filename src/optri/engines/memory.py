"""Estimate table memory and refuse before allocating what cannot fit."""

from __future__ import annotations

from .. import config
from ..errors import TableTooLargeError

__all__ = ["require_memory"]


def require_memory(nbytes: int, what: str, hint: str = "") -> None:
    """Raise :class:`TableTooLargeError` if ``nbytes`` exceeds the memory ceiling.

    Parameters
    ----------
    nbytes : int
        Estimated peak bytes of the allocation.
    what : str
        What would be allocated (for the message).
    hint : str
        How to get by with less (float32, another engine, ...).

    Examples
    --------
    >>> require_memory(1 << 60, "a 2^60-byte table", "use less")
    Traceback (most recent call last):
    ...
    optri.errors.TableTooLargeError: a 2^60-byte table needs 1152921504606.8 MB ...
    """
    limit = config.available_memory_bytes()
    if nbytes > limit:
        msg = (
            f"{what} needs {nbytes / 1e6:.1f} MB but only {limit / 1e6:.1f} MB may be "
            f"used (config.MEMORY_FRACTION of the available memory)"
        )
        raise TableTooLargeError(f"{msg}; {hint}" if hint else msg)
