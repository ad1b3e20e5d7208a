"""Where a batch writes: part files, the manifest, ``_SUCCESS``, resume checks, the lock.

Two layouts, chosen by the output path:

* a single file, by its suffix (``.gpkg``, ``.fgb``, ``.parquet``, ``.geojson``,
  ``.json``, ``.ndjson``, ``.jsonl``), or by ``out_fmt`` whatever its suffix:
  the parts are made in a hidden directory ``.OUT.parts`` beside it, joined
  into ``OUT`` atomically at the end, and the hidden directory removed;
* a directory, asked for explicitly: a path ending in ``/``, an existing
  directory, or a name without any suffix (``out_fmt`` then picks the parts'
  format): ``OUT/part-00000.ndjson``, ... plus
  ``OUT/_manifest.json`` (the options and input the parts were made from) and,
  once every part is written, ``OUT/_SUCCESS``.

Any other suffix is refused: a directory is never made under a name that looks
like a file. Part ``k`` always holds input polygons ``k*chunk_size`` to
``(k+1)*chunk_size - 1``, so a part that exists is the same whichever run
wrote it. While a run writes, ``.OUT.lock`` beside the output holds its pid and
an exclusive lock, so a second run into the same output is refused.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import BatchInputError, BatchLockedError
from ..io.atomic import write_json
from .writers import OUTPUT_FORMATS, PART_FORMATS, SINGLE_FILE_SUFFIXES

__all__ = ["Layout", "output_lock", "plan_layout"]

MANIFEST = "_manifest.json"
SUCCESS = "_SUCCESS"


@dataclass(frozen=True)
class Layout:
    """Paths of one batch output.

    ``fmt`` is the output format; ``part_fmt`` the format of the part files
    (the same, except for single GeoPackage / FlatGeobuf files, assembled
    from Parquet parts).
    """

    target: Path
    parts_dir: Path
    fmt: str
    single: bool

    @property
    def part_fmt(self) -> str:
        """Format of the part files."""
        return PART_FORMATS[self.fmt] if self.single else self.fmt

    def part(self, index: int) -> Path:
        """Path of part ``index``."""
        return self.parts_dir / f"part-{index:05d}{OUTPUT_FORMATS[self.part_fmt]}"

    def parts(self) -> list[Path]:
        """Existing complete part files, in order."""
        return sorted(self.parts_dir.glob(f"part-*{OUTPUT_FORMATS[self.part_fmt]}"))

    @property
    def manifest(self) -> Path:
        """The ``_manifest.json`` path."""
        return self.parts_dir / MANIFEST

    @property
    def success(self) -> Path:
        """The ``_SUCCESS`` marker path."""
        return self.parts_dir / SUCCESS

    @property
    def lock(self) -> Path:
        """The lock file beside the output."""
        return self.target.parent / f".{self.target.name}.lock"

    def started(self) -> bool:
        """True when an earlier run left output here."""
        if self.single and self.target.exists():
            return True
        return self.manifest.exists() or bool(self.parts())

    def clear(self) -> None:
        """Remove earlier output (``overwrite``): only files a batch writes."""
        if self.single:
            with contextlib.suppress(FileNotFoundError):
                self.target.unlink()
            shutil.rmtree(self.parts_dir, ignore_errors=True)
            return
        if not self.parts_dir.is_dir():
            return
        for p in self.parts_dir.iterdir():
            if p.name in (MANIFEST, SUCCESS) or _is_ours(p.name):
                p.unlink()

    def remove_stale_temporaries(self) -> None:
        """Delete half-written files left by a run killed with SIGKILL."""
        if self.parts_dir.is_dir():
            for p in self.parts_dir.glob(".part-*.tmp*"):
                with contextlib.suppress(FileNotFoundError):
                    p.unlink()

    def check_manifest(self, manifest: dict[str, Any]) -> None:
        """Write the manifest, or check it matches the one of the run being resumed."""
        if self.manifest.exists():
            try:
                old = json.loads(self.manifest.read_text())
            except (OSError, ValueError) as exc:
                raise BatchInputError(f"{self.manifest}: unreadable ({exc})") from None
            diff = sorted(k for k in manifest.keys() | old.keys() if manifest.get(k) != old.get(k))
            if diff:
                raise BatchInputError(
                    f"{self.target} was written from a different input or options "
                    f"(changed: {', '.join(diff)}); pass --overwrite to redo it"
                )
            return
        write_json(self.manifest, manifest)


def plan_layout(out: str | os.PathLike[str], out_fmt: str | None) -> Layout:
    """Pick the layout and format for output path ``out``.

    >>> plan_layout("results.gpkg", None).fmt, plan_layout("results.gpkg", None).part_fmt
    ('gpkg', 'parquet')
    >>> plan_layout("results/", None).part(3).name
    'part-00003.ndjson'
    >>> plan_layout("results.csv", None)
    Traceback (most recent call last):
    ...
    optri.errors.BatchInputError: results.csv: unknown output suffix '.csv'; ...
    """
    if out_fmt is not None and out_fmt not in OUTPUT_FORMATS:
        raise BatchInputError(
            f"unknown output format {out_fmt!r}; choose one of {list(OUTPUT_FORMATS)}"
        )
    text = os.fspath(out)
    target = Path(text)
    suffix = target.suffix.lower()
    # a directory named like a file (out.gpkg/) is used only when asked for with a "/"
    explicit_dir = text.endswith(("/", os.sep)) or (
        target.is_dir() and suffix not in SINGLE_FILE_SUFFIXES
    )
    if explicit_dir or not suffix:
        if target.exists() and not target.is_dir():
            raise BatchInputError(f"{target}: exists and is not a directory")
        return Layout(target, target, out_fmt or "ndjson", False)
    fmt = out_fmt or SINGLE_FILE_SUFFIXES.get(suffix)
    if fmt is None:
        known = ", ".join(sorted(SINGLE_FILE_SUFFIXES))
        raise BatchInputError(
            f"{target}: unknown output suffix {suffix!r}; use one of {known}, pass "
            "--out-format, or end the path with / for a directory of parts"
        )
    _check_replaceable(target)
    return Layout(target, target.parent / f".{target.name}.parts", fmt, True)


def _check_replaceable(target: Path) -> None:
    # an output replaces only a regular file: never a device, a FIFO or a directory
    try:
        mode = target.stat().st_mode
    except FileNotFoundError:
        return
    if not stat.S_ISREG(mode):
        kind = "a directory" if stat.S_ISDIR(mode) else "not a regular file"
        raise BatchInputError(f"{target}: is {kind}; choose another output path")


@contextlib.contextmanager
def output_lock(path: Path, target: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``path`` (which names our pid) while writing ``target``.

    Uses ``fcntl.flock``, so a lock held by a process that died, even by
    SIGKILL, is free again; the file is removed when the run ends.

    Raises
    ------
    BatchLockedError
        Another live process holds the lock.
    """
    try:
        import fcntl
    except ImportError:  # no flock (Windows): run unlocked
        yield
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = _acquire(path, target, fcntl)
    try:
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()  # before unlocking: a waiter then finds the file gone and retries
        os.close(fd)


def _acquire(path: Path, target: Path, fcntl: Any) -> int:
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            holder = os.read(fd, 64).decode(errors="replace").strip() or "unknown"
            os.close(fd)
            raise BatchLockedError(
                f"{target} is being written by another optri batch (pid {holder}; lock file "
                f"{path}); wait for it to finish, or write elsewhere"
            ) from None
        try:
            same = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:  # still the file at path (not one a finishing run just removed)
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode())
            return fd
        os.close(fd)


def _is_ours(name: str) -> bool:
    return name.startswith(("part-", ".part-")) and (
        name.split(".")[-1] in (*(s.lstrip(".") for s in OUTPUT_FORMATS.values()), "tmp")
        or ".tmp" in name
    )
