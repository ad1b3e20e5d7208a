"""How many threads the compiled core's parallel kernels use.

One rule for every caller: ``OPTRI_NUM_THREADS`` when set (a positive integer),
else the compiled core's own limit for the calling thread (OpenMP's: it follows
``OMP_NUM_THREADS`` and threadpoolctl; 1 in a build without OpenMP).
"""

from __future__ import annotations

import os

from ..errors import OptriError

__all__ = ["available_threads"]


def available_threads() -> int:
    """Threads a parallel kernel of the core may use now; at least 1.

    Raises
    ------
    OptriError
        ``OPTRI_NUM_THREADS`` is set to something other than a positive integer.

    Examples
    --------
    >>> available_threads() >= 1
    True
    """
    env = os.environ.get("OPTRI_NUM_THREADS", "").strip()
    if env:
        try:
            count = int(env)
        except ValueError:
            count = 0
        if count < 1:
            raise OptriError(f"OPTRI_NUM_THREADS must be a positive integer, not {env!r}")
        return count
    from .. import _core

    return max(1, int(_core.max_threads()))
