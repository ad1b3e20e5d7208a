"""Writing outputs atomically: a temporary file beside the target, renamed into place."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_write", "write_json"]


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike[str], mode: str = "w") -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; rename it over ``path`` on success.

    On any exception (or interruption) the temporary file is removed and an
    existing ``path`` is left untouched. Ctrl-C, SIGTERM and SIGHUP are held
    from creating the temporary file until the guard that removes it is in
    place, so a signal at any moment leaves no temporary file behind.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_write(out) as fh:
    ...     _ = fh.write("done")
    >>> out.read_text()
    'done'
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    held = _hold_signals()  # no Ctrl-C / SIGTERM handler may run before the guard below
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except BaseException:
        _release(held)
        raise
    fh = None
    try:
        _release(held)  # a signal that came meanwhile is handled here, inside the guard
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual file mode
        fh = os.fdopen(fd, mode)
        with fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        if fh is None:
            with contextlib.suppress(OSError):
                os.close(fd)
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


#: signals whose Python handlers raise (Ctrl-C, and SIGTERM / SIGHUP in the CLI and batches)
_HELD = frozenset(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


def _hold_signals() -> set[int | signal.Signals] | None:
    """Block the signals of ``_HELD`` in the main thread; the old mask (None: nothing done).

    Python runs a signal's handler between two bytecodes of the main thread: one
    arriving between creating the temporary file and entering the ``try`` that
    removes it would leave the file behind. Held, it waits until the guard is set.
    """
    if not hasattr(signal, "pthread_sigmask"):
        return None
    if threading.current_thread() is not threading.main_thread():
        return None  # handlers only ever run in the main thread
    return signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)


def _release(old: set[int | signal.Signals] | None) -> None:
    if old is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_json(path: str | os.PathLike[str], obj: Any) -> None:
    """Write ``obj`` as indented JSON, atomically."""
    with atomic_write(path) as fh:
        json.dump(obj, fh, indent=2)
        fh.write("\n")
