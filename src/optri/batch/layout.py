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

Nothing is trusted for being there: the lock file is opened without following a
link, a parts folder that is a link or belongs to another user is refused, and a
part file is adopted on resume only when the ledger ``_parts.ndjson`` names it
with the SHA-256 of its bytes and the job (:func:`job_key`) it was made for. A
single output file, once assembled, gets ``.OUT.optri.json`` beside it: the job
it was made for, so a rerun reuses it only for the same job. An output that is
(or resolves to) the input, or a folder holding the input, is always refused.

Durability: nothing is synced to the disk part by part. A part is renamed into
place whole (no other process ever sees half of it) and its ledger line,
appended after the rename, names the SHA-256 of its bytes. A power cut may
lose the end of the ledger (a cut line is skipped) or leave a part short or
empty on disk: its bytes then no longer match the hash, so resume redoes it.
Hence neither the parts nor the ledger need an ``fsync`` of their own; each
file is synced once, when the job is complete: the assembled single file
before its rename, or, for a directory of parts, every part, the ledger and
the folder (:meth:`Layout.sync`) before ``_SUCCESS`` is written.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import shutil
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import BatchInputError, BatchLockedError
from ..io.atomic import fsync_path, write_json
from .writers import OUTPUT_FORMATS, PART_FORMATS, SINGLE_FILE_SUFFIXES

__all__ = ["Layout", "file_sha256", "job_key", "output_lock", "plan_layout"]

MANIFEST = "_manifest.json"
SUCCESS = "_SUCCESS"
LEDGER = "_parts.ndjson"
#: Manifest entries that do not change what the records are (how the work was cut).
_NOT_JOB = ("chunk_size",)
_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)


def file_sha256(path: str | os.PathLike[str]) -> str:
    """SHA-256 of a file's bytes, read in blocks (memory stays flat)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def job_key(manifest: dict[str, Any]) -> str:
    """A short hash of what makes a batch's records what they are (input, options, version)."""
    job = {k: v for k, v in manifest.items() if k not in _NOT_JOB}
    return hashlib.sha256(json.dumps(job, sort_keys=True).encode()).hexdigest()[:16]


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

    @property
    def ledger(self) -> Path:
        """The ledger of complete parts: one JSON line per part, with its hash and job."""
        return self.parts_dir / LEDGER

    @property
    def receipt(self) -> Path:
        """Beside a single output file: the job it was assembled for."""
        return self.target.parent / f".{self.target.name}.optri.json"

    def check_paths(self, inp: Path) -> None:
        """Refuse an output that is, or would hold, the input (whatever the path's spelling)."""
        source = inp.resolve()
        target = self.target.resolve()
        if source == target or (self.target.exists() and _same_file(inp, self.target)):
            raise BatchInputError(
                f"{self.target}: is the input {inp}; write the output to another path"
            )
        folder = self.parts_dir.resolve()
        if folder in source.parents:
            raise BatchInputError(
                f"{inp}: the input is inside the output {self.parts_dir}; "
                "move it out or write the output elsewhere"
            )

    def prepare(self) -> None:
        """Make the parts folder (private when hidden), or check the one there."""
        if not os.path.lexists(self.parts_dir):
            self.parts_dir.mkdir(mode=0o700 if self.single else 0o777, parents=True)
        self.check_work_folder()

    def check_work_folder(self) -> None:
        """Refuse a parts folder that is a link (hidden ones) or belongs to another user."""
        try:
            st = os.lstat(self.parts_dir)
        except FileNotFoundError:
            return
        if stat.S_ISLNK(st.st_mode) and self.single:
            raise BatchInputError(
                f"{self.parts_dir}: the work folder is a symbolic link; remove it "
                "(optri never writes through a link it did not make)"
            )
        st = os.stat(self.parts_dir)
        if not stat.S_ISDIR(st.st_mode):
            raise BatchInputError(f"{self.parts_dir}: exists and is not a directory")
        if hasattr(os, "geteuid") and st.st_uid != os.geteuid():
            raise BatchInputError(
                f"{self.parts_dir}: the work folder is owned by another user "
                f"(uid {st.st_uid}); remove it or write the output elsewhere"
            )

    def recorded(self, job: str) -> dict[str, str]:
        """``{part name: sha256}`` of the parts the ledger names for ``job``."""
        out: dict[str, str] = {}
        try:
            fd = os.open(self.ledger, os.O_RDONLY | _NOFOLLOW)
        except FileNotFoundError:
            return out
        except OSError as exc:
            raise BatchInputError(f"{self.ledger}: unreadable ({exc.strerror})") from None
        with os.fdopen(fd, encoding="utf-8", errors="replace") as fh:
            for line in fh:
                try:
                    entry = json.loads(line)
                except ValueError:
                    continue  # a line cut short by a kill: its part is redone
                if isinstance(entry, dict) and entry.get("job") == job:
                    out[str(entry.get("part"))] = str(entry.get("sha256"))
        return out

    def adopted(self, index: int, recorded: dict[str, str]) -> bool:
        """True when part ``index`` exists and holds exactly the bytes the ledger names."""
        part = self.part(index)
        digest = recorded.get(part.name)
        if digest is None or part.is_symlink() or not part.is_file():
            return False
        return file_sha256(part) == digest

    def record(
        self, index: int, first: int, count: int, job: str, sha256: str | None = None
    ) -> None:
        """Ledger entry for part ``index`` (input polygons ``first`` to ``first + count - 1``).

        ``sha256`` is the part's hash when its writer computed it (else read here).
        """
        part = self.part(index)
        entry = {
            "part": part.name,
            "first": first,
            "records": count,
            "sha256": sha256 or file_sha256(part),
            "job": job,
        }
        fd = os.open(self.ledger, os.O_WRONLY | os.O_APPEND | os.O_CREAT | _NOFOLLOW, 0o666)
        try:  # no fsync: the hash vouches for the part (see the module's docstring)
            os.write(fd, (json.dumps(entry, separators=(",", ":")) + "\n").encode())
        finally:
            os.close(fd)

    def sync(self) -> None:
        """Flush every part, the ledger and the folder's entries to the disk, once, at the end."""
        for p in (*self.parts(), self.ledger):
            if p.is_file():
                fsync_path(p)
        fsync_path(self.parts_dir)

    def drop_unrecorded(self, recorded: dict[str, str]) -> None:
        """Delete part files the ledger does not name (planted, or cut short by a kill)."""
        for p in self.parts():
            if p.name not in recorded:
                p.unlink()

    def check_receipt(self, manifest: dict[str, Any]) -> None:
        """A finished single file is reused only for the job its receipt names."""
        try:
            fd = os.open(self.receipt, os.O_RDONLY | _NOFOLLOW)
            with os.fdopen(fd, encoding="utf-8") as fh:
                old = json.load(fh)
        except FileNotFoundError:
            raise BatchInputError(
                f"{self.target} exists and was not written by this batch (no record of "
                f"its job in {self.receipt.name}); pass --overwrite to replace it"
            ) from None
        except (OSError, ValueError) as exc:
            raise BatchInputError(f"{self.receipt}: unreadable ({exc}); pass --overwrite") from None
        _compare(self.target, {k: v for k, v in manifest.items() if k not in _NOT_JOB}, old)
        if old.get("output_sha256") != file_sha256(self.target):
            raise BatchInputError(
                f"{self.target} was changed after the batch wrote it; pass --overwrite to redo it"
            )

    def write_receipt(self, manifest: dict[str, Any]) -> None:
        """Name the job beside the assembled single file."""
        job = {k: v for k, v in manifest.items() if k not in _NOT_JOB}
        write_json(self.receipt, {**job, "output_sha256": file_sha256(self.target)})

    def started(self) -> bool:
        """True when an earlier run left output here."""
        if self.single and self.target.exists():
            return True
        return self.manifest.exists() or bool(self.parts())

    def clear(self) -> None:
        """Remove earlier output (``overwrite``): only files a batch writes.

        A single output file stays until its replacement is renamed over it: a
        run that fails loses nothing, and the new file keeps the old one's mode.
        """
        if self.single:
            if self.parts_dir.is_symlink():
                self.parts_dir.unlink()  # the link only, never what it points to
            else:
                shutil.rmtree(self.parts_dir, ignore_errors=True)
            return
        if not self.parts_dir.is_dir():
            return
        for p in self.parts_dir.iterdir():
            if p.name in (MANIFEST, SUCCESS, LEDGER) or _is_ours(p.name):
                p.unlink()

    def remove_stale_temporaries(self) -> None:
        """Delete half-written files left by a run killed with SIGKILL.

        Called with the output's lock held, so no live run owns any of them:
        the parts' temporaries and the final file's (``.OUT.<pid>.<token>.tmp``).
        """
        stale = list(self.target.parent.glob(f".{_glob_escape(self.target.name)}.*.tmp"))
        if self.parts_dir.is_dir():
            stale += self.parts_dir.glob(".part-*.tmp*")
        for p in stale:
            with contextlib.suppress(FileNotFoundError):
                p.unlink()

    def check_manifest(self, manifest: dict[str, Any]) -> None:
        """Write the manifest, or check it matches the one of the run being resumed."""
        if self.manifest.exists():
            try:
                old = json.loads(self.manifest.read_text())
            except (OSError, ValueError) as exc:
                raise BatchInputError(f"{self.manifest}: unreadable ({exc})") from None
            _compare(self.target, manifest, old)
            return
        write_json(self.manifest, manifest)


def _compare(target: Path, manifest: dict[str, Any], old: Any) -> None:
    old = old if isinstance(old, dict) else {}
    diff = sorted(k for k in manifest if manifest.get(k) != old.get(k))
    if diff:
        raise BatchInputError(
            f"{target} was written from a different input or options "
            f"(changed: {', '.join(diff)}); pass --overwrite to redo it"
        )


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _glob_escape(name: str) -> str:
    return "".join(f"[{c}]" if c in "*?[" else c for c in name)


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
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | _NOFOLLOW, 0o600)
        except OSError as exc:
            if exc.errno != errno.ELOOP:
                raise
            raise BatchInputError(
                f"{path}: the lock file is a symbolic link; remove it (optri never writes "
                "through a link it did not make)"
            ) from None
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or (hasattr(os, "geteuid") and st.st_uid != os.geteuid()):
            os.close(fd)
            raise BatchInputError(
                f"{path}: the lock file is not a regular file of yours; remove it"
            )
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
