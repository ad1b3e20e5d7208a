"""Writing outputs atomically: a temporary file beside the target, renamed into place."""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

__all__ = ["atomic_write", "fsync_path", "kept_mode", "write_json"]


def fsync_path(path: str | os.PathLike[str]) -> None:
    """Flush a file (or a directory's entries) already written to the disk."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def kept_mode(target: str | os.PathLike[str]) -> int | None:
    """The permission bits of an existing ``target`` (None: there is none), for its replacement.

    A private (0600) file replaced by a new one made under the umask would
    become readable by others: every replacement gets the old file's bits.
    """
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except (FileNotFoundError, NotADirectoryError):
        return None


@contextlib.contextmanager
def atomic_write(
    path: str | os.PathLike[str], mode: str = "w", *, durable: bool = True
) -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; rename it over ``path`` on success.

    With ``durable`` (the default) the file's bytes reach the disk (``fsync``)
    before the rename; without it the rename is still atomic for every other
    process, but a power cut may leave the file empty or short, so a caller
    passing ``durable=False`` must verify the file before trusting it (as a
    batch's ledger does with each part's SHA-256) or sync it later.

    On any exception (or interruption) the temporary file is removed and an
    existing ``path`` is left untouched; a replaced ``path`` keeps its
    permission bits (:func:`kept_mode`). The temporary's name (this process's
    id and a random token) is chosen before the file is made, inside the guard
    that removes it, so a Ctrl-C or SIGTERM at any moment, even as the file
    comes into being, leaves nothing behind.

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
    tmp = target.parent / f".{target.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp"
    ours = True
    try:
        try:
            fd = os.open(tmp, _CREATE, 0o666)  # the umask applies: the usual file mode
        except FileExistsError:
            ours = False  # a name taken by chance: not ours to remove
            raise
        with os.fdopen(fd, mode) as fh:
            yield fh
            fh.flush()
            if durable:
                os.fsync(fh.fileno())
            bits = kept_mode(target)
            if bits is not None:
                os.chmod(fh.fileno(), bits)
        os.replace(tmp, target)
    except BaseException:
        if ours:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise


#: as ``tempfile.mkstemp`` opens its files: new, exclusive, not through a link
_CREATE = (
    os.O_RDWR
    | os.O_CREAT
    | os.O_EXCL
    | getattr(os, "O_NOFOLLOW", 0)
    | getattr(os, "O_CLOEXEC", 0)
    | getattr(os, "O_BINARY", 0)
)


def write_json(path: str | os.PathLike[str], obj: Any) -> None:
    """Write ``obj`` as indented JSON, atomically."""
    with atomic_write(path) as fh:
        json.dump(obj, fh, indent=2)
        fh.write("\n")
