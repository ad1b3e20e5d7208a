"""The compiled core, ``optri._core``, as the engines import it.

Importing this module imports the extension and applies ``OPTRI_SIMD`` once: the
instruction-set level the kernels run at (``avx512``, ``avx2``, ``baseline`` or
``portable``; unset or empty: the best this CPU has). Every level gives the same
results bit for bit; a lower one is for tests and comparisons. A level this CPU (or
this build) lacks raises :class:`~optri.errors.SimdUnavailableError`, naming the
levels there are.

>>> from optri.engines import core
>>> core.simd_level() in core.simd_levels()
True
"""

from __future__ import annotations

import os
from types import ModuleType

from .. import _core
from ..errors import InvalidParameterError

__all__ = ["SimdUnavailableError", "core", "minplus", "set_simd", "simd_level", "simd_levels"]

core: ModuleType = _core
minplus: ModuleType = _core.minplus  # type: ignore[attr-defined]

LEVELS = ("portable", "baseline", "avx2", "avx512")


class SimdUnavailableError(InvalidParameterError):
    """``OPTRI_SIMD`` (or :func:`set_simd`) asked for a level this CPU or build lacks."""


def simd_levels() -> list[str]:
    """Levels this CPU and build can run, lowest first.

    >>> "portable" in simd_levels()
    True
    """
    return list(_core.simd_levels())  # type: ignore[attr-defined]


def simd_level() -> str:
    """The level the kernels run at now.

    >>> simd_level() in LEVELS
    True
    """
    return str(_core.simd_level())  # type: ignore[attr-defined]


def set_simd(level: str) -> None:
    """Run the kernels at ``level`` from now on (one of :func:`simd_levels`).

    >>> before = simd_level()
    >>> set_simd("portable"); simd_level()
    'portable'
    >>> set_simd(before)
    """
    name = str(level).strip().lower()
    if not _core.set_simd(name):  # type: ignore[attr-defined]
        known = "one of " + ", ".join(LEVELS) if name not in LEVELS else "not available here"
        raise SimdUnavailableError(
            f"SIMD level {level!r} is {known}; this CPU and build have {', '.join(simd_levels())}"
        )


def _apply_environment() -> None:
    wanted = os.environ.get("OPTRI_SIMD", "").strip()
    if wanted:
        try:
            set_simd(wanted)
        except SimdUnavailableError as exc:
            raise SimdUnavailableError(f"OPTRI_SIMD: {exc}") from None


_apply_environment()
