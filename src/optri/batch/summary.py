"""What a batch run reports: :class:`BatchSummary`, the running counts, duplicate ids."""

from __future__ import annotations

import collections
import hashlib
import shutil
import tempfile
import warnings
import weakref
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import config
from ..errors import DuplicateIdWarning

__all__ = ["BatchSummary", "Counter", "IdHashes", "id_hash"]

#: Duplicate ids named in the warning.
_NAMED = 5
#: Spilled hashes go to this many bucket files, by their top bits.
_BUCKET_BITS = 8


@dataclass(frozen=True)
class BatchSummary:
    """Counts of a batch run.

    Attributes
    ----------
    total, ok, errors : int
        Polygons read, triangulated, and given error records.
    partitions, reused : int
        Part files in the output, and how many an earlier run had already written.
    seconds : float
        Wall time of this run.
    output : Path
        The output directory or file.
    duplicates : int
        Records whose id an earlier record of the same output already has.

    Examples
    --------
    >>> import optri, tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "footprints.ndjson"
    >>> s = optri.batch(optri.data.path("footprints.ndjson"), out, workers=1)
    >>> s.total, s.ok, s.errors       # one bow-tie among the 31 footprints
    (31, 30, 1)
    """

    total: int
    ok: int
    errors: int
    partitions: int
    reused: int
    seconds: float
    output: Path
    duplicates: int = 0

    def __str__(self) -> str:
        rate = self.total / self.seconds if self.seconds > 0 else 0.0
        dup = f", {self.duplicates} duplicate ids" if self.duplicates else ""
        return (
            f"{self.total} polygons: {self.ok} ok, {self.errors} errors{dup} in "
            f"{self.seconds:.2f} s ({rate:.0f}/s; {self.partitions} partitions, "
            f"{self.reused} reused) -> {self.output}"
        )


class IdHashes:
    """The 64-bit hashes of a run's ids, to count the ones that repeat, in flat memory.

    Up to ``config.BATCH_ID_HASHES_IN_MEMORY`` hashes are held in memory. Beyond, they
    are appended to 256 temporary files by their top 8 bits, so that equal hashes share
    a file and :meth:`repeated` sorts one file at a time: the memory held stays below
    that limit plus one file, whatever the number of rows. The files live in a private
    temporary folder, removed by :meth:`repeated`, :meth:`close` or garbage collection.
    Hashes that cannot be written (a full disk) stay in memory, counted with their
    bucket's file; a half-written append is cut back first, so none counts twice.

    Examples
    --------
    >>> h = IdHashes(limit=2)
    >>> for part in ([1, 2], [3, 1], [2, 5]):
    ...     h.add(np.array(part, dtype=np.int64))
    >>> count, which = h.repeated()
    >>> count, sorted(which)
    (2, [1, 2])
    """

    def __init__(self, limit: int | None = None) -> None:
        self.limit = int(config.BATCH_ID_HASHES_IN_MEMORY if limit is None else limit)
        self._held: list[np.ndarray] = []
        self._held_n = 0
        self._folder: Path | None = None
        self._cleanup: weakref.finalize | None = None

    def add(self, hashes: np.ndarray) -> None:
        """Keep one part's hashes."""
        self._held.append(np.asarray(hashes, dtype=np.int64))
        self._held_n += len(hashes)
        if self._held_n > self.limit:
            self._spill()

    def _spill(self) -> None:
        """Append the held hashes to their bucket files; what cannot be written stays held."""
        held = np.concatenate(self._held)
        try:
            if self._folder is None:
                self._folder = Path(tempfile.mkdtemp(prefix="optri-ids-"))
                self._cleanup = weakref.finalize(
                    self, shutil.rmtree, self._folder, ignore_errors=True
                )
        except OSError:  # no room for a folder: memory it is (a later spill may retry)
            self.limit = max(self.limit, 2 * self._held_n)
            return
        kept = [rows for b, rows in _buckets(held) if not _append(self._bucket(b), rows)]
        self._held, self._held_n = kept, sum(len(k) for k in kept)
        if kept:  # a full disk: hold these until the held count doubles
            self.limit = max(self.limit, 2 * self._held_n)

    def _bucket(self, b: int) -> Path:
        assert self._folder is not None
        return self._folder / f"{b:03d}.bin"

    def repeated(self) -> tuple[int, set[int]]:
        """How many hashes repeat an earlier one, and which hashes repeat; the files go."""
        if self._folder is None:
            return _repeats(self._held)
        if self._held:
            self._spill()
        held = dict(_buckets(np.concatenate(self._held))) if self._held else {}
        count, which = 0, set[int]()
        try:
            for b in range(1 << _BUCKET_BITS):  # a file and what a full disk kept held
                path = self._bucket(b)
                parts = [np.fromfile(path, dtype=np.int64)] if path.exists() else []
                c, w = _repeats(parts + ([held[b]] if b in held else []))
                count += c
                which |= w
            return count, which
        finally:
            self.close()

    def close(self) -> None:
        """Remove the temporary files now."""
        if self._cleanup is not None:
            self._cleanup()


def _buckets(hashes: np.ndarray) -> Iterator[tuple[int, np.ndarray]]:
    """``(bucket, its hashes)`` for every bucket (the top bits) that ``hashes`` use."""
    bucket = (hashes.view(np.uint64) >> np.uint64(64 - _BUCKET_BITS)).astype(np.intp)
    order = np.argsort(bucket, kind="stable")
    bounds = np.searchsorted(bucket[order], np.arange((1 << _BUCKET_BITS) + 1))
    for b in np.flatnonzero(np.diff(bounds)):
        yield int(b), hashes[order[bounds[b] : bounds[b + 1]]]


def _append(path: Path, rows: np.ndarray) -> bool:
    """Append ``rows`` to ``path``; False, and the file as it was, when it cannot be written."""
    try:
        with open(path, "ab") as fh:
            start = fh.tell()
            try:
                _write(fh, rows)
            except OSError:
                fh.truncate(start)  # a half-written part would be counted twice
                raise
    except OSError:
        return False
    return True


def _write(fh: Any, rows: np.ndarray) -> None:
    rows.tofile(fh)


def _repeats(parts: list[np.ndarray]) -> tuple[int, set[int]]:
    if not parts:
        return 0, set()
    all_ = np.sort(np.concatenate(parts))
    same = all_[1:] == all_[:-1]
    return int(np.count_nonzero(same)), {int(h) for h in all_[1:][same]}


class Counter:
    """Running totals, reported to ``progress`` after each chunk, and the ids seen.

    Ids are kept as 64-bit hashes (:class:`IdHashes`, flat in memory); the ids
    themselves are looked up again in the output only when some hashes repeat.
    """

    def __init__(self, progress: Callable[[int, int], None] | None, total: int) -> None:
        self.progress, self.total = progress, total
        self.n = self.ok = self.errors = self.parts = self.reused = 0
        self.hashes = IdHashes()
        if progress is not None:
            progress(0, total)

    def add(self, records: Iterable[dict], reused: bool) -> None:
        """Count one part's records."""
        ids = []
        ok = 0
        for rec in records:
            ok += rec["status"] == "ok"
            ids.append(id_hash(rec["id"]))
        self.add_counts(np.array(ids, dtype=np.int64), ok, reused)

    def add_counts(self, hashes: np.ndarray, ok: int, reused: bool = False) -> None:
        """Count one part given as its ids' hashes (:func:`id_hash`) and its ok records."""
        self.n += len(hashes)
        self.ok += ok
        self.hashes.add(hashes)
        self.errors = self.n - self.ok
        self.parts += 1
        self.reused += reused
        if self.progress is not None:
            self.progress(self.n, max(self.total, self.n))

    def add_rows(self, ids: list[Any], statuses: list[str]) -> None:
        """Count one part's rows, given as columns."""
        self.add(({"id": i, "status": st} for i, st in zip(ids, statuses)), reused=False)

    def repeated_hashes(self) -> tuple[int, set[int]]:
        """How many records repeat an earlier id hash, and which hashes repeat."""
        return self.hashes.repeated()

    def summary(self, output: Path, seconds: float, duplicates: int = 0) -> BatchSummary:
        """The summary of this run."""
        return BatchSummary(
            self.n, self.ok, self.errors, self.parts, self.reused, seconds, output, duplicates
        )


def id_hash(value: Any) -> int:
    """A 64-bit hash of an id, the same in every process (worker processes hash their parts).

    By text: table formats may store the ids of a file mixing numbers and text as text.

    >>> id_hash(7) == id_hash("7"), id_hash("a") == id_hash("b")
    (True, False)
    """
    digest = hashlib.blake2b(str(value).encode("utf-8", "surrogatepass"), digest_size=8)
    return int.from_bytes(digest.digest(), "little", signed=True)


def report_duplicates(count: int, hashes: set[int], records: Iterator[dict]) -> None:
    """Warn about duplicate ids, naming a few (looked up in ``records``, the output)."""
    if not count:
        return
    seen: collections.Counter[Any] = collections.Counter()
    for rec in records:
        rid = rec["id"]
        if id_hash(rid) in hashes:
            seen[str(rid)] += 1
    named = [f"{k!r} x{v}" for k, v in seen.most_common() if v > 1][:_NAMED]
    warnings.warn(
        f"{count} record(s) repeat an earlier id ({', '.join(named)}); ids should be unique",
        DuplicateIdWarning,
        stacklevel=3,
    )
