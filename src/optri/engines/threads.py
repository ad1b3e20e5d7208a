"""How many threads a compiled engine runs on.

The compiled core's kernels take their thread count as an argument, read here in
the calling thread: ``OPTRI_NUM_THREADS`` when set, else the core's limit for the
calling thread (OpenMP's, which ``OMP_NUM_THREADS`` and threadpoolctl's
``threadpool_limits`` set). A problem's ``options["threads"]`` wins over both.

>>> import os
>>> os.environ["OPTRI_NUM_THREADS"] = "3"
>>> available(), threads_for(None, n=10, parallel_min_n=100), threads_for(2, 10, 100)
(3, 1, 2)
>>> del os.environ["OPTRI_NUM_THREADS"]
"""

from __future__ import annotations

import os

from ..errors import InvalidParameterError

__all__ = ["ENV", "available", "threads_for"]

#: The environment variable that sets the compiled engines' thread count.
ENV = "OPTRI_NUM_THREADS"


def available() -> int:
    """Threads the calling thread may use: ``$OPTRI_NUM_THREADS``, else the core's limit.

    Raises
    ------
    InvalidParameterError
        ``OPTRI_NUM_THREADS`` is set to something other than a positive integer.
    """
    text = os.environ.get(ENV, "").strip()
    if text:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise InvalidParameterError(f"{ENV} must be a positive integer, got {text!r}")
        return value
    from .. import _core

    return max(1, int(_core.max_threads()))


def threads_for(wanted: int | None, n: int, parallel_min_n: int) -> int:
    """Threads for a problem of ``n`` vertices.

    ``wanted`` (a problem's ``options["threads"]``) when given, else
    :func:`available` from ``parallel_min_n`` vertices on and 1 below (where
    starting the threads costs more than they save).
    """
    if wanted is not None:
        return max(1, int(wanted))
    return available() if n >= parallel_min_n else 1
