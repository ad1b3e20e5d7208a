"""Estimate memory and refuse before allocating what cannot fit.

The ceiling is ``config.MEMORY_FRACTION`` of the memory this process may still
take: the least of the container's room (cgroup v2 ``memory.max`` minus
``memory.current``, or cgroup v1 ``memory.limit_in_bytes`` minus
``memory.usage_in_bytes``, less reclaimable page cache, over the process's
cgroup and its ancestors) and the machine's ``MemAvailable`` (``/proc/meminfo``);
``config.MEMORY_LIMIT_BYTES`` overrides it all. Where the cgroup files are is
found once and cached; their values are read on every check of at least
``config.MEMORY_CHECK_MIN_BYTES`` (32 MiB), with plain ``os.read`` calls, and a
cgroup's usage only where it has a limit. That takes 18 us with the files in
cache and 70-80 us right after a solve at n = 1000 (whose table has pushed them
out of the CPU's caches): a tenth of a small polygon's solve, for a table far
smaller than the interpreter itself, so smaller requests are let through.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

from .. import config
from ..errors import TableTooLargeError

__all__ = ["available_memory_bytes", "cgroup_room", "require_memory"]

_ROOT = Path("/sys/fs/cgroup")
#: cgroup v1 reports "no limit" as a number near 2**63 rounded to pages.
_NO_LIMIT = 1 << 60


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
    if nbytes < config.MEMORY_CHECK_MIN_BYTES and config.MEMORY_LIMIT_BYTES is None:
        return
    limit = available_memory_bytes()
    if nbytes > limit:
        source = (
            "config.MEMORY_LIMIT_BYTES"
            if config.MEMORY_LIMIT_BYTES is not None
            else "config.MEMORY_FRACTION of the memory available to this process"
        )
        msg = (
            f"{what} needs {nbytes / 1e6:.1f} MB but only {limit / 1e6:.1f} MB may be used "
            f"({source})"
        )
        raise TableTooLargeError(f"{msg}; {hint}" if hint else msg)


def available_memory_bytes() -> int:
    """Bytes an allocation may take now: ``MEMORY_FRACTION`` of the process's room.

    ``config.MEMORY_LIMIT_BYTES`` overrides the OS when set.

    >>> available_memory_bytes() > 0
    True
    """
    if config.MEMORY_LIMIT_BYTES is not None:
        return int(config.MEMORY_LIMIT_BYTES)
    room = [r for r in (_meminfo_available(), cgroup_room()) if r is not None]
    avail = min(room) if room else _physical()
    return int(max(avail, 0) * config.MEMORY_FRACTION)


def cgroup_room() -> int | None:
    """Bytes the process's cgroups (v2 or v1, every ancestor) still allow; None: no limit."""
    best: int | None = None
    for limit_file, usage_file in _cgroup_files():
        limit = _read_int(limit_file)
        if limit is None or limit >= _NO_LIMIT:
            continue
        usage = _read_int(usage_file) or 0
        room = limit - max(usage - _inactive_file(limit_file.parent), 0)
        best = room if best is None else min(best, room)
    return best


@functools.cache
def _cgroup_files() -> tuple[tuple[Path, Path], ...]:
    """(limit, usage) file pairs of the process's memory cgroups, innermost first."""
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
    except OSError:
        return ()
    pairs: list[tuple[Path, Path]] = []
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        _, controllers, path = parts
        if controllers == "":  # v2 unified hierarchy
            for base in (_ROOT, _ROOT / "unified"):
                pairs += _chain(base, path, "memory.max", "memory.current")
        elif "memory" in controllers.split(","):
            base = _ROOT / "memory"
            pairs += _chain(base, path, "memory.limit_in_bytes", "memory.usage_in_bytes")
    return tuple(dict.fromkeys(pairs))


def _chain(base: Path, path: str, limit: str, usage: str) -> list[tuple[Path, Path]]:
    """The cgroup at ``path`` under ``base`` and each ancestor up to ``base`` (which exist).

    Inside a container the cgroup is often mounted at ``base`` itself while
    ``/proc/self/cgroup`` still names the host's path; ``base`` is always tried.
    """
    out = []
    here = base / path.strip("/")
    for folder in (here, *here.parents):
        if (folder / limit).is_file():
            out.append((folder / limit, folder / usage))
        if folder == base:
            break
    if (base / limit).is_file():
        out.append((base / limit, base / usage))
    return out


def _read(path: str | Path) -> bytes | None:
    """The whole of a small file (a /proc or /sys file), or None if it cannot be read."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return None
    try:
        parts = []
        while chunk := os.read(fd, 65536):
            parts.append(chunk)
        return b"".join(parts)
    except OSError:
        return None
    finally:
        os.close(fd)


def _field(data: bytes | None, keys: tuple[bytes, ...]) -> int | None:
    """The integer after the first of ``keys`` that starts a line of ``data``."""
    for line in (data or b"").splitlines():
        key, _, rest = line.partition(b" ")
        if key in keys:
            try:
                return int(rest.split()[0])
            except (ValueError, IndexError):
                return None
    return None


def _inactive_file(folder: Path) -> int:
    """Page cache the kernel reclaims before it refuses memory (counted in the usage)."""
    value = _field(_read(folder / "memory.stat"), (b"inactive_file", b"total_inactive_file"))
    return value or 0


def _read_int(path: Path) -> int | None:
    data = _read(path)
    if data is None:
        return None
    text = data.strip()
    if text == b"max":
        return _NO_LIMIT
    try:
        return int(text)
    except ValueError:
        return None


def _meminfo_available() -> int | None:
    kib = _field(_read("/proc/meminfo"), (b"MemAvailable:",))
    return None if kib is None else kib * 1024


def _physical() -> int:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8 << 30
