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

The compiled engine's tables come from :func:`new_table` and go back through
:func:`release_table`: a table of at least ``config.TABLE_CACHE_MIN_BYTES`` is kept
for the next solve for ``config.TABLE_CACHE_SECONDS``, its pages handed back to the
kernel lazily (``MADV_FREE``), so that back-to-back solves of large polygons skip
the kernel's zeroing of fresh pages.
"""

from __future__ import annotations

import functools
import mmap
import os
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import config
from ..errors import TableTooLargeError

__all__ = [
    "available_memory_bytes",
    "cgroup_room",
    "clear_table_cache",
    "new_table",
    "release_table",
    "require_memory",
]

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


# --- the compiled engine's tables ----------------------------------------------------

_MADV_FREE = getattr(mmap, "MADV_FREE", None)  # Linux 4.5+, macOS, the BSDs
_MADV_HUGEPAGE = getattr(mmap, "MADV_HUGEPAGE", None)  # Linux
#: private: a shared anonymous mapping (Python's default) is shared memory, which gets
#: no transparent huge pages and cannot be freed lazily
_PRIVATE = getattr(mmap, "MAP_PRIVATE", 0) | getattr(mmap, "MAP_ANONYMOUS", 0)


_HUGE = 2 << 20  # a transparent huge page of x86-64 and arm64 Linux


class _TableBuffer(mmap.mmap):
    """Anonymous memory of one table: the only buffers :func:`release_table` keeps.

    ``start``: where the table starts, the buffer's first huge-page boundary, so
    that no 4 KB pages are left at its ends (the mapping is a huge page larger).
    """

    start = 0

    @property
    def room(self) -> int:
        """Bytes from ``start`` to the end."""
        return len(self) - self.start


class _Cache:
    """At most one released table buffer, kept until a solve takes it or its time is up.

    One daemon thread, started with the first buffer kept, lets a buffer go when its
    time is up (a thread started per solve took 0.2-0.6 ms on the machine of
    ``docs/fast-engine.md``, more than marking the pages free).
    """

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.wake = threading.Condition(self.lock)
        self.buffer: _TableBuffer | None = None
        self.deadline = 0.0  # time.monotonic() when the kept buffer is let go
        self.thread: threading.Thread | None = None

    def take(self, nbytes: int) -> _TableBuffer | None:
        """The kept buffer if it holds ``nbytes``; else none, and a smaller one is let go."""
        with self.lock:
            buffer, self.buffer = self.buffer, None
        if buffer is not None and buffer.room >= nbytes:
            return buffer
        return None  # a smaller buffer is unmapped here, before the new table is made

    def keep(self, buffer: _TableBuffer, seconds: float) -> None:
        with self.lock:
            old, self.buffer = self.buffer, buffer
            self.deadline = time.monotonic() + seconds
            if self.thread is None:
                self.thread = threading.Thread(
                    target=self._expire, name="optri-kept-table", daemon=True
                )
                self.thread.start()
            self.wake.notify()
        del old  # unmapped outside the lock

    def clear(self) -> None:
        with self.lock:
            old, self.buffer = self.buffer, None
        del old

    def _expire(self) -> None:
        """The daemon thread: lets the kept buffer go when its time is up."""
        while True:
            with self.lock:
                while self.buffer is None or time.monotonic() < self.deadline:
                    left = None if self.buffer is None else self.deadline - time.monotonic()
                    self.wake.wait(left)
                old, self.buffer = self.buffer, None
            del old  # unmapped outside the lock


_CACHE = _Cache()


def _reset_after_fork() -> None:
    global _CACHE
    _CACHE = _Cache()  # the parent's lock may have been held; its thread did not follow


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_reset_after_fork)


def new_table(n: int, dtype: Any) -> NDArray[Any]:
    """An uninitialized ``n x n`` table whose first cell starts a 64-byte cache line.

    A table of at least ``config.TABLE_CACHE_MIN_BYTES`` reuses the memory of the
    last one given to :func:`release_table`, if that is large enough and was
    released less than ``config.TABLE_CACHE_SECONDS`` ago; a smaller one kept is
    unmapped first, so that at most one table is held. Its contents are arbitrary:
    the engines write every cell before they read it.

    Smaller tables come from numpy, whose blocks start 16 bytes into a page: the
    table starts a few values in, so that the kernels' 64-byte vector loads and
    stores of a row do not each span two cache lines (1-6 % of the min-plus fill at
    n = 1000 and 4000, where every row starts a line, in interleaved runs).

    Parameters
    ----------
    n : int
        Rows and columns.
    dtype : numpy dtype
        Cell type.

    Returns
    -------
    numpy.ndarray
        C-contiguous, writable, ``(n, n)``.

    Examples
    --------
    >>> import numpy as np
    >>> int(new_table(100, np.dtype(np.float64)).ctypes.data % 64)
    0
    """
    dtype = np.dtype(dtype)
    nbytes = n * n * dtype.itemsize
    if _cacheable(nbytes):
        buffer = _CACHE.take(nbytes)
        if buffer is None:
            buffer = _TableBuffer(-1, nbytes + _HUGE, flags=_PRIVATE)  # untouched: no memory
            buffer.start = -np.frombuffer(buffer, np.uint8, 1).ctypes.data % _HUGE
            _advise(buffer, _MADV_HUGEPAGE)  # as numpy advises its large blocks
        return np.frombuffer(buffer, dtype, n * n, buffer.start).reshape(n, n)
    spare = 64 // dtype.itemsize
    block = np.empty(n * n + spare, dtype=dtype)
    start = (-block.ctypes.data % 64) // dtype.itemsize
    return block[start : start + n * n].reshape(n, n)


def release_table(table: NDArray[Any]) -> None:
    """Give back a table of :func:`new_table` that nothing will read or write again.

    Its buffer is kept for the next :func:`new_table` for
    ``config.TABLE_CACHE_SECONDS``, its pages marked free (``MADV_FREE``): the
    kernel takes them back whenever it needs memory, and until then a new table
    reuses them without the kernel zeroing fresh pages (4-7 ms of a 230 ms solve at
    n = 4000 on the machine of ``docs/fast-engine.md``). The process's resident
    size keeps counting them until then. Tables from numpy are left to numpy.

    Parameters
    ----------
    table : numpy.ndarray
        A table of :func:`new_table`, or any view of it. The caller must not use it
        afterwards: the next solve may write it.

    References
    ----------
    .. [1] madvise(2), ``MADV_FREE``: https://man7.org/linux/man-pages/man2/madvise.2.html

    Examples
    --------
    >>> import numpy as np
    >>> release_table(new_table(10, np.dtype(np.float64)))  # small: numpy's, not kept
    """
    buffer = _buffer_of(table)
    if buffer is None or not _cacheable(buffer.room):
        return
    if _advise(buffer, _MADV_FREE):
        _CACHE.keep(buffer, float(config.TABLE_CACHE_SECONDS))


def _buffer_of(table: NDArray[Any]) -> _TableBuffer | None:
    """The mapping under a table of :func:`new_table` (or a view of it); None: numpy's."""
    base = table.base
    while isinstance(base, np.ndarray):
        base = base.base
    if isinstance(base, memoryview):  # how np.frombuffer holds its buffer
        base = base.obj
    return base if isinstance(base, _TableBuffer) else None


def clear_table_cache() -> None:
    """Let go of the table memory kept for the next solve (:func:`release_table`) now.

    Examples
    --------
    >>> clear_table_cache()
    """
    _CACHE.clear()


def _cacheable(nbytes: int) -> bool:
    return (
        _MADV_FREE is not None
        and config.TABLE_CACHE_SECONDS > 0
        and nbytes >= config.TABLE_CACHE_MIN_BYTES
    )


def _advise(buffer: mmap.mmap, advice: int | None) -> bool:
    if advice is None:
        return False
    try:
        buffer.madvise(advice)
    except OSError:  # a kernel without it
        return False
    return True
